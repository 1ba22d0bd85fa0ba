"""Protocol v2's hyperparameter search with optuna, on validation seeds only, resumable.

    python -m agents.training.tuning --algo sac --until 04:10          # trials until the budget or 04:10
    python -m agents.training.tuning --algo sac --status               # the trials so far
    python -m agents.training.tuning --algo sac --export               # agents/tuning/sac.json (+ the chosen yml)

One optuna study per algorithm (``protocol<V>-<algo>``) in an optuna storage (default
``sqlite:///agents/tuning/tuning.db``, committed with the trials as they land, so a search
resumes from a checkout on another machine; any RDB URL, so several processes or machines can work on one
study; sqlite for the processes of one machine, a server database - PostgreSQL, say - for
several machines), the budget of :mod:`agents.protocol` (``TUNING_*``: trials, steps, validation
episodes, pruner, sampler seed; the sampler reseeded with the trials done, so a resumed or
parallel process does not replay draws), the search spaces of :mod:`agents.training.search_spaces`. A trial trains
as a protocol run does (the shipped start bank, ``N_ENVS`` envs, VecNormalize), validates every
``VALIDATION_EVERY_STEPS`` env steps on ``TUNING_VALIDATION_EPISODES`` validation episodes and
reports the IQM of their normalised scores (0: the validation constant by protocol 2's rule,
``TUNING_VALIDATION_RULE``, 1: the hindsight constant,
the board's denominator floor: :func:`validation_score`); optuna's median pruner may stop it
there (never at its last validation). Its value: the mean of its last ``TUNING_LAST_VALIDATIONS``
scores. Its training seed: ``TUNING_TRAIN_SEED`` + its slot in the budget (:func:`trial_slot`)
x ``RUN_SEED_STRIDE``. The training env's reward normalisation uses the trial's gamma (as RL Zoo). A trial interrupted
(``--until`` stops starting trials, not a running one) is failed by optuna's heartbeat check
(the storage's ``heartbeat_interval``/``grace_period``) on the next start and its slot run again. ``--export`` writes every trial (parameters,
intermediate scores, value, state, wall time), the spaces and the budget to
``agents/tuning/<algo>.json`` and, once the budget's trials are done, the best trial's settings to
``agents/hyperparams/v2/<algo>.yml`` (RL Zoo's format).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS

from agents import protocol as P
from agents.paths import HYPERPARAMS_DIR, PACKAGE_DIR, runs_dir
from agents.training import search_spaces as S

__all__ = ["study_name", "validation_score", "trial_slot", "objective", "run", "export", "yaml_number", "main", "TUNING_DIR",
           "CHOSEN_DIR"]

#: the committed tuning logs and the chosen hyperparameters
TUNING_DIR = PACKAGE_DIR / "tuning"
CHOSEN_DIR = HYPERPARAMS_DIR / "v2"


def study_name(algo: str) -> str:
    return f"protocol{P.TUNING_PROTOCOL_VERSION}-{algo}"


def validation_score(returns: np.ndarray, r0: np.ndarray, r1: np.ndarray) -> float:
    """The IQM (25 % trimmed mean) of the normalised validation scores of one validation."""
    from scipy.stats import trim_mean

    from agents.leaderboard.scoring import normalised_scores
    return float(trim_mean(normalised_scores(returns, r0, r1), 0.25))


def _storage(url: str):
    import optuna
    if url.startswith("sqlite:///"):
        Path(url.removeprefix("sqlite:///")).parent.mkdir(parents=True, exist_ok=True)
    return optuna.storages.RDBStorage(url, heartbeat_interval=60, grace_period=300)


def _sampler(trials_so_far: int):
    """TPE, seeded by the trials the study already holds: a resumed or parallel process draws
    on, instead of replaying the seed's first draws."""
    import optuna
    return optuna.samplers.TPESampler(seed=P.TUNING_SAMPLER_SEED + trials_so_far, multivariate=True,
                                      n_startup_trials=P.TUNING_RANDOM_TRIALS)


