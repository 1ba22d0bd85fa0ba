"""The env's integrator (25 us, Newmark tolerance 1e-10 m) against a four times smaller step at
the library's tolerance: the bounds of issue 15's target 3, computed by
``benchmarks/bench_accuracy.py`` (checks 1 and 2; check 3, the reward map, is its full run)."""


import pytest

from benchmarks import bench_accuracy

from bearing_gym.task import ENV_DT_S, ENV_NEWMARK_TOL_M
from bearing_gym.envs import BearingPreloadEnv, env_params


def test_the_env_runs_its_integrator_and_env_params_keeps_it():
    base = BearingPreloadEnv(tier="paper").batch.base
    assert base.integrator.dt_s == ENV_DT_S and base.integrator.newmark_tol_m == ENV_NEWMARK_TOL_M
    p = env_params(shaft_speed_rpm=15000.0)
    assert p.integrator.dt_s == ENV_DT_S and p.shaft_speed_rpm == 15000.0
    # the control interval and the actuator update stay whole numbers of steps
    assert BearingPreloadEnv(tier="paper").control_dt_s == pytest.approx(0.02, rel=1e-12)


def test_critical_preload_within_5_n_of_a_quarter_step():
    res = bench_accuracy.check_critical_preload(bench_accuracy.integrators())
    assert res["difference_n"] <= 5.0, res


def test_steady_amplitudes_within_1_percent_of_a_quarter_step():
    res = bench_accuracy.check_amplitudes(bench_accuracy.integrators())
    assert res["max_relative_error"] <= 0.01, res
