"""Start banks: a reset from a bank's settled start is the same, bit for bit, as settling on the
fly; a bank made by another kernel is refused; its scenario part draws every start once before any
repeats."""

import json
from collections import OrderedDict

import numpy as np
import pytest

from bearing_gym.envs import BearingPreloadVectorEnv, core
from bearing_gym.envs import start_bank as SB

TIER = "transient"
SEEDS = (7, 8, 9)


@pytest.fixture
def clean_caches(monkeypatch):
    """No settled start remembered from other tests: the bank's or a fresh settle only."""
    monkeypatch.setattr(core, "_SETTLED", OrderedDict())
    monkeypatch.setattr(core, "_BANKED", {})


def _episode(venv, seeds, steps=3):
    obs, _ = venv.reset(seed=list(seeds))
    out = [obs.copy()]
    for _ in range(steps):
        obs, reward, *_ = venv.step(np.full(venv.num_envs, 0.2))
        out += [obs.copy(), reward.copy()]
    return out, np.concatenate([venv.batch.X.ravel(), venv.batch.V.ravel()])


def _bank_of_another_kernel(path):
    """A bank of SEEDS[0] saved at ``path`` as if kernel 0123456789abcdef had made it."""
    SB.build(TIER, SEEDS[:1]).save(path)
    with np.load(path) as f:
        meta = json.loads(str(f["meta"]))
        arrays = {k: f[k] for k in f.files if k != "meta"}
    meta["kernel_hash"] = "0123456789abcdef"
    np.savez_compressed(path, meta=np.array(json.dumps(meta)), **arrays)
    return path


def test_a_reset_from_the_bank_is_the_settle_bit_for_bit(tmp_path, clean_caches, monkeypatch):
    fresh, state = _episode(BearingPreloadVectorEnv(num_envs=3, tier=TIER, max_episode_steps=None), SEEDS)
    bank = SB.build(TIER, SEEDS, batch_envs=2)
    assert len(bank) == 3 and len(set(bank.digests)) == 3
    path = bank.save(tmp_path / "bank.npz")
    monkeypatch.setattr(core, "_SETTLED", OrderedDict())          # forget the settles above
    SB.load(path).install()

    def no_settle(self, todo):
        raise AssertionError(f"envs {todo} were settled although the bank holds their starts")
    monkeypatch.setattr(core.PreloadBatch, "_run_settle", no_settle)
    banked, banked_state = _episode(BearingPreloadVectorEnv(num_envs=3, tier=TIER, max_episode_steps=None), SEEDS)
    for a, b in zip(fresh, banked):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(state, banked_state)
    # the bank's scenarios are the tier's own for those seeds
    venv = BearingPreloadVectorEnv(num_envs=3, tier=TIER, max_episode_steps=None)
    venv.reset(seed=list(SEEDS))
    assert tuple(venv.batch.scenarios) == SB.load(path).scenarios


def test_a_bank_of_another_kernel_is_refused_with_the_rebuild_command(tmp_path, clean_caches):
    path = _bank_of_another_kernel(tmp_path / "bank.npz")
    with pytest.raises(ValueError, match="kernel 0123456789abcdef.*python -m bearing_gym.envs.start_bank --tier transient"):
        SB.load(path)


def test_bank_scenarios_draw_every_start_once_before_any_repeats(clean_caches):
    bank = SB.StartBank(TIER, (1, 2, 3), tuple(core.Scenario(initial_preload_n=p) for p in (500.0, 900.0, 1300.0)),
                        ("a", "b", "c"), {}, "x", {})
    part = SB.BankScenarios(bank)
    rng = np.random.default_rng(0)
    first = [part.sample(rng, 3.0).initial_preload_n for _ in range(3)]
    assert sorted(first) == [500.0, 900.0, 1300.0]
    second = [part.sample(rng, 3.0).initial_preload_n for _ in range(3)]
    assert sorted(second) == [500.0, 900.0, 1300.0]
    with pytest.raises(ValueError, match="cannot pin"):
        part.sample(rng, 3.0, {"clearance_m": 1e-5})
    # an env built with it draws the bank's scenarios
    venv = BearingPreloadVectorEnv(num_envs=2, tier=TIER, scenario=part, max_episode_steps=None)
    venv.reset(seed=[0, 1])
    assert all(sc in bank.scenarios for sc in venv.batch.scenarios)


