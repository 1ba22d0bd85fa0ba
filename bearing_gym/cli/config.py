"""``--config FILE``: options from a TOML or YAML file (keys are the long option names with
underscores; a table named after a subcommand applies to it only)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from .errors import CLIError, one_line
from .parser import COMMANDS, integer, number

__all__ = ["load_config", "config_defaults", "reproduce_config_args"]


def load_config(path: str) -> dict:
    """Read a TOML or YAML file into a dict (CLIError naming --config on any problem)."""
    p = Path(path)
    if not p.is_file():
        raise CLIError(f"--config: no such file: {path}")
    suffix = p.suffix.lower()
    text = p.read_text()
    if suffix == ".toml":
        try:
            import tomllib
        except ModuleNotFoundError:  # Python < 3.11
            try:
                import tomli as tomllib  # type: ignore[no-redef]
            except ModuleNotFoundError:
                raise CLIError("--config: reading TOML needs Python >= 3.11 or the tomli "
                               "package (pip install tomli); or use YAML") from None
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as err:
            raise CLIError(f"--config: {path}: invalid TOML: {one_line(err)}") from None
    elif suffix in (".yaml", ".yml"):
        import yaml

        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as err:
            raise CLIError(f"--config: {path}: invalid YAML: {one_line(err)}") from None
        data = {} if data is None else data
    else:
        raise CLIError(f"--config: {path}: unknown format {suffix or '(no suffix)'!r}; use "
                       ".toml, .yaml or .yml")
    if not isinstance(data, dict):
        raise CLIError(f"--config: {path}: must hold a table of options, got {type(data).__name__}")
    return data


def _option_actions(parser: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    skip = {"help", "config", "version"}
    return {a.dest: a for a in parser._actions if a.option_strings and a.dest not in skip}


def _long(action: argparse.Action) -> str:
    return max(action.option_strings, key=len)


def _convert_config_value(action: argparse.Action, key: str, value: Any) -> Any:
    opt = _long(action)
    where = f"{opt} (config key {key!r})"
    if isinstance(action, argparse._StoreTrueAction):
        if not isinstance(value, bool):
            raise CLIError(f"{where}: must be true or false, got {value!r}")
        return value

    def scalar(v: Any) -> Any:
        typ = action.type
        if typ in (number, integer):
            if isinstance(v, bool) or not isinstance(v, (int, float, str)):
                raise CLIError(f"{where}: must be a number, got {v!r}")
            if typ is integer:
                if isinstance(v, float) and not v.is_integer():
                    raise CLIError(f"{where}: must be an integer, got {v!r}")
                try:
                    v = int(v)
                except ValueError:
                    raise CLIError(f"{where}: must be an integer, got {v!r}") from None
            else:
                try:
                    v = float(v)
                except ValueError:
                    raise CLIError(f"{where}: must be a number, got {v!r}") from None
        elif v is not None and not isinstance(v, str):
            raise CLIError(f"{where}: must be a string, got {v!r}")
        if action.choices is not None and v not in action.choices:
            raise CLIError(f"{where}: must be one of {', '.join(map(str, action.choices))}, "
                           f"got {v!r}")
        return v

    if action.nargs in ("+", "*"):
        items = value if isinstance(value, (list, tuple)) else [value]
        if action.nargs == "+" and not items:
            raise CLIError(f"{where}: needs at least one value")
        return [scalar(v) for v in items]
    return scalar(value)


def config_defaults(cfg: dict, command: str, subs: dict[str, argparse.ArgumentParser]) -> dict:
    """Defaults for ``command`` from the config: top-level keys valid for the command plus its
    own table. A top-level key that no subcommand knows, or a key of the command's table that
    it does not know, is an error."""
    known = {k for name, sp in subs.items() if name != "reproduce" for k in _option_actions(sp)}
    actions = _option_actions(subs[command])
    out: dict = {}
    for key, value in cfg.items():
        if key in COMMANDS:
            if not isinstance(value, dict):
                raise CLIError(f"--config: [{key}] must be a table of options")
            continue
        k = str(key).replace("-", "_")
        if k not in known:
            raise CLIError(f"--config: unknown key {key!r} (keys are the long option names "
                           "with underscores, e.g. clearance_um)")
        if k in actions:
            out[k] = _convert_config_value(actions[k], key, value)
    table = cfg.get(command, {})
    for key, value in table.items():
        k = str(key).replace("-", "_")
        if k not in actions:
            raise CLIError(f"--config: unknown key {key!r} in [{command}] (valid: "
                           f"{', '.join(sorted(actions))})")
        out[k] = _convert_config_value(actions[k], key, value)
    return out


def reproduce_config_args(cfg: dict) -> list[str]:
    """The [reproduce] table as command-line options of bearing_gym.reproduction."""
    table = cfg.get("reproduce", {})
    if not isinstance(table, dict):
        raise CLIError("--config: [reproduce] must be a table of options")
    argv: list[str] = []
    for key, value in table.items():
        opt = "--" + str(key).replace("_", "-")
        if isinstance(value, bool):
            if value:
                argv.append(opt)
        elif isinstance(value, (list, tuple)):
            argv += [opt, *map(str, value)]
        else:
            argv += [opt, str(value)]
    return argv
