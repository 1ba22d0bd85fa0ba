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


def first_python_block(page, section: str) -> str:
    """The first ``python`` code block after the heading ``section`` of the markdown file ``page``
    (what a docs test executes as written)."""
    import re
    text = page.read_text(encoding="utf-8")
    assert section in text, f"{page.name} has no section {section!r}"
    m = re.search(r"```python\n(.*?)```", text.split(section, 1)[1], re.S)
    assert m, f"no python block in {page.name}'s {section!r}"
    return m.group(1)
