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
