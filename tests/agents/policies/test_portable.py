"""The portable float64 path of the SB3 policies (agents/policies/portable.py) agrees with torch's
float32 actions to float32 precision, on observations recorded along an episode (with the
recurrent state carried and reset at an episode start). The SB3 files it is checked against:
the shipped policies that keep theirs (CrossQ, RecurrentPPO) and protocol 1's PPO and SAC runs
(protocol 2 ships PPO and SAC as portable exports alone). Its bit-identity across CPUs is
tests/portability's business (the probe runs the shipped RecurrentPPO through it)."""

import numpy as np
import pytest

from agents.evaluation.trained import PRETRAINED_DIR, load_trained
from agents.paths import TRAINED_DIR
from agents.policies.portable import PortablePolicy, export_arrays
from bearing_gym.envs import BearingPreloadEnv

#: actions are in [-1, 1]: float32's spacing near 1 is 1.2e-7; torch's float32 network rounds
#: every layer, so a few of those spacings apart is float32 precision, a wrong weight is not
TOLERANCE = 5e-7
#: SB3 model directories (model.zip, vec_normalize.pkl) of each architecture the portable path covers
SB3_DIRS = {"ppo": TRAINED_DIR / "ppo" / "seed_0", "sac": TRAINED_DIR / "sac" / "seed_0",
            "ppo_lstm": PRETRAINED_DIR / "ppo_lstm", "crossq": PRETRAINED_DIR / "crossq"}


def recorded(policy, steps: int = 40, seed: int = 300002):
    """(observations, episode_start flags) along an episode that ``policy`` drives, with a reset in
    the middle so a recurrent state must be cleared."""
    env = BearingPreloadEnv(tier="transient")
    obs_list, starts = [], []
    obs, _ = env.reset(seed=seed)
    state, start = None, True
    for k in range(steps):
        if k == steps // 2:
            obs, _ = env.reset(seed=seed + 1)
            start = True
        obs_list.append(obs)
        starts.append(start)
        a, state = policy.predict(obs[None], state=state, episode_start=np.array([start]))
        obs, *_ = env.step(a[0])
        start = False
    return np.array(obs_list), np.array(starts)


@pytest.mark.parametrize("algo", sorted(SB3_DIRS))
def test_portable_actions_match_torch_to_float32_precision(algo):
    assert (SB3_DIRS[algo] / "model.zip").exists()
    torch_policy = load_trained(SB3_DIRS[algo])
    portable = load_trained(SB3_DIRS[algo], portable=True)
    assert isinstance(portable, PortablePolicy) and portable.name == torch_policy.name
    observations, starts = recorded(torch_policy)
    st_t = st_p = None
    worst = 0.0
    actions = []
    for obs, start in zip(observations, starts):
        a_t, st_t = torch_policy.predict(obs[None], state=st_t, episode_start=np.array([start]))
        a_p, st_p = portable.predict(obs[None], state=st_p, episode_start=np.array([start]))
        assert a_p.dtype == np.float32 and a_p.shape == a_t.shape == (1, 1)
        worst = max(worst, float(np.max(np.abs(a_t - a_p))))
        actions.append(float(a_p[0, 0]))
    assert worst <= TOLERANCE, f"{algo}: portable action {worst:.3g} away from torch's"
    assert len(set(actions)) > 1            # the observations exercise the network


def test_the_exported_file_is_the_models_weights():
    sb3 = load_trained(PRETRAINED_DIR / "ppo_lstm")
    in_memory = PortablePolicy(export_arrays(sb3.model, sb3.obs_rms, sb3.clip_obs, sb3.epsilon))
    from_file = PortablePolicy.load(PRETRAINED_DIR / "ppo_lstm")
    obs, starts = recorded(from_file, steps=10)
    a, _ = in_memory.predict(obs[:1], episode_start=starts[:1])
    b, _ = from_file.predict(obs[:1], episode_start=starts[:1])
    np.testing.assert_array_equal(a, b)


def test_the_recurrent_state_resets_at_an_episode_start():
    pol = PortablePolicy.load(PRETRAINED_DIR / "ppo_lstm")
    obs, _ = recorded(pol, steps=6)
    fresh, _ = pol.predict(obs[3:4], state=None, episode_start=np.array([True]))
    _, state = pol.predict(obs[:1], episode_start=np.array([True]))
    _, state = pol.predict(obs[1:2], state=state, episode_start=np.array([False]))
    carried, _ = pol.predict(obs[3:4], state=state, episode_start=np.array([False]))
    reset, _ = pol.predict(obs[3:4], state=state, episode_start=np.array([True]))
    np.testing.assert_array_equal(reset, fresh)
    assert not np.array_equal(carried, fresh)       # the memory matters


def test_an_unsupported_policy_is_refused_by_name():
    class Fake:
        policy = type("CnnPolicy", (), {})()
    with pytest.raises(ValueError, match="no portable path for CnnPolicy"):
        export_arrays(Fake())


