"""Scoring the constrained variant (safe RL): maximise the reward without its vibration term
(heat, fatigue, actuation: :func:`bearing_gym.envs.reward.constrained_reward`) while the episode's
cost - the sum of ``info["cost"]``, one per quasi-periodic interval (a termination: one per
interval left) - stays within ``bearing_gym.task.COST_BUDGET_PER_EPISODE``.

A constrained row reports, over every (training seed, test episode): the mean constrained return
and the mean cost with stratified-bootstrap 95 % intervals (seeds and episodes redrawn, as the
board's intervals), and the share of episodes within the budget. There is no normalised score:
the board's 0 and 1 (the validation constant, the planner) optimise the benchmark's reward, not
this one; their constrained returns and costs on the same episodes stand beside the row instead
(:func:`reference_rows`, from the stored references' reward terms).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bearing_gym.task import COST_BUDGET_PER_EPISODE

from agents.evaluation.result import EvalResult
from agents.leaderboard import scoring
from agents.leaderboard.upper import PLANNER_ROW
from agents.references.store import StoredReferences

__all__ = ["constrained_row", "reference_rows"]


def _row(returns: np.ndarray, costs: np.ndarray, budget: float, bootstrap_reps: int) -> dict[str, Any]:
    ret, ret_lo, ret_hi = scoring.mean_interval(returns, reps=bootstrap_reps)
    cost, cost_lo, cost_hi = scoring.mean_interval(costs, reps=bootstrap_reps)
    return {"kind": "constrained", "variant": "constrained", "cost_budget": budget,
            "constrained_return_mean": ret, "return_ci_low": ret_lo, "return_ci_high": ret_hi,
            "cost_mean": cost, "cost_ci_low": cost_lo, "cost_ci_high": cost_hi,
            "within_budget_fraction": float(np.mean(costs <= budget)),
            "n_seeds": int(returns.shape[0]), "n_episodes": int(returns.shape[1]),
            "episode_returns": returns.tolist(), "episode_costs": costs.tolist()}


def constrained_row(results: list[EvalResult], budget: float = COST_BUDGET_PER_EPISODE,
                    bootstrap_reps: int = scoring.BOOTSTRAP_REPS, **extra: Any) -> dict[str, Any]:
    """The constrained row of ``results`` (one per training seed, run with the constrained reward:
    their returns are the constrained returns, their ``cost`` the episodes' costs)."""
    if any(r.cost is None for r in results):
        raise ValueError("the constrained variant needs every run's cost (run_policies records it)")
    returns = np.array([r.returns for r in results], dtype=np.float64)
    costs = np.array([r.cost for r in results], dtype=np.float64)
    return {**_row(returns, costs, budget, bootstrap_reps), **extra}


def reference_rows(refs: StoredReferences, budget: float = COST_BUDGET_PER_EPISODE,
                   bootstrap_reps: int = scoring.BOOTSTRAP_REPS) -> dict[str, dict[str, Any]]:
    """The references' constrained rows on their stored episodes: the constrained return is the
    sum of their heat, fatigue and actuation terms, the cost their quasi-periodic intervals
    (exact where an episode did not terminate; a terminated episode's termination term is the
    benchmark reward's, larger than the constrained variant's: they are left out and the rows say
    how many; a reference whose every episode terminated has no row)."""
    rows: dict[str, dict[str, Any]] = {}
    named = [(f"validation constant ({refs.validation_preload_n:.0f} N)", refs.validation_constant),
             (f"hindsight constant ({refs.hindsight_grid_step_n:g} N grid)", refs.hindsight)]
    if refs.planner is not None:
        named.append((PLANNER_ROW, refs.planner))
    for name, r in named:
        terminated = np.zeros(len(r.returns), bool) if r.terminated is None else np.asarray(r.terminated, bool)
        returns = sum(np.asarray(r.terms[k], dtype=np.float64) for k in ("heat", "fatigue", "actuation"))
        costs = np.rint(np.asarray(r.qp_fraction, dtype=np.float64) * refs.episode_steps)
        costs = np.where(terminated, np.nan, costs)
        keep = ~terminated
        if not keep.any():                       # every episode terminated: nothing exact to show
            continue
        row = _row(returns[keep][None, :], costs[keep][None, :], budget, bootstrap_reps)
        row.update(kind="reference", terminated_episodes_left_out=int(terminated.sum()))
        rows[name] = row
    return rows

