"""The reward-map oracle: its table is the map's best preload per cell (speed, radial load,
clearance, unbalance), looked up by the nearest cell (never interpolated across windows) at the
true operating point, eccentricity included."""

import numpy as np
import pytest

from agents.policies.oracle import MAP_PATH, TABLE_PATH, MapOracle, build_table
from bearing_gym.envs.reward_map import GRID_ECCENTRICITIES_M, best_preloads, read_csv


def test_shipped_table_is_the_maps_best_preload_per_cell(tmp_path):
    rows = build_table(MAP_PATH, tmp_path / "t.csv")
    assert (tmp_path / "t.csv").read_text() == TABLE_PATH.read_text()
    best = best_preloads(read_csv(MAP_PATH))
    assert len(rows) == len(best) == 27 * len(GRID_ECCENTRICITIES_M)
    assert {r["eccentricity_um"] for r in rows} == {e * 1e6 for e in GRID_ECCENTRICITIES_M}
    for r in rows:
        cell = (r["speed_rpm"], r["radial_load_n"], r["clearance_um"], r["eccentricity_um"])
        assert r["best_preload_n"] == best[cell].preload_n


def test_nearest_cell_not_interpolation():
    o = MapOracle()
    best = best_preloads(read_csv(MAP_PATH))
    cells = np.array(list(best))
    got = o.preload_n(cells)
    np.testing.assert_array_equal(got, [best[tuple(c)].preload_n for c in cells])
    # 17,500 rpm / 250 N / 4 um / 10 um has windows 600-1900 N, at 5 um 300 and 1100-2000 N: a
    # point near the 10 um cell takes that cell's best, whatever its neighbours say
    near = o.preload_n(np.array([[17000.0, 240.0, 5.0, 11.0]]))[0]
    assert near == best[(17500.0, 250.0, 4.0, 10.0)].preload_n
    assert near in {p.preload_n for p in read_csv(MAP_PATH)}          # a grid preload, never a mix


def test_scenarios_differing_only_in_unbalance_get_their_own_cells_preloads():
    """Through the evaluation loop's path (the vector env's ``operating_points`` ->
    ``set_conditions`` -> ``predict``): at 17,500 rpm / 0 N / 4 um the best preload is 300, 500
    and 1100 N at 5, 10 and 20 um of unbalance; an env with 7 um takes the 5 um cell's (distances
    scaled by the grid's 15 um span) and one with 30 um (the field tier's top) the 20 um cell's."""
    from bearing_gym.envs import BearingPreloadVectorEnv
    best = best_preloads(read_csv(MAP_PATH))
    eccentricities_m = (5e-6, 10e-6, 20e-6, 7e-6, 30e-6)
    expected_cells_um = (5.0, 10.0, 20.0, 5.0, 20.0)
    venv = BearingPreloadVectorEnv(num_envs=len(eccentricities_m), tier="stationary", episode_steps=2)
    pinned = {"shaft_speed_rpm": 17500.0, "radial_load_n": 0.0, "clearance_m": 4e-6, "waviness_amplitude_m": 0.0}
    venv.reset(seed=0, options=dict(pinned, eccentricity_m=eccentricities_m[0]))   # the first resets all
    for b, e in enumerate(eccentricities_m[1:], start=1):
        mask = np.arange(len(eccentricities_m)) == b
        venv.reset(seed=b, options=dict(pinned, eccentricity_m=e, reset_mask=mask))
    speed, radial, clearance, eccentricity = venv.operating_points()
    np.testing.assert_array_equal(eccentricity, eccentricities_m)
    np.testing.assert_allclose(speed, 17500.0, rtol=1e-12)
    o = MapOracle()
    o.set_conditions(speed, radial, clearance, eccentricity)
    action, _ = o.predict(np.zeros((len(eccentricities_m), 15)))
    preloads = [o.actuator.setpoint_n(a) for a in action[:, 0]]
    want = [best[(17500.0, 0.0, 4.0, e)].preload_n for e in expected_cells_um]
    assert want == [300.0, 500.0, 1100.0, 300.0, 1100.0]      # the cells differ: the test can fail
    np.testing.assert_allclose(preloads, want, rtol=1e-6)     # float32 actions
    venv.close()


def test_oracle_needs_the_operating_point():
    o = MapOracle()
    with pytest.raises(RuntimeError, match="set_conditions"):
        o.predict(np.zeros((1, 15)))
    with pytest.raises(ValueError, match="eccentricity_m"):
        o.set_conditions(np.array([25000.0]), np.array([500.0]), np.array([17e-6]))
    o.set_conditions(np.array([25000.0]), np.array([500.0]), np.array([17e-6]), np.array([10e-6]))
    action, _ = o.predict(np.zeros((1, 15)))
    assert o.actuator.setpoint_n(action[0, 0]) == pytest.approx(1900.0, rel=1e-6)
