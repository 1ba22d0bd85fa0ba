"""The evaluation loop: hindsight constants, batch independence, episodes that terminate."""

import numpy as np
from tests.agents.helpers import diverging, eval_result

from agents.evaluation.episodes import run_policies
from agents.policies.scripted import ConstantPreload, FeedbackRule


def test_hindsight_constant_takes_the_best_candidate_of_each_scenario():
    from agents.evaluation.episodes import hindsight_constant
    a = eval_result("constant 800 N", [-10.0, -50.0, -30.0], qp=[0.0, 0.9, 0.1])
    b = eval_result("constant 1400 N", [-20.0, -25.0, -40.0], qp=[0.0, 0.0, 0.0])
    h = hindsight_constant([a, b])
    np.testing.assert_array_equal(h.returns, [-10.0, -25.0, -30.0])
    np.testing.assert_array_equal(h.qp_fraction, [0.0, 0.0, 0.1])
    # the terms come from the chosen candidate and still add up to its return
    np.testing.assert_allclose(sum(h.terms.values()), h.returns)


def test_episode_results_do_not_depend_on_the_batch_they_run_in():
    # evaluate() reuses the best constant's sweep row instead of running it again next to the
    # other policies; that is only sound if an episode's outcome is independent of its batch
    alone = run_policies([ConstantPreload(1000.0)], episodes=2, seed=100000, episode_steps=3)[0]
    mixed = run_policies([ConstantPreload(600.0), FeedbackRule(), ConstantPreload(1000.0)],
                         episodes=2, seed=100000, episode_steps=3)[2]
    np.testing.assert_array_equal(alone.returns, mixed.returns)
    np.testing.assert_array_equal(alone.trace["qpi"], mixed.trace["qpi"])


def test_terminated_episodes_do_not_disturb_the_others_in_the_batch():
    # at this limit the low preload diverges within a few steps, the high one does not
    kw = diverging(1e-4)
    low, high = run_policies([ConstantPreload(300.0), ConstantPreload(2000.0)], episodes=2, seed=0,
                             episode_steps=30, env_kwargs=kw)
    alone = run_policies([ConstantPreload(2000.0)], episodes=2, seed=0, episode_steps=30, env_kwargs=kw)[0]
    assert low.terminated.all() and not high.terminated.any()
    assert len(low.trace["t"]) < 30 and len(high.trace["t"]) == 30
    np.testing.assert_array_equal(high.returns, alone.returns)
    np.testing.assert_array_equal(high.trace["qpi"], alone.trace["qpi"])
    assert low.row()["terminated_episodes"] == 2 and high.row()["terminated_episodes"] == 0