def _study(algo: str, storage: str):
    import optuna
    study = optuna.create_study(
        study_name=study_name(algo), storage=_storage(storage), direction="maximize", load_if_exists=True,
        sampler=_sampler(0),
        pruner=optuna.pruners.MedianPruner(n_startup_trials=P.TUNING_STARTUP_TRIALS,
                                           n_warmup_steps=P.TUNING_PRUNE_AFTER_STEPS,
                                           interval_steps=P.VALIDATION_EVERY_STEPS))
    optuna.storages.fail_stale_trials(study)      # a killed process's trial: its heartbeat stopped
    return study


def trial_slot(trial) -> int:
    """The trial's place in the budget: the study's trials before it that did not fail (so a failed
    or interrupted trial's slot, and its training seed, go to the next one); ValueError past the
    budget (its seed would leave the block the protocol keeps for tuning)."""
    import optuna
    before = [t for t in trial.study.get_trials(deepcopy=False)
              if t.number < trial.number and t.state != optuna.trial.TrialState.FAIL]
    slot = len(before)
    if slot >= P.TUNING_TRIALS:
        raise ValueError(f"trial {trial.number} would be the {slot + 1}th of a budget of {P.TUNING_TRIALS}")
    return slot


def objective(trial, algo: str, steps: int, validation_episodes: int, tier: str = DEFAULT_TIER,
              threads: int | None = None, out_dir: Path | None = None,
              eval_every: int = P.VALIDATION_EVERY_STEPS, overrides: dict[str, Any] | None = None) -> float:
    """Train one trial of ``algo`` for ``steps`` env steps (module docstring); its value."""
    import importlib

    import optuna
    import torch
    from stable_baselines3.common.vec_env import VecNormalize

    from agents.evaluation.trained import ALGORITHM_CLASSES
    from agents.paths import start_bank_path
    from agents.references.store import load_choice
    from agents.training.callbacks import ValidationCallback
    from agents.training.setup import load_start_bank, make_env

    torch.set_num_threads(1)
    hp = {**S.sample(trial, algo), **(overrides or {})}           # overrides: tests' tiny sizes only
    module, cls_name = ALGORITHM_CLASSES[algo]
    cls = getattr(importlib.import_module(module), cls_name)
    seed = P.TUNING_TRAIN_SEED + (trial_slot(trial) if hasattr(trial, "study") else trial.number) * P.RUN_SEED_STRIDE
    bank_path = start_bank_path(tier)
    bank = load_start_bank(bank_path, tier, EPISODE_STEPS) if bank_path.exists() else None
    env = VecNormalize(make_env(S.N_ENVS, seed, EPISODE_STEPS, tier, threads, bank), norm_obs=True, norm_reward=True,
                       clip_obs=10.0, gamma=hp["gamma"])          # the return it normalises by: the trial's gamma
    eval_env = VecNormalize(make_env(validation_episodes, P.VALIDATION.start, EPISODE_STEPS, tier, threads),
                            norm_obs=True, norm_reward=False, training=False)
    seeds = list(range(P.VALIDATION.start, P.VALIDATION.start + validation_episodes))
    choice = load_choice(tier)
    r0, r1 = choice.validation_references(seeds, choice.preload_for_rule(P.TUNING_VALIDATION_RULE))
    out = Path(out_dir or runs_dir("tuning", study_name(algo), f"trial_{trial.number}"))
    scores: list[float] = []

    class Reporting(ValidationCallback):
        pruned = False

        def _on_step(self) -> bool:
            before = len(self.per_seed_returns)
            keep_going = super()._on_step()
            if len(self.per_seed_returns) > before:            # a validation just ended
                scores.append(validation_score(np.asarray(self.per_seed_returns[-1]), r0, r1))
                trial.report(scores[-1], int(self.num_timesteps))
                trial.set_user_attr("scores", scores)
                if self.num_timesteps < steps and trial.should_prune():     # never at the budget's end
                    self.pruned = True
                    return False
            return keep_going

    policy = "MlpLstmPolicy" if algo == "ppo_lstm" else "MlpPolicy"
    model = cls(policy, env, seed=seed, device="cpu", verbose=0, **hp)
    callback = Reporting(eval_env, validation_seed=P.VALIDATION.start, best_model_save_path=str(out),
                         log_path=str(out), n_eval_episodes=validation_episodes, verbose=0,
                         eval_freq=max(1, eval_every // S.N_ENVS), deterministic=True)
    t0 = time.time()
    model.learn(total_timesteps=steps, callback=callback, progress_bar=False)
    trial.set_user_attr("wall_s", time.time() - t0)
    trial.set_user_attr("seed", seed)
    if callback.pruned:
        raise optuna.TrialPruned(f"pruned at {model.num_timesteps} steps (score {scores[-1]:.3f})")
    if not scores:
        raise RuntimeError(f"trial {trial.number}: no validation in {steps} steps")
    return float(np.mean(scores[-P.TUNING_LAST_VALIDATIONS:]))


def _finished(study, running: bool = False) -> int:
    """Trials complete or pruned (and running, with ``running``: what parallel workers have taken)."""
    import optuna
    states = (optuna.trial.TrialState.COMPLETE, optuna.trial.TrialState.PRUNED) + \
        ((optuna.trial.TrialState.RUNNING,) if running else ())
    return sum(t.state in states for t in study.get_trials(deepcopy=False))


def run(algo: str, storage: str, until: float | None = None, trials: int = P.TUNING_TRIALS,
        steps: int = P.TUNING_STEPS, validation_episodes: int = P.TUNING_VALIDATION_EPISODES,
        threads: int | None = None, estimate_s: float | None = None, **objective_kw: Any) -> int:
    """Run trials of ``algo``'s study until it has ``trials`` finished (complete or pruned) or
    the clock passes ``until`` (epoch seconds) - a trial is started only if ``estimate_s`` (default:
    the slowest finished trial's wall time, else none) fits before it; returns the trials run."""
    import optuna
    study = _study(algo, storage)
    ran = 0
    while _finished(study, running=True) < trials:
        walls = [t.user_attrs.get("wall_s", 0.0) for t in study.trials if "wall_s" in t.user_attrs]
        need = estimate_s if estimate_s is not None else (max(walls) if walls else 0.0)
        if until is not None and time.time() + need > until:
            print(f"{study_name(algo)}: the next trial (~{need / 60:.0f} min) would not end by the deadline: "
                  f"stopping with {_finished(study)}/{trials} done", flush=True)
            break
        study.sampler = _sampler(len(study.trials))
        mine: list = []                           # this process's trial (others may run beside it)
        study.optimize(lambda tr: objective(tr, algo, steps, validation_episodes, threads=threads, **objective_kw),
                       n_trials=1, catch=(), callbacks=[lambda _study, frozen: mine.append(frozen)])
        optuna.storages.fail_stale_trials(study)
        ran += 1
        last = mine[-1]
        print(f"{study_name(algo)}: trial {last.number} {last.state.name.lower()}, value {last.value}, "
              f"{last.user_attrs.get('wall_s', 0.0) / 60:.1f} min; {_finished(study)}/{trials} done", flush=True)
    return ran


def export(algo: str, storage: str, trials: int = P.TUNING_TRIALS, out_dir: Path = TUNING_DIR,
           chosen_dir: Path = CHOSEN_DIR) -> Path:
    """Write the study's trials to ``out_dir/<algo>.json`` and, when ``trials`` are finished, the
    best trial's settings to ``chosen_dir/<algo>.yml``."""
    import optuna
    study = optuna.load_study(study_name=study_name(algo), storage=_storage(storage))
    rows = [{"number": t.number, "state": t.state.name, "value": t.value, "params": t.params,
             "intermediate": {str(k): v for k, v in sorted(t.intermediate_values.items())},
             "user_attrs": t.user_attrs} for t in study.trials]
    budget = {k: getattr(P, k) for k in dir(P) if k.startswith("TUNING_")}
    out = Path(out_dir) / f"{algo}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"study": study_name(algo), "budget": budget, "search_space": S.describe(),
                               "trials": rows}, indent=1) + "\n")
    if _finished(study) >= trials:
        best = study.best_trial
        hp = S.sample(optuna.trial.FixedTrial(best.params), algo)
        _write_yml(Path(chosen_dir) / f"{algo}.yml", algo, hp, best)
    return out


