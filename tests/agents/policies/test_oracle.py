"""The reward-map oracle: its table is the map's best preload per cell, looked up by the
nearest cell (never interpolated across windows)."""

import numpy as np
import pytest

from agents.policies.oracle import MAP_PATH, TABLE_PATH, MapOracle, build_table
from bearing_gym.envs.reward_map import best_preloads, read_csv


def test_shipped_table_is_the_maps_best_preload_per_cell(tmp_path):
    rows = build_table(MAP_PATH, tmp_path / "t.csv")
    assert (tmp_path / "t.csv").read_text() == TABLE_PATH.read_text()
    best = best_preloads(read_csv(MAP_PATH))
    assert len(rows) == len(best) == 27
    for r in rows:
        assert r["best_preload_n"] == best[(r["speed_rpm"], r["radial_load_n"], r["clearance_um"])].preload_n


def test_nearest_cell_not_interpolation():
    o = MapOracle()
    best = best_preloads(read_csv(MAP_PATH))
    cells = np.array(list(best))
    got = o.preload_n(cells)
    np.testing.assert_array_equal(got, [best[tuple(c)].preload_n for c in cells])
    # 17,500 rpm / 250 N / 4 um has windows 600-900, 1100 and 1500-1900 N: a point near it takes
    # that cell's best, whatever its neighbours say
    near = o.preload_n(np.array([[17000.0, 240.0, 5.0]]))[0]
    assert near == best[(17500.0, 250.0, 4.0)].preload_n
    assert near in {p.preload_n for p in read_csv(MAP_PATH)}          # a grid preload, never a mix


def test_oracle_needs_the_operating_point():
    o = MapOracle()
    with pytest.raises(RuntimeError, match="set_conditions"):
        o.predict(np.zeros((1, 15)))
    o.set_conditions(np.array([25000.0]), np.array([500.0]), np.array([17e-6]))
    action, _ = o.predict(np.zeros((1, 15)))
    assert o.actuator.setpoint_n(action[0, 0]) == pytest.approx(1900.0, rel=1e-6)
