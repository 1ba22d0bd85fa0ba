"""Planner runs are resumable: one file per episode, a stale file (another kernel or other
settings) counts as missing, and the set loads only when complete."""

import json

import pytest

from agents.policies.planner import PlannerSettings
from agents.references import planner_runs as R

SMALL = PlannerSettings.plain(replan_every=3, grid_step_n=850.0, local_n=(-50.0, 50.0), block_n=(), jumps_n=())


def test_runs_write_one_file_per_episode_and_resume(tmp_path):
    seeds = R.missing("transient", episodes=2, settings=SMALL, episode_steps=4, data_dir=tmp_path)
    assert seeds == [300000, 300001]
    with pytest.raises(ValueError, match="planner_runs --tier transient"):
        R.load_plans("transient", 2, SMALL, 4, tmp_path)
    R.run("transient", seeds[:1], SMALL, 4, tmp_path)
    assert R.missing("transient", 2, SMALL, 4, tmp_path) == [300001]
    R.run("transient", [300001], SMALL, 4, tmp_path)
    plans = R.load_plans("transient", 2, SMALL, 4, tmp_path)
    assert [p.seed for p in plans] == seeds and all(p.return_ >= p.hindsight_return for p in plans)
    # another kernel's file, or other settings, is planned again
    path = R.episode_path("transient", 300001, tmp_path)
    d = json.loads(path.read_text())
    path.write_text(json.dumps({**d, "kernel_hash": "0" * 16}))
    assert R.missing("transient", 2, SMALL, 4, tmp_path) == [300001]
    other = PlannerSettings(replan_every=2, grid_step_n=850.0, local_n=(-50.0, 50.0), block_n=(), jumps_n=())
    assert R.missing("transient", 2, other, 4, tmp_path) == seeds


def test_a_run_stored_before_the_settle_pass_is_resumed_to_the_whole_search(tmp_path):
    """Files planned with ``settings.before_settle()`` count as missing for ``settings``; a run
    resumes them (the settle pass only) and writes what a whole run of ``settings`` gives, bit
    for bit."""
    from agents.policies.planner import plan_episode
    settle = PlannerSettings(replan_every=3, grid_step_n=850.0, local_n=(-50.0,), block_n=(), jumps_n=(300.0, 1000.0),
                             block_levels_n=(2000.0,), block_intervals=(2,), ramp_down_intervals=(),
                             decide_at_start=False, start_ramp_intervals=())
    R.run("field", [300000], settle.before_settle(), 9, tmp_path)
    assert R.missing("field", 1, settle, 9, tmp_path) == [300000]
    # mark the stored run (its wall time is carried into the resumed result, a new run's is not)
    path = R.episode_path("field", 300000, tmp_path)
    path.write_text(json.dumps({**json.loads(path.read_text()), "wall_s": 1e6}))
    R.run("field", [300000], settle, 9, tmp_path)
    assert R.missing("field", 1, settle, 9, tmp_path) == []
    got = R.load_plans("field", 1, settle, 9, tmp_path)[0]
    whole = plan_episode("field", 300000, 9, settle)
    assert got.return_ == whole.return_ and list(got.plan_n) == list(whole.plan_n)
    assert got.settings == settle.as_dict() and got.wall_s >= 1e6      # resumed, not planned again
