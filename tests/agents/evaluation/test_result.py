"""A policy's results (EvalResult): cutting and joining per-episode arrays."""

import numpy as np
import pytest


def test_eval_result_first_cuts_every_per_episode_array():
    from agents.evaluation.result import EvalResult
    from bearing_gym.envs.reward import REWARD_TERMS
    n = 5
    r = EvalResult("p", np.arange(n, dtype=float), {k: np.arange(n) + i for i, k in enumerate(REWARD_TERMS)},
                   np.linspace(0, 1, n), np.full(n, 900.0), terminated=np.array([0, 1, 0, 0, 1], bool),
                   first_obs=np.zeros((n, 14)), vibration_um=np.arange(n) * 0.5)
    c = r.first(2)
    assert c.episodes == 2 and c.terminated_count == 1 and c.first_obs.shape == (2, 14)
    np.testing.assert_array_equal(c.vibration_um, [0.0, 0.5])
    assert all(len(v) == 2 for v in c.terms.values()) and len(r.returns) == n     # the original untouched
    with pytest.raises(ValueError, match="6 episodes asked of a result on 5"):
        r.first(6)


def test_eval_result_concat_joins_in_order_and_drops_an_array_one_part_lacks():
    from agents.evaluation.result import EvalResult
    from bearing_gym.envs.reward import REWARD_TERMS

    def part(lo, n, vib):
        return EvalResult("p", np.arange(lo, lo + n, dtype=float), {k: np.arange(lo, lo + n) for k in REWARD_TERMS},
                          np.zeros(n), np.full(n, 900.0), terminated=None if lo == 0 else np.ones(n, bool),
                          vibration_um=np.ones(n) if vib else None)
    c = EvalResult.concat([part(0, 2, True), part(2, 3, False)])
    np.testing.assert_array_equal(c.returns, [0, 1, 2, 3, 4])
    np.testing.assert_array_equal(c.terminated, [False, False, True, True, True])   # None = none ended early
    assert c.vibration_um is None                                                   # not known for every episode
    assert EvalResult.concat([part(0, 2, True), part(0, 1, True)]).terminated is None
    with pytest.raises(ValueError, match="different policies"):
        EvalResult.concat([part(0, 2, True), EvalResult("q", np.zeros(1), {}, np.zeros(1), np.zeros(1))])
