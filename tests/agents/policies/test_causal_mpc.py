"""The causal MPC: it does not know the scenario's future (its decisions before an event are the
same with and without the event), its branches hold the present operating point, and its stored
set-points replay to its return bit for bit."""

import json

import numpy as np
import pytest

from bearing_gym.envs import BearingPreloadVectorEnv
from bearing_gym.envs.scenario import FixedScenario, Scenario
from bearing_gym.task import CONTROL_DT_S

from agents.policies.causal_mpc import CausalMPCSettings, plan_causal
from agents.protocol import TEST
from agents.references import causal_mpc_runs

SMALL = CausalMPCSettings(candidates_n=(600.0, 1200.0, 1800.0), horizon=4, replan_every=5)
STEPS = 40
EVENT_AT = 25                              # the interval at whose start the load step comes


def _scenario(load_step_n: float) -> FixedScenario:
    t = EVENT_AT * CONTROL_DT_S
    return FixedScenario(Scenario(speed_profile=((0.0, 20000.0),), radial_load_profile=((0.0, 0.0), (t, load_step_n)),
                                  clearance_m=4e-6, eccentricity_m=1e-5, initial_preload_n=1000.0))


def test_decisions_before_an_event_do_not_depend_on_it():
    """A load step of 0 N (no event) or 1500 N at interval 25: the same set-points up to it (the
    branches held the present load), bit for bit; the real episodes differ after it."""
    quiet = plan_causal("paper", TEST.start, STEPS, SMALL, env_kwargs={"scenario": _scenario(0.0)})
    loaded = plan_causal("paper", TEST.start, STEPS, SMALL, env_kwargs={"scenario": _scenario(1500.0)})
    assert np.array_equal(quiet.plan_n[:EVENT_AT], loaded.plan_n[:EVENT_AT])
    assert quiet.return_ != loaded.return_
    assert quiet.decisions == loaded.decisions == -(-STEPS // SMALL.replan_every)
    assert set(np.unique(quiet.plan_n)) <= set(SMALL.candidates_n)


def test_a_held_branch_keeps_the_present_speed_and_load():
    """Env 1, copied from env 0 mid-ramp and held: its speed and load stay at the values the
    schedule gives at the copy's time (the linear ramp's point), while env 0 follows the ramp."""
    ramp = FixedScenario(Scenario(speed_profile=((0.0, 15000.0), (0.4, 19000.0)),
                                  radial_load_profile=((0.0, 200.0), (0.3, 900.0)), eccentricity_m=1e-5))
    env = BearingPreloadVectorEnv(num_envs=2, scenario=ramp, max_episode_steps=None)
    env.reset(seed=[TEST.start] * 2)
    action = np.zeros(2)
    for _ in range(5):                                    # to t = 0.1 s
        env.step_some(action, np.array([0]))
    env.copy_env(0, [1])
    env.hold_operating_point([1])
    for _ in range(11):                                   # to t = 0.32 s (the load step is at 0.3 s)
        env.step(action)
    speed_rpm, load_n, _, _ = env.operating_points()
    assert speed_rpm[1] == pytest.approx(15000.0 + 4000.0 * 0.1 / 0.4, rel=1e-12)
    assert load_n[1] == pytest.approx(200.0, rel=1e-12)
    assert speed_rpm[0] > 17000.0 and load_n[0] == pytest.approx(900.0, rel=1e-12)
    with pytest.raises(ValueError, match="idx must be env indices"):
        env.hold_operating_point([2])


def test_stored_runs_replay_bit_for_bit_and_stale_ones_are_missing(tmp_path):
    seeds = [TEST.start]
    written = causal_mpc_runs.run("paper", seeds, SMALL, STEPS, data_dir=tmp_path)
    assert len(written) == 1 and causal_mpc_runs.missing("paper", 1, SMALL, STEPS, tmp_path) == []
    runs = causal_mpc_runs.load_runs("paper", 1, SMALL, STEPS, tmp_path)
    row = causal_mpc_runs.replay("paper", runs, STEPS)
    assert float(row.returns[0]) == runs[0].return_
    path = written[0]
    d = json.loads(path.read_text())
    d["kernel_hash"] = "0" * 16
    path.write_text(json.dumps(d))
    assert causal_mpc_runs.missing("paper", 1, SMALL, STEPS, tmp_path) == seeds
    with pytest.raises(ValueError, match="causal_mpc_runs --tier paper"):
        causal_mpc_runs.load_runs("paper", 1, SMALL, STEPS, tmp_path)


def test_settings_are_checked_and_fingerprinted():
    with pytest.raises(ValueError, match="horizon must be an integer >= 1"):
        CausalMPCSettings(horizon=0)
    with pytest.raises(ValueError, match="candidates_n"):
        CausalMPCSettings(candidates_n=())
    assert CausalMPCSettings().digest() != SMALL.digest() and len(SMALL.digest()) == 16
