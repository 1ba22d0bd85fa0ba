"""A policy's results on a batch of evaluation episodes (:class:`EvalResult`): per episode the
return, the reward terms, the time quasi-periodic, the mean preload, early termination, the first
observation and the mean non-synchronous vibration amplitude, plus the first episode's trace and
scenario; cut, joined and summarised."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bearing_gym.envs.reward import REWARD_TERMS


__all__ = ["EvalResult"]


@dataclass
class EvalResult:
    name: str
    returns: np.ndarray
    terms: dict[str, np.ndarray]
    qp_fraction: np.ndarray
    mean_preload: np.ndarray
    trace: dict[str, np.ndarray] = field(default_factory=dict)
    terminated: np.ndarray | None = None    # per episode: ended early (None: none did)
    scenario: Any = None                    # the first episode's Scenario (the one traced)
    trace_label: str = ""                   # what the trace is, if not the policy itself
    first_obs: np.ndarray | None = None     # per episode: the observation after reset
    vibration_um: np.ndarray | None = None  # per episode: mean non-synchronous RMS amplitude (um)
    cost: np.ndarray | None = None          # per episode: the sum of info["cost"] (quasi-periodic intervals)

    @property
    def terminated_count(self) -> int:
        return 0 if self.terminated is None else int(np.count_nonzero(self.terminated))

    @property
    def episodes(self) -> int:
        return len(self.returns)

    def first(self, n: int) -> "EvalResult":
        """The result on the first ``n`` episodes (the per-episode arrays cut; the trace, which
        is the first episode's, kept)."""
        if not 1 <= n <= self.episodes:
            raise ValueError(f"{n} episodes asked of a result on {self.episodes}")

        def cut(x):
            return None if x is None else np.asarray(x)[:n]
        return dataclasses.replace(self, returns=cut(self.returns), terms={k: cut(v) for k, v in self.terms.items()},
                                   qp_fraction=cut(self.qp_fraction), mean_preload=cut(self.mean_preload),
                                   terminated=cut(self.terminated), first_obs=cut(self.first_obs),
                                   vibration_um=cut(self.vibration_um), cost=cut(self.cost))

    @staticmethod
    def concat(parts: "list[EvalResult]") -> "EvalResult":
        """One result of ``parts`` run on consecutive episode ranges, in order (name, trace and
        scenario from the first part; an optional per-episode array kept only if every part has it)."""
        if not parts:
            raise ValueError("nothing to concatenate")
        if len({p.name for p in parts}) != 1:
            raise ValueError(f"results of different policies: {sorted({p.name for p in parts})}")
        if any(set(p.terms) != set(parts[0].terms) for p in parts):
            raise ValueError("results with different reward terms")

        def join(get):
            xs = [get(p) for p in parts]
            return None if any(x is None for x in xs) else np.concatenate([np.asarray(x) for x in xs])
        terminated = (None if all(p.terminated is None for p in parts) else   # None: no episode ended early
                      join(lambda p: np.zeros(p.episodes, bool) if p.terminated is None else p.terminated))
        return dataclasses.replace(parts[0], returns=join(lambda p: p.returns),
                                   terms={k: join(lambda p, k=k: p.terms[k]) for k in parts[0].terms},
                                   qp_fraction=join(lambda p: p.qp_fraction), mean_preload=join(lambda p: p.mean_preload),
                                   terminated=terminated, first_obs=join(lambda p: p.first_obs),
                                   vibration_um=join(lambda p: p.vibration_um), cost=join(lambda p: p.cost))

    def ci95(self) -> tuple[float, float]:
        from scipy import stats
        n = len(self.returns)
        m = float(np.mean(self.returns))
        if n < 2:
            return m, m
        h = float(stats.t.ppf(0.975, n - 1) * np.std(self.returns, ddof=1) / math.sqrt(n))
        return m - h, m + h

    def row(self) -> dict[str, Any]:
        lo, hi = self.ci95()
        r = {"policy": self.name, "episodes": self.episodes, "mean_return": float(np.mean(self.returns)),
             "ci95_low": lo, "ci95_high": hi}
        for k in REWARD_TERMS:
            r[f"mean_{k}"] = float(np.mean(self.terms[k]))
        r["quasi_periodic_fraction"] = float(np.mean(self.qp_fraction))
        r["mean_preload_n"] = float(np.mean(self.mean_preload))
        r["terminated_episodes"] = self.terminated_count
        return r
