"""The references' one store: what the leaderboard's references cost once, kept in
``agents/data/`` so that evaluation only reads them.

**The validation-chosen constants.** The stored validation-chosen best constant preload of each tier (reading and writing only).

``agents/data/reference_constants.json`` holds, per tier, the constant preload with the best
mean return on validation episodes, with what it was chosen on: the seeds (every one in
``agents.protocol.VALIDATION``, checked on reading and on writing), the grid of candidates, the
episode length and each candidate's mean return. Evaluation reads the choice from here and never
chooses on its own (test) episodes. ``python -m agents.references --tier T --episodes N``
(:mod:`agents.references.validation`) computes an entry and writes it.

**The test references.** The expensive references on the test episodes, stored so that a leaderboard of new policies
(and the main job's) takes minutes, not the hours the references (the planner above all) cost.

``agents/data/test_references_<tier>.json`` holds, per test episode (seeds ``TEST.start`` on,
in order), every metric the leaderboard reports of

* the validation-chosen constant (its run in the hindsight sweep),
* the hindsight best constant of the 50 N grid,
* the planner (the upper reference; the true simulator and the episode's future) on every one
  of them, its plans replayed through the evaluation loop,

written by the full leaderboard run (``python -m agents.leaderboard``, which computes them) or
joined from parts (``python -m agents.leaderboard.reference_parts``, the same rows computed a part at a time) and
read by ``python -m agents.leaderboard --stored-references`` and by ``train.py``'s evaluation,
on a prefix of the stored episodes. A stored set is only valid for the kernel it was computed
with: it carries that kernel's fingerprint (:func:`bearing_gym.envs.provenance.kernel_hash`) and the
package version, and a reader refuses a store made by another kernel before running anything
(:meth:`StoredReferences.check_kernel`). The kernel is portable (the same bits on every CPU), so
every reader also runs the validation-chosen constant again on its episodes and refuses the
store (naming the command that rebuilds it) unless those returns equal the stored ones bit for
bit (``STALE_TOLERANCE`` = 0): the physics, the reward, the scenarios or the stored constant
changed since.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.envs.provenance import kernel_hash, package_version
from bearing_gym.envs.reward import REWARD_TERMS

from agents.protocol import VALIDATION, VALIDATION_CONSTANT_EPISODES, VALIDATION_RULES, VALIDATION_GRID_STEP_N, episodes_for_tier, preload_grid, range_of
from agents.evaluation.result import EvalResult
from agents.paths import DATA_DIR


__all__ = ["STORE_PATH", "ValidationChoice", "load_choice", "save_choice", "validation_problems", "only_the_rule_differs", "rebuild_command", "validation_episodes",
           "StoredReferences", "references_path", "parts_dir", "stored_hindsight", "load_references", "result_to_json", "result_from_json",
           "STALE_TOLERANCE", "DATA_DIR"]

STORE_PATH = DATA_DIR / "reference_constants.json"
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
    candidate that ``rule`` picks (:func:`rule_choice`; ``"best_mean"``: the highest mean return)."""

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
    #: the fingerprint of the kernel that computed it (None: an entry from before fingerprints)
    kernel_hash: str | None = None
    #: the protocol's rule that picked ``preload_n`` (agents.protocol.VALIDATION_RULES)
    rule: str = "best_mean"

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
        if self.episode_returns is not None and (
                len(self.episode_returns) != len(self.grid_n)
                or any(len(r) != len(self.seeds) for r in self.episode_returns)):
            raise ValueError(f"tier {self.tier}: episode_returns must hold {len(self.seeds)} returns for each of "
                             f"the {len(self.grid_n)} candidates")
        best = self.preload_for_rule(self.rule) if self.grid_n else None
        if self.preload_n != best:
            raise ValueError(f"tier {self.tier}: the chosen preload {self.preload_n} N is not the one rule {self.rule!r} "
                             f"picks from the validation returns ({best} N); rebuild it: {rebuild_command(self.tier)}")

    def preload_for_rule(self, rule: str) -> float:
        """The candidate ``rule`` picks from the stored validation returns (:func:`rule_choice`)."""
        return self.grid_n[rule_choice(rule, self.grid_n, self.mean_returns, self.episode_returns, self.tier)]

    @property
    def episodes(self) -> int:
        return len(self.seeds)

    def protocol_problems(self) -> list[str]:
        """What keeps this entry from being the protocol's (empty if nothing): too few
        episodes, short episodes, another grid."""
        from bearing_gym.task import EPISODE_STEPS
        out = []
        want = validation_episodes(self.tier)
        if self.episodes < want:
            out.append(f"{self.episodes} validation episodes (the protocol: {want})")
        if self.episode_steps != EPISODE_STEPS:
            out.append(f"{self.episode_steps}-step episodes (the benchmark: {EPISODE_STEPS})")
        if tuple(self.grid_n) != preload_grid(VALIDATION_GRID_STEP_N):
            out.append(f"a {self.grid_step_n:g} N grid (the protocol: {VALIDATION_GRID_STEP_N:g} N over the actuator's range)")
        return out

    def validation_references(self, seeds, preload_n: float | None = None) -> tuple["np.ndarray", "np.ndarray"]:
        """(the chosen constant's return, the hindsight best constant's return) on each validation
        episode of ``seeds`` (each one of :attr:`seeds`, or any validation seed on a deterministic
        tier, where every seed gives the stored episode): 0 and 1 of the validation score.
        ``preload_n``: another candidate as the 0 (e.g. :meth:`preload_for_rule` of another rule)."""
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
        chosen = table[self.grid_n.index(self.preload_n if preload_n is None else float(preload_n))]
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
                                    tuple(tuple(float(x) for x in r) for r in d["episode_returns"])),
                   kernel_hash=d.get("kernel_hash"), rule=d.get("rule", "best_mean"))