def test_an_export_of_other_model_files_is_not_used(tmp_path):
    import shutil

    from agents.evaluation.trained import export
    from agents.policies.portable import is_current
    d = tmp_path / "ppo"
    shutil.copytree(SB3_DIRS["ppo"], d)
    export(d)
    assert is_current(d)
    shutil.copy(SB3_DIRS["sac"] / "vec_normalize.pkl", d / "vec_normalize.pkl")   # another run's statistics
    assert not is_current(d)
    fresh = load_trained(d, portable=True)               # exported again from the files there now
    torch_policy = load_trained(d)
    obs, starts = recorded(torch_policy, steps=4)
    a, _ = fresh.predict(obs[:1])
    b, _ = torch_policy.predict(obs[:1])
    assert float(np.max(np.abs(a - b))) <= TOLERANCE


@pytest.mark.parametrize("algo", ["tqc", "crossq"])
def test_tqc_and_crossq_actors_are_portable(algo):
    """TQC's actor is SAC's; CrossQ's batch-renormalisation layers are folded into the linear layers
    at export. After a little training (CrossQ's running statistics move off their start), the
    portable actions match torch's to float32 precision (the folding reorders float64 sums, far
    below float32's spacing)."""
    import sb3_contrib
    from stable_baselines3.common.vec_env import DummyVecEnv
    cls = {"tqc": sb3_contrib.TQC, "crossq": sb3_contrib.CrossQ}[algo]
    env = DummyVecEnv([lambda: BearingPreloadEnv(tier="paper", episode_steps=40)])
    model = cls("MlpPolicy", env, seed=0, device="cpu", learning_starts=50, batch_size=32,
                policy_kwargs={"net_arch": [32, 32]})
    model.learn(200)
    if algo == "crossq":
        assert float(model.policy.actor.latent_pi[0].ra_mean.abs().sum()) > 0       # the statistics moved
    portable = PortablePolicy(export_arrays(model))
    obs = np.random.default_rng(0).uniform(-2, 2, (50, 15)).astype(np.float32)
    a_t, _ = model.predict(obs, deterministic=True)
    a_p, _ = portable.predict(obs)
    assert np.max(np.abs(a_t - a_p)) <= TOLERANCE and len(np.unique(a_p)) > 10


def test_auto_loads_portable_where_covered_and_torch_with_a_warning_elsewhere(tmp_path):
    """``portable="auto"`` (how the board, agents.submit, agents.evaluate and the watch load a
    model): a covered architecture comes back as the portable policy; one the portable path refuses
    (gSDE) comes back through torch, with a warning naming why; ``is_model_dir`` tells a model
    directory (model.zip, or a portable export alone) from an empty one."""
    import json

    from stable_baselines3 import PPO

    from agents.evaluation.trained import SB3Policy, is_model_dir
    assert isinstance(load_trained(SB3_DIRS["ppo"], portable="auto"), PortablePolicy)
    env = BearingPreloadEnv(tier="transient")
    d = tmp_path / "sde"
    d.mkdir()
    assert not is_model_dir(d)
    PPO("MlpPolicy", env, use_sde=True, n_steps=8, batch_size=8, seed=0, device="cpu").save(d / "model.zip")
    (d / "config.json").write_text(json.dumps({"algo": "ppo"}))
    assert is_model_dir(d)
    with pytest.warns(UserWarning, match="gSDE.*through torch"):
        policy = load_trained(d, portable="auto")
    assert isinstance(policy, SB3Policy)
    a, _ = policy.predict(env.reset(seed=1)[0][None])
    assert a.shape == (1, 1) and np.all(np.abs(a) <= 1.0)


def test_auto_raises_what_is_not_an_uncovered_architecture(tmp_path):
    """``portable="auto"`` falls back to torch only for an architecture the portable path does not
    cover: a broken export (an unknown policy kind) is reported as itself, not as a missing model.zip."""
    import shutil

    d = tmp_path / "sac"
    shutil.copytree(PRETRAINED_DIR / "sac", d)
    arrays = dict(np.load(d / "portable_policy.npz"))
    arrays["kind"] = np.array("mlp2")
    np.savez(d / "portable_policy.npz", **arrays)
    with pytest.raises(ValueError, match="unknown portable policy kind 'mlp2'"):
        load_trained(d, portable="auto")


def test_a_path_on_the_board_is_loaded_as_the_board_loads_it(tmp_path):
    """agents.submit's ``as_policy`` with a directory: the portable policy under the given name; a
    directory without a model: FileNotFoundError naming both files it looked for."""
    from agents.submit.adapters import as_policy
    pol = as_policy(PRETRAINED_DIR / "sac", name="my SAC")
    assert isinstance(pol, PortablePolicy) and pol.name == "my SAC"
    with pytest.raises(FileNotFoundError, match="no model.zip and no portable_policy.npz"):
        as_policy(tmp_path)
