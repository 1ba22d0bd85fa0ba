"""The env's parts on their own: reward, sensor, scenario distribution, actuator, swapping them,
and the spec round trip."""

import dataclasses
import math

import gymnasium as gym
import numpy as np
import pytest

import bearing_gym  # noqa: F401
from bearing_gym.analysis.signals import QPI_THRESHOLD
from bearing_gym.envs import (EPISODE_STEPS, FEATURE_NAMES, BearingPreloadEnv, FixedScenario, ObservationModel,
                              PreloadActuator, Scenario, ScenarioDistribution, StepMeasurement,
                              VibrationFirstReward)
from bearing_gym.envs.contact import N_CONTACT
from bearing_gym.envs.features import F_MEAN_X, F_NS_RMS, F_QPI, F_RMS_X, N_FEATURES
from bearing_gym.envs.kernel import operating_point
from bearing_gym.envs.tiers import TIERS, tier_is_deterministic

RPM = math.pi / 30.0


def meas(qpi=0.01, ns_um=0.1, preload=1000.0, before=None, rpm=20000.0, radial=0.0,
         terminated=False, steps_left=10, rms_um=(5.0, 5.0, 1.0), life_used_per_s=1e-7):
    """A one-env StepMeasurement with the given features (everything else plausible)."""
    f = np.zeros((1, N_FEATURES))
    f[0, F_QPI] = qpi
    f[0, F_NS_RMS] = ns_um * 1e-6
    f[0, F_RMS_X:F_RMS_X + 3] = np.array(rms_um) * 1e-6
    f[0, F_MEAN_X:F_MEAN_X + 3] = (10e-6, 0.0, -40e-6)
    a = lambda v: np.array([float(v)])  # noqa: E731
    return StepMeasurement(features=f, preload_n=a(preload), preload_before_n=a(preload if before is None else before),
                           setpoint_n=a(preload), shaft_speed_rad_s=a(rpm * RPM), radial_load_n=a(radial),
                           kinematic_cage_speed_rad_s=a(0.44 * rpm * RPM), t_s=a(0.1),
                           steps_left=np.array([steps_left]), terminated=np.array([terminated]),
                           contact=np.zeros((1, N_CONTACT)), life_used_per_s=a(life_used_per_s),
                           friction_torque_n_m=a(0.05))


# --- reward -----------------------------------------------------------------------------------
def test_reward_terms_follow_their_physical_laws():
    r = VibrationFirstReward()
    u_ref = r.reference_life_used_per_s
    # heat ~ P^1.33 n (Palmgren, f_1 ~ (P_0/C_0)^0.33): doubling the speed doubles it, doubling
    # the preload multiplies it by 2^1.33 = 2.51
    h1, f1 = r.secondary_costs(800.0, 12000 * RPM, 0.1 * u_ref)
    h2, f2 = r.secondary_costs(1600.0, 12000 * RPM, 0.3 * u_ref)
    h3, _ = r.secondary_costs(800.0, 24000 * RPM, 0.0)
    assert h2 == pytest.approx(2 ** 1.33 * h1, rel=1e-12) and h3 == pytest.approx(2 * h1, rel=1e-12)
    # fatigue is the fraction of the L10 life used per second, relative to the costliest corner's
    assert f1 == pytest.approx(0.1 * r.fatigue_share, rel=1e-12) and f2 == pytest.approx(3 * f1, rel=1e-12)
    # the costliest corner of the envelope: heat 0.5, fatigue's raw 0.5 meets its room 0.5 and
    # the smooth cap bends it to 0.45 + 0.05 / 2 (reward docstring): 0.975 in all
    hc, fc = r.secondary_costs(2000.0, 25000 * RPM, u_ref)
    assert hc + fc == pytest.approx(0.975, rel=1e-12)
    # beyond it (unbalance, vibration) heat + fatigue stay below 1 in the envelope but still
    # rank the life used; the cap leaves the fatigue alone where heat leaves room for it
    h3, f3 = r.secondary_costs(2000.0, 25000 * RPM, 3.0 * u_ref)
    h4, f4 = r.secondary_costs(2000.0, 25000 * RPM, 4.0 * u_ref)
    assert hc + fc < h3 + f3 < h4 + f4 < 1.0
    hl, fl = r.secondary_costs(300.0, 25000 * RPM, 1.2 * u_ref)
    assert fl == pytest.approx(1.2 * r.fatigue_share, rel=1e-12) and hl + fl < 1.0


