"""The preload map: its rows derived from the measured points (by hand on made-up points), its
classification and margins checked by direct simulations through the env's own API, and the
command on a small grid."""

import math

import numpy as np
import pytest

from bearing_gym import cli
from bearing_gym.envs import BearingPreloadEnv
from bearing_gym.engineering.preload_map import cell_row, preload_map, read_csv, static_stiffness, write_csv
from bearing_gym.envs.reward_map import MEASURE_INTERVALS, MapPoint
from bearing_gym.envs.scenario import Scenario


def _pt(preload, qp, heat, fatigue=-1.0, life=1e-6):
    return MapPoint(20000.0, 250.0, 4.0, 10.0, preload, -1.0, 0.0, heat, fatigue, 0.2 if qp else 0.0, 0.0, 0.0, 0.0,
                    False, 5e7, 4e7, life, 0.01)


def test_a_row_is_derived_from_its_points():
    """Grid 300..1000 N step 100: quasi-periodic at 300, 400 and 800; secondary costs rising with
    preload. Cheapest period-1: 500 N (margins 100 below, 300 above); with a 150 N minimum margin:
    600 N (200 / 200); with 250 N: none (700 N has 100 above, 1000 N 200 below). Without the
    window at 800 N and a 300 N minimum: 700 N, no window above (NaN)."""
    qp = {300, 400, 800}
    pts = [_pt(p, p in qp, heat=-p / 1000) for p in range(300, 1001, 100)]
    r = cell_row(pts)
    assert (r.lowest_period1_n, r.preferred_n, r.margin_below_n, r.margin_above_n) == (500, 500, 100, 300)
    assert (r.period1_preloads, r.grid_preloads, r.grid_step_n) == (5, 8, 100)
    assert r.l10_life_h == pytest.approx(1.0 / 3.6e-3) and r.radial_stiffness_n_per_um == pytest.approx(50.0)
    r = cell_row(pts, min_margin_n=150)
    assert (r.preferred_n, r.margin_below_n, r.margin_above_n) == (600, 200, 200)
    r = cell_row(pts, min_margin_n=250)
    assert r.lowest_period1_n == 500 and math.isnan(r.preferred_n)
    r = cell_row([_pt(p, p in (300, 400), heat=-p / 1000) for p in range(300, 1001, 100)], min_margin_n=300)
    assert r.preferred_n == 700 and r.margin_below_n == 300 and math.isnan(r.margin_above_n)
    none = cell_row([_pt(p, True, -1.0) for p in (300, 400)])
    assert math.isnan(none.lowest_period1_n) and none.period1_preloads == 0


def _quasi_periodic_direct(speed, radial, preload):
    """The map's measurement through the env's API: reset at the preload, held 25 intervals."""
    env = BearingPreloadEnv(tier="stationary")
    env.reset(seed=0, options={"scenario": Scenario(speed_profile=((0.0, speed),), radial_load_profile=((0.0, radial),),
                                                    clearance_m=4e-6, eccentricity_m=10e-6, initial_preload_n=preload)})
    a = np.array([env.actuator.action_for(preload)], dtype=np.float32)
    return any(env.step(a)[4]["quasi_periodic"] for _ in range(MEASURE_INTERVALS))


def test_the_margins_hold_in_direct_simulations(tmp_path):
    """25,000 rpm, 500 N: the preferred preload and the last preload inside each margin run
    period-1, the preload at each margin quasi-periodic, each in a single env of its own; the
    stiffness is the static equilibrium's; the CSV reads back."""
    rows, points = preload_map([25000.0], [500.0], preloads_n=tuple(float(p) for p in range(900, 2001, 100)),
                               workers=1, progress=False, min_margin_n=150.0)
    r, = rows
    assert r.preferred_n - r.margin_below_n >= 900 and r.margin_below_n >= 150
    assert not _quasi_periodic_direct(25000.0, 500.0, r.preferred_n)
    assert _quasi_periodic_direct(25000.0, 500.0, r.preferred_n - r.margin_below_n)
    assert not _quasi_periodic_direct(25000.0, 500.0, r.preferred_n - r.margin_below_n + r.grid_step_n)
    if not math.isnan(r.margin_above_n):
        assert _quasi_periodic_direct(25000.0, 500.0, r.preferred_n + r.margin_above_n)
    k_r, k_a = static_stiffness(25000.0, 500.0, 4e-6, r.preferred_n)
    assert r.radial_stiffness_n_per_um == pytest.approx(k_r * 1e-6, rel=1e-12) and k_a > 0
    assert read_csv(write_csv(rows, tmp_path / "m.csv"))[0].preferred_n == r.preferred_n


def test_the_command_writes_the_map_and_names_bad_options(tmp_path, capsys):
    out = tmp_path / "pm.csv"
    assert cli.main(["preload-map", "--rpms", "20000", "--radial-loads", "0", "--preload-min", "600",
                     "--preload-max", "1000", "--preload-step", "200", "--workers", "1", "--out", str(out), "-q"]) == 0
    rows = read_csv(out)
    assert len(rows) == 1 and rows[0].grid_preloads == 3 and out.with_suffix(".png").exists()
    for bad, name in ((["--preload-step", "0"], "--preload-step"), (["--min-margin", "-5"], "--min-margin"),
                      (["--preload-min", "900", "--preload-max", "800"], "--preload-min")):
        assert cli.main(["preload-map", "--rpms", "20000", "--out", str(out), "-q"] + bad) == 2
        assert name in capsys.readouterr().err
