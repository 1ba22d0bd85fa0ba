"""The full-horizon planner: never below the hindsight best constant, its hindsight the same bits
as the board's, its plan's return reproduced by the evaluation loop, deterministic."""

import numpy as np
import pytest

from agents.evaluation.episodes import constant_sweep, hindsight_constant, run_policies
from agents.policies.planner import PlannerSettings, PlanResult, ScheduledPreload, plan_episode
from agents.protocol import preload_grid

#: a small plain search on short episodes (the default's wider searches off): the properties do
#: not depend on the size
SMALL = PlannerSettings.plain(replan_every=4, grid_step_n=425.0, local_n=(-100.0, 100.0), block_n=(50.0,),
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


def test_the_wider_search_only_adds_to_the_plain_one():
    """The searches added for a tighter bound (block levels, a decision at t = 0 with ramps from the
    initial preload, a second pass, a warm start from a plan found before) are stored only where
    they are on, so the plain search keeps its stored settings; the defaults switch four of them
    on (and the settle pass, tested below). Switched on, the plan here ends at or above the plain one's (likely, not guaranteed: a
    change accepted early changes what the later decisions see; what is guaranteed is the
    hindsight constant, tested above) and replays bit for bit; a warm plan is the incumbent when it is better."""
    plain_keys = {"replan_every", "grid_step_n", "local_n", "block_n", "jumps_n"}
    assert set(SMALL.as_dict()) == plain_keys
    assert set(PlannerSettings().as_dict()) == plain_keys | {"block_levels_n", "decide_at_start", "start_ramp_intervals",
                                                             "block_intervals", "ramp_down_intervals", "settle_pass"}
    tier, seed = "transient", 300016
    plain = plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL)
    wide_s = PlannerSettings(replan_every=4, grid_step_n=425.0, local_n=(-100.0, 100.0), block_n=(50.0,),
                             jumps_n=(300.0, 2000.0), block_levels_n=(300.0, 1150.0, 2000.0),
                             decide_at_start=True, passes=2, start_ramp_intervals=(1, 2, 3),
                             beam_starts_n=(2000.0,), settle_pass=False)
    assert wide_s.as_dict()["passes"] == 2 and wide_s.as_dict()["start_ramp_intervals"] == [1, 2, 3]
    wide = plan_episode(tier, seed, episode_steps=STEPS, settings=wide_s)
    assert wide.return_ >= plain.return_ and wide.decisions == 2 * 2 * len(range(0, STEPS, 4))   # 2 starts x 2 passes
    replay = run_policies([ScheduledPreload([wide.plan_n])], 1, seed, STEPS, env_kwargs={"tier": tier})[0]
    assert replay.returns[0] == wide.return_
    warm = plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL, warm_plan_n=wide.plan_n)
    assert warm.return_ >= wide.return_
    with pytest.raises(ValueError, match="passes"):
        PlannerSettings(passes=0)
    with pytest.raises(ValueError, match="warm plan needs 12 set-points"):
        plan_episode(tier, seed, episode_steps=STEPS, settings=SMALL, warm_plan_n=np.full(5, 1000.0))


class _Range:
    """What the candidate list needs of an episode: the actuator's range and the initial preload."""
    initial_preload_n = 700.0

    @staticmethod
    def in_range(v: float) -> bool:
        return 300.0 <= v <= 2000.0


def test_candidates_kicks_ramps_and_no_swept_constant_at_the_start():
    """Block levels come in each of ``block_intervals``' lengths and return to the incumbent after
    it; at t = 0 a level held from t would be a constant plan, and those of the hindsight sweep
    are left out (none can beat its best), while ramps from the initial preload (700 N here) rise
    linearly to the incumbent's set-point."""
    from agents.policies.planner import _candidates
    s = PlannerSettings(replan_every=10, local_n=(-50.0, 50.0), block_n=(), jumps_n=(300.0,),
                        block_levels_n=(2000.0,), block_intervals=(3, 10), decide_at_start=True,
                        start_ramp_intervals=(4,), ramp_down_intervals=())
    plan = np.full(30, 1500.0)
    swept = frozenset(preload_grid(50.0))
    at_start = _candidates(plan, 0, s, _Range, swept)
    assert not any(np.all(c == c[0]) for c in at_start)            # no constant plan at t = 0
    kicks = [c for c in at_start if c[0] == 2000.0]
    assert sorted(int((c == 2000.0).sum()) for c in kicks) == [3, 10]
    assert all(np.all(c[(c != 2000.0)] == 1500.0) for c in kicks)   # back to the incumbent after the kick
    ramp = [c for c in at_start if c[0] not in (2000.0, 1500.0)]
    assert len(ramp) == 1
    np.testing.assert_allclose(ramp[0][:5], [860.0, 1020.0, 1180.0, 1340.0, 1500.0], rtol=0, atol=1e-9)
    later = _candidates(plan, 10, s, _Range, swept)                 # later on: levels held, blocks, kicks
    held = sorted(float(c[-1]) for c in later if c[-1] != 1500.0)
    assert held == [300.0, 1450.0, 1550.0] and all(np.all(c[:10] == 1500.0) for c in later)
    assert len(later) == 3 + 2
    with pytest.raises(ValueError, match="block_intervals"):
        PlannerSettings(block_intervals=(0,))


