"""Helpers shared by the agents' tests (not tests themselves)."""

import numpy as np


def eval_result(name, returns, qp=None):
    from agents.evaluation.result import EvalResult
    from bearing_gym.envs.reward import REWARD_TERMS
    r = np.asarray(returns, dtype=float)
    terms = {k: r / len(REWARD_TERMS) for k in REWARD_TERMS}
    q = np.zeros_like(r) if qp is None else np.asarray(qp, dtype=float)
    return EvalResult(name, r, terms, q, np.full_like(r, 1000.0))


def diverging(limit_m):
    # a tight divergence limit makes the integrator "diverge" (terminate the episode) on purpose
    from bearing_gym.envs import env_params
    return {"scenario": "paper", "params": env_params(divergence_limit_m=limit_m)}
