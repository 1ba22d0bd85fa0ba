"""The full-horizon planner: never below the hindsight best constant, its hindsight the same bits
as the board's, its plan's return reproduced by the evaluation loop, deterministic."""

import numpy as np
import pytest

from agents.evaluation.episodes import constant_sweep, hindsight_constant, run_policies
from agents.policies.planner import PlannerSettings, PlanResult, ScheduledPreload, plan_episode
from agents.protocol import preload_grid

#: a small search on short episodes: the properties do not depend on the size
SMALL = PlannerSettings(replan_every=4, grid_step_n=425.0, local_n=(-100.0, 100.0), block_n=(50.0,),
                        jumps_n=(300.0, 2000.0))
STEPS = 12


@pytest.mark.parametrize("tier, seed", [("transient", 300016), ("field", 300003)])
def test_the_plan_is_never_below_the_hindsight_constant_and_replays_bit_for_bit(tier, seed):
    res = plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL)
    # the hindsight constant is the board's (constant_sweep + hindsight_constant), bit for bit
    sweep = constant_sweep(preload_grid(SMALL.grid_step_n), 1, seed, STEPS, env_kwargs={"tier": tier})
    board = hindsight_constant(sweep)
    assert res.hindsight_return == board.returns[0]
    assert res.return_ >= res.hindsight_return
    assert res.plan_n.shape == (STEPS,) and res.decisions == len(range(SMALL.replan_every, STEPS, SMALL.replan_every))
    # the plan replayed by the evaluation loop gives the planner's return
    replay = run_policies([ScheduledPreload([res.plan_n])], 1, seed, STEPS, env_kwargs={"tier": tier})[0]
    assert replay.returns[0] == res.return_
    # and the same again (deterministic), through its JSON form
    again = PlanResult.from_json(res.to_json())
    np.testing.assert_array_equal(again.plan_n, res.plan_n)
    assert plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL).return_ == res.return_


def test_planner_settings_name_a_bad_interval():
    with pytest.raises(ValueError, match="replan_every"):
        PlannerSettings(replan_every=0)


def test_a_stored_hindsight_gives_the_same_plan_and_a_stale_one_is_refused():
    """Starting from a stored hindsight constant (the sweep skipped) plans the same bits; a stored
    return the episode does not reproduce (far above it here, so no candidate beats it and the
    plan stays the constant) is named stale instead of silently bounding the search."""
    tier, seed = "transient", 300016
    own = plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL)
    given = plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL,
                         hindsight=(own.hindsight_preload_n, own.hindsight_return))
    assert (own.hindsight_from, given.hindsight_from) == ("sweep", "stored")
    assert given.return_ == own.return_ and np.array_equal(given.plan_n, own.plan_n)
    assert given.env_steps < own.env_steps
    with pytest.raises(RuntimeError, match="stored sweep is stale"):
        plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL,
                     hindsight=(own.hindsight_preload_n, own.hindsight_return + 1e6))
    with pytest.raises(ValueError, match="outside the actuator's range"):
        plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL, hindsight=(2500.0, 0.0))


def test_pruning_changes_no_decision_only_the_cost():
    """A candidate whose running return (costs only: it can only fall) is already at or below the
    incumbent's whole-episode return is stopped: the same plan and return, fewer env steps (on
    this 40-step episode about a quarter fewer)."""
    full = plan_episode("transient", 300016, episode_steps=40, settings=SMALL, prune=False)
    pruned = plan_episode("transient", 300016, episode_steps=40, settings=SMALL)
    assert pruned.return_ == full.return_ and np.array_equal(pruned.plan_n, full.plan_n)
    assert pruned.accepted == full.accepted and pruned.env_steps < full.env_steps