def test_quasi_periodic_costs_more_than_any_periodic_preload_anywhere_in_the_envelope():
    r = VibrationFirstReward()
    worst_periodic = -min(r(meas(qpi=0.0, preload=2000.0, rpm=25000.0, radial=500.0, life_used_per_s=1.0))[0])
    best_qp = -max(r(meas(qpi=QPI_THRESHOLD * 1.01, ns_um=0.0, preload=300.0, rpm=10000.0))[0])
    assert best_qp > worst_periodic
    # amplitude ranks quasi-periodic states: 10 um more costs 1 more
    a = r(meas(qpi=0.8, ns_um=20.0))[0][0]
    b = r(meas(qpi=0.8, ns_um=30.0))[0][0]
    assert a - b == pytest.approx(1.0, rel=1e-12)
    # period-1 motion pays no vibration, whatever its non-synchronous rest
    assert r(meas(qpi=QPI_THRESHOLD, ns_um=3.0))[1]["vibration"][0] == 0.0


def test_termination_costs_at_least_the_worst_continuation():
    r = VibrationFirstReward()
    for steps_left in (0, 1, 75, EPISODE_STEPS):
        term = r(meas(terminated=True, steps_left=steps_left))[0][0]
        worst_step = min(r(meas(qpi=1.0, ns_um=1e4, preload=2000.0, before=300.0, rpm=25000.0, radial=500.0,
                                life_used_per_s=1.0))[0][0],
                         r(meas(qpi=1.0, ns_um=1e4, preload=300.0, before=2000.0, rpm=25000.0, radial=500.0,
                                life_used_per_s=1.0))[0][0])
        assert term <= worst_step * (steps_left + 1) * (1 - 1e-12)


def test_actuation_cost_is_proportional_to_the_preload_moved():
    r = VibrationFirstReward()
    full = r(meas(preload=2000.0, before=300.0))[1]["actuation"][0]
    assert full == pytest.approx(-r.actuation_weight, rel=1e-12)
    assert r(meas(preload=1000.0, before=1170.0))[1]["actuation"][0] == pytest.approx(full / 10, rel=1e-9)


# --- sensor -----------------------------------------------------------------------------------
def test_default_sensor_reads_the_features_in_their_scales():
    s = ObservationModel()
    m = meas(qpi=0.5, ns_um=12.0)
    obs = s(m, s.make_state(1), np.array([0]), [np.random.default_rng(0)])[0]
    assert obs.shape == (len(FEATURE_NAMES),)
    assert obs[FEATURE_NAMES.index("qpi")] == pytest.approx(0.5, rel=1e-6)
    assert obs[FEATURE_NAMES.index("nonsync_rms")] == pytest.approx(1.2, rel=1e-6)
    assert obs[FEATURE_NAMES.index("rms_x")] == pytest.approx(0.1, rel=1e-6)
    assert obs[FEATURE_NAMES.index("axial_offset")] == pytest.approx(-0.4, rel=1e-6)
    assert obs[FEATURE_NAMES.index("preload")] == pytest.approx(2 * 700 / 1700 - 1, rel=1e-6)


def test_field_sensor_errors_have_their_stated_size():
    s = TIERS["field"]["observation"]
    state = s.make_state(1)
    rng = np.random.default_rng(3)
    s.reset_state(state, 0, rng)
    r = state["runout_m"][0]
    assert 0.0 <= r <= s.runout_max_m and np.all(np.abs(state["offset_m"][0]) <= s.offset_bias_m)
    m = meas(qpi=0.0, ns_um=0.0, rms_um=(5.0, 5.0, 1.0))
    obs = s(m, state, np.array([0]), [rng])[0]
    sigma = s.displacement_noise_m
    assert obs[FEATURE_NAMES.index("nonsync_rms")] == pytest.approx(math.sqrt(3) * sigma / 10e-6, rel=1e-5)
    assert obs[FEATURE_NAMES.index("rms_z")] == pytest.approx(math.hypot(1e-6, sigma) / 50e-6, rel=1e-5)
    assert obs[FEATURE_NAMES.index("rms_x")] == pytest.approx(
        math.sqrt(25e-12 + sigma ** 2 + r ** 2 / 2) / 50e-6, rel=1e-5)
    assert obs[FEATURE_NAMES.index("cage_speed_ratio")] == 0.0       # no cage sensor
    assert 0.0 < obs[FEATURE_NAMES.index("qpi")] < 0.1               # noise alone: a small index


