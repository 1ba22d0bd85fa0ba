"""The reward's required properties over the grid of operating points (docs/reward_map.csv, the
ground truth the agents face), and that the committed grid is what the code computes."""

import os
from pathlib import Path

import numpy as np
import pytest

from bearing_gym.envs import BearingPreloadEnv, VibrationFirstReward
from bearing_gym.envs.reward_map import (GRID_PRELOADS_N, cells_of, period1_windows, read_csv,
                                         reward_map)

MAP = Path(__file__).resolve().parents[2] / "docs" / "reward_map.csv"


def check_properties(points):
    cells = cells_of(points)
    assert len(cells) >= 27
    n_checked = 0
    for cell, pts in cells.items():
        assert [p.preload_n for p in pts] == list(GRID_PRELOADS_N), cell     # every 100 N
        periodic = [p for p in pts if p.period1]
        if not periodic:
            continue
        n_checked += 1
        best_periodic = max(p.mean_reward for p in periodic)
        # vibration comes first: every quasi-periodic preload earns less than the best period-1 one
        for p in pts:
            if not p.period1:
                assert p.mean_reward < best_periodic, (cell, p.preload_n, p.mean_reward, best_periodic)
        # among period-1 preloads the lower one is preferred (heat and life)
        rewards = [p.mean_reward for p in periodic]
        assert all(a > b for a, b in zip(rewards, rewards[1:])), (cell, rewards)
    return n_checked


def test_committed_map_has_the_required_reward_properties():
    n = check_properties(read_csv(MAP))
    assert n >= 20          # most cells have a period-1 preload: the properties are exercised


def test_the_map_has_isolated_windows_somewhere():
    # the stability map is not one boundary: some cell has two period-1 windows or a
    # quasi-periodic band above a period-1 window (what the oracle must not interpolate over)
    cells = cells_of(read_csv(MAP))
    assert any(len(period1_windows(pts)) > 1 or (period1_windows(pts) and not pts[-1].period1)
               for pts in cells.values())


def test_committed_map_is_what_the_code_computes():
    # one cell, recomputed (the whole grid: the slow test below)
    committed = {p.preload_n: p for p in read_csv(MAP) if p.cell == (17500.0, 250.0, 17.0)}
    fresh = reward_map(speeds_rpm=(17500.0,), radial_loads_n=(250.0,), clearances_m=(17e-6,))
    for p in fresh:
        c = committed[p.preload_n]
        assert p.period1 == c.period1
        assert p.mean_reward == pytest.approx(c.mean_reward, rel=1e-5, abs=1e-6)
        assert p.mean_nonsync_rms_um == pytest.approx(c.mean_nonsync_rms_um, rel=1e-5, abs=1e-6)


@pytest.mark.slow
@pytest.mark.skipif(not os.environ.get("BEARING_GYM_SLOW"), reason="set BEARING_GYM_SLOW=1 (whole grid, ~10 min)")
def test_reward_properties_on_a_fresh_grid():
    check_properties(reward_map())


def test_a_crash_earns_less_than_the_worst_continuation():
    import bearing_gym
    params = bearing_gym.envs.env_params(divergence_limit_m=2e-5)
    env = BearingPreloadEnv(tier="paper", params=params, episode_steps=30)
    env.reset(seed=0, options={"initial_preload_n": 1000.0})
    low = np.array([-1.0], np.float32)
    rewards = []
    for _ in range(30):
        _, r, term, _, info = env.step(low)
        rewards.append(r)
        if term:
            break
    assert term, "the small divergence limit must end the episode"
    steps_left = 30 - len(rewards)
    worst = VibrationFirstReward().worst_step_cost(info["shaft_speed_rpm"] * np.pi / 30, info["radial_load_n"])
    assert rewards[-1] <= -worst * (steps_left + 1)
    assert sum(rewards) < -worst * steps_left      # below any continuation of the remaining steps