def rule_choice(rule: str, grid_n, mean_returns, episode_returns=None, tier: str = "") -> int:
    """The index of the candidate a validation rule picks (agents.protocol.VALIDATION_RULES).

    ``"best_mean"``: the highest mean return (the first of equal ones). ``"one_se_largest"``: the
    largest-preload candidate of ``grid_n`` whose mean is at least the best
    mean minus the standard error of the best candidate's mean, ``std(ddof=1) / sqrt(n)`` over its
    ``n`` episode returns (0 for a single episode: then the best mean, the largest preload among
    exactly equal means)."""
    import numpy as np
    means = np.asarray(mean_returns, dtype=float)
    if rule not in VALIDATION_RULES:
        raise ValueError(f"validation rule {rule!r}: expected one of {', '.join(VALIDATION_RULES)}")
    best = int(np.argmax(means))
    if rule == "best_mean":
        return best
    if episode_returns is None:
        raise LookupError(f"rule {rule!r} needs the per-episode validation returns; none given"
                          + (f" (tier {tier}: rebuild its choice: {rebuild_command(tier)})" if tier else ""))
    r = np.asarray(episode_returns[best], dtype=float)
    se = float(np.std(r, ddof=1) / np.sqrt(r.size)) if r.size > 1 else 0.0
    within = np.flatnonzero(means >= means[best] - se)
    return int(within[np.argmax(np.asarray(grid_n, dtype=float)[within])])


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


def validation_problems(tier: str, path: str | Path, episodes: int, episode_steps: int,
                        grid_step_n: float) -> list[str]:
    """What keeps the stored choice of ``tier`` from being what choosing it now would store
    (empty: nothing; the regeneration's check for adopting it): absent, made by another kernel,
    on other validation episodes or another grid, or picked by another rule than the
    protocol's (``agents.protocol.VALIDATION_RULE``; the pick itself is checked against the
    stored returns on loading)."""
    from bearing_gym.envs.provenance import kernel_hash
    from agents.protocol import VALIDATION_RULE
    try:
        c = load_choice(tier, path)
    except (LookupError, ValueError) as err:
        return [str(err)]
    want = {"kernel_hash": kernel_hash(), "seeds": tuple(range(VALIDATION.start, VALIDATION.start + episodes)),
            "episode_steps": episode_steps, "grid_step_n": grid_step_n, "grid_n": preload_grid(grid_step_n),
            "rule": VALIDATION_RULE}
    out = [f"{k}: stored {_brief(getattr(c, k))}, today's {_brief(v)}" for k, v in want.items() if getattr(c, k) != v]
    if c.episode_returns is None:
        out.append("episode_returns: not stored (a choice made now stores every candidate's per-episode returns)")
    return out


def only_the_rule_differs(tier: str, path: str | Path, episodes: int, episode_steps: int,
                          grid_step_n: float) -> bool:
    """Whether the stored choice of ``tier`` is today's sweep (this kernel, these validation
    episodes and grid, every per-episode return) picked by another rule than the protocol's: it
    can then be picked again from its stored returns (:func:`agents.references.validation.repicked`)."""
    problems = validation_problems(tier, path, episodes, episode_steps, grid_step_n)
    return bool(problems) and all(p.startswith("rule:") for p in problems)


def _brief(v) -> str:
    s = repr(v)
    return s if len(s) <= 40 else s[:37] + "..."


