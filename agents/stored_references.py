"""The expensive references on the test episodes, stored so that a leaderboard of new policies
(and the main job's) takes minutes, not the hour the references cost.

``agents/data/test_references_<tier>.json`` holds, per test episode (seeds ``TEST.start`` on,
in order), every metric the leaderboard reports of

* the validation-chosen constant (its run in the hindsight sweep),
* the hindsight best constant of the 50 N grid,
* the MPC with the true simulator on the first ``MPC_EPISODES`` of them,

written by the full leaderboard run (``python -m agents.leaderboard``, which computes them) or
joined from parts (``python -m agents.reference_parts``, the same rows computed a part at a time) and
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
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.envs.reward import REWARD_TERMS
from bearing_gym.envs.provenance import kernel_hash, package_version

from .eval_result import EvalResult

__all__ = ["StoredReferences", "references_path", "load_references", "result_to_json", "result_from_json",
           "STALE_TOLERANCE", "DATA_DIR"]

DATA_DIR = Path(__file__).with_name("data")
#: Reward units per episode: none. The kernel gives the same bits on every CPU
#: (bearing_gym.physics.portable_math; tests/portability), so the same kernel repeats a stored
#: return exactly, on this machine or any other.
STALE_TOLERANCE = 0.0
ROWS = ("validation constant", "hindsight", "mpc")


def references_path(tier: str, data_dir: Path = DATA_DIR) -> Path:
    return Path(data_dir) / f"test_references_{tier}.json"


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
    """The stored references of one tier on its first ``len(seeds)`` test episodes."""

    tier: str
    seeds: tuple[int, ...]
    episode_steps: int
    validation_preload_n: float
    hindsight_grid_step_n: float
    validation_constant: EvalResult
    hindsight: EvalResult
    mpc: EvalResult | None           # on the first len(mpc.returns) episodes
    mpc_settings: dict[str, Any]
    mpc_wall_s_per_episode: float | None = None   # the MPC's mean wall time per episode
    kernel_hash: str | None = field(default_factory=kernel_hash)        # of the kernel that made it
    package_version: str | None = field(default_factory=package_version)

    @property
    def mpc_episodes(self) -> int:
        return 0 if self.mpc is None else len(self.mpc.returns)

    def first(self, episodes: int) -> "StoredReferences":
        """The references of the first ``episodes`` stored episodes."""
        if not 1 <= episodes <= len(self.seeds):
            raise ValueError(f"{episodes} episodes asked, {len(self.seeds)} stored for tier {self.tier}")
        m = min(self.mpc_episodes, episodes)
        return StoredReferences(self.tier, self.seeds[:episodes], self.episode_steps, self.validation_preload_n,
                              self.hindsight_grid_step_n, self.validation_constant.first(episodes),
                              self.hindsight.first(episodes), self.mpc.first(m) if m else None, self.mpc_settings,
                              self.mpc_wall_s_per_episode if m else None, self.kernel_hash,
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
        return {"about": __doc__.split("\n\n")[0].replace("\n", " "), "tier": self.tier, "seeds": list(self.seeds),
                "episode_steps": self.episode_steps, "validation_preload_n": self.validation_preload_n,
                "hindsight_grid_step_n": self.hindsight_grid_step_n, "mpc_settings": self.mpc_settings,
                "validation constant": result_to_json(self.validation_constant),
                "hindsight": result_to_json(self.hindsight),
                "mpc": None if self.mpc is None else result_to_json(self.mpc),
                "mpc_wall_s_per_episode": self.mpc_wall_s_per_episode,
                "kernel_hash": self.kernel_hash, "package_version": self.package_version}

    @classmethod
    def from_json(cls, d: dict[str, Any]) -> "StoredReferences":
        missing = [k for k in ROWS + ("tier", "seeds", "episode_steps") if k not in d]
        if missing:
            raise ValueError(f"stored test references lack {', '.join(missing)}")
        for k in ("validation constant", "hindsight"):
            if set(d[k]["terms"]) != set(REWARD_TERMS):
                raise ValueError(f"stored {k} terms {sorted(d[k]['terms'])} are not the reward's {list(REWARD_TERMS)}")
        return cls(d["tier"], tuple(int(s) for s in d["seeds"]), int(d["episode_steps"]),
                   float(d["validation_preload_n"]), float(d["hindsight_grid_step_n"]),
                   result_from_json(d["validation constant"]), result_from_json(d["hindsight"]),
                   None if d["mpc"] is None else result_from_json(d["mpc"]), dict(d.get("mpc_settings") or {}),
                   d.get("mpc_wall_s_per_episode"), d.get("kernel_hash"), d.get("package_version"))

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
