"""What a stored data product is (:class:`Product`), its independent pieces of work
(:class:`Part`), where a regeneration writes (:class:`Layout`) and the digests of files.

A product names the files it writes, the products it is made from (``upstream``), whether the
kernel made it (``kernel``: :func:`bearing_gym.envs.provenance.kernel_hash`, which covers the
physics, the env and its reward), its settings (JSON values) and the files it reads that no
product writes (``sources``: the trained policies). Its parts run independently of one another
(in worker processes or on a Ray cluster); a part's ``fn`` runs in the worker and its ``commit``,
if any, in the driver with what ``fn`` returned (for a file that several parts write into, such
as the validation constants of every tier). ``finish`` runs in the driver once every part is done.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

from agents.paths import file_digest

__all__ = ["Layout", "Part", "Product", "tree_digest", "missing_files", "json_entry_digest",
           "as_json", "env_cost", "PART_OVERHEAD_S", "STEP_CORE_S", "SETTLE_STEPS"]

#: what a part costs besides its simulation (a worker's imports, the numba cache), seconds
PART_OVERHEAD_S = 5.0
#: core-seconds per env step in an evaluation batch, and a reset's settle in env steps (the
#: median). Measured on benchmark v2's kernel on the 2-core development VM, two workers:
#: validation:transient 663 s and contextual:transient 677 s against 3,408 s and 3,504 s at
#: v1's 0.011 (about 90 env steps per core-second then, ~460 now)
STEP_CORE_S = 0.0022
SETTLE_STEPS = 27


def env_cost(episodes: int, episode_steps: int, policies: int = 1) -> float:
    """The estimated core-seconds of ``policies`` x ``episodes`` episodes of ``episode_steps`` steps."""
    return PART_OVERHEAD_S + policies * episodes * (episode_steps + SETTLE_STEPS) * STEP_CORE_S


@dataclass(frozen=True)
class Layout:
    """Where a regeneration writes: the checkout's layout under ``root`` (the checkout itself,
    or a scratch directory)."""

    root: Path

    @property
    def data(self) -> Path:
        return self.root / "agents" / "data"

    @property
    def env_data(self) -> Path:
        """The env's own data (bearing_gym/data: the start banks that ``gymnasium.make`` reads)."""
        return self.root / "bearing_gym" / "data"

    @property
    def docs(self) -> Path:
        return self.root / "docs"

    @property
    def manifest(self) -> Path:
        return self.data / "regeneration.json"

    def rel(self, path: Path) -> str:
        """``path`` relative to the root (as the manifest records it)."""
        try:
            return Path(path).relative_to(self.root).as_posix()
        except ValueError:
            return Path(path).as_posix()


@dataclass(frozen=True)
class Part:
    """One independent piece of a product: ``fn(*args)`` in a worker (a module-level function,
    so that it pickles), then ``commit(result)`` in the driver if given. ``cost_s``: the estimate
    in core-seconds (one thread), for ``--until`` and the schedule."""

    key: str
    fn: Callable[..., Any]
    args: tuple = ()
    cost_s: float = PART_OVERHEAD_S
    commit: Callable[[Any], None] | None = None


@dataclass(frozen=True)
class Product:
    """A stored data product: the files it writes and what they are made from (module docstring)."""

    name: str
    what: str
    outputs: tuple[Path, ...]
    parts: tuple[Part, ...]
    upstream: tuple[str, ...] = ()
    kernel: bool = True
    settings: Mapping[str, Any] = field(default_factory=dict)
    sources: tuple[Path, ...] = ()
    finish: Callable[[], None] | None = None
    #: the outputs' digest (None: missing); default :func:`tree_digest` of ``outputs``
    digest: Callable[[], str | None] | None = None
    #: the hand-run command(s) it stands for
    command: str = ""
    #: what differs between the files in place and what today's inputs build, as the files' own
    #: records show (empty: nothing); a product with one can be adopted (agents.regenerate.adopt)
    verify: Callable[[], list[str]] | None = None

    @property
    def cost_s(self) -> float:
        return sum(p.cost_s for p in self.parts)

    def output_digest(self, root: Path) -> str | None:
        return self.digest() if self.digest is not None else tree_digest(self.outputs, root)


def as_json(value: Any) -> Any:
    """``value`` as plain JSON values (dataclasses as dicts, tuples as lists, paths as strings)."""
    import dataclasses

    def default(x: Any) -> Any:
        if dataclasses.is_dataclass(x):
            return dataclasses.asdict(x)
        if isinstance(x, Path):
            return x.as_posix()
        raise TypeError(f"not a JSON value: {x!r}")
    return json.loads(json.dumps(value, default=default, sort_keys=True))


def _files(paths: tuple[Path, ...]) -> list[Path]:
    out: list[Path] = []
    for p in paths:
        out += sorted(f for f in p.rglob("*") if f.is_file()) if p.is_dir() else [p]
    return out


def missing_files(paths: tuple[Path, ...]) -> list[Path]:
    """The ``paths`` that do not exist (a directory counts when it holds no file)."""
    return [p for p in paths if not (p.is_file() or (p.is_dir() and any(f.is_file() for f in p.rglob("*"))))]


def tree_digest(paths: tuple[Path, ...], root: Path) -> str | None:
    """SHA-256 (16 hex digits) over the files of ``paths`` (directories: every file below them)
    and their names relative to ``root``; None if one is missing."""
    if missing_files(paths):
        return None
    h = hashlib.sha256()
    for f in _files(paths):
        try:
            name = f.relative_to(root).as_posix()
        except ValueError:
            name = f.as_posix()
        h.update(name.encode() + b"\0" + file_digest(f).encode() + b"\n")
    return h.hexdigest()[:16]


def json_entry_digest(path: Path, *keys: str) -> str | None:
    """The digest of one entry of a JSON file (``data[k1][k2]...``), None if it is not there:
    for a file that several products write into."""
    try:
        value: Any = json.loads(path.read_text())
        for k in keys:
            value = value[k]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return hashlib.sha256(json.dumps(value, sort_keys=True).encode()).hexdigest()[:16]
