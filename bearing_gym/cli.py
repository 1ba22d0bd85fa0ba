"""``bearing-gym``: the command line of bearing_gym.

Subcommands (``bearing-gym COMMAND --help`` lists every option with its unit and default):

* ``simulate``     run the Simulator at an operating point, print a summary (peak-to-peak,
                   principal frequencies, periodic or quasi-periodic) and save time-series,
                   orbit, spectrum and Poincare plots plus the raw record (NPZ) in ``--out``;
* ``equilibrium``  static equilibrium: contact angles, loads per ball, 5x5 stiffness matrix;
* ``floquet``      Floquet multipliers of the settled response (finite differences);
* ``sweep``        stability map over preloads x speeds x radial loads x clearances, written
                   to a CSV file; a rerun with the same ``--out`` reuses the finished points;
                   tasks run on a local process pool or on Ray (``--backend ray --address``);
* ``watch``        play a trained policy (``--model DIR`` of train.py) or a scripted baseline
                   (``--policy constant:1000``) in BearingPreload-v0 with ``render_mode="human"``
                   (a live window, or PNG frames on a headless machine) and print each step;
* ``reproduce``    the reproduction of Bai & Xu (2006) (``python -m bearing_gym.reproduce``;
                   its options are passed through).

Every subcommand takes ``--config FILE`` (TOML or YAML; keys are the long option names with
underscores, e.g. ``clearance_um = 4``; a table named after a subcommand, e.g. ``[sweep]``,
applies to that subcommand only; options given on the command line win) and ``-q/--quiet``
(print nothing but errors). Bad values exit with status 2 and a one-line message on stderr
naming the option and its allowed range.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import contextlib
import csv
import importlib.util
import json
import math
import os
import re
import sys
import threading
from pathlib import Path
from typing import Any, Callable, Sequence

PROG = "bearing-gym"
COMMANDS = ("simulate", "equilibrium", "floquet", "sweep", "watch", "reproduce")

__all__ = ["main", "CLIError"]


class CLIError(Exception):
    """A user error: printed as ``bearing-gym: error: <message>``, exit status 2."""


class _RunError(Exception):
    """A failure of the computation itself (integration or equilibrium): exit status 1."""


# ---------------------------------------------------------------------------------------------
# operating-point options <-> BearingParams fields
# ---------------------------------------------------------------------------------------------
# option dest -> (BearingParams flat fields, divisor from the option's unit to SI, unit);
# divisors, not factors, so that 10 us is exactly 1e-5 s
_PARAM_OPTIONS: dict[str, tuple[tuple[str, ...], float | None, str]] = {
    "rpm": (("shaft_speed_rpm",), 1.0, "rpm"),
    "preload": (("axial_preload_n",), 1.0, "N"),
    "clearance_um": (("clearance_inner_m", "clearance_outer_m"), 1e6, "um"),
    "radial_load": (("radial_load_x_n", "radial_load_y_n"), 1.0, "N"),
    "eccentricity_um": (("eccentricity_m",), 1e6, "um"),
    "damping_ratio": (("damping_ratio",), 1.0, ""),
    "dt_us": (("dt_s",), 1e6, "us"),
    "race_control": (("race_control",), None, ""),
}
# list options of the sweep -> the single option with the same meaning
_LIST_OPTIONS = {"preloads": "preload", "rpms": "rpm", "radial_loads": "radial_load",
                 "clearances_um": "clearance_um", "damping_ratios": "damping_ratio"}


def _defaults() -> dict:
    from bearing_gym import default_params

    p = default_params()
    g = p.geometry
    return dict(clearance_max_um=(min(g.inner_groove_radius_m, g.outer_groove_radius_m)
                                  - g.ball_diameter_m / 2) * 1e6, rpm=p.shaft_speed_rpm, preload=p.loads.axial_preload_n,
                clearance_um=p.geometry.clearance_inner_m * 1e6,
                radial_load=p.loads.radial_load_x_n, eccentricity_um=p.rotor.eccentricity_m * 1e6,
                damping_ratio=p.damping.damping_ratio, dt_us=p.integrator.dt_s * 1e6,
                race_control=p.race_control)


_RANGE = re.compile(r"in ([\[(])([^,\]()]+), ([^,\]()]+)([\])])")


def _scaled_range(msg: str, divisor: float) -> str | None:
    """The first interval of a params error message, converted from SI to the option's unit."""
    m = _RANGE.search(msg)
    if not m:
        return None

    def conv(txt: str) -> str:
        try:
            v = float(txt)
        except ValueError:
            return txt
        return txt if math.isinf(v) else f"{v * divisor:g}"

    return f"{m.group(1)}{conv(m.group(2))}, {conv(m.group(3))}{m.group(4)}"


def _explain_params_error(err: Exception, owner: dict[str, tuple[str, str, Any]]) -> str:
    """One line naming the option behind a ValueError of bearing_gym.params."""
    msg = " ".join(str(err).split())
    field = msg.split(" ", 1)[0]
    if (field in ("inner_groove_radius_m", "outer_groove_radius_m", "clearance_inner_m",
                  "clearance_outer_m") and "clearance_inner_m" in owner):
        from bearing_gym import default_params

        g = default_params().geometry
        limit = min(g.inner_groove_radius_m, g.outer_groove_radius_m) - g.ball_diameter_m / 2
        opt, _, value = owner["clearance_inner_m"]
        if limit < 1e-3:
            return (f"{opt}: the clearance must be in [0, {limit * 1e6:g}) um (below the groove "
                    f"radius minus the ball radius), got {value:g}")
    if field not in owner:
        return f"invalid operating point: {msg}"
    opt, dest, value = owner[field]
    divisor = _PARAM_OPTIONS[dest][1]
    unit = _PARAM_OPTIONS[dest][2]
    text = f"{opt}: {msg}"
    if divisor not in (None, 1.0):
        rng = _scaled_range(msg, divisor)
        if rng:
            text += f" (i.e. {opt} must be in {rng} {unit}, got {value:g})"
    return text


def _make_params(items: Sequence[tuple[str, str, Any]], base=None):
    """BearingParams from (option string, option dest, value) triples; a bad value raises
    CLIError naming the option."""
    from bearing_gym import default_params

    over: dict[str, Any] = {}
    owner: dict[str, tuple[str, str, Any]] = {}
    for opt, dest, value in items:
        fields, divisor, _ = _PARAM_OPTIONS[dest]
        for f in fields:
            over[f] = value if divisor is None else value / divisor
            owner[f] = (opt, dest, value)
    try:
        return base.replace(**over) if base is not None else default_params(**over)
    except (ValueError, TypeError) as err:
        raise CLIError(_explain_params_error(err, owner)) from None


def _params_from_args(args, exclude: Sequence[str] = ()):
    items = [(f"--{d.replace('_', '-')}", d, getattr(args, d)) for d in _PARAM_OPTIONS
             if d not in exclude and hasattr(args, d)]
    return _make_params(items)


def _check(opt: str, value: Any, low: float, high: float, unit: str = "",
           low_open: bool = False) -> float:
    """``value`` if finite and in range, else CLIError('--opt: must be ... in [low, high] unit')."""
    rng = f"{'(' if low_open else '['}{low:g}, {high:g}]{(' ' + unit) if unit else ''}"
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise CLIError(f"{opt}: must be a finite number in {rng}, got {value!r}")
    if value < low or value > high or (low_open and value == low):
        raise CLIError(f"{opt}: must be in {rng}, got {value:g}")
    return float(value)