def save_choice(choice: ValidationChoice, path: str | Path = STORE_PATH) -> None:
    """Write ``choice`` into the store at ``path`` (the other tiers' entries are kept)."""
    path = Path(path)
    data = _read(path)
    data["about"] = ABOUT
    data["tiers"][choice.tier] = choice.to_json()
    data["tiers"] = dict(sorted(data["tiers"].items()))
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")      # whole or not at all: parallel readers (agents.regenerate)
    tmp.write_text(json.dumps(data, indent=1) + "\n")
    os.replace(tmp, path)


# --- the test references --------------------------------------------------------------------
#: Reward units per episode: none. The kernel gives the same bits on every CPU
#: (bearing_gym.physics.portable_math; tests/portability), so the same kernel repeats a stored
#: return exactly, on this machine or any other.
STALE_TOLERANCE = 0.0
ROWS = ("validation constant", "hindsight", "planner")
#: the "about" of a stored test-references file (the first paragraph of the docstring of the
#: module that held them before the two stores became one, so stored files keep their text)
TEST_REFERENCES_ABOUT = ("The expensive references on the test episodes, stored so that a leaderboard of new policies "
                         "(and the main job's) takes minutes, not the hours the references (the planner above all) cost.")


def references_path(tier: str, data_dir: Path = DATA_DIR) -> Path:
    return Path(data_dir) / f"test_references_{tier}.json"


def parts_dir(tier: str, data_dir: Path = DATA_DIR) -> Path:
    """Where the test references of ``tier`` are kept in parts (:mod:`agents.leaderboard.reference_parts`)."""
    return Path(data_dir) / f"test_references_{tier}_parts"


def stored_hindsight(tier: str, seed: int, grid_step_n: float, episode_steps: int,
                     data_dir: Path = DATA_DIR) -> tuple[float, float] | None:
    """(the hindsight best constant, its return) of test episode ``seed`` from a sweep part made
    by this kernel on the same grid and episode length, or None if there is none."""
    here = kernel_hash()
    for path in sorted(parts_dir(tier, data_dir).glob("sweep_*.json")):
        try:
            part = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        first, n = part.get("first_seed"), part.get("episodes")
        if (part.get("kernel_hash") != here or part.get("hindsight_grid_step_n") != grid_step_n
                or part.get("episode_steps") != episode_steps or part.get("hindsight_preload_n") is None
                or not first <= seed < first + n):
            continue
        k = seed - first
        return float(part["hindsight_preload_n"][k]), float(part["rows"]["hindsight"]["returns"][k])
    return None


def result_to_json(r: EvalResult) -> dict[str, Any]:
    def arr(x):
        return None if x is None else [float(v) for v in np.asarray(x, dtype=float)]
    return {"name": r.name, "returns": arr(r.returns), "terms": {k: arr(v) for k, v in r.terms.items()},
            "qp_fraction": arr(r.qp_fraction), "mean_preload": arr(r.mean_preload),
            "terminated": None if r.terminated is None else [bool(v) for v in r.terminated],
            "vibration_um": arr(r.vibration_um)}


def result_from_json(d: dict[str, Any]) -> EvalResult:
    def arr(x):
        return None if x is None else np.asarray(x, dtype=float)
    return EvalResult(d["name"], arr(d["returns"]), {k: arr(v) for k, v in d["terms"].items()},
                      arr(d["qp_fraction"]), arr(d["mean_preload"]),
                      terminated=None if d["terminated"] is None else np.asarray(d["terminated"], bool),
                      vibration_um=arr(d["vibration_um"]))