# --- scenarios and the kernel's schedule ------------------------------------------------------
def test_transient_tier_draws_several_events_both_ways_inside_the_window():
    dist = TIERS["transient"]["scenario"]
    episode_s = EPISODE_STEPS * 0.02
    ups = downs = 0
    for seed in range(60):
        sc = dist.sample(np.random.default_rng(seed), episode_s)
        times = [t for t, _ in sc.speed_profile[1::2]] + [t for t, _ in sc.radial_load_profile[1:]]
        assert len(times) == dist.events
        assert all(dist.event_window[0] * episode_s <= t <= dist.event_window[1] * episode_s for t in times)
        times.sort()
        assert all(b - a >= dist.min_event_spacing_s - 1e-12 for a, b in zip(times, times[1:]))
        for (_, v0), (_, v1) in zip(sc.speed_profile[0::2], sc.speed_profile[2::2]):
            assert abs(v1 - v0) >= dist.min_speed_change_rpm - 1e-9
            ups, downs = ups + (v1 > v0), downs + (v1 < v0)
        for (_, f0), (_, f1) in zip(sc.radial_load_profile, sc.radial_load_profile[1:]):
            assert abs(f1 - f0) >= dist.min_load_change_n - 1e-9
            ups, downs = ups + (f1 > f0), downs + (f1 < f0)
    assert ups > 20 and downs > 20


def test_kernel_schedule_follows_the_profiles():
    sc = Scenario(speed_profile=((0.0, 10000.0), (1.0, 10000.0), (1.5, 20000.0)),
                  radial_load_profile=((0.0, 100.0), (0.7, 400.0), (2.0, 0.0)), radial_load_angle_rad=0.0)
    row = sc.schedule_array()
    for t, rpm, load in ((0.0, 10000, 100), (0.69, 10000, 100), (0.7, 10000, 400), (1.25, 15000, 400),
                         (1.5, 20000, 400), (2.5, 20000, 0)):
        omega, fx, fy = operating_point(row, t)
        assert omega == pytest.approx(rpm * RPM, rel=1e-12) and fx == pytest.approx(load) and fy == 0.0


def test_scenario_validation_names_the_field():
    with pytest.raises(ValueError, match="times must start at 0"):
        Scenario(speed_profile=((0.5, 10000.0),))
    with pytest.raises(ValueError, match="speed_profile rpm"):
        Scenario(speed_profile=((0.0, 100.0),))
    with pytest.raises(ValueError, match="min_event_spacing_s"):
        ScenarioDistribution(events=2, min_event_spacing_s=0.1)


# --- swapping parts ---------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class HeatOnlyReward:
    """A user's reward: friction heat only (a test of the protocol, not a recommendation)."""

    term_names: tuple = ("heat",)

    def __call__(self, m):
        heat = -m.preload_n / 1000.0
        return heat, {"heat": heat}


class ZSensor:
    """A user's sensor: only the axial probe's RMS, in um."""

    space = gym.spaces.Box(-1e3, 1e3, shape=(1,), dtype=np.float32)

    def make_state(self, num_envs):
        return None

    def reset_state(self, state, i, rng):
        pass

    def __call__(self, m, state, env_ids, rngs):
        return (m.rms_m[:, 2:3] * 1e6).astype(np.float32)


def test_a_custom_reward_and_sensor_plug_in_without_editing_the_package():
    env = gym.make("BearingPreload-v0", tier="paper", reward=HeatOnlyReward(), observation=ZSensor())
    ref = gym.make("BearingPreload-v0", tier="paper")
    obs, _ = env.reset(seed=0)
    ref.reset(seed=0)
    assert obs.shape == (1,)
    action = np.array([PreloadActuator().action_for(1000.0)], np.float32)
    obs, r, _, _, info = env.step(action)
    ref_obs = ref.step(action)[0]
    assert r == pytest.approx(-info["preload_n"] / 1000.0) and set(k for k in info if k.startswith("reward_")) == {"reward_heat"}
    # the same motion seen by the default sensor (RMS z / 50 um)
    assert obs[0] == pytest.approx(ref_obs[FEATURE_NAMES.index("rms_z")] * 50.0, rel=1e-5)


def test_spec_json_round_trip_rebuilds_the_same_env():
    from gymnasium.envs.registration import EnvSpec
    env = gym.make("BearingPreload-v0", tier="stationary",
                   reward=VibrationFirstReward(amplitude_scale_um=5.0),
                   observation=ObservationModel(displacement_noise_m=1e-7),
                   scenario=ScenarioDistribution(speed_rpm=(12000.0, 14000.0), events=1))
    again = gym.make(EnvSpec.from_json(env.spec.to_json()))
    for name in ("reward_model", "observation_model", "scenario_dist", "actuator"):
        assert getattr(again.unwrapped, name) == getattr(env.unwrapped, name), name
    o1, _ = env.reset(seed=5)
    o2, _ = again.reset(seed=5)
    np.testing.assert_array_equal(o1, o2)
    assert 12000.0 <= again.unwrapped.scenario.initial_speed_rpm <= 14000.0


