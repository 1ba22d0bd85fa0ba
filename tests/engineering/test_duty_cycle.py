"""The duty-cycle schedule: the cycle's speed and load reach the kernel as the CSV says, a run of
the cycle is the env's own episode bit for bit, a kept transition move beats the plain switch on
its stretch, and on the shipped example the schedule costs no more than the best constant."""

import json

import numpy as np
import pytest

from bearing_gym import cli
from bearing_gym.engineering import duty_cycle as D
from bearing_gym.envs import BearingPreloadEnv
from bearing_gym.envs.kernel import operating_point
from bearing_gym.envs.scenario import Scenario
from bearing_gym.units import rad_s_to_rpm

TWELVE = D.Cycle(tuple(float(t) for t in range(12)),
                 tuple(10000.0 + 1000.0 * (k % 5) for k in range(12)), tuple(100.0 * (k % 4) for k in range(12)))


def test_the_kernel_sees_the_cycle_at_every_time():
    """The schedule row of each time's window, read by the kernel's own interpolation, gives the
    CSV's piecewise-linear speed and stepped load (12 rows: past one window of MAX_EVENTS)."""
    for t in np.linspace(0.0, 10.99, 157):
        omega, fx, fy = operating_point(TWELVE.schedule_row(t), t)
        v, f = TWELVE.at(t)
        assert rad_s_to_rpm(omega) == pytest.approx(v, rel=1e-12)
        assert np.hypot(fx, fy) == pytest.approx(f, rel=1e-12, abs=1e-9)


def test_a_bad_cycle_is_refused_naming_what(tmp_path):
    with pytest.raises(ValueError, match="start at 0 and increase"):
        D.Cycle((1.0, 2.0), (10000.0, 10000.0), (0.0, 0.0))
    with pytest.raises(ValueError, match="speed_rpm"):
        D.Cycle((0.0, 2.0), (10000.0, 90000.0), (0.0, 0.0))
    bad = tmp_path / "c.csv"
    bad.write_text("time,speed\n0,10000\n")
    with pytest.raises(ValueError, match="columns time_s, speed_rpm, radial_load_n"):
        D.read_cycle(bad)
    assert cli.main(["schedule", "--duty", str(bad), "-q"]) == 2


@pytest.mark.filterwarnings("ignore:.*not the benchmark's horizon")
def test_a_run_of_the_cycle_is_the_envs_episode_bit_for_bit():
    """A cycle the env can express (a ramp and a load step) at a constant preload: the run's
    rewards are the env's episode's, interval by interval, exactly (at the set-point the env's
    float32 action gives)."""
    cycle = D.Cycle((0.0, 0.3, 0.5, 1.0), (15000.0, 15000.0, 22000.0, 22000.0), (300.0, 300.0, 0.0, 0.0))
    env = BearingPreloadEnv(tier="stationary", episode_steps=50)
    a = np.array([env.actuator.action_for(900.0)], dtype=np.float32)
    setpoint = float(env.actuator.setpoint_n(a)[0])
    run = D.CycleRun(cycle, [900.0])
    assert run.steps == 50
    for _ in range(run.steps):
        run.step(np.array([setpoint]))
        run.advance()
    sc = Scenario(speed_profile=((0.0, 15000.0), (0.3, 15000.0), (0.5, 22000.0)),
                  radial_load_profile=((0.0, 300.0), (0.5, 0.0)), eccentricity_m=10e-6, initial_preload_n=900.0)
    env.reset(seed=0, options={"scenario": sc})
    rewards = [env.step(a)[1] for _ in range(run.steps)]
    np.testing.assert_array_equal(run.rewards[0], np.array(rewards))


def test_a_kept_move_beats_the_plain_switch_and_the_costs_are_its_courses():
    """A cycle whose two switches ring (10,000 rpm / 500 N to 25,000 rpm / 100 N): each kept move
    earned the most over its stretch; the reported costs are those of the planned course run
    again alone from the start, and the best constant's those of that constant run alone."""
    cycle = D.Cycle((0.0, 1.0, 1.2, 2.4), (10000.0, 10000.0, 25000.0, 25000.0), (500.0, 500.0, 100.0, 100.0))
    s = D.plan_schedule(cycle, preloads_n=tuple(float(p) for p in range(300, 2001, 100)),
                        constants_n=(600.0, 1200.0, 1800.0), workers=1, progress=None)
    assert len(s.setpoints_n) == 120 and np.all((300.0 <= s.setpoints_n) & (s.setpoints_n <= 2000.0))
    kept = [tr for tr in s.transitions if tr["kept"] != "switch"]
    assert kept, "no move kept: the cycle was chosen so that its switches ring"
    for tr in kept:
        r = tr["stretch_returns"]
        assert tr["rang"] and r[tr["kept"]] > r["switch"] and r[tr["kept"]] == max(r.values())
    for course, costs in ((s.setpoints_n, s.costs), (np.full(120, s.best_constant_n), s.constant_costs)):
        alone = D.CycleRun(cycle, [course[0]])
        for k in range(alone.steps):
            alone.step(np.array([course[k]]))
            alone.advance()
        assert alone.costs(0).as_dict() == costs.as_dict()


def test_a_dense_log_is_refused_and_a_diverged_run_is_scored_once():
    """Rows closer than one control interval cannot all reach the kernel: refused, naming what to
    do. A run that has diverged is not scored again (the env's episode ends at its termination)."""
    with pytest.raises(ValueError, match="at least one control interval"):
        D.Cycle((0.0, 0.001, 1.0), (10000.0, 10000.0, 12000.0), (0.0, 0.0, 0.0))
    cycle = D.Cycle((0.0, 0.2), (20000.0, 20000.0), (0.0, 0.0))
    run = D.CycleRun(cycle, [1000.0])
    run.failed[0] = True                       # as if the first interval had diverged
    for _ in range(run.steps):
        run.step(np.array([1000.0]))
        run.advance()
    assert not run.rewards.any() and run.costs(0).terminated


@pytest.mark.slow
def test_on_the_shipped_example_the_schedule_costs_no_more_than_the_best_constant(tmp_path):
    out = tmp_path / "s.csv"
    assert cli.main(["schedule", "--duty", str(D.EXAMPLE_CYCLE), "--out", str(out), "--json", str(tmp_path / "s.json"),
                     "-q"]) == 0
    res = json.loads((tmp_path / "s.json").read_text())
    assert res["schedule"]["return"] >= res["best_constant"]["return"]
    assert out.with_suffix(".png").exists() and len(out.read_text().splitlines()) == 1 + 3000
