"""Protocol v2's hyperparameter search: a tiny study runs its trials through the protocol's
training (validation on validation seeds, scores against the stored validation references),
resumes to its budget, prunes, and exports every trial and the chosen RL Zoo file."""

import json

import numpy as np
import optuna
import pytest
import yaml

from agents import protocol as P
from agents.training import search_spaces as S
from agents.training import tuning

TINY = dict(steps=300, validation_episodes=2, eval_every=100,
            overrides={"buffer_size": 2000, "learning_starts": 100, "batch_size": 32})


def always_pruning():
    """A fixed SAC trial whose pruner always says stop."""
    class Pruning(optuna.trial.FixedTrial):
        def should_prune(self) -> bool:
            return True
    return Pruning({"utd": 0.25, "net_arch": "64x64", "learning_rate": 3e-4, "gamma": 0.95, "batch_size": 128,
                    "tau": 0.02})


def test_a_tiny_study_runs_to_its_budget_and_exports_every_trial(tmp_path, monkeypatch):
    monkeypatch.setattr(tuning, "runs_dir", lambda *p: tmp_path.joinpath("runs", *p))
    storage = f"sqlite:///{tmp_path / 'tuning.db'}"
    assert tuning.run("sac", storage, trials=2, **TINY) == 2
    assert tuning.run("sac", storage, trials=2, **TINY) == 0                  # resumed: the budget is done
    first = json.loads(tuning.export("sac", storage, trials=2, out_dir=tmp_path / "t0", chosen_dir=tmp_path / "c0")
                       .read_text())["trials"]
    assert first[0]["params"] != first[1]["params"]
    out = tuning.export("sac", storage, trials=2, out_dir=tmp_path / "tuning", chosen_dir=tmp_path / "v2")
    data = json.loads(out.read_text())
    assert data["study"] == f"protocol{P.TUNING_PROTOCOL_VERSION}-sac" and data["budget"]["TUNING_TRIALS"] == P.TUNING_TRIALS
    assert [t["state"] for t in data["trials"]] == ["COMPLETE", "COMPLETE"]
    for t in data["trials"]:
        scores = t["user_attrs"]["scores"]
        assert [int(k) for k in t["intermediate"]] == [100, 200, 300] and len(scores) == 3
        assert t["value"] == pytest.approx(np.mean(scores[-P.TUNING_LAST_VALIDATIONS:]))
        assert t["user_attrs"]["seed"] == P.TUNING_TRAIN_SEED + t["number"] * P.RUN_SEED_STRIDE
    best = max(data["trials"], key=lambda t: t["value"])
    chosen = yaml.safe_load((tmp_path / "v2" / "sac.yml").read_text())["BearingPreload-v0"]
    expect = S.sample(optuna.trial.FixedTrial(best["params"]), "sac")
    assert eval(chosen.pop("policy_kwargs"), {"dict": dict}) == expect.pop("policy_kwargs")
    assert {k: chosen[k] for k in expect} == expect and chosen["n_timesteps"] == P.V2_STEP_BUDGET_PER_RUN


def test_a_trial_below_the_median_is_pruned_at_its_validation(tmp_path):
    trial = always_pruning()
    with pytest.raises(optuna.TrialPruned, match="pruned at 100 steps"):
        tuning.objective(trial, "sac", out_dir=tmp_path, **TINY)


def test_a_resumed_study_draws_on_instead_of_replaying_its_first_trials(tmp_path, monkeypatch):
    monkeypatch.setattr(tuning, "runs_dir", lambda *p: tmp_path.joinpath("runs", *p))
    storage = f"sqlite:///{tmp_path / 'tuning.db'}"
    tuning.run("ppo", storage, trials=1, **{**TINY, "steps": 100, "overrides": {"n_steps": 64, "batch_size": 64}})
    tuning.run("ppo", storage, trials=2, **{**TINY, "steps": 100, "overrides": {"n_steps": 64, "batch_size": 64}})
    study = optuna.load_study(study_name=tuning.study_name("ppo"), storage=storage)
    a, b = study.trials
    assert a.params != b.params and b.user_attrs["seed"] == P.TUNING_TRAIN_SEED + P.RUN_SEED_STRIDE


def test_a_trial_is_not_pruned_at_its_last_validation(tmp_path):
    trial = always_pruning()
    value = tuning.objective(trial, "sac", out_dir=tmp_path, **{**TINY, "steps": 100})
    assert np.isfinite(value)


def test_the_chosen_file_writes_floats_that_yaml_reads_as_floats():
    for v in (1e-05, 5e-05, 0.0003, 2.5e-4, 1234.5):
        assert yaml.safe_load(tuning.yaml_number(v)) == v


def test_the_validation_score_is_the_iqm_of_the_normalised_scores():
    r0, r1 = np.zeros(8), np.full(8, 10.0)
    returns = np.array([-30.0, 0, 1, 2, 3, 4, 5, 40])                     # scores -3, 0, .1, ..., .5, 4
    assert tuning.validation_score(returns, r0, r1) == pytest.approx(np.mean([0.1, 0.2, 0.3, 0.4]))


@pytest.mark.parametrize("algo,params,expect", [
    ("sac", {"utd": 0.5, "net_arch": "256x256", "learning_rate": 1e-3, "gamma": 0.99, "batch_size": 256,
             "tau": 0.005}, {"gradient_steps": 8, "train_freq": 8, "policy_kwargs": {"net_arch": [256, 256]}}),
    ("crossq", {"utd": 1.0, "net_arch": "64x64", "learning_rate": 1e-3, "gamma": 0.99, "batch_size": 256,
                "critic_width": 1024}, {"gradient_steps": 16,
                                        "policy_kwargs": {"net_arch": {"pi": [64, 64], "qf": [1024, 1024]}}}),
    ("ppo_lstm", {"net_arch": "64x64", "learning_rate": 3e-4, "gamma": 0.98, "gae_lambda": 0.95, "n_steps": 256,
                  "batch_size": 64, "n_epochs": 10, "ent_coef": 1e-4, "clip_range": 0.2, "log_std_init": -1.0,
                  "lstm_hidden_size": 128},
     {"policy_kwargs": {"net_arch": [64, 64], "log_std_init": -1.0, "lstm_hidden_size": 128}}),
])
def test_the_search_space_maps_a_trials_parameters_to_sb3_arguments(algo, params, expect):
    hp = S.sample(optuna.trial.FixedTrial(params), algo)
    assert {k: hp[k] for k in expect} == expect and hp["gamma"] == params["gamma"]
    with pytest.raises(ValueError, match="no search space"):
        S.sample(optuna.trial.FixedTrial(params), "dqn")