# -- the shipped bank from gymnasium.make and the vector env ----------------------------------------
def test_the_shipped_bank_through_gym_make_draws_its_scenarios_and_never_settles(clean_caches, monkeypatch):
    """start_bank="shipped": every reset is a copy (no settle runs: the reset costs no simulated
    interval; its wall time in env steps is benchmarks/bench_reset.py's), the episode is the one
    the bank's scenario gives without the bank, bit for bit, and reset(seed=s) is reproducible."""
    import gymnasium as gym

    import bearing_gym  # noqa: F401
    bank = SB.load(SB.shipped_path(TIER))
    env = gym.make("BearingPreload-v0", start_bank="shipped")

    def no_settle(self, todo):
        raise AssertionError(f"envs {todo} were settled although the shipped bank holds their starts")
    with monkeypatch.context() as m:
        m.setattr(core.PreloadBatch, "_run_settle", no_settle)
        obs, info = env.reset(seed=11)
        again, _ = env.reset(seed=11)
        banked = [obs] + [env.step(np.array([0.3], np.float32))[0] for _ in range(2)]
    scenario = env.unwrapped.scenario
    assert scenario in bank.scenarios and info["cost"] == 0.0
    np.testing.assert_array_equal(obs, again)
    plain = gym.make("BearingPreload-v0")
    fresh = [plain.reset(seed=11, options={"scenario": scenario})[0]]
    fresh += [plain.step(np.array([0.3], np.float32))[0] for _ in range(2)]
    for a, b in zip(banked, fresh):
        np.testing.assert_array_equal(a, b)
    # the vector env takes it too
    venv = BearingPreloadVectorEnv(num_envs=2, start_bank="shipped", max_episode_steps=None)
    venv.reset(seed=3)
    assert all(sc in bank.scenarios for sc in venv.batch.scenarios)


def test_gymnasiums_env_checker_passes_with_the_shipped_bank():
    import gymnasium as gym
    from gymnasium.utils.env_checker import check_env

    import bearing_gym  # noqa: F401
    check_env(gym.make("BearingPreload-v0", start_bank="shipped").unwrapped, skip_render_check=True)


def test_a_bank_that_does_not_fit_the_env_is_refused_saying_why(tmp_path, clean_caches):
    import bearing_gym
    from bearing_gym.envs import BearingPreloadEnv
    path = SB.shipped_path(TIER)
    with pytest.raises(ValueError, match="holds tier 'transient' starts, this env is of tier 'stationary'"):
        BearingPreloadEnv(tier="stationary", start_bank=path)
    with pytest.raises(ValueError, match="150-step episodes, this env's have 50"):
        BearingPreloadEnv(episode_steps=50, start_bank=path)
    with pytest.raises(ValueError, match="other env settings"):
        BearingPreloadEnv(start_bank=path, params=bearing_gym.envs.env_params(divergence_limit_m=1e-4))
    with pytest.raises(FileNotFoundError, match="no bank ships for tier 'field' .*tiers with one: transient"):
        BearingPreloadEnv(tier="field", start_bank="shipped")
    with pytest.raises(ValueError, match="not both"):
        BearingPreloadEnv(start_bank="shipped", scenario="paper")
    with pytest.raises(TypeError, match="start_bank must be"):
        BearingPreloadEnv(start_bank=3)
    with pytest.raises(ValueError, match="cannot pin"):
        BearingPreloadEnv(start_bank="shipped").reset(seed=0, options={"clearance_m": 1e-5})
    stale = _bank_of_another_kernel(tmp_path / "bank.npz")
    with pytest.raises(ValueError, match="made by kernel 0123456789abcdef"):
        BearingPreloadEnv(start_bank=stale)
    in_memory = SB.load(path, check_kernel=False)
    import dataclasses
    with pytest.raises(ValueError, match="made by kernel 0123456789abcdef"):
        BearingPreloadEnv(start_bank=dataclasses.replace(in_memory, kernel_hash="0123456789abcdef"))
    assert BearingPreloadEnv(start_bank=in_memory).scenario_dist.bank is in_memory      # this kernel's: taken