def yaml_number(v: Any) -> str:
    """``v`` as YAML reads it back: a float's mantissa with a point (PyYAML reads ``1e-05`` as a
    string, ``1.0e-05`` as a float)."""
    r = repr(v)
    if isinstance(v, float) and "e" in r and "." not in r.split("e")[0]:
        r = r.replace("e", ".0e")
    return r


def _write_yml(path: Path, algo: str, hp: dict[str, Any], best) -> None:
    """``hp`` as an RL Zoo file (``policy_kwargs`` as RL Zoo's string)."""
    lines = [f"# Protocol v{P.TUNING_PROTOCOL_VERSION}'s {algo}: the best trial ({best.number}, value {best.value:.4f}) of "
             f"python -m agents.training.tuning --algo {algo}", f"# (agents/tuning/{algo}.json has every trial).",
             "BearingPreload-v0:", f"  n_timesteps: {P.V2_STEP_BUDGET_PER_RUN}",
             f"  policy: '{'MlpLstmPolicy' if algo == 'ppo_lstm' else 'MlpPolicy'}'", "  normalize: true",
             f"  n_envs: {S.N_ENVS}"]
    for k, v in hp.items():
        if k == "policy_kwargs":
            v = "dict(" + ", ".join(f"{kk}={vv!r}" for kk, vv in v.items()) + ")"
            lines.append(f'  policy_kwargs: "{v}"')
        else:
            lines.append(f"  {k}: {yaml_number(v)}")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m agents.training.tuning", description=__doc__.split("\n\n")[0])
    ap.add_argument("--algo", required=True, choices=S.ALGORITHMS)
    ap.add_argument("--storage", default=f"sqlite:///{TUNING_DIR / 'tuning.db'}",
                    help="optuna storage URL (several processes/machines may share one; default: the committed "
                         "sqlite file agents/tuning/tuning.db, so a search resumes on another machine from a checkout)")
    ap.add_argument("--until", metavar="HH:MM", help="start no trial that would not end by then (today, local time)")
    ap.add_argument("--threads", type=int, help="numba threads for the envs")
    ap.add_argument("--status", action="store_true", help="the trials so far; runs nothing")
    ap.add_argument("--export", action="store_true", help="write agents/tuning/<algo>.json (and the chosen yml)")
    a = ap.parse_args(argv)
    if a.status:
        import optuna
        for t in optuna.load_study(study_name=study_name(a.algo), storage=_storage(a.storage)).trials:
            where = ""
            if t.intermediate_values:                   # how far a trial got: its last validation
                step = max(t.intermediate_values)
                where = f" (at {step:,} of {P.TUNING_STEPS:,} steps: score {t.intermediate_values[step]:.3f})"
            print(f"trial {t.number:3d} {t.state.name:9s} value {t.value}{where} {t.params}")
        return 0
    if a.export:
        print(f"wrote {export(a.algo, a.storage)}")
        return 0
    until = None
    if a.until:
        hh, mm = (int(x) for x in a.until.split(":"))
        lt = time.localtime()
        until = time.mktime((lt.tm_year, lt.tm_mon, lt.tm_mday, hh, mm, 0, 0, 0, -1))
        if until <= time.time():                  # a time already past today: tomorrow's
            until += 24 * 3600
    run(a.algo, a.storage, until, threads=a.threads)
    export(a.algo, a.storage)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
