"""BearingPreload-v0: API conformance, determinism, errors, robustness, golden trajectory."""

import pickle
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import bearing_gym  # noqa: F401  (registers the env)
from bearing_gym.envs import EPISODE_STEPS, BearingPreloadEnv, Scenario

GOLDEN = Path(__file__).resolve().parents[1] / "data" / "paper_golden.npz"


def golden_actions(n):
    """Preload set-points 1000 -> 700 -> 1400 N in steps (the golden trajectory's actions)."""
    env = BearingPreloadEnv(scenario="paper")
    seq = [1000.0] * 5 + [700.0] * 10 + [1400.0] * (n - 15)
    return np.array([[env.actuator.action_for(p)] for p in seq], dtype=np.float32)


def run(env, actions, seed):
    obs, info = env.reset(seed=seed)
    out_obs, out_rew, out_info = [obs], [], []
    for a in actions:
        obs, r, term, trunc, info = env.step(a)
        out_obs.append(obs)
        out_rew.append(r)
        out_info.append(info)
        if term or trunc:
            break
    return np.array(out_obs), np.array(out_rew), out_info


def test_gymnasium_env_checker():
    from gymnasium.utils.env_checker import check_env
    env = gym.make("BearingPreload-v0", scenario="paper")
    check_env(env.unwrapped, skip_render_check=True)


def test_sb3_env_checker():
    from stable_baselines3.common.env_checker import check_env
    check_env(BearingPreloadEnv(scenario="paper"), warn=True)


def test_make_by_module_path_and_spaces():
    env = gym.make("bearing_gym:BearingPreload-v0")
    assert env.spec.max_episode_steps == EPISODE_STEPS
    assert env.action_space == gym.spaces.Box(-1, 1, (1,), np.float32)
    assert env.observation_space.dtype == np.float32
    assert np.all(np.isfinite(env.observation_space.low)) and np.all(np.isfinite(env.observation_space.high))


def test_same_seed_identical_over_100_steps():
    rng = np.random.default_rng(3)
    actions = rng.uniform(-1, 1, size=(100, 1)).astype(np.float32)
    a = run(BearingPreloadEnv(), actions, seed=11)
    b = run(BearingPreloadEnv(), actions, seed=11)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    assert a[2] == b[2]
    c = run(BearingPreloadEnv(), actions[:5], seed=12)
    assert not np.array_equal(a[0][:6], c[0])      # another seed, another scenario


def test_pickle_round_trip_continues_identically():
    env = BearingPreloadEnv()
    env.reset(seed=5)
    for _ in range(3):
        env.step(np.array([0.2], dtype=np.float32))
    clone = pickle.loads(pickle.dumps(env))
    for a in (-0.5, 0.1, 0.9):
        o1, r1, *_ = env.step(np.array([a], dtype=np.float32))
        o2, r2, *_ = clone.step(np.array([a], dtype=np.float32))
        np.testing.assert_array_equal(o1, o2)
        assert r1 == r2