def test_a_drop_wider_than_the_local_steps_is_also_tried_as_a_ramp():
    """With ``ramp_down_intervals`` a level held from t more than the widest local step below the
    set-point before t is also tried as a linear ramp down to it (a sudden drop can ring the
    rotor): here 1500 -> 300 N over 4 intervals, 240 N each; the 50 N local steps get no ramp."""
    from agents.policies.planner import _candidates
    s = PlannerSettings(replan_every=10, local_n=(-50.0, 50.0), block_n=(), jumps_n=(300.0,), block_levels_n=(),
                        ramp_down_intervals=(4,))
    plan = np.full(30, 1500.0)
    later = _candidates(plan, 10, s, _Range, frozenset(preload_grid(50.0)))
    ramps = [c for c in later if 300.0 < c[10] < 1450.0]
    assert len(later) == 3 + 1 and len(ramps) == 1
    np.testing.assert_allclose(ramps[0][8:16], [1500.0, 1500.0, 1260.0, 1020.0, 780.0, 540.0, 300.0, 300.0],
                               rtol=0, atol=1e-9)
    assert PlannerSettings.plain(ramp_down_intervals=(3,)).as_dict()["ramp_down_intervals"] == [3]


def test_settle_candidates_kick_then_ramp_down_to_each_lower_level():
    """The settle pass's plans at t: ``block_levels_n`` for each ``block_intervals`` length, then
    a linear ramp down over each ``ramp_down_intervals`` length to each lower ``jumps_n`` level,
    held to the end; the plan before t is the incumbent's. Here 2000 N for 3 intervals from t = 10,
    then 2000 -> 500 N over 2 intervals (2000 - 1500/3 = 1500, 1000) and 500 N to the end; the 2000 N
    jump is no lower level and 2500 N is out of range."""
    from agents.policies.planner import _settle_candidates
    s = PlannerSettings(replan_every=10, jumps_n=(500.0, 1100.0, 2000.0, 2500.0), block_levels_n=(2000.0,),
                        block_intervals=(3, 6), ramp_down_intervals=(2,))
    plan = np.full(30, 1500.0)
    cands = _settle_candidates(plan, 10, s, _Range)
    assert len(cands) == 2 * 2                                       # 2 kick lengths x 2 lower levels
    assert all(np.all(c[:10] == 1500.0) for c in cands)
    one = [c for c in cands if c[-1] == 500.0 and (c == 2000.0).sum() == 3]
    assert len(one) == 1
    np.testing.assert_allclose(one[0][10:17], [2000.0, 2000.0, 2000.0, 1500.0, 1000.0, 500.0, 500.0], rtol=0, atol=1e-9)
    assert _settle_candidates(plan, 25, s, _Range)[0][25:].tolist() == [2000.0, 2000.0, 2000.0, 1500.0, 1000.0]
    assert _settle_candidates(plan, 28, s, _Range) == []             # no interval left after the kick
    cut = [c for c in _settle_candidates(plan, 26, s, _Range) if (c == 2000.0).sum() == 3]
    assert [c[26:].tolist() for c in cut] == [[2000.0, 2000.0, 2000.0, 1500.0], [2000.0, 2000.0, 2000.0, 1700.0]]
    step = PlannerSettings(jumps_n=(500.0,), block_levels_n=(2000.0,), block_intervals=(2,), ramp_down_intervals=())
    assert _settle_candidates(plan, 0, step, _Range)[0][:4].tolist() == [2000.0, 2000.0, 500.0, 500.0]
    # with no kick level or no level to settle to there is no settle pass, and none is stored
    assert not PlannerSettings(block_levels_n=()).settles and "settle_pass" not in PlannerSettings(jumps_n=()).as_dict()


def test_the_settle_pass_resumed_from_the_search_before_it_is_the_same_plan():
    """A run of the search up to the settle pass (``before_settle()``), stored and resumed, ends
    with the same plan and return, bit for bit, as the whole search run at once, at the settle
    pass's cost; a resume with other settings or a stale stored return is refused."""
    tier, seed, steps = "field", 20, 32               # a training episode where the settle pass changes the plan
    full_s = PlannerSettings(replan_every=4, grid_step_n=425.0, local_n=(-100.0, 100.0), block_n=(50.0,),
                             jumps_n=(300.0, 700.0, 1100.0), block_levels_n=(2000.0,), block_intervals=(3,),
                             ramp_down_intervals=(3,), decide_at_start=True, start_ramp_intervals=())
    assert full_s.settle_pass and not full_s.before_settle().settle_pass
    whole = plan_episode(tier, seed, episode_steps=steps, settings=full_s)
    first = plan_episode(tier, seed, episode_steps=steps, settings=full_s.before_settle())
    stored = PlanResult.from_json(first.to_json())
    resumed = plan_episode(tier, seed, episode_steps=steps, settings=full_s, resume=stored)
    assert resumed.return_ == whole.return_ and np.array_equal(resumed.plan_n, whole.plan_n)
    assert (resumed.decisions, resumed.accepted, resumed.env_steps) == (whole.decisions, whole.accepted, whole.env_steps)
    assert whole.accepted > first.accepted and whole.return_ > first.return_ and whole.settings["settle_pass"] is True
    assert whole.decisions == 2 * len(range(0, steps, 4))            # the search and the settle pass
    replay = run_policies([ScheduledPreload([whole.plan_n])], 1, seed, steps, env_kwargs={"tier": tier})[0]
    assert replay.returns[0] == whole.return_
    with pytest.raises(ValueError, match="settings before the settle pass"):
        plan_episode(tier, seed, episode_steps=steps, settings=full_s, resume=whole)
    with pytest.raises(ValueError, match="brings its own start"):
        plan_episode(tier, seed, episode_steps=steps, settings=full_s, resume=stored, hindsight=(1000.0, -1.0))
    stale = PlanResult.from_json({**first.to_json(), "return": first.return_ + 1.0})
    with pytest.raises(RuntimeError, match="stored run is stale"):
        plan_episode(tier, seed, episode_steps=steps, settings=full_s, resume=stale)
