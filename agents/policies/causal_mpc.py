"""The causal MPC: receding-horizon control with the true simulator that assumes the present
operating point persists. A model-based baseline, not a bound: it knows the physics down to the
last bit and the rotor's whole state (no observation noise), but not the scenario's future.

Every ``replan_every`` control intervals the real env (env 0 of a
:class:`agents.policies.planner.BranchedEpisode`) is copied once per candidate; each copy holds
the shaft speed and radial load of the present moment from then on
(``BearingPreloadVectorEnv.hold_operating_point``: a speed ramp under way stops where it is,
a coming load step never comes) and holds its candidate set-point for ``horizon`` intervals (or
to the episode's end); the candidate whose copy earned the most reward (summed in step order;
the first of equal ones) is applied to the real env for the next ``replan_every`` intervals.
The defaults are the tier-design study's receding-horizon MPC (:mod:`agents.policies.mpc`: nine
levels 300-2000 N, a horizon of 10 intervals, a decision every 5), which sees the future: the
two differ only in what they know of it. Cost: ``len(candidates_n) * horizon / replan_every``
simulated intervals per real one (18 with the defaults), about 2,900 env steps per
150-interval episode.

The episode's real course depends on nothing the copies do, so the set-points it applied
(:attr:`CausalPlan.plan_n`), replayed through the evaluation loop by
:class:`agents.policies.planner.ScheduledPreload`, give its return bit for bit: the board's row.
"""

from __future__ import annotations

import hashlib
import json
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bearing_gym.task import EPISODE_STEPS

from agents.policies.mpc import DEFAULT_CANDIDATES_N
from agents.policies.planner import BranchedEpisode, sequential_sum

__all__ = ["CausalMPCSettings", "CausalPlan", "plan_causal"]


@dataclass(frozen=True)
class CausalMPCSettings:
    """What the causal MPC tries (module docstring)."""

    candidates_n: tuple[float, ...] = DEFAULT_CANDIDATES_N
    horizon: int = 10
    replan_every: int = 5

    def __post_init__(self) -> None:
        for name in ("horizon", "replan_every"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ValueError(f"causal MPC: {name} must be an integer >= 1 (control intervals), got {v!r}")
        if not self.candidates_n:
            raise ValueError("causal MPC: candidates_n must hold at least one set-point (N)")

    def as_dict(self) -> dict[str, Any]:
        return {"controller": "causal_mpc", "candidates_n": [float(p) for p in self.candidates_n],
                "horizon": self.horizon, "replan_every": self.replan_every}

    def digest(self) -> str:
        """A short fingerprint of the settings (stored with the protocol and with every run)."""
        return hashlib.sha256(json.dumps(self.as_dict(), sort_keys=True).encode()).hexdigest()[:16]


@dataclass
class CausalPlan:
    """One episode of the causal MPC: the set-point it applied at each interval, the real
    return, its decisions and what it cost."""

    seed: int
    plan_n: np.ndarray
    return_: float
    decisions: int
    env_steps: int
    wall_s: float
    terminated: bool
    settings: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        return {"seed": self.seed, "return": self.return_, "decisions": self.decisions, "env_steps": self.env_steps,
                "wall_s": self.wall_s, "terminated": self.terminated, "settings": self.settings,
                "plan_n": [float(p) for p in self.plan_n]}

    @classmethod
    def from_json(cls, d: dict[str, Any]) -> "CausalPlan":
        return cls(d["seed"], np.asarray(d["plan_n"], dtype=float), d["return"], d["decisions"], d["env_steps"],
                   d["wall_s"], d["terminated"], d.get("settings", {}))


def plan_causal(tier: str, seed: int, episode_steps: int = EPISODE_STEPS,
                settings: CausalMPCSettings = CausalMPCSettings(), env_kwargs: dict | None = None) -> CausalPlan:
    """Run the causal MPC on one episode of ``tier`` (module docstring); deterministic."""
    t0 = time.perf_counter()
    s = settings
    T = episode_steps
    ep = BranchedEpisode(tier, seed, T, len(s.candidates_n), env_kwargs)
    bad = [p for p in s.candidates_n if not ep.in_range(float(p))]
    if bad:
        raise ValueError(f"causal MPC: candidate {bad[0]} N is outside the actuator's range")
    plan = np.full(T, float(s.candidates_n[0]))
    rewards: list[float] = []
    decisions, terminated, t = 0, False, 0
    while t < T and not terminated:
        horizon = [np.full(T, float(p)) for p in s.candidates_n]
        scores = [sequential_sum(r) for r in ep.rollouts(horizon, t, until=t + s.horizon, hold_operating_point=True)]
        best = float(s.candidates_n[int(np.argmax(scores))])
        decisions += 1
        t1 = min(t + s.replan_every, T)
        plan[t:] = best
        got, terminated = ep.advance(plan, t, t1)
        rewards += got
        t = t1
    return CausalPlan(seed, plan, sequential_sum(rewards), decisions, ep.steps, time.perf_counter() - t0, terminated,
                      s.as_dict())