# ---------------------------------------------------------------------------------------------
# parser
# ---------------------------------------------------------------------------------------------
class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors are one line: ``bearing-gym: error: argument --rpm:
    ...`` (raised as CLIError, exit status 2)."""

    def error(self, message: str):  # type: ignore[override]
        raise CLIError(f"{message} (see '{self.prog} --help')")


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None


def _integer(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None


_number.__name__ = "number"
_integer.__name__ = "integer"


def _common(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("general")
    g.add_argument("--config", metavar="FILE", default=None,
                   help="TOML (.toml) or YAML (.yaml/.yml) file of options: keys are the long "
                        "option names with underscores (clearance_um = 4); a table named after "
                        "the subcommand ([sweep]) applies to it only; command-line options win")
    g.add_argument("-q", "--quiet", action="store_true",
                   help="print nothing but errors (no summary, no progress bar)")


def _operating_point(p: argparse.ArgumentParser, d: dict, *, preload: bool = True,
                     dt: bool = True) -> None:
    g = p.add_argument_group("operating point")
    g.add_argument("--rpm", type=_number, default=d["rpm"], metavar="RPM",
                   help="shaft speed (rpm, 0-200000; default %(default)g)")
    if preload:
        g.add_argument("--preload", type=_number, default=d["preload"], metavar="N",
                       help="axial preload P_z (N, 0-1e6; default %(default)g)")
    g.add_argument("--clearance-um", type=_number, default=d["clearance_um"], metavar="UM",
                   help=f"radial clearance c_i = c_o (um, 0 to below {d['clearance_max_um']:g}; "
                        "default %(default)g)")
    g.add_argument("--radial-load", type=_number, default=d["radial_load"], metavar="N",
                   help="radial load P_x = P_y (N, -1e6 to 1e6; default %(default)g)")
    g.add_argument("--eccentricity-um", type=_number, default=d["eccentricity_um"], metavar="UM",
                   help="rotor mass eccentricity e (um, 0-10000; default %(default)g)")
    g.add_argument("--damping-ratio", type=_number, default=d["damping_ratio"], metavar="ZETA",
                   help="viscous damping ratio on each rotor DOF (dimensionless, 0-1; "
                        "default %(default)g)")
    g.add_argument("--race-control", choices=("outer", "inner", "auto"),
                   default=d["race_control"],
                   help="race-control hypothesis of the ball kinematics (default %(default)s)")
    if dt:
        g.add_argument("--dt-us", type=_number, default=d["dt_us"], metavar="US",
                       help="integration time step (us, 0-1000; default %(default)g)")


def build_parser() -> tuple[argparse.ArgumentParser, dict[str, argparse.ArgumentParser]]:
    """The top-level parser and the subparsers by name."""
    from bearing_gym.analysis.sweeps import SweepSettings

    d = _defaults()
    s = SweepSettings()
    fmt = argparse.RawDescriptionHelpFormatter
    top = _Parser(
        prog=PROG, formatter_class=fmt,
        description="High-speed ball-bearing spindle (Bai & Xu 2006 model): simulation, "
                    "equilibrium, Floquet stability, stability maps and the paper's reproduction.",
        epilog="Options go after the subcommand; 'bearing-gym COMMAND --help' lists them.")
    from bearing_gym import __version__
    top.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = top.add_subparsers(dest="command", metavar="COMMAND", required=True)
    subs: dict[str, argparse.ArgumentParser] = {}

    p = sub.add_parser("simulate", help="time simulation with summary, plots and NPZ record",
                       description="Simulate the rotor from its static equilibrium; summarise the "
                                   "second half of the run (peak-to-peak, principal frequencies, "
                                   "periodic or quasi-periodic) and save plots and the record.")
    _operating_point(p, d)
    g = p.add_argument_group("simulation")
    g.add_argument("--duration", type=_number, default=0.5, metavar="S",
                   help="simulated time (s, > 0; default %(default)g); the summary uses the "
                        "second half")
    g.add_argument("--record-every", type=_integer, default=1, metavar="STEPS",
                   help="keep every STEPS-th time step in the record (default %(default)d)")
    g.add_argument("--qpi-threshold", type=_number, default=s.qpi_threshold, metavar="Q",
                   help="quasi-periodicity index above which the motion is called "
                        "quasi-periodic (dimensionless, 0-2; default %(default)g)")
    g.add_argument("--out", default="simulation", metavar="DIR",
                   help="output directory for record.npz, summary.json and the PNG plots "
                        "(default %(default)s)")
    g.add_argument("--no-plots", action="store_true", help="save the record and summary only")
    _common(p)
    subs["simulate"] = p

    p = sub.add_parser("equilibrium", help="static equilibrium: contact angles, loads, stiffness",
                       description="Quasi-static equilibrium of the rotor on the bearing at the "
                                   "operating point (no unbalance): rotor displacement, per-ball "
                                   "contact angles and loads, and the 5x5 stiffness matrix.")
    _operating_point(p, d, dt=False)
    g = p.add_argument_group("output")
    g.add_argument("--json", metavar="FILE", default=None,
                   help="also write the results as JSON to FILE ('-': stdout, instead of the table)")
    _common(p)
    subs["equilibrium"] = p

    p = sub.add_parser("floquet", help="Floquet multipliers of the settled periodic response",
                       description="Settle the response from the static equilibrium, then "
                                   "compute the Floquet multipliers of the stroboscopic map "
                                   "(one shaft period) by central finite differences.")
    _operating_point(p, d)
    g = p.add_argument_group("floquet")
    g.add_argument("--settle-s", type=_number, default=s.cold_settle_s, metavar="S",
                   help="simulated time before the multipliers are computed (s, >= 0; "
                        "default %(default)g)")
    g.add_argument("--measure-s", type=_number, default=s.measure_s, metavar="S",
                   help="window after settling used to check that the motion is periodic "
                        "(s, > 0, at least 3 shaft periods; default %(default)g)")
    g.add_argument("--fd-step-um", type=_number, default=0.1, metavar="UM",
                   help="finite-difference step of the translations (um, 0-10; tilts and "
                        "velocities are scaled from it; default %(default)g)")
    g.add_argument("--include-cage-angle", action="store_true",
                   help="add the cage angle as an 11th coordinate and drop its trivial multiplier")
    g.add_argument("--qpi-threshold", type=_number, default=s.qpi_threshold, metavar="Q",
                   help="quasi-periodicity index above which a warning says the motion is not "
                        "period-1 (dimensionless; default %(default)g)")
    g.add_argument("--json", metavar="FILE", default=None,
                   help="also write the results as JSON to FILE ('-': stdout, instead of the table)")
    _common(p)
    subs["floquet"] = p

    p = sub.add_parser("sweep", help="stability map over preload and other parameters (CSV)",
                       description="Stability map (bearing_gym.analysis.sweeps.stability_map): "
                                   "every preload for every combination of speed, radial load, "
                                   "clearance and damping ratio. Rows are appended to --out as "
                                   "points finish; a rerun with the same --out reuses the points "
                                   "already in it (same label, mode, preloads and operating "
                                   "point) and computes only the others; a rerun with other "
                                   "durations, criteria, --dt-us or --race-control is refused.")
    _operating_point(p, d, preload=False)
    g = p.add_argument_group("grid")
    g.add_argument("--preloads", type=_number, nargs="+", metavar="N", default=None,
                   help="axial preloads (N, 0-1e6; required); with --mode continuation give them "
                        "in the order to follow, descending to track the period-1 orbit down")
    g.add_argument("--rpms", type=_number, nargs="+", metavar="RPM", default=None,
                   help="shaft speeds (rpm; default: --rpm only)")
    g.add_argument("--radial-loads", type=_number, nargs="+", metavar="N", default=None,
                   help="radial loads P_x = P_y (N; default: --radial-load only)")
    g.add_argument("--clearances-um", type=_number, nargs="+", metavar="UM", default=None,
                   help="clearances c_i = c_o (um; default: --clearance-um only)")
    g.add_argument("--damping-ratios", type=_number, nargs="+", metavar="ZETA", default=None,
                   help="damping ratios (dimensionless; default: --damping-ratio only)")
    g.add_argument("--mode", choices=("continuation", "cold"), default="continuation",
                   help="continuation: each preload starts from the previous end state; cold: "
                        "every point from its static equilibrium (default %(default)s)")
    g = p.add_argument_group("sweep settings")
    g.add_argument("--settle-s", type=_number, default=s.settle_s, metavar="S",
                   help="settling time of a continuation point (s, >= 0; default %(default)g)")
    g.add_argument("--cold-settle-s", type=_number, default=s.cold_settle_s, metavar="S",
                   help="settling time of a cold start and of the first point of a chain "
                        "(s, >= 0; default %(default)g)")
    g.add_argument("--measure-s", type=_number, default=s.measure_s, metavar="S",
                   help="measured window per point (s, > 0, at least 3 shaft periods; "
                        "default %(default)g)")
    g.add_argument("--qpi-threshold", type=_number, default=s.qpi_threshold, metavar="Q",
                   help="quasi-periodicity index above which a point is not period-1 "
                        "(dimensionless; default %(default)g)")
    g.add_argument("--refine-step", type=_number, default=s.refine_step_n, metavar="N",
                   help="finer preload step to bracket the first loss of stability in a "
                        "continuation chain (N, > 0; default: no refinement)")
    g.add_argument("--no-floquet", action="store_true",
                   help="skip the Floquet multipliers (faster; stability from the index only)")
    g.add_argument("--workers", type=_integer, default=min(2, os.cpu_count() or 1), metavar="N",
                   help="parallel worker processes of the local backend, or CPUs of the local "
                        "Ray instance of --backend ray without --address (>= 1; default "
                        "%(default)d)")
    g.add_argument("--backend", choices=("local", "ray"), default="local",
                   help="where the tasks run: local = a pool of --workers processes on this "
                        "machine; ray = Ray tasks, on a new local Ray instance or on the cluster "
                        "at --address, one CPU per chain or cold start (needs pip install "
                        "'bearing-gym[ray]'); the rows are the same (default %(default)s)")
    g.add_argument("--address", default=None, metavar="ADDR",
                   help="with --backend ray: the Ray cluster: 'auto' (the cluster this node "
                        "joined with 'ray start', or $RAY_ADDRESS), HOST:6379, or "
                        "ray://HOST:10001 (Ray Client, from outside the cluster); every node "
                        "needs the same bearing-gym install (default: start a local Ray "
                        "instance with --workers CPUs, stopped at the end)")
    g = p.add_argument_group("output")
    g.add_argument("--out", default="stability_map.csv", metavar="CSV",
                   help="CSV file of the points (columns of sweeps.COLUMNS; lengths in m); "
                        "reused on a rerun (default %(default)s)")
    g.add_argument("--plot", default=None, metavar="PNG",
                   help="also save a stability-map (or preload-sweep) figure to PNG")
    _common(p)
    subs["sweep"] = p

    p = sub.add_parser("watch", help="play a trained or scripted policy in the env, live",
                       description="Play a policy in BearingPreload-v0 with render_mode='human': "
                                   "a matplotlib window showing the orbit, the Poincare section "
                                   "and the preload, updated every control interval (20 ms); on "
                                   "a machine without a display the frames are written as PNG "
                                   "files instead (--frames). Prints one line per step: t, "
                                   "preload, set-point, quasi-periodicity index, reward.")
    g = p.add_argument_group("policy (one of)")
    g.add_argument("--model", metavar="DIR", default=None,
                   help="directory written by train.py (model.zip, config.json and "
                        "vec_normalize.pkl, whose statistics normalise the observations)")
    g.add_argument("--policy", metavar="NAME", default=None,
                   help="scripted baseline: constant:N (fixed set-point, N in 300-2000), "
                        "feedback (raise on quasi-periodic vibration, lower slowly), "
                        "schedule[:MARGIN] (speed-scheduled table, + MARGIN N, default 100), "
                        "oracle[:MARGIN] (true operating point + stability map)")
    g = p.add_argument_group("episodes")
    g.add_argument("--episodes", type=_integer, default=1, metavar="N",
                   help="episodes to play (1-1000; default %(default)d)")
    g.add_argument("--steps", type=_integer, default=250, metavar="N",
                   help="control intervals (20 ms) per episode (1-100000; default %(default)d "
                        "= 5 s)")
    g.add_argument("--seed", type=_integer, default=0, metavar="S",
                   help="seed of the first episode; episode k uses S + k (>= 0; default "
                        "%(default)d)")
    g.add_argument("--scenario", choices=("randomized", "paper"), default="randomized",
                   help="operating conditions: randomized (speed, radial load, clearance, "
                        "waviness drawn per episode) or paper (20000 rpm, c = 4 um; default "
                        "%(default)s)")
    g.add_argument("--frames", metavar="DIR", default=None,
                   help="also save every frame as DIR/frame_NNNNN.png (default without a "
                        "display: only the latest frame, in <temp dir>/bearing_gym/latest.png)")
    _common(p)
    subs["watch"] = p

    p = sub.add_parser("reproduce", add_help=False, allow_abbrev=False,
                       help="reproduce Bai & Xu (2006) (options of python -m bearing_gym.reproduce)",
                       description="Run python -m bearing_gym.reproduce; every option other than "
                                   "--config and --quiet is passed through (see "
                                   "'bearing-gym reproduce --help'). The config file's "
                                   "[reproduce] table is turned into options.")
    _common(p)
    subs["reproduce"] = p
    return top, subs


# ---------------------------------------------------------------------------------------------
# config files
# ---------------------------------------------------------------------------------------------
def _one_line(text: Any) -> str:
    return " ".join(str(text).split())


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
            raise CLIError(f"--config: {path}: invalid TOML: {_one_line(err)}") from None
    elif suffix in (".yaml", ".yml"):
        import yaml

        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as err:
            raise CLIError(f"--config: {path}: invalid YAML: {_one_line(err)}") from None
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
        if typ in (_number, _integer):
            if isinstance(v, bool) or not isinstance(v, (int, float, str)):
                raise CLIError(f"{where}: must be a number, got {v!r}")
            if typ is _integer:
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


def _config_defaults(cfg: dict, command: str, subs: dict[str, argparse.ArgumentParser]) -> dict:
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


def _reproduce_config_args(cfg: dict) -> list[str]:
    """The [reproduce] table as command-line options of bearing_gym.reproduce."""
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


# ---------------------------------------------------------------------------------------------
# output helpers
# ---------------------------------------------------------------------------------------------
class _Out:
    """print() unless --quiet."""

    def __init__(self, quiet: bool):
        self.quiet = quiet

    def __call__(self, *a: Any, **k: Any) -> None:
        if not self.quiet:
            print(*a, **k)


def _jsonable(x: Any) -> Any:
    import numpy as np

    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, complex):
        return dict(re=_jsonable(x.real), im=_jsonable(x.imag))
    return x


def _write_json(data: dict, dest: str | None) -> None:
    if dest is None:
        return
    text = json.dumps(_jsonable(data), indent=1) + "\n"
    if dest == "-":
        sys.stdout.write(text)
        return
    path = Path(dest)
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def _op_text(params) -> str:
    g, ld = params.geometry, params.loads
    c = (f"c = {g.clearance_inner_m * 1e6:g} um" if g.clearance_inner_m == g.clearance_outer_m
         else f"c_i = {g.clearance_inner_m * 1e6:g} um, c_o = {g.clearance_outer_m * 1e6:g} um")
    return (f"{params.shaft_speed_rpm:g} rpm, P_z = {ld.axial_preload_n:g} N, "
            f"P_x = {ld.radial_load_x_n:g} N, P_y = {ld.radial_load_y_n:g} N, {c}, "
            f"e = {params.rotor.eccentricity_m * 1e6:g} um, zeta = {params.damping.damping_ratio:g}, "
            f"{params.race_control}-race control")


def _params_dict(params) -> dict:
    import dataclasses

    return _jsonable(dataclasses.asdict(params))


def _advance(sim, duration_s: float, record_every: int, quiet: bool, desc: str):
    """sim.advance in chunks with a tqdm bar (shown only if the run takes more than ~1 s).
    The chunks are whole multiples of record_every steps, so the record equals one call's."""
    import numpy as np

    from bearing_gym.physics import SimulationError, SimulationRecord

    dt = sim.dt_s
    n_total = int(round(duration_s / dt))
    chunk = max(record_every, (max(n_total // 100, 1) // record_every) * record_every)
    bar = None
    if not quiet:
        from tqdm.auto import tqdm

        bar = tqdm(total=round(n_total * dt, 9), desc=desc, unit="s", delay=1.0,
                   bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s simulated [{elapsed}<{remaining}]")
    parts = []
    done = 0
    try:
        while done < n_total:
            k = min(chunk, n_total - done)
            try:
                rec = sim.advance(k * dt, record_every)
            except SimulationError as err:    # hand back everything computed so far
                if err.record is not None:
                    parts.append(err.record.data)
                partial = SimulationRecord(np.concatenate(parts), err.record.status
                                           if err.record is not None else str(err))
                raise SimulationError(str(err), partial) from None
            parts.append(rec.data)
            done += k
            if bar is not None:
                bar.update(k * dt)
    finally:
        if bar is not None:
            bar.close()
    return SimulationRecord(np.concatenate(parts) if parts else np.empty((0, 0)))


# ---------------------------------------------------------------------------------------------
# simulate
# ---------------------------------------------------------------------------------------------
_RECORD_FIELDS = ("t", "x", "y", "z", "theta_x", "theta_y", "x_dot", "y_dot", "z_dot",
                  "theta_x_dot", "theta_y_dot", "cage_speed", "cage_angle", "shaft_angle",
                  "bearing_force", "n_inner_contacts")


class _Window:
    """A SimulationRecord restricted to a boolean mask (for the analysis functions)."""

    def __init__(self, rec, mask):
        self._rec, self._mask = rec, mask

    def __getattr__(self, name: str):
        return getattr(self._rec, name)[self._mask]


def cmd_simulate(args, say: _Out) -> int:
    import time

    import numpy as np

    from bearing_gym.analysis.poincare import shaft_section
    from bearing_gym.analysis.signals import quasi_periodicity_index
    from bearing_gym.analysis.spectra import (ball_pass_frequency, ball_pass_frequency_inner,
                                              principal_frequency, spectral_peaks)
    from bearing_gym.physics import SimulationError, Simulator
    from bearing_gym.physics.equilibrium import EquilibriumError

    params = _params_from_args(args)
    duration = _check("--duration", args.duration, 0.0, 1e4, "s", low_open=True)
    if isinstance(args.record_every, bool) or not 1 <= args.record_every <= 10**6:
        raise CLIError(f"--record-every: must be an integer in [1, 1000000], got {args.record_every}")
    _check("--qpi-threshold", args.qpi_threshold, 0.0, 2.0, low_open=True)
    dt = params.integrator.dt_s
    if int(round(duration / dt)) < 4 * args.record_every:
        raise CLIError(f"--duration: must span at least 4 recorded steps "
                       f"({4 * args.record_every * dt:g} s at --dt-us {dt * 1e6:g} and "
                       f"--record-every {args.record_every}), got {duration:g}")
    out = Path(args.out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise CLIError(f"--out: cannot create {out}: {err.strerror or err}") from None

    say(f"bearing-gym simulate: {_op_text(params)}; {duration:g} s at dt = {dt * 1e6:g} us")
    t0 = time.perf_counter()
    try:
        sim = Simulator(params)
    except (EquilibriumError, SimulationError) as err:
        raise _RunError(f"no static equilibrium at this operating point: {_one_line(err)}") from None
    status = "ok"
    try:
        rec = _advance(sim, duration, args.record_every, say.quiet, "simulate")
    except SimulationError as err:
        rec, status = err.record, _one_line(err)
    wall = time.perf_counter() - t0

    fields = {}
    if len(rec.data):
        fields = {f: getattr(rec, f) for f in _RECORD_FIELDS}
    np.savez_compressed(out / "record.npz", **fields, status=np.array(status),
                        record_every=np.array(args.record_every), dt_s=np.array(dt),
                        params_json=np.array(json.dumps(_params_dict(params))))
    if status != "ok":
        raise _RunError(f"simulation stopped: {status} (partial record in {out / 'record.npz'})")

    t = rec.t
    late = t >= t[0] + 0.5 * (t[-1] - t[0])
    w = params.shaft_speed_rad_s
    win = _Window(rec, late)
    ptp = {k: float(np.ptp(getattr(win, k))) for k in ("x", "y", "z", "cage_speed")}
    cage_mean = float(np.mean(win.cage_speed))
    xyz = np.column_stack([win.x, win.y, win.z])
    try:
        qpi = quasi_periodicity_index(win.t, xyz, w)
    except ValueError:
        qpi = None
    if qpi is None:
        verdict = "undetermined (the second half spans fewer than 3 shaft periods)"
    elif w == 0:
        verdict = "static (shaft not turning)"
    elif qpi < args.qpi_threshold:
        verdict = "periodic (period-1)"
    else:
        verdict = "quasi-periodic (or chaotic)"
    freqs = {}
    for k in ("x", "y", "z", "cage_speed"):
        try:
            f = principal_frequency(win.t, getattr(win, k))
        except (ValueError, IndexError):
            f = math.nan
        freqs[k] = f
    try:
        peaks_x = spectral_peaks(win.t, win.x, 3, fmin_hz=1.0)
    except (ValueError, IndexError):
        peaks_x = []
    nb = params.geometry.n_balls
    ref = dict(shaft_hz=w / (2 * math.pi), ball_pass_outer_hz=ball_pass_frequency(cage_mean, nb),
               ball_pass_inner_hz=ball_pass_frequency_inner(w, cage_mean, nb))
    summary = dict(operating_point=_op_text(params), duration_s=duration, dt_s=dt,
                   window_s=[float(win.t[0]), float(win.t[-1])], wall_s=wall,
                   ptp_x_um=ptp["x"] * 1e6, ptp_y_um=ptp["y"] * 1e6, ptp_z_um=ptp["z"] * 1e6,
                   cage_speed_ptp_rad_s=ptp["cage_speed"], cage_speed_mean_rad_s=cage_mean,
                   principal_frequency_hz={k: v for k, v in freqs.items()},
                   spectral_peaks_x_hz=[f for f, _ in peaks_x], reference_frequencies_hz=ref,
                   quasi_periodicity_index=qpi, qpi_threshold=args.qpi_threshold,
                   motion=verdict, params=_params_dict(params))

    def hz(v: float) -> str:
        return "n/a" if not math.isfinite(v) else f"{v:.1f}"

    say(f"simulated {duration:g} s in {wall:.2f} s wall; summary over "
        f"t = {win.t[0]:.4g}-{win.t[-1]:.4g} s:")
    say(f"  peak-to-peak: x {ptp['x'] * 1e6:.3f} um, y {ptp['y'] * 1e6:.3f} um, "
        f"z {ptp['z'] * 1e6:.3f} um, cage speed {ptp['cage_speed']:.3f} rad/s "
        f"(mean {cage_mean:.2f} rad/s)")
    say(f"  principal frequencies (Hz): x {hz(freqs['x'])}, y {hz(freqs['y'])}, "
        f"z {hz(freqs['z'])}, cage speed {hz(freqs['cage_speed'])}  "
        f"(resolution {1.0 / max(win.t[-1] - win.t[0], 1e-12):.3g} Hz)")
    say(f"  reference (Hz): shaft {ref['shaft_hz']:.1f}, ball pass N w_c {ref['ball_pass_outer_hz']:.1f}, "
        f"N (w - w_c) {ref['ball_pass_inner_hz']:.1f}")
    q_txt = "n/a" if qpi is None else f"{qpi:.3f}"
    say(f"  motion: {verdict} (quasi-periodicity index {q_txt}, threshold {args.qpi_threshold:g})")

    written = ["record.npz", "summary.json"]
    if not args.no_plots:
        written += _simulate_plots(rec, late, params, freqs, ref, qpi, out, shaft_section)
    (out / "summary.json").write_text(json.dumps(_jsonable(dict(summary, files=written)),
                                                 indent=1) + "\n")
    say(f"  wrote {', '.join(written)} in {out}")
    return 0


def _simulate_plots(rec, late, params, freqs, ref, qpi, out: Path, shaft_section) -> list[str]:
    import numpy as np
    from matplotlib.figure import Figure

    from bearing_gym.analysis.spectra import power_spectrum

    title = _op_text(params)
    t = rec.t
    written = []

    fig = Figure(figsize=(8, 8), layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    for ax, (k, f, unit) in zip(axes, (("x", 1e6, "um"), ("y", 1e6, "um"), ("z", 1e6, "um"),
                                       ("cage_speed", 1.0, "rad/s"))):
        ax.plot(t * 1e3, getattr(rec, k) * f, lw=0.6)
        ax.axvspan(t[0] * 1e3, t[late][0] * 1e3, color="0.9", lw=0)
        ax.set_ylabel(f"{k} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].set_title(f"time series (grey: first half, not summarised)\n{title}", fontsize=8)
    axes[-1].set_xlabel("t (ms)")
    fig.savefig(out / "timeseries.png", dpi=110)
    written.append("timeseries.png")

    fig = Figure(figsize=(9, 4.2), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    a1.plot(rec.x[late] * 1e6, rec.y[late] * 1e6, lw=0.5)
    a1.set_xlabel("x (um)")
    a1.set_ylabel("y (um)")
    a1.set_aspect("equal", adjustable="datalim")
    a2.plot(rec.x[late] * 1e6, rec.z[late] * 1e6, lw=0.5)
    a2.set_xlabel("x (um)")
    a2.set_ylabel("z (um)")
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    fig.suptitle(f"orbit, second half\n{title}", fontsize=8)
    fig.savefig(out / "orbit.png", dpi=110)
    written.append("orbit.png")

    fig = Figure(figsize=(8, 6), layout="constrained")
    axes = fig.subplots(2, 1)
    tl = t[late]
    top = [0.0, 0.0]
    for k in ("x", "y", "z"):
        try:
            f, p = power_spectrum(tl, getattr(rec, k)[late])
        except ValueError:
            continue
        axes[0].semilogy(f, np.maximum(p, 1e-40) * 1e12, lw=0.8, label=f"{k} (PSD, um^2/Hz)")
        top[0] = max(top[0], float(np.max(p)) * 1e12)
    try:
        f, p = power_spectrum(tl, rec.cage_speed[late])
        axes[1].semilogy(f, np.maximum(p, 1e-40), lw=0.8, color="C3", label="cage speed")
        top[1] = float(np.max(p))
    except ValueError:
        pass
    for ax, hi in zip(axes, top):
        if hi > 0:
            ax.set_ylim(hi * 1e-12, hi * 10)       # 12 decades: the noise floor is not news
        for (lab, v), ls in zip(ref.items(), (":", "--", "-.")):
            if v > 0 and math.isfinite(v):
                ax.axvline(v, color="0.4", ls=ls, lw=0.8, label=lab.replace("_hz", ""))
        ax.set_xlim(0, max(5 * max(ref.values()), 10.0))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("PSD of x, y, z (um^2/Hz)")
    axes[1].set_ylabel("PSD of cage speed ((rad/s)^2/Hz)")
    axes[1].set_xlabel("frequency (Hz)")
    axes[0].set_title(f"spectra, second half; principal x {freqs['x']:.1f} Hz, cage "
                      f"{freqs['cage_speed']:.1f} Hz\n{title}", fontsize=8)
    fig.savefig(out / "spectrum.png", dpi=110)
    written.append("spectrum.png")

    fig = Figure(figsize=(9, 4.2), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    try:
        pts = shaft_section(_Window(rec, late), ("x", "y", "z")) * 1e6
    except ValueError:
        pts = np.empty((0, 3))
    a1.plot(pts[:, 0], pts[:, 1], "o", ms=3)
    a1.set_xlabel("x (um)")
    a1.set_ylabel("y (um)")
    a2.plot(pts[:, 0], pts[:, 2], "o", ms=3)
    a2.set_xlabel("x (um)")
    a2.set_ylabel("z (um)")
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    q = "n/a" if qpi is None else f"{qpi:.3f}"
    fig.suptitle(f"Poincare section once per shaft revolution ({len(pts)} points, "
                 f"quasi-periodicity index {q})\n{title}", fontsize=8)
    fig.savefig(out / "poincare.png", dpi=110)
    written.append("poincare.png")
    return written


# ---------------------------------------------------------------------------------------------
# equilibrium
# ---------------------------------------------------------------------------------------------
_K_ROWS = ("F_x", "F_y", "F_z", "M_x", "M_y")
_K_COLS = ("x", "y", "z", "theta_x", "theta_y")


def cmd_equilibrium(args, say: _Out) -> int:
    import numpy as np

    from bearing_gym.physics import static_equilibrium
    from bearing_gym.physics.equilibrium import EquilibriumError

    params = _params_from_args(args)
    if args.json == "-":               # JSON on stdout: no table mixed into it
        say = _Out(True)
    try:
        eq = static_equilibrium(params)
    except EquilibriumError as err:
        raise _RunError(_one_line(err)) from None
    n = params.geometry.n_balls
    phi = np.degrees(2 * np.pi * np.arange(n) / n + params.initial_cage_angle_rad)
    U = eq.U
    say(f"static equilibrium: {_op_text(params)}")
    say(f"rotor displacement: x {U[0] * 1e6:.4f} um, y {U[1] * 1e6:.4f} um, z {U[2] * 1e6:.4f} um, "
        f"theta_x {U[3] * 1e6:.4f} urad, theta_y {U[4] * 1e6:.4f} urad")
    say(f"cage/shaft speed ratio {eq.cage_speed_ratio:.5f} (cage speed {eq.cage_speed_rad_s:.2f} "
        f"rad/s); residual {eq.residual:.2g} N after {eq.iterations} iterations")
    say("")
    say(f"{'ball':>4} {'angle':>7} {'alpha_i':>8} {'alpha_o':>8} {'Q_i':>9} {'Q_o':>9} "
        f"{'delta_i':>8} {'delta_o':>8} {'omega_m':>9} {'control':>7}")
    say(f"{'':>4} {'(deg)':>7} {'(deg)':>8} {'(deg)':>8} {'(N)':>9} {'(N)':>9} "
        f"{'(um)':>8} {'(um)':>8} {'(rad/s)':>9} {'race':>7}")
    for j in range(n):
        say(f"{j:>4d} {phi[j]:7.1f} {math.degrees(eq.alpha_i[j]):8.3f} "
            f"{math.degrees(eq.alpha_o[j]):8.3f} {eq.q_i[j]:9.2f} {eq.q_o[j]:9.2f} "
            f"{eq.delta_i[j] * 1e6:8.4f} {eq.delta_o[j] * 1e6:8.4f} {eq.orbital_speed[j]:9.2f} "
            f"{'inner' if eq.inner_race_control[j] else 'outer':>7}")
    say("")
    say("stiffness matrix K = -dF/dU (rows F_x, F_y, F_z in N and M_x, M_y in N m; columns "
        "x, y, z in m and theta_x, theta_y in rad):")
    say(f"{'':>5}" + "".join(f"{c:>12}" for c in _K_COLS))
    for i, r in enumerate(_K_ROWS):
        say(f"{r:>5}" + "".join(f"{v:12.4e}" for v in eq.stiffness[i]))
    data = dict(operating_point=_op_text(params), params=_params_dict(params),
                rotor_displacement=dict(zip(("x_m", "y_m", "z_m", "theta_x_rad", "theta_y_rad"), U)),
                cage_speed_ratio=eq.cage_speed_ratio, cage_speed_rad_s=eq.cage_speed_rad_s,
                residual_n=eq.residual, iterations=eq.iterations,
                balls=dict(angle_deg=phi, alpha_i_deg=np.degrees(eq.alpha_i),
                           alpha_o_deg=np.degrees(eq.alpha_o), q_i_n=eq.q_i, q_o_n=eq.q_o,
                           delta_i_m=eq.delta_i, delta_o_m=eq.delta_o,
                           orbital_speed_rad_s=eq.orbital_speed, spin_speed_rad_s=eq.spin_speed,
                           gyroscopic_moment_n_m=eq.gyroscopic_moment,
                           inner_race_control=eq.inner_race_control),
                stiffness=dict(rows=_K_ROWS, columns=_K_COLS, matrix=eq.stiffness,
                               units="rows F_x, F_y, F_z (N), M_x, M_y (N m); columns x, y, z (m), "
                                     "theta_x, theta_y (rad)"))
    _write_json(data, args.json)
    return 0


# ---------------------------------------------------------------------------------------------
# floquet
# ---------------------------------------------------------------------------------------------
def cmd_floquet(args, say: _Out) -> int:
    import numpy as np

    from bearing_gym.analysis.floquet import simulator_floquet
    from bearing_gym.analysis.signals import quasi_periodicity_index
    from bearing_gym.physics import SimulationError, Simulator
    from bearing_gym.physics.equilibrium import EquilibriumError

    params = _params_from_args(args)
    if args.json == "-":               # JSON on stdout: no table mixed into it
        say = _Out(True)
    settle = _check("--settle-s", args.settle_s, 0.0, 1e4, "s")
    measure = _check("--measure-s", args.measure_s, 0.0, 1e4, "s", low_open=True)
    h_um = _check("--fd-step-um", args.fd_step_um, 0.0, 10.0, "um", low_open=True)
    if params.shaft_speed_rpm <= 0:
        raise CLIError("--rpm: must be > 0 for Floquet multipliers (the stroboscopic section is "
                       "one shaft period), got 0")
    period = 60.0 / params.shaft_speed_rpm
    if measure < 3 * period:
        raise CLIError(f"--measure-s: must be at least 3 shaft periods ({3 * period:.3g} s at "
                       f"{params.shaft_speed_rpm:g} rpm), got {measure:g}")
    say(f"bearing-gym floquet: {_op_text(params)}")
    try:
        sim = Simulator(params)
    except (EquilibriumError, SimulationError) as err:
        raise _RunError(f"no static equilibrium at this operating point: {_one_line(err)}") from None
    try:
        if settle > 0:
            _advance(sim, settle, 100, say.quiet, "settle")
        rec = sim.advance(measure)
    except SimulationError as err:
        raise _RunError(f"simulation stopped: {_one_line(err)}") from None
    w = params.shaft_speed_rad_s
    qpi = quasi_periodicity_index(rec.t, np.column_stack([rec.x, rec.y, rec.z]), w)
    periodic = qpi < args.qpi_threshold
    say(f"settled {settle:g} s; quasi-periodicity index over the next {measure:g} s: {qpi:.3f}"
        + ("" if periodic else f" (above {args.qpi_threshold:g}: the motion is not period-1, so "
                                "these are not Floquet multipliers of a periodic orbit)"))
    try:
        res = simulator_floquet(sim, h_m=h_um * 1e-6, include_cage_angle=args.include_cage_angle)
    except (RuntimeError, ValueError, SimulationError) as err:
        raise _RunError(f"Floquet computation failed: {_one_line(err)}") from None
    prod = float(np.real(np.prod(res.multipliers)))
    say(f"section: {res.section}")
    say(f"leading |mu| = {res.leading_modulus:.5f}: "
        f"{'stable' if res.stable else 'UNSTABLE'} periodic orbit")
    say(f"product of the multipliers {prod:.5g}, Liouville's formula "
        f"{res.info.get('liouville_det', math.nan):.5g}")
    say("")
    say(f"{'#':>3} {'|mu|':>9} {'arg (deg)':>10} {'rate (1/s)':>11} {'freq (Hz)':>10}  dominant")
    modes = res.modes()
    for m in modes:
        dom = ", ".join(f"{lab} {share:.0%}" for lab, share in m["dominant"])
        say(f"{m['index']:>3d} {m['modulus']:9.5f} {m['angle_deg']:10.2f} {m['rate_per_s']:11.3f} "
            f"{m['freq_hz']:10.2f}  {dom}")
    data = dict(operating_point=_op_text(params), params=_params_dict(params), settle_s=settle,
                measure_s=measure, quasi_periodicity_index=qpi, periodic_before=periodic,
                section=res.section, period_s=res.period_s, leading_modulus=res.leading_modulus,
                stable=res.stable, product=prod, liouville_det=res.info.get("liouville_det"),
                dropped=res.dropped, labels=res.labels,
                multipliers=[dict(re=m["mu"].real, im=m["mu"].imag, modulus=m["modulus"],
                                  angle_deg=m["angle_deg"], rate_per_s=m["rate_per_s"],
                                  freq_hz=m["freq_hz"],
                                  dominant=[dict(label=lab, share=s) for lab, s in m["dominant"]])
                             for m in modes],
                monodromy=res.monodromy)
    _write_json(data, args.json)
    return 0


# ---------------------------------------------------------------------------------------------
# sweep
# ---------------------------------------------------------------------------------------------
def _fmt_cell(v: Any) -> Any:
    return f"{v:.10g}" if isinstance(v, float) else v


def _chains(rows: Sequence[dict]) -> dict[tuple, list[dict]]:
    """Finished tasks in a CSV: continuation chains by ("continuation", label) (the last chain
    of a label if the file holds several) and cold points by ("cold", label, preload)."""
    out: dict[tuple, list[dict]] = {}
    for r in rows:
        mode, label = r.get("mode"), str(r.get("label"))
        if mode == "continuation":
            key = ("continuation", label)
            if r.get("order") == 0 or key not in out:
                out[key] = []
            out[key].append(r)
        elif mode == "cold":
            out[("cold", label, _pkey(r.get("axial_preload_n")))] = [r]
    return out


def _pkey(p: Any) -> float:
    try:
        return round(float(p), 6)
    except (TypeError, ValueError):
        return math.nan


def _same(a: Any, b: Any) -> bool:
    try:
        fa, fb = float(a), float(b)
    except (TypeError, ValueError):
        return a == b
    if math.isnan(fa) and math.isnan(fb):
        return True
    return math.isclose(fa, fb, rel_tol=1e-8, abs_tol=1e-15)


def _truthy(v: Any) -> bool:
    if isinstance(v, str):
        return v.strip().lower() in ("true", "1", "yes")
    return bool(v)


def _operating_columns(params) -> dict:
    """The operating-point columns of a sweep row (sweeps.COLUMNS) other than the preload."""
    from bearing_gym.analysis.sweeps import _operating_point
    cols = _operating_point(params)
    cols.pop("axial_preload_n")
    return cols


def _matches(stored: list[dict], params, preloads: Sequence[float] | None) -> bool:
    """A stored task is reused only if its operating point and (chains) preloads are this
    task's."""
    if not stored:
        return False
    op = _operating_columns(params)
    r0 = stored[0]
    if not all(_same(r0.get(k), v) for k, v in op.items()):
        return False
    if preloads is not None:
        have = sorted(_pkey(r["axial_preload_n"]) for r in stored if not r.get("refined"))
        return have == sorted(_pkey(p) for p in preloads)
    return True


# settings of a sweep written into every computed row (column -> option); a rerun whose
# settings differ from the rows already in the file is refused (cold starts do not use the
# continuation-only ones)
_RUN_COLUMNS = {"settle_s": "--settle-s", "cold_settle_s": "--cold-settle-s",
                "measure_s": "--measure-s", "qpi_threshold": "--qpi-threshold",
                "floquet": "--no-floquet", "refine_step_n": "--refine-step", "dt_s": "--dt-us",
                "race_control": "--race-control"}
_CONTINUATION_ONLY = ("settle_s", "refine_step_n")


def _run_columns(settings, params) -> dict:
    return dict(settle_s=settings.settle_s, cold_settle_s=settings.cold_settle_s,
                measure_s=settings.measure_s, qpi_threshold=settings.qpi_threshold,
                floquet=settings.floquet,
                refine_step_n="none" if settings.refine_step_n is None else settings.refine_step_n,
                dt_s=params.integrator.dt_s, race_control=params.race_control)


def _setting_text(col: str, value: Any) -> str:
    if col == "floquet":
        return "Floquet multipliers" if _truthy(value) else "--no-floquet"
    if col == "refine_step_n" and value == "none":
        return "no --refine-step"
    if col == "dt_s":
        return f"--dt-us {float(value) * 1e6:g}"
    return f"{_RUN_COLUMNS[col]} {value:g}" if isinstance(value, float) else f"{_RUN_COLUMNS[col]} {value}"


def _check_run_columns(existing: Sequence[dict], run: dict, path: Path) -> None:
    """CLIError naming the option if a row of the file was computed with other settings
    (rows written before the settings were recorded have empty cells and are not checked)."""
    for r in existing:
        if r.get("measure_s") in (None, ""):
            continue
        for col, opt in _RUN_COLUMNS.items():
            if r.get("mode") == "cold" and col in _CONTINUATION_ONLY:
                continue
            if not _same(r.get(col), run[col]):
                raise CLIError(f"{opt}: {path} holds points computed with "
                               f"{_setting_text(col, r.get(col))}, this run has "
                               f"{_setting_text(col, run[col])}; rerun with the same value, or "
                               "choose another --out (or delete the file) to start afresh")


def _sweep_pool(args, n_workers: int, quiet: bool) -> Callable[[], Any]:
    """A function making the executor of the tasks to compute (called only if there is one):
    a process pool (one worker: this process) or a RayExecutor."""
    if args.backend == "ray":
        def ray_pool():
            import logging

            from bearing_gym.analysis.ray_backend import RayExecutor
            try:
                return RayExecutor(address=args.address, num_cpus=n_workers,
                                   logging_level=logging.ERROR if quiet else logging.WARNING)
            except Exception as err:  # noqa: BLE001 - ray raises several kinds
                if args.address is not None:
                    raise CLIError(f"--address: cannot connect to the Ray cluster at "
                                   f"{args.address}: {_one_line(err)}") from None
                raise _RunError(f"could not start a local Ray instance: {_one_line(err)}") from None
        return ray_pool

    def local_pool():
        from bearing_gym.analysis.sweeps import SerialExecutor

        return SerialExecutor() if n_workers <= 1 else cf.ProcessPoolExecutor(max_workers=n_workers)
    return local_pool


class _ResumingExecutor:
    """concurrent.futures-style executor for stability_map: a task whose result is already in
    the CSV returns it at once; the others run on the executor made by ``make_pool`` (a
    process pool, this process or Ray) and their rows, with the ``run`` columns, are appended
    to the CSV as soon as they finish."""

    def __init__(self, make_pool: Callable[[], Any], stored: dict[tuple, list[dict]], path: Path,
                 fieldnames: list[str], preloads: Sequence[float], run: dict):
        self.make_pool, self.stored, self.path = make_pool, stored, path
        self.fieldnames, self.preloads, self.run = fieldnames, list(preloads), run
        self.reused: set[tuple] = set()
        self.submitted: set[tuple] = set()
        self._pool: Any = None
        self._lock = threading.Lock()
        self._appended = threading.Condition()
        self._pending = 0                     # submitted tasks whose rows are not appended yet
        self.write_error: Exception | None = None

    def _key(self, fn: Callable, args: tuple) -> tuple[tuple, Any, Any]:
        if fn.__name__ == "continuation_chain":
            params, preloads, _settings, label = args[:4]
            return ("continuation", str(label)), params, preloads
        params, _settings, label = args[:3]
        return ("cold", str(label), _pkey(params.loads.axial_preload_n)), params, None

    def submit(self, fn: Callable, /, *args: Any) -> cf.Future:
        key, params, preloads = self._key(fn, args)
        self.submitted.add(key)
        stored = self.stored.get(key)
        if stored is not None and _matches(stored, params, preloads):
            self.reused.add(key)
            fut: cf.Future = cf.Future()
            fut.set_result([dict(r) for r in stored] if key[0] == "continuation" else dict(stored[0]))
            return fut
        if self._pool is None:
            self._pool = self.make_pool()
        fut = self._pool.submit(fn, *args)
        with self._appended:
            self._pending += 1
        fut.add_done_callback(self._append)
        return fut

    def wait_for_appends(self) -> None:
        """Block until every finished task's rows are in the CSV. A future's result is visible
        to the waiting thread before its done-callbacks have run (they run in the thread that
        set the result: the pool's or Ray's), so the final rewrite of the file must wait for
        them or a late append would duplicate rows."""
        with self._appended:
            self._appended.wait_for(lambda: self._pending == 0)

    def _append(self, fut: cf.Future) -> None:
        try:
            self._write_rows(fut)
        finally:
            with self._appended:
                self._pending -= 1
                self._appended.notify_all()

    def _write_rows(self, fut: cf.Future) -> None:
        if fut.cancelled() or fut.exception() is not None:
            return
        res = fut.result()
        rows = res if isinstance(res, list) else [res]
        for r in rows:
            if r.get("mode") == "cold":      # stability_map sets it after the run; same value
                ps = [_pkey(p) for p in self.preloads]
                pk = _pkey(r.get("axial_preload_n"))
                r["order"] = ps.index(pk) if pk in ps else 0
        try:
            with self._lock, open(self.path, "a", newline="") as fh:
                w = csv.DictWriter(fh, fieldnames=self.fieldnames, restval="", extrasaction="ignore")
                for r in rows:
                    w.writerow({k: _fmt_cell(v) for k, v in {**self.run, **r}.items()})
        except OSError as err:
            self.write_error = err

    def shutdown(self, wait: bool = True) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=wait)


def cmd_sweep(args, say: _Out) -> int:
    from bearing_gym.analysis import sweeps
    from bearing_gym.analysis.sweeps import COLUMNS, SweepSettings

    if not args.preloads:
        raise CLIError("--preloads: at least one axial preload (N) is required, e.g. "
                       "--preloads 1000 900 800 700")
    base = _params_from_args(args, exclude=("preload",))
    lists: dict[str, list[float]] = {}
    for dest, single in _LIST_OPTIONS.items():
        values = getattr(args, dest)
        if values is None:
            continue
        opt = f"--{dest.replace('_', '-')}"
        for v in values:      # every value checked before anything runs
            _make_params([(opt, single, v)], base)
        lists[dest] = [float(v) for v in values]
    try:
        settings = SweepSettings(settle_s=args.settle_s, measure_s=args.measure_s,
                                 cold_settle_s=args.cold_settle_s,
                                 qpi_threshold=args.qpi_threshold, floquet=not args.no_floquet,
                                 refine_step_n=args.refine_step)
    except ValueError as err:
        msg = _one_line(err)
        m = re.match(r"SweepSettings\.(\w+)", msg)
        opt = {"settle_s": "--settle-s", "measure_s": "--measure-s",
               "cold_settle_s": "--cold-settle-s", "refine_step_n": "--refine-step"}.get(
            m.group(1) if m else "", "sweep settings")
        raise CLIError(f"{opt}: {msg}") from None
    _check("--qpi-threshold", args.qpi_threshold, 0.0, 2.0, low_open=True)
    if isinstance(args.workers, bool) or not 1 <= args.workers <= 1024:
        raise CLIError(f"--workers: must be an integer in [1, 1024], got {args.workers}")
    if args.backend == "ray":
        from bearing_gym.analysis.ray_backend import INSTALL_HINT
        if importlib.util.find_spec("ray") is None:
            raise CLIError(f"--backend: ray is not installed; {INSTALL_HINT}")
        if args.address is not None and not str(args.address).strip():
            raise CLIError("--address: must not be empty (e.g. auto, HOST:6379 or "
                           "ray://HOST:10001; omit it for a local Ray instance)")
    elif args.address is not None:
        raise CLIError("--address: only used with --backend ray")
    speeds = lists.get("rpms", [base.shaft_speed_rpm])
    if min(speeds) > 0:
        longest = 60.0 / min(speeds)
        if settings.measure_s < 3 * longest:
            raise CLIError(f"--measure-s: must be at least 3 shaft periods ({3 * longest:.3g} s "
                           f"at {min(speeds):g} rpm), got {settings.measure_s:g}")

    path = Path(args.out)
    if path.is_dir():
        raise CLIError(f"--out: {path} is a directory; give a CSV file name")
    existing: list[dict] = []
    if path.exists():
        try:
            existing = sweeps.load_csv(path)
        except (OSError, csv.Error, UnicodeDecodeError) as err:
            raise CLIError(f"--out: cannot read {path}: {_one_line(err)}") from None
        if existing and "label" not in existing[0]:
            raise CLIError(f"--out: {path} is not a sweep CSV (no 'label' column); choose "
                           "another file")
    run = _run_columns(settings, base)
    _check_run_columns(existing, run, path)
    for r in existing:                       # rows written before the settings were recorded
        for col in _RUN_COLUMNS:
            r.setdefault(col, "")
    fieldnames = list(COLUMNS) + sorted(({k for r in existing for k in r} | set(run))
                                        - set(COLUMNS))
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        # normalise the file (header, formatting) so that finished rows can be appended
        sweeps.save_csv(existing, path) if existing else _write_header(path, fieldnames)
    except OSError as err:
        raise CLIError(f"--out: cannot write {path}: {err.strerror or err}") from None
    stored = _chains(existing)

    n_combo = 1
    for k, v in lists.items():
        if k != "preloads":
            n_combo *= len(v)
    n_tasks = n_combo if args.mode == "continuation" else n_combo * len(args.preloads)
    say(f"bearing-gym sweep ({args.mode}): {len(args.preloads)} preloads x {n_combo} "
        f"combination(s) = {n_tasks} task(s); base {_op_text(base)}")
    ex = _ResumingExecutor(_sweep_pool(args, min(args.workers, n_tasks), say.quiet), stored,
                           path, fieldnames, args.preloads, run)
    try:
        rows = sweeps.stability_map(
            base, args.preloads, shaft_speeds_rpm=lists.get("rpms"),
            radial_loads_n=lists.get("radial_loads"),
            clearances_m=[c / 1e6 for c in lists["clearances_um"]] if "clearances_um" in lists
            else None,
            damping_ratios=lists.get("damping_ratios"), mode=args.mode, settings=settings,
            executor=ex, progress=not say.quiet)
        ex.wait_for_appends()                # every task has finished: only callbacks are left
    except (CLIError, _RunError):
        raise
    except Exception as err:  # noqa: BLE001 - a failed task stops the map; finished rows stay
        cause = getattr(err, "cause", None)      # a Ray task's error: the exception it wraps
        err = cause if isinstance(cause, Exception) else err
        raise _RunError(f"sweep stopped: {type(err).__name__}: {_one_line(err)}; the finished "
                        f"points are in {path}, rerun the same command to resume") from None
    finally:
        ex.shutdown()
    if ex.write_error is not None:
        raise _RunError(f"could not append to {path}: {ex.write_error}")
    # final file: rows of other grids kept, this grid's rows in grid order
    other = [r for r in existing if not _in(r, ex.submitted)]
    rows = [{**run, **r} for r in rows]      # reused rows keep their own (possibly empty) cells
    sweeps.save_csv(other + rows, path)
    n_reused = len(ex.reused)
    say(f"{n_tasks - n_reused} task(s) computed, {n_reused} reused from {path}; "
        f"{len(rows)} rows for this grid, {len(other) + len(rows)} in the file")
    by_label: dict[str, list[dict]] = {}
    for r in rows:
        by_label.setdefault(str(r["label"]), []).append(r)
    for label, rs in by_label.items():
        c = sweeps.critical_preload(rs)
        failed = [r for r in rs if not str(r.get("status", "ok")).startswith(("ok", "floquet"))]
        crit = (f"critical preload {c['critical_n']:g} N (between {c['bracket_n'][0]:g} and "
                f"{c['bracket_n'][1]:g} N)" if math.isfinite(c["critical_n"]) else c["note"])
        fails = f"; {len(failed)} point(s) failed" if failed else ""
        periodic = sum(_truthy(r["periodic"]) for r in rs)
        say(f"  {label}: {periodic}/{len(rs)} points period-1; {crit}{fails}")
    if args.plot:
        _sweep_plot(rows, lists, Path(args.plot), args.mode)
        say(f"  figure: {args.plot}")
    return 0


def _in(row: dict, keys: set) -> bool:
    label = str(row.get("label"))
    if row.get("mode") == "continuation":
        return ("continuation", label) in keys
    return ("cold", label, _pkey(row.get("axial_preload_n"))) in keys


def _write_header(path: Path, fieldnames: list[str]) -> None:
    with open(path, "w", newline="") as fh:
        csv.DictWriter(fh, fieldnames=fieldnames).writeheader()


def _sweep_plot(rows: list[dict], lists: dict, path: Path, mode: str) -> None:
    from bearing_gym.analysis import sweeps

    title = f"bearing-gym sweep ({mode})"
    varied = [k for k, v in lists.items() if k != "preloads" and len(v) > 1]
    column = {"rpms": "shaft_speed_rpm", "radial_loads": "radial_load_x_n",
              "clearances_um": "clearance_m", "damping_ratios": "damping_ratio"}
    if varied:
        fig = sweeps.plot_stability_map(rows, y=column[varied[0]], title=title)
    else:
        fig = sweeps.plot_sweep(rows, title=title)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


# ---------------------------------------------------------------------------------------------
# watch
# ---------------------------------------------------------------------------------------------
_POLICY_HELP = "constant:N, feedback, schedule[:MARGIN] or oracle[:MARGIN]"


def _watch_policy(args):
    """The policy of --model or --policy (agents/ is imported here only: it ships with the
    package but sits above bearing_gym in the layering)."""
    if (args.model is None) == (args.policy is None):
        raise CLIError("--model/--policy: give exactly one (a train.py output directory, or a "
                       f"scripted policy: {_POLICY_HELP})")
    if args.model is not None:
        d = Path(args.model)
        if not d.is_dir():
            raise CLIError(f"--model: no such directory: {d}")
        for name in ("model.zip", "config.json"):
            if not (d / name).is_file():
                raise CLIError(f"--model: {d} has no {name} (expected a directory written by "
                               "train.py)")
        from agents.evaluate import load_trained
        try:
            return load_trained(d)
        except Exception as err:  # noqa: BLE001 - a broken zip, an unknown algo, ...
            raise CLIError(f"--model: cannot load {d}: {type(err).__name__}: "
                           f"{_one_line(err)}") from None
    from agents.policies import ConstantPreload, FeedbackRule, OraclePreload, SpeedScheduledPreload

    name, _, value = str(args.policy).strip().partition(":")
    name = name.lower()
    if name == "feedback" and not value:
        return FeedbackRule()
    if name == "constant" or name in ("schedule", "oracle"):
        if name == "constant" and not value:
            raise CLIError("--policy: constant needs a preload, e.g. constant:1000 (N)")
        try:
            number = float(value) if value else 100.0
        except ValueError:
            raise CLIError(f"--policy: not a number after '{name}:': {value!r}") from None
        if name == "constant":
            from bearing_gym.envs import PreloadActuator
            a = PreloadActuator()
            if not (math.isfinite(number) and a.min_preload_n <= number <= a.max_preload_n):
                raise CLIError(f"--policy: the constant preload must be in [{a.min_preload_n:g}, "
                               f"{a.max_preload_n:g}] N, got {number:g}")
            return ConstantPreload(number)
        if not (math.isfinite(number) and -2000 <= number <= 2000):
            raise CLIError(f"--policy: the margin of {name} must be in [-2000, 2000] N, got "
                           f"{number:g}")
        from agents.stability_table import StabilityTable
        try:
            table = StabilityTable.load()
        except FileNotFoundError as err:
            raise CLIError(f"--policy: {name} needs the stability table: {_one_line(err)}") from None
        cls = SpeedScheduledPreload if name == "schedule" else OraclePreload
        return cls(table, margin_n=number)
    raise CLIError(f"--policy: unknown policy {args.policy!r} (use {_POLICY_HELP})")


def cmd_watch(args, say: _Out) -> int:
    import warnings

    import gymnasium as gym
    import numpy as np

    import bearing_gym  # noqa: F401 - registers BearingPreload-v0
    from bearing_gym.envs.bearing_preload import _latest_path

    for opt, value, low, high in (("--episodes", args.episodes, 1, 1000),
                                  ("--steps", args.steps, 1, 100000),
                                  ("--seed", args.seed, 0, 2**32 - 1)):
        if not low <= value <= high:
            raise CLIError(f"{opt}: must be an integer in [{low}, {high}], got {value}")
    if args.frames is not None and Path(args.frames).exists() and not Path(args.frames).is_dir():
        raise CLIError(f"--frames: {args.frames} is a file; give a directory")
    policy = _watch_policy(args)
    oracle = type(policy).__name__ == "OraclePreload"
    env = gym.make("BearingPreload-v0", scenario=args.scenario, render_mode="human",
                   render_dir=args.frames, max_episode_steps=args.steps, episode_steps=args.steps)
    base = env.unwrapped
    say(f"bearing-gym watch: {policy.name} on BearingPreload-v0 (scenario {args.scenario}, "
        f"{args.episodes} episode(s) of {args.steps} steps of {base.control_dt_s * 1e3:g} ms)")
    try:
        for ep in range(args.episodes):
            with warnings.catch_warnings():      # the headless note is printed below instead
                warnings.filterwarnings("ignore", message=".*render_mode='human'")
                obs, info = env.reset(seed=args.seed + ep)
            if ep == 0 and base._window_state == "none":
                say("no display (or no interactive matplotlib backend): "
                    + (f"frames go to {args.frames}" if args.frames else
                       f"the latest frame goes to {_latest_path()} (--frames DIR keeps all)"))
            sc = base.scenario
            speed = (f"{sc.speed_start_rpm:.0f}" if sc.speed_start_rpm == sc.speed_end_rpm
                     else f"{sc.speed_start_rpm:.0f} -> {sc.speed_end_rpm:.0f}")
            load = (f"{sc.radial_load_before_n:.0f}" if sc.radial_load_before_n == sc.radial_load_after_n
                    else f"{sc.radial_load_before_n:.0f} -> {sc.radial_load_after_n:.0f}")
            say(f"episode {ep} (seed {args.seed + ep}): {speed} rpm, radial load {load} N, "
                f"clearance {sc.clearance_m * 1e6:.1f} um, initial preload "
                f"{info['preload_n']:.0f} N")
            say(f"{'ep':>3} {'step':>5} {'t (s)':>7} {'preload (N)':>12} {'set-point (N)':>14} "
                f"{'qpi':>7} {'reward':>9}")
            state, start, ret, n, qp, preload_sum = None, True, 0.0, 0, 0, 0.0
            reason = ""
            while True:
                if oracle:
                    b = base._batch
                    policy.set_conditions(b.omega()[:1] * 30.0 / math.pi, b.radial_load_n()[:1],
                                          np.array([sc.clearance_m]))
                act, state = policy.predict(obs[None], state=state,
                                            episode_start=np.array([start]), deterministic=True)
                start = False
                action = np.clip(np.asarray(act, dtype=np.float32).reshape(1), -1.0, 1.0)
                obs, reward, term, trunc, info = env.step(action)
                n += 1
                ret += reward
                qp += info["qpi"] > 0.3
                preload_sum += info["preload_n"]
                say(f"{ep:>3d} {n:>5d} {info['t']:>7.3f} {info['preload_n']:>12.1f} "
                    f"{info['setpoint_n']:>14.1f} {info['qpi']:>7.3f} {reward:>9.3f}")
                if term or trunc:
                    reason = f"; terminated: {info['termination_reason']}" if term else ""
                    break
            say(f"episode {ep}: return {ret:.3f} over {n} steps, mean preload "
                f"{preload_sum / n:.0f} N, quasi-periodic (index > 0.3) {100 * qp / n:.0f} % of "
                f"the time{reason}")
    finally:
        env.close()
    return 0


# ---------------------------------------------------------------------------------------------
# reproduce
# ---------------------------------------------------------------------------------------------
def cmd_reproduce(args, extras: list[str], cfg: dict, say: _Out) -> int:
    from bearing_gym import reproduce

    argv = _reproduce_config_args(cfg) + list(extras)
    if say.quiet and "--no-progress" not in argv:
        argv.append("--no-progress")
    if say.quiet:
        with open(os.devnull, "w") as devnull, contextlib.redirect_stdout(devnull):
            return int(reproduce.main(argv) or 0)
    return int(reproduce.main(argv) or 0)


# ---------------------------------------------------------------------------------------------
# entry point
# ---------------------------------------------------------------------------------------------
def _run(argv: list[str]) -> int:
    top, subs = build_parser()
    args, extras = top.parse_known_args(argv)
    cfg: dict = {}
    if args.config:
        cfg = load_config(args.config)
        if args.command != "reproduce":
            subs[args.command].set_defaults(**_config_defaults(cfg, args.command, subs))
            args, extras = top.parse_known_args(argv)
        elif isinstance(cfg.get("quiet"), bool) and cfg["quiet"]:
            args.quiet = True
    if args.command != "reproduce" and extras:
        subs[args.command].error(f"unrecognized arguments: {' '.join(extras)}")
    say = _Out(bool(args.quiet))
    if args.command == "reproduce":
        return cmd_reproduce(args, extras, cfg, say)
    return {"simulate": cmd_simulate, "equilibrium": cmd_equilibrium, "floquet": cmd_floquet,
            "sweep": cmd_sweep, "watch": cmd_watch}[args.command](args, say)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``bearing-gym`` command line; returns the exit status (0 ok, 1 the computation
    failed, 2 bad options)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        return _run(argv)
    except CLIError as err:
        print(f"{PROG}: error: {_one_line(err)}", file=sys.stderr)
        return 2
    except _RunError as err:
        print(f"{PROG}: error: {_one_line(err)}", file=sys.stderr)
        return 1
    except SystemExit as err:          # argparse (--help, usage errors) and reproduce's parser
        code = err.code
        if code is None:
            return 0
        if isinstance(code, int):
            return code
        print(code, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:            # output piped into e.g. head: stop quietly
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return 1


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
