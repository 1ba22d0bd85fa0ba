"""The stored validation-chosen best constant preload of each tier (reading and writing only).

``agents/data/reference_constants.json`` holds, per tier, the constant preload with the best
mean return on validation episodes, with what it was chosen on: the seeds (every one in
``agents.protocol.VALIDATION``, checked on reading and on writing), the grid of candidates, the
episode length and each candidate's mean return. Evaluation reads the choice from here and never
chooses on its own (test) episodes. ``python -m agents.references --tier T --episodes N``
(:mod:`agents.references`) computes an entry and writes it.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from .protocol import (VALIDATION, VALIDATION_CONSTANT_EPISODES, VALIDATION_GRID_STEP_N, episodes_for_tier,
                       preload_grid, range_of)

if TYPE_CHECKING:
    import numpy as np

__all__ = ["STORE_PATH", "ValidationChoice", "load_choice", "save_choice", "rebuild_command", "validation_episodes"]

STORE_PATH = Path(__file__).with_name("data") / "reference_constants.json"
ABOUT = ("Per tier: the constant preload with the best mean return on validation episodes "
         "(agents.references); rebuild an entry with `python -m agents.references --tier T --episodes N`.")


def validation_episodes(tier: str) -> int:
    """The protocol's number of validation episodes for ``tier``'s constant (1 on a deterministic tier)."""
    return episodes_for_tier(tier, VALIDATION_CONSTANT_EPISODES)


def rebuild_command(tier: str, episodes: int | None = None) -> str:
    """The command that (re)builds ``tier``'s entry of the store (by default on the protocol's
    episodes: :func:`validation_episodes`)."""
    if episodes is None:
        episodes = validation_episodes(tier)
    return f"python -m agents.references --tier {tier} --episodes {episodes}"


@dataclass(frozen=True)
class ValidationChoice:
    """The constant preload chosen on validation episodes of one tier.

    ``grid_n`` are the candidates, ``mean_returns`` their mean returns over the episodes of
    ``seeds`` (all in VALIDATION) of ``episode_steps`` control intervals; ``preload_n`` is the
    candidate with the highest mean return."""

    tier: str
    preload_n: float
    seeds: tuple[int, ...]
    grid_step_n: float
    grid_n: tuple[float, ...]
    mean_returns: tuple[float, ...]
    episode_steps: int
    wall_s: float | None = None
    #: per candidate, the return of each episode of ``seeds`` (the validation score's references)
    episode_returns: tuple[tuple[float, ...], ...] | None = None

    def __post_init__(self) -> None:
        outside = [s for s in self.seeds if s not in VALIDATION]
        if not self.seeds or outside:
            where = range_of(outside[0]) if outside else None
            raise ValueError(f"tier {self.tier}: the best constant must be chosen on validation seeds "
                             f"[{VALIDATION.start}, {VALIDATION.stop}) only; got "
                             f"{'no seeds' if not self.seeds else f'seed {outside[0]} ({where} range)'}. "
                             f"Rebuild it: {rebuild_command(self.tier)}")
        if len(self.grid_n) != len(self.mean_returns):
            raise ValueError(f"tier {self.tier}: {len(self.grid_n)} candidates but {len(self.mean_returns)} mean returns")
        best = self.grid_n[max(range(len(self.grid_n)), key=lambda k: self.mean_returns[k])] if self.grid_n else None
        if self.episode_returns is not None and (
                len(self.episode_returns) != len(self.grid_n)
                or any(len(r) != len(self.seeds) for r in self.episode_returns)):
            raise ValueError(f"tier {self.tier}: episode_returns must hold {len(self.seeds)} returns for each of "
                             f"the {len(self.grid_n)} candidates")
        if self.preload_n != best:
            raise ValueError(f"tier {self.tier}: the chosen preload {self.preload_n} N is not the candidate with the "
                             f"best mean validation return ({best} N); rebuild it: {rebuild_command(self.tier)}")

    @property
    def episodes(self) -> int:
        return len(self.seeds)

    def protocol_problems(self) -> list[str]:
        """What keeps this entry from being the protocol's (empty if nothing): too few
        episodes, short episodes, another grid."""
        from bearing_gym.benchmark import EPISODE_STEPS
        out = []
        want = validation_episodes(self.tier)
        if self.episodes < want:
            out.append(f"{self.episodes} validation episodes (the protocol: {want})")
        if self.episode_steps != EPISODE_STEPS:
            out.append(f"{self.episode_steps}-step episodes (the benchmark: {EPISODE_STEPS})")
        if tuple(self.grid_n) != preload_grid(VALIDATION_GRID_STEP_N):
            out.append(f"a {self.grid_step_n:g} N grid (the protocol: {VALIDATION_GRID_STEP_N:g} N over the actuator's range)")
        return out

    def validation_references(self, seeds) -> tuple["np.ndarray", "np.ndarray"]:
        """(the chosen constant's return, the hindsight best constant's return) on each validation
        episode of ``seeds`` (each one of :attr:`seeds`, or any validation seed on a deterministic
        tier, where every seed gives the stored episode): 0 and 1 of the validation score."""
        import numpy as np
        from bearing_gym.envs.tiers import tier_is_deterministic
        if self.episode_returns is None:
            raise LookupError(f"tier {self.tier}: the stored choice has no per-episode returns; rebuild it: "
                              f"{rebuild_command(self.tier)}")
        where = {s: k for k, s in enumerate(self.seeds)}
        if tier_is_deterministic(self.tier):
            where = {s: 0 for s in seeds if range_of(s) == "validation"}
        missing = [s for s in seeds if s not in where]
        if missing:
            raise ValueError(f"tier {self.tier}: seed {missing[0]} is not one of the stored validation episodes "
                             f"{self.seeds[0]}..{self.seeds[-1]}")
        cols = [where[s] for s in seeds]
        table = np.asarray(self.episode_returns)[:, cols]          # (candidates, episodes)
        chosen = table[self.grid_n.index(self.preload_n)]
        return chosen, table.max(axis=0)

    def describe(self) -> str:
        return (f"{self.preload_n:.0f} N, chosen on {self.episodes} validation episodes (seeds {self.seeds[0]}.."
                f"{self.seeds[-1]}, {self.episode_steps} steps) from a {self.grid_step_n:g} N grid "
                f"{self.grid_n[0]:.0f}-{self.grid_n[-1]:.0f} N")

    def to_json(self) -> dict:
        """The store's entry (the tier is its key, so it is left out)."""
        d = asdict(self)
        d.pop("tier")
        d["episodes"] = self.episodes
        return d

    @classmethod
    def from_json(cls, tier: str, d: dict) -> "ValidationChoice":
        """The choice of ``tier`` from its store entry (checked as on construction)."""
        return cls(tier=tier, preload_n=float(d["preload_n"]), seeds=tuple(int(s) for s in d["seeds"]),
                   grid_step_n=float(d["grid_step_n"]), grid_n=tuple(float(p) for p in d["grid_n"]),
                   mean_returns=tuple(float(r) for r in d["mean_returns"]),
                   episode_steps=int(d["episode_steps"]), wall_s=d.get("wall_s"),
                   episode_returns=(None if d.get("episode_returns") is None else
                                    tuple(tuple(float(x) for x in r) for r in d["episode_returns"])))


def _read(path: Path) -> dict:
    if not path.exists():
        return {"about": ABOUT, "tiers": {}}
    data = json.loads(path.read_text())
    if not isinstance(data.get("tiers"), dict):
        raise ValueError(f"{path}: no 'tiers' object; rebuild the store with `python -m agents.references`")
    return data


def load_choice(tier: str, path: str | Path = STORE_PATH) -> ValidationChoice:
    """The stored choice of ``tier``; raises LookupError with the command that builds it."""
    path = Path(path)
    entry = _read(path)["tiers"].get(tier)
    if entry is None:
        raise LookupError(f"no validation-chosen constant for tier {tier!r} in {path}; build it with "
                          f"`{rebuild_command(tier)}`")
    return ValidationChoice.from_json(tier, entry)


def save_choice(choice: ValidationChoice, path: str | Path = STORE_PATH) -> None:
    """Write ``choice`` into the store at ``path`` (the other tiers' entries are kept)."""
    path = Path(path)
    data = _read(path)
    data["about"] = ABOUT
    data["tiers"][choice.tier] = choice.to_json()
    data["tiers"] = dict(sorted(data["tiers"].items()))
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=1) + "\n")
