"""The scoring API scores any policy exactly as the board does, and says what is wrong with a policy.

The board's row for a policy is computed by the board itself (:func:`agents.leaderboard.board.run_tier`
with the stored references, on the first test episodes) and compared with the API's row field by
field: the same actions must give the same numbers, bit for bit (the env is deterministic and
the statistics seeded). Bootstrap replications are reduced for time, equally on both sides.
"""

import dataclasses

import numpy as np
import pytest

from agents.leaderboard import board as leaderboard
from agents.leaderboard.settings import FULL
from agents.submit import CallablePolicy, as_policies, score

REPS = dict(bootstrap_reps=500, poi_reps=100)
#: the row's fields that depend on what the policy did (the board's learned row has more metadata)
NUMBERS = ("normalised_score_iqm", "ci_low", "ci_high", "normalised_score_mean", "above_one_fraction",
           "probability_of_improvement", "poi_ci_low", "poi_ci_high", "poi_over", "mean_return",
           "quasi_periodic_fraction", "vibration_amplitude_um", "vibration_cost", "heat_cost", "fatigue_cost",
           "mean_preload_n", "terminated_episodes", "episode_returns", "n_seeds", "n_episodes")
#: (tier, test episodes) for the comparisons: the deterministic tier's one episode, and a random tier's first few
CASES = [("paper", 1), ("transient", 3)]


def qp_rule(obs: np.ndarray) -> np.ndarray:
    """Raise the set-point while the interval is quasi-periodic, else ease it down (a NumPy rule)."""
    return np.clip(obs[:, 10] + np.where(obs[:, 8] > 0.1, 0.2, -0.02), -1.0, 1.0)


def board_row(tier: str, episodes: int, policies: list, name: str = "rule") -> dict:
    from agents.references.store import load_references
    group = leaderboard.LearnedGroup(name, "rule", tier, list(policies), [None] * len(policies),
                                     [None] * len(policies))
    s = dataclasses.replace(FULL, episodes=episodes, **REPS)
    t = leaderboard.run_tier(tier, s, [group], stored=load_references(tier), progress=False)
    return t["policies"][name]


@pytest.mark.parametrize("tier,episodes", CASES)
def test_a_numpy_policy_scores_as_the_board_scores_it_bit_for_bit(tier, episodes):
    api = score(qp_rule, tier=tier, episodes=episodes, progress=False, **REPS)
    board = board_row(tier, episodes, [CallablePolicy(qp_rule)])
    for key in NUMBERS:
        assert api.row[key] == board[key], key
    assert api.row["kind"] == "submitted" and api.row["n_runs"] == 1
    assert api.seeds == tuple(range(300_000, 300_000 + episodes))


def test_several_training_seeds_are_rows_of_runs_and_the_shipped_sac_scores_its_board_returns():
    """A list is one run per training seed; a train.py directory (here the shipped SAC) is loaded as
    the board loads it, so its returns are the board row's."""
    from agents.evaluation.trained import PRETRAINED_DIR, load_trained
    sac = PRETRAINED_DIR / "sac"
    api = score([sac, qp_rule], tier="transient", episodes=2, progress=False, **REPS)
    board = board_row("transient", 2, [load_trained(sac, portable=True), CallablePolicy(qp_rule)])
    assert api.row["n_seeds"] == 2 and api.row["episode_returns"] == board["episode_returns"]
    assert api.row["normalised_score_iqm"] == board["normalised_score_iqm"]


def test_a_function_of_one_observation_gives_the_batched_functions_actions():
    one = as_policies(lambda o: np.clip(o[10] + 0.1, -1, 1), batched=False)[0]
    batch = as_policies(lambda o: np.clip(o[:, 10] + 0.1, -1, 1))[0]
    obs = np.random.default_rng(0).uniform(-1, 1, (5, 15)).astype(np.float32)
    assert np.array_equal(one.predict(obs)[0], batch.predict(obs)[0])
    assert one.predict(obs)[0].shape == (5, 1) and one.predict(obs)[0].dtype == np.float32