@dataclass
class StoredReferences:
    """The stored references of one tier on its first ``len(seeds)`` test episodes; ``planner``
    (the upper reference: :mod:`agents.policies.planner`, replayed) on every one of them, or None
    where it has not run."""

    tier: str
    seeds: tuple[int, ...]
    episode_steps: int
    validation_preload_n: float
    hindsight_grid_step_n: float
    validation_constant: EvalResult
    hindsight: EvalResult
    planner: EvalResult | None
    planner_settings: dict[str, Any] | None
    planner_wall_s_per_episode: float | None = None   # the planner's mean wall time per episode (its search)
    kernel_hash: str | None = field(default_factory=kernel_hash)        # of the kernel that made it
    package_version: str | None = field(default_factory=package_version)

    def __post_init__(self) -> None:
        if self.planner is not None and len(self.planner.returns) != len(self.seeds):
            raise ValueError(f"tier {self.tier}: the planner row has {len(self.planner.returns)} episodes, "
                             f"the references {len(self.seeds)}: it runs on every test episode or on none")

    def first(self, episodes: int) -> "StoredReferences":
        """The references of the first ``episodes`` stored episodes."""
        if not 1 <= episodes <= len(self.seeds):
            raise ValueError(f"{episodes} episodes asked, {len(self.seeds)} stored for tier {self.tier}")
        return StoredReferences(self.tier, self.seeds[:episodes], self.episode_steps, self.validation_preload_n,
                                self.hindsight_grid_step_n, self.validation_constant.first(episodes),
                                self.hindsight.first(episodes),
                                None if self.planner is None else self.planner.first(episodes),
                                self.planner_settings, self.planner_wall_s_per_episode, self.kernel_hash,
                                self.package_version)

    def check_kernel(self, rebuild: str) -> None:
        """Raise if the store was made by another kernel than this one (or by one before
        fingerprints were stored), naming the command that rebuilds it."""
        here = kernel_hash()
        if self.kernel_hash != here:
            made = (f"kernel {self.kernel_hash} (bearing_gym {self.package_version})" if self.kernel_hash
                    else "a kernel without a fingerprint (before the portable kernel)")
            raise RuntimeError(f"the stored test references of tier {self.tier} were made by {made}, not by this "
                               f"kernel ({here}, bearing_gym {package_version()}): they are stale; rebuild them "
                               f"with `{rebuild}`")

    def check_fresh(self, live_validation_returns: np.ndarray, rebuild: str) -> None:
        """Raise if the validation constant's returns, run again now on the same episodes,
        differ from the stored ones (the env or the stored constant changed)."""
        live = np.asarray(live_validation_returns, dtype=float)
        stored = np.asarray(self.validation_constant.returns, dtype=float)
        if live.shape != stored.shape:
            raise RuntimeError(f"{len(live)} live returns against {len(stored)} stored ones for tier {self.tier}")
        worst = float(np.max(np.abs(live - stored))) if len(live) else 0.0
        if not worst <= STALE_TOLERANCE:           # NaN too
            raise RuntimeError(f"the stored test references of tier {self.tier} are stale: the validation constant "
                               f"({self.validation_preload_n:.0f} N) returns differ from the stored ones by up to "
                               f"{worst:.3g} (tolerance {STALE_TOLERANCE:g}); rebuild them with `{rebuild}`")

    def to_json(self) -> dict[str, Any]:
        return {"about": TEST_REFERENCES_ABOUT, "tier": self.tier, "seeds": list(self.seeds),
                "episode_steps": self.episode_steps, "validation_preload_n": self.validation_preload_n,
                "hindsight_grid_step_n": self.hindsight_grid_step_n, "planner_settings": self.planner_settings,
                "validation constant": result_to_json(self.validation_constant),
                "hindsight": result_to_json(self.hindsight),
                "planner": None if self.planner is None else result_to_json(self.planner),
                "planner_wall_s_per_episode": self.planner_wall_s_per_episode,
                "kernel_hash": self.kernel_hash, "package_version": self.package_version}

    @classmethod
    def from_json(cls, d: dict[str, Any]) -> "StoredReferences":
        if "mpc" in d and "planner" not in d:
            raise ValueError(f"stored test references of tier {d.get('tier')} from before the planner (their upper "
                             f"reference is the MPC): rebuild them with "
                             f"`python -m agents.leaderboard.reference_parts --tier {d.get('tier')} --merge`")
        missing = [k for k in ROWS + ("tier", "seeds", "episode_steps") if k not in d]
        if missing:
            raise ValueError(f"stored test references lack {', '.join(missing)}")
        for k in ("validation constant", "hindsight"):
            if set(d[k]["terms"]) != set(REWARD_TERMS):
                raise ValueError(f"stored {k} terms {sorted(d[k]['terms'])} are not the reward's {list(REWARD_TERMS)}")
        return cls(d["tier"], tuple(int(s) for s in d["seeds"]), int(d["episode_steps"]),
                   float(d["validation_preload_n"]), float(d["hindsight_grid_step_n"]),
                   result_from_json(d["validation constant"]), result_from_json(d["hindsight"]),
                   None if d["planner"] is None else result_from_json(d["planner"]), d.get("planner_settings"),
                   d.get("planner_wall_s_per_episode"), d.get("kernel_hash"), d.get("package_version"))

    def save(self, data_dir: Path = DATA_DIR) -> Path:
        path = references_path(self.tier, data_dir)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(self.to_json()) + "\n")
        return path


def load_references(tier: str, data_dir: Path = DATA_DIR) -> StoredReferences:
    """The stored test references of ``tier``; FileNotFoundError naming the command that builds them."""
    path = references_path(tier, data_dir)
    if not path.exists():
        raise FileNotFoundError(f"no stored test references for tier {tier} ({path}); the full leaderboard run "
                                f"computes and stores them: `python -m agents.leaderboard --tier {tier}`")
    return StoredReferences.from_json(json.loads(path.read_text()))
