"""Protocol v2's search spaces: per algorithm, the hyperparameters optuna samples (the SB3 keyword
arguments of one trial) and what stays fixed. Fixed in a commit before any trial ran; RL Zoo's
spaces (``rl_zoo3/hyperparams_opt.py``) narrowed to what a 2-core budget can search, with the
discount factor and the update-to-data ratio searched for every algorithm (the protocol issue:
SAC's gamma 0.95 and 0.5 gradient steps per transition were set by hand).

Off-policy (SAC, TQC, CrossQ): gradient steps per environment transition (the update-to-data
ratio, UTD) in {0.25, 0.5, 1}, with one training call every ``TRAIN_FREQ`` steps of each of the
run's ``N_ENVS`` envs. On-policy (PPO, RecurrentPPO): rollout length, minibatch, epochs, GAE,
entropy bonus, clip range, initial log-std.
"""

from __future__ import annotations

from typing import Any

__all__ = ["ALGORITHMS", "N_ENVS", "TRAIN_FREQ", "sample", "describe"]

ALGORITHMS = ("sac", "tqc", "crossq", "ppo", "ppo_lstm")
#: envs per run (train.py --n-envs; the protocol's runs)
N_ENVS = 2
#: off-policy: a training call every this many steps of each env
TRAIN_FREQ = 8

GAMMAS = [0.95, 0.98, 0.99, 0.995]
NETS = {"64x64": [64, 64], "256x256": [256, 256]}
UTDS = [0.25, 0.5, 1.0]


def _off_policy(trial: Any, algo: str) -> dict[str, Any]:
    utd = trial.suggest_categorical("utd", UTDS)
    net = NETS[trial.suggest_categorical("net_arch", list(NETS))]
    hp: dict[str, Any] = {
        "learning_rate": trial.suggest_float("learning_rate", 1e-4, 2e-3, log=True),
        "gamma": trial.suggest_categorical("gamma", GAMMAS),
        "batch_size": trial.suggest_categorical("batch_size", [128, 256, 512]),
        "buffer_size": 300_000, "learning_starts": 1000, "train_freq": TRAIN_FREQ,
        "gradient_steps": max(1, int(round(utd * TRAIN_FREQ * N_ENVS))),
    }
    if algo in ("sac", "tqc"):
        hp["tau"] = trial.suggest_categorical("tau", [0.005, 0.02])
        hp["policy_kwargs"] = {"net_arch": net}
    if algo == "tqc":
        hp["top_quantiles_to_drop_per_net"] = trial.suggest_categorical("top_quantiles_to_drop_per_net", [0, 2, 5])
        hp["policy_kwargs"].update(n_quantiles=25, n_critics=2)
    if algo == "crossq":          # wide critics are CrossQ's design; the actor as the others'
        critic = trial.suggest_categorical("critic_width", [256, 1024])
        hp["policy_kwargs"] = {"net_arch": {"pi": net, "qf": [critic, critic]}}
    return hp


def _on_policy(trial: Any, algo: str) -> dict[str, Any]:
    net = NETS[trial.suggest_categorical("net_arch", list(NETS))]
    hp: dict[str, Any] = {
        "learning_rate": trial.suggest_float("learning_rate", 5e-5, 1e-3, log=True),
        "gamma": trial.suggest_categorical("gamma", GAMMAS),
        "gae_lambda": trial.suggest_categorical("gae_lambda", [0.9, 0.95, 0.98]),
        "n_steps": trial.suggest_categorical("n_steps", [128, 256, 512]),
        "batch_size": trial.suggest_categorical("batch_size", [64, 128, 256]),
        "n_epochs": trial.suggest_categorical("n_epochs", [5, 10, 20]),
        "ent_coef": trial.suggest_float("ent_coef", 1e-6, 1e-2, log=True),
        "clip_range": trial.suggest_categorical("clip_range", [0.1, 0.2, 0.3]),
        "policy_kwargs": {"net_arch": net,
                          "log_std_init": trial.suggest_categorical("log_std_init", [-2.0, -1.0, 0.0])},
    }
    if algo == "ppo_lstm":
        hp["policy_kwargs"]["lstm_hidden_size"] = trial.suggest_categorical("lstm_hidden_size", [64, 128])
    return hp


def sample(trial: Any, algo: str) -> dict[str, Any]:
    """One trial's SB3 keyword arguments for ``algo`` (``trial``: an optuna trial, or anything with
    its ``suggest_*`` methods)."""
    if algo not in ALGORITHMS:
        raise ValueError(f"no search space for {algo!r}: the protocol's are {', '.join(ALGORITHMS)}")
    return _off_policy(trial, algo) if algo in ("sac", "tqc", "crossq") else _on_policy(trial, algo)


def describe() -> dict[str, Any]:
    """The spaces as data (for the committed tuning logs)."""
    return {"gamma": GAMMAS, "net_arch": list(NETS), "utd (off-policy)": UTDS, "train_freq (off-policy)": TRAIN_FREQ,
            "n_envs": N_ENVS, "learning_rate": {"off-policy": [1e-4, 2e-3, "log"], "on-policy": [5e-5, 1e-3, "log"]},
            "batch_size": {"off-policy": [128, 256, 512], "on-policy": [64, 128, 256]},
            "tau (sac, tqc)": [0.005, 0.02], "top_quantiles_to_drop_per_net (tqc)": [0, 2, 5],
            "critic_width (crossq)": [256, 1024], "gae_lambda": [0.9, 0.95, 0.98], "n_steps": [128, 256, 512],
            "n_epochs": [5, 10, 20], "ent_coef": [1e-6, 1e-2, "log"], "clip_range": [0.1, 0.2, 0.3],
            "log_std_init": [-2.0, -1.0, 0.0], "lstm_hidden_size (ppo_lstm)": [64, 128]}