@pytest.mark.parametrize("fn,match", [
    (lambda o: np.zeros(1), "batched=False"),                      # one action for a batch of 4
    (lambda o: np.full(len(o), 1.5), "action 1.5 .* \\[-1, 1\\]"),
    (lambda o: np.full(len(o), np.nan), "finite"),
    (lambda o: "fast", "not numbers"),
])
def test_a_wrong_policy_output_is_refused_naming_the_policy(fn, match):
    pol = as_policies(fn, name="mine")[0]
    with pytest.raises(ValueError, match=match) as err:
        pol.predict(np.zeros((4, 15), np.float32))
    assert "'mine'" in str(err.value)


def test_bad_arguments_are_refused_by_name():
    with pytest.raises(ValueError, match="tier must be one of"):
        score(qp_rule, tier="hard")
    with pytest.raises(ValueError, match=r"episodes must be a whole number in \[1, 100\]"):
        score(qp_rule, tier="transient", episodes=101)
    with pytest.raises(ValueError, match="variant must be one of"):
        score(qp_rule, tier="paper", variant="safe")
    with pytest.raises(ValueError, match="no policy to score"):
        score([], tier="paper")
    with pytest.raises(FileNotFoundError, match="no model.zip"):
        score("no/such/run", tier="paper")


def test_fewer_episodes_than_the_protocol_are_marked(tmp_path):
    api = score(qp_rule, tier="transient", episodes=2, progress=False, **REPS)
    assert not api.protocol_sized and "2 test episodes" in api.row["protocol_deviations"][0]
    text = api.markdown()
    assert "**Not the protocol:**" in text and "| submitted policy |" in text and "validation constant (" in text


def test_a_predict_object_is_checked_and_an_rllib_object_is_recognised():
    from agents.submit.adapters import as_policy
    from agents.submit.rllib import RLlibPolicy

    class Wild:
        def predict(self, obs, state=None, episode_start=None, deterministic=True):
            return np.full((len(obs), 1), 2.0), state
    with pytest.raises(ValueError, match="action 2.0"):
        as_policy(Wild(), "wild").predict(np.zeros((2, 15), np.float32))

    class Module:                                # RLlib's RLModule interface, duck-typed
        def forward_inference(self, batch):
            raise AssertionError("not run here")
    class Algorithm:
        def get_module(self):
            return Module()
    assert isinstance(as_policy(Module()), RLlibPolicy) and isinstance(as_policy(Algorithm()), RLlibPolicy)
    with pytest.raises(TypeError, match="RLlib Algorithm or RLModule"):
        RLlibPolicy(object())


def test_an_sb3_model_uses_its_observation_normalisation_only_where_it_normalises():
    pytest.importorskip("stable_baselines3", reason="an SB3 model needs the rl extra")
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    from agents.evaluation.trained import SB3Policy
    from agents.submit.adapters import as_policy
    from bearing_gym.envs import BearingPreloadEnv
    for norm_obs in (True, False):
        venv = VecNormalize(DummyVecEnv([lambda: BearingPreloadEnv(tier="paper")]), norm_obs=norm_obs)
        pol = as_policy(PPO("MlpPolicy", venv, n_steps=8, batch_size=8, seed=0))
        assert isinstance(pol, SB3Policy) and (pol.obs_rms is not None) == norm_obs


def test_a_time_aware_policy_sees_the_steps_of_its_episode():
    from agents.submit.adapters import TimeAwarePolicy
    seen = []
    pol = TimeAwarePolicy(lambda o: (seen.append(o[:, -1].copy()), np.zeros(len(o)))[1])
    obs = np.zeros((2, 15), np.float32)
    pol.predict(obs, episode_start=np.array([True, True]))
    pol.predict(obs, episode_start=np.array([False, False]))
    pol.predict(obs, episode_start=np.array([False, True]))
    assert [list(x) for x in seen] == [[0, 0], [1, 1], [2, 0]]


def test_a_single_observation_function_without_batched_false_is_told_so():
    with pytest.raises(IndexError, match="batched=False"):
        as_policies(lambda o: o[10] * 0.0)[0].predict(np.zeros((1, 15), np.float32))