def test_golden_trajectory_of_the_paper_preset():
    data = np.load(GOLDEN)
    obs, rew, _ = run(BearingPreloadEnv(scenario="paper"), data["actions"], seed=0)
    # same machine: bit for bit; other CPUs/libm may differ in the last bits of periodic motion
    np.testing.assert_allclose(obs, data["observations"], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(rew, data["rewards"], rtol=1e-6, atol=1e-9)


def test_info_reports_each_reward_term():
    env = BearingPreloadEnv(scenario="paper")
    env.reset(seed=0)
    _, r, _, _, info = env.step(np.array([0.0], dtype=np.float32))
    terms = [info[k] for k in ("reward_vibration", "reward_heat", "reward_fatigue", "reward_actuation", "reward_termination")]
    assert r == pytest.approx(sum(terms), rel=1e-12)
    assert all(t <= 0 for t in terms)


@pytest.mark.parametrize("bad,match", [(np.array([np.nan], np.float32), "NaN"),
                                       (np.array([1.5], np.float32), "outside the action space"),
                                       (np.array([-1.01], np.float32), "outside the action space"),
                                       (np.array([0.1, 0.2], np.float32), r"one element \(shape \(1,\)"),
                                       (np.array([0.1, 0.2, 0.3], np.float32), r"one element \(shape \(1,\)")])
def test_bad_actions_raise(bad, match):
    env = BearingPreloadEnv(scenario="paper")
    env.reset(seed=0)
    with pytest.raises(ValueError, match=match) as err:
        env.step(bad)
    assert "batch" not in str(err.value) and "per env" not in str(err.value)    # the single env's words


@pytest.mark.parametrize("bad", ["0.5", None, b"1", {"a": 1}])
def test_actions_that_are_not_numbers_raise_type_error(bad):
    env = BearingPreloadEnv(scenario="paper")
    env.reset(seed=0)
    with pytest.raises(TypeError, match="action must be a number"):
        env.step(bad)


def test_unknown_reset_option_raises():
    env = BearingPreloadEnv()
    with pytest.raises(ValueError, match="preload_target"):
        env.reset(seed=0, options={"preload_target": 5})
    with pytest.raises(ValueError, match="clearance_m"):
        env.reset(seed=0, options={"clearance_m": -1.0})


def test_reset_options_pin_the_scenario():
    env = BearingPreloadEnv()
    _, info = env.reset(seed=0, options={"shaft_speed_rpm": 15000.0, "radial_load_n": 0.0,
                                         "clearance_m": 1e-5, "initial_preload_n": 1200.0})
    assert info["shaft_speed_rpm"] == pytest.approx(15000.0)
    assert info["preload_n"] == 1200.0 and env.scenario.clearance_m == 1e-5
    sc = Scenario(speed_profile=((0.0, 12000.0),))
    _, info = env.reset(options={"scenario": sc})
    assert env.scenario == sc


def test_bad_constructor_arguments():
    with pytest.raises(ValueError, match="scenario preset"):
        BearingPreloadEnv(scenario="moon")
    with pytest.raises(ValueError, match="unknown tier 'moon'"):
        BearingPreloadEnv(tier="moon")
    with pytest.raises(TypeError, match="reward must provide term_names"):
        BearingPreloadEnv(reward=object())
    with pytest.raises(ValueError, match="control_dt_s"):
        BearingPreloadEnv(control_dt_s=0.0)
    with pytest.raises(ValueError, match="render_mode"):
        BearingPreloadEnv(render_mode="ansi")


def test_integrator_failure_terminates_with_reason_and_finite_observation():
    params = bearing_gym.envs.env_params(divergence_limit_m=2e-5)
    env = BearingPreloadEnv(scenario="paper", params=params)
    env.reset(seed=0)
    for _ in range(20):
        obs, r, term, trunc, info = env.step(np.array([-1.0], dtype=np.float32))
        if term:
            break
    assert term and "diverged" in info["termination_reason"]
    assert np.all(np.isfinite(obs)) and np.isfinite(r)


def test_render_rgb_array():
    env = BearingPreloadEnv(scenario="paper", render_mode="rgb_array")
    env.reset(seed=0)
    for _ in range(3):
        env.step(np.array([0.0], dtype=np.float32))
    img = env.render()
    assert img.ndim == 3 and img.shape[2] == 3 and img.dtype == np.uint8 and img.std() > 0


def test_render_human_headless_writes_png_frames(tmp_path):
    env = gym.make("BearingPreload-v0", scenario="paper", render_mode="human",
                   render_dir=tmp_path / "frames")
    env.reset(seed=0)
    assert env.render() is None
    for _ in range(2):
        env.step(np.array([0.0], dtype=np.float32))
    frames = sorted(p.name for p in (tmp_path / "frames").iterdir())
    assert frames == ["frame_00000.png", "frame_00001.png", "frame_00002.png"]   # reset + 2 steps
    assert (tmp_path / "frames" / frames[-1]).read_bytes()[:4] == b"\x89PNG"
    env.close()


def test_render_human_updates_a_window_and_stops_when_it_is_closed(monkeypatch):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from bearing_gym.envs import rendering
    fig = plt.figure()                      # stands in for the interactive window
    monkeypatch.setattr(rendering, "open_window", lambda: fig)
    monkeypatch.setattr(plt, "pause", lambda s: None)
    env = BearingPreloadEnv(scenario="paper", render_mode="human")
    env.reset(seed=0)
    env.step(np.array([0.0], dtype=np.float32))
    assert len(fig.axes) == 3 and "quasi-periodicity index" in fig._suptitle.get_text()
    plt.close(fig)
    env.step(np.array([0.0], dtype=np.float32))           # no error, no new window
    assert env.human_render_target is None and env._window.state == "closed"
    env.close()


def test_timings_the_step_kernel_cannot_run_are_refused_not_rounded():
    """The kernel runs whole integrator steps per actuator update and whole updates per control
    interval: anything else is an error naming the parameter and the nearest valid values."""
    from bearing_gym.envs.actuator import PreloadActuator
    with pytest.raises(ValueError, match=r"control_dt_s = 0.0205 s must be a whole multiple of the actuator's "
                                         r"update_interval_s = 0.001 s.*0.02, 0.021"):
        BearingPreloadEnv(scenario="paper", control_dt_s=0.0205)
    with pytest.raises(ValueError, match=r"update_interval_s = 0.00101 s must be a whole multiple of the integrator step"):
        BearingPreloadEnv(scenario="paper", actuator=PreloadActuator(update_interval_s=1.01e-3))
    env = BearingPreloadEnv(scenario="paper", control_dt_s=0.015, actuator=PreloadActuator(update_interval_s=5e-4))
    assert env.control_dt_s == pytest.approx(0.015, rel=1e-12)


def test_an_actuator_whose_dynamics_the_kernel_cannot_run_is_refused():
    import dataclasses

    from bearing_gym.envs.actuator import PreloadActuator

    @dataclasses.dataclass(frozen=True)
    class ThreeParameterActuator(PreloadActuator):
        def as_array(self):
            return np.array([0.02, 2e4, 1.0])
    with pytest.raises(ValueError, match=r"as_array\(\) must be \[time_constant_s >= 0, slew_rate_n_per_s > 0\]"):
        BearingPreloadEnv(scenario="paper", actuator=ThreeParameterActuator())