def test_spec_round_trip_with_a_fixed_scenario_and_params():
    from gymnasium.envs.registration import EnvSpec

    sc = Scenario(speed_profile=((0.0, 15000.0), (0.5, 15000.0), (0.7, 18000.0)), clearance_m=8e-6,
                  initial_preload_n=900.0)
    params = bearing_gym.envs.env_params(damping_ratio=0.03)
    env = gym.make("BearingPreload-v0", scenario=sc, params=params)
    again = gym.make(EnvSpec.from_json(env.spec.to_json()))
    assert again.unwrapped.scenario_dist.scenario == sc
    assert again.unwrapped.batch.base == params
    o1, _ = env.reset(seed=1)
    o2, _ = again.reset(seed=1)
    np.testing.assert_array_equal(o1, o2)


def test_every_tier_builds_and_the_default_is_the_transient_one():
    assert gym.make("BearingPreload-v0").unwrapped.tier == "transient"
    for tier in TIERS:
        env = BearingPreloadEnv(tier=tier)
        assert env.observation_space.shape == (len(FEATURE_NAMES),)
        obs, _ = env.reset(seed=11)
        for _ in range(3):
            obs, r, term, trunc, info = env.step(env.action_space.sample())
            assert env.observation_space.contains(obs) and np.isfinite(r) and not term
    # the field tier's sensor has no cage channel; the others do
    assert not TIERS["field"]["observation"].cage_speed_sensor and TIERS["transient"]["observation"].cage_speed_sensor


def _first_steps(tier: str, seed: int, steps: int = 3) -> tuple[np.ndarray, list[float]]:
    env = BearingPreloadEnv(tier=tier)
    obs, _ = env.reset(seed=seed)
    trace, rewards = [obs], []
    for _ in range(steps):
        obs, reward, *_ = env.step(np.array([0.2], dtype=np.float32))
        trace.append(obs)
        rewards.append(reward)
    return np.array(trace), rewards


@pytest.mark.parametrize("tier", ["paper", "transient", "field"])
def test_a_deterministic_tier_gives_every_seed_the_same_episode(tier):
    """tier_is_deterministic is a claim about the simulation: where it holds, two seeds give
    bit-identical observations and rewards under one action sequence; where it does not, the
    first observation already differs (another operating point or sensor error)."""
    a, b = _first_steps(tier, 11), _first_steps(tier, 12)
    same = np.array_equal(a[0], b[0]) and a[1] == b[1]
    assert tier_is_deterministic(tier) == (tier == "paper")
    assert same == tier_is_deterministic(tier)


def test_deterministic_parts_say_so():
    assert FixedScenario().deterministic and ObservationModel().deterministic
    assert not ScenarioDistribution().deterministic
    fixed = dict(speed_rpm=15000.0, clearance_m=5e-6, waviness_amplitude_m=0.0, eccentricity_m=1e-5,
                 initial_preload_n=(900.0, 900.0))
    assert ScenarioDistribution(radial_load_n=0.0, **fixed).deterministic
    # a fixed radial load still has a random direction (sample draws its angle)
    loaded = ScenarioDistribution(radial_load_n=(100.0, 100.0), **fixed)
    assert not loaded.deterministic
    a, b = (loaded.sample(np.random.default_rng(k), 3.0) for k in (1, 2))
    assert a.radial_load_angle_rad != b.radial_load_angle_rad
    assert not ScenarioDistribution(speed_rpm=15000.0, radial_load_n=100.0, clearance_m=5e-6, waviness_amplitude_m=0.0,
                                    eccentricity_m=1e-5, initial_preload_n=900.0, events=1).deterministic
    assert not ObservationModel(displacement_noise_m=1e-7).deterministic
    assert not ObservationModel(offset_drift_m_per_sqrt_s=1e-6).deterministic


# --- actuator ---------------------------------------------------------------------------------
def test_actuator_maps_actions_linearly_and_inverts():
    a = PreloadActuator()
    assert a.setpoint_n(np.array([-1.0, 0.0, 1.0])).tolist() == [300.0, 1150.0, 2000.0]
    for p in (300.0, 777.0, 2000.0):
        assert a.setpoint_n(a.action_for(p)) == pytest.approx(p, rel=1e-12)


def test_actuator_dynamics_are_a_rate_limited_first_order_lag():
    from bearing_gym.envs.actuator import actuator_update
    # small step: pure lag, 1 - exp(-h / tau) of the way
    assert actuator_update(1000.0, 1010.0, 1e-3, 0.02, 2e4) == pytest.approx(1000.0 + 10.0 * (1 - math.exp(-0.05)), rel=1e-12)
    # large step: the rate limit (20 kN/s x 1 ms = 20 N) binds, both ways
    assert actuator_update(1000.0, 2000.0, 1e-3, 0.02, 2e4) == pytest.approx(1020.0, rel=1e-12)
    assert actuator_update(1000.0, 300.0, 1e-3, 0.02, 2e4) == pytest.approx(980.0, rel=1e-12)
    # no lag: straight to the set-point (within the rate limit)
    assert actuator_update(1000.0, 1005.0, 1e-3, 0.0, 2e4) == 1005.0
