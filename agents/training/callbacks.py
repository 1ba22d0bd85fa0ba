"""Training callbacks: checkpoint selection on a fixed validation set.

SB3's ``EvalCallback`` evaluates on whatever scenarios its eval env draws next, so two
evaluations of the same policy see different scenarios and the "best model" it keeps is partly
the luck of the draw (on this env the scenario-to-scenario spread of the return is several
times the difference between two checkpoints). :class:`ValidationCallback` re-seeds the eval
env before every evaluation, so every checkpoint is scored on the *same* validation scenarios,
and saves the VecNormalize statistics beside the best model (the model alone cannot be
evaluated without the observation statistics it was trained with).

With one validation episode per eval env (train.py runs as many eval envs as validation
episodes), env i runs the scenario of seed ``validation_seed + i``; each evaluation's returns
are kept in that order (``log_path/validation_returns.npz``: ``timesteps``, ``seeds``,
``returns``), so a learning curve can score every episode against the references of its own
scenario (:mod:`agents.leaderboard.learning_curves`).

The validation seeds must differ from the held-out test seeds of ``agents.evaluation``
(``agents.protocol.TEST``, 300000 and up): choosing a checkpoint on the test scenarios would bias the test.
"""

from __future__ import annotations

import json
import shutil
import math
import time
from pathlib import Path

import numpy as np
from stable_baselines3.common.callbacks import BaseCallback, CheckpointCallback, EvalCallback, ProgressBarCallback


__all__ = ["ValidationCallback", "ResumePoints", "StopBefore", "checkpoint_steps", "restore_selection", "ProgressLines", "ProgressBar",
           "planned_timesteps", "BEST_MODEL", "BEST_VECNORMALIZE", "BEST_INFO"]

BEST_MODEL = "best_model.zip"
BEST_VECNORMALIZE = "best_vec_normalize.pkl"
BEST_INFO = "best.json"


class ValidationCallback(EvalCallback):
    """``EvalCallback`` on a fixed validation set.

    :param eval_env: the validation VecEnv (wrapped like the training env, VecNormalize with
        ``training=False``); it is re-seeded with ``validation_seed`` before each evaluation.
    :param validation_seed: seed of the validation scenarios (env i of the VecEnv gets
        ``validation_seed + i``; each env then runs its episodes one after the other).
    :param best_model_save_path: directory for ``best_model.zip``, ``best_vec_normalize.pkl`` and
        ``best.json`` (mean validation return and step count of the best checkpoint).
    :param progress_every_s: during an evaluation, print a line with the episodes done at most
        this often (None: only SB3's line at the end).
    :param resume: continue an earlier run: its ``best.json`` is read, so a later checkpoint must
        beat the earlier best, and the validation history in ``log_path/evaluations.npz`` is
        extended rather than overwritten. A new run (``False``) deletes an earlier run's best
        files, so that they cannot be selected as this run's.
    :param snapshot_at: env steps (a validation point) at which the best checkpoint so far is also
        copied to ``best_model_save_path/by_<steps>/`` (the run's row at that budget: the checkpoint
        validation selects among those up to it); None: no copy. A resumed run keeps a copy made
        by an earlier session.
    :param verbose: 1 (default) prints one line when a validation starts and one with its result
        (in the voice of train.py's progress lines; SB3's own ``Eval num_timesteps=...`` lines
        are not printed), 0 nothing.
    Other arguments as for ``EvalCallback``.
    """

    def __init__(self, eval_env, validation_seed: int, best_model_save_path: str, resume: bool = False,
                 progress_every_s: float | None = None, verbose: int = 1, snapshot_at: int | None = None, **kwargs):
        super().__init__(eval_env, best_model_save_path=best_model_save_path, verbose=0, **kwargs)
        self.snapshot_at = snapshot_at
        self.report = int(verbose)
        self.validation_seed = int(validation_seed)
        self.progress_every_s = progress_every_s
        self._val_t0 = self._val_last = 0.0
        self.best_dir = Path(best_model_save_path)
        info = self.best_dir / BEST_INFO
        if not resume:
            for name in (BEST_MODEL, BEST_VECNORMALIZE, BEST_INFO, "validation_returns.npz", "evaluations.npz"):
                (self.best_dir / name).unlink(missing_ok=True)
            if snapshot_at is not None:
                shutil.rmtree(self.snapshot_dir, ignore_errors=True)
        elif info.exists():
            self.best_mean_reward = float(json.loads(info.read_text())["mean_validation_return"])
        self._by_env: dict[int, float] = {}
        self.per_seed_timesteps: list[int] = []
        self.per_seed_returns: list[list[float]] = []
        per_seed = self._per_seed_path()
        if resume and per_seed is not None and per_seed.exists():
            with np.load(per_seed) as log:
                self.per_seed_timesteps = [int(t) for t in log["timesteps"]]
                self.per_seed_returns = [list(r) for r in log["returns"]]
        history = Path(f"{self.log_path}.npz") if self.log_path else None
        if resume and history is not None and history.exists():
            with np.load(history) as log:
                self.evaluations_timesteps = [int(t) for t in log["timesteps"]]
                self.evaluations_results = [list(r) for r in log["results"]]
                self.evaluations_length = [list(n) for n in log["ep_lengths"]]

    def _on_training_start(self) -> None:
        # a resumed run continues from its last checkpoint: drop validations made after it
        keep = [k for k, t in enumerate(self.per_seed_timesteps) if t <= self.model.num_timesteps]
        self.per_seed_timesteps = [self.per_seed_timesteps[k] for k in keep]
        self.per_seed_returns = [self.per_seed_returns[k] for k in keep]
        super()._on_training_start()

    def _on_step(self) -> bool:
        due = self.eval_freq > 0 and self.n_calls % self.eval_freq == 0
        if due:
            self.eval_env.seed(self.validation_seed)
            if self.report >= 1:
                print(f"validation at {self.num_timesteps:,} steps: {self.n_eval_episodes} episodes on the "
                      f"validation scenarios (seeds from {self.validation_seed})...", flush=True)
            self._val_t0 = self._val_last = time.monotonic()
        best_before = self.best_mean_reward
        keep_going = super()._on_step()
        if due:
            self._save_per_seed()
        if due and self.report >= 1:
            spread = ""
            if self.evaluations_results:          # kept by SB3 when there is a log_path
                last = np.asarray(self.evaluations_results[-1], dtype=float)
                spread = f" (sd {np.std(last):.1f})"
            print(f"validation at {self.num_timesteps:,} steps: mean return {self.last_mean_reward:.1f}{spread} "
                  f"over {self.n_eval_episodes} episodes, {time.monotonic() - self._val_t0:.0f} s"
                  + ("; the best so far: saved as the run's selected checkpoint"
                     if self.best_mean_reward > best_before else f"; the best stays {self.best_mean_reward:.1f}"),
                  flush=True)
        if due and self.best_mean_reward > best_before:
            vn = self.model.get_vec_normalize_env()
            if vn is not None:
                vn.save(str(self.best_dir / BEST_VECNORMALIZE))
            (self.best_dir / BEST_INFO).write_text(json.dumps(
                {"mean_validation_return": float(self.best_mean_reward),
                 "num_timesteps": int(self.num_timesteps),
                 "validation_seed": self.validation_seed,
                 "episodes": int(self.n_eval_episodes)}, indent=2))
        if due and self.snapshot_at is not None and self.num_timesteps >= self.snapshot_at \
                and not (self.snapshot_dir / BEST_INFO).exists():
            self.snapshot_dir.mkdir(parents=True, exist_ok=True)
            for name in (BEST_MODEL, BEST_VECNORMALIZE, BEST_INFO):
                if (self.best_dir / name).exists():
                    shutil.copyfile(self.best_dir / name, self.snapshot_dir / name)
            if self.report >= 1:
                print(f"the best checkpoint up to {self.snapshot_at:,} steps kept in {self.snapshot_dir}", flush=True)
        return keep_going

    @property
    def snapshot_dir(self) -> Path:
        return self.best_dir / f"by_{self.snapshot_at}"

    def _per_seed_path(self) -> Path | None:
        # log_path is "<dir>/evaluations" (SB3 appends .npz); the per-seed file goes beside it
        return Path(self.log_path).with_name("validation_returns.npz") if self.log_path else None

    def _save_per_seed(self) -> None:
        n = self.eval_env.num_envs
        if self.n_eval_episodes != n or len(self._by_env) != n:
            self._by_env = {}
            return                        # several episodes per env: no fixed seed per episode
        self.per_seed_timesteps.append(int(self.num_timesteps))
        self.per_seed_returns.append([self._by_env[i] for i in range(n)])
        self._by_env = {}
        path = self._per_seed_path()
        if path is not None:
            np.savez(path, timesteps=np.array(self.per_seed_timesteps),
                     seeds=self.validation_seed + np.arange(n), returns=np.array(self.per_seed_returns))

    def _log_success_callback(self, locals_, globals_) -> None:
        super()._log_success_callback(locals_, globals_)
        info = locals_["info"]
        if locals_["done"] and "episode" in info:
            self._by_env[int(locals_["i"])] = float(info["episode"]["r"])
        if self.progress_every_s is None:
            return
        now = time.monotonic()
        if now - self._val_last >= self.progress_every_s:
            self._val_last = now
            done = int(np.sum(locals_["episode_counts"]))
            print(f"validation: {done}/{self.n_eval_episodes} episodes done (the running ones at step "
                  f"{int(np.max(locals_['current_lengths']))}), {now - self._val_t0:.0f} s", flush=True)


def restore_selection(eval_dir: Path, checkpoint_dir: Path, resume_step: int, snapshot_at: int | None = None) -> None:
    """Make a run's validation record what it was at its checkpoint of ``resume_step``, before a
    resumed session continues from there: the validations made after it (by the stopped session,
    on a trajectory now discarded) are dropped from ``evaluations.npz`` and ``validation_returns.npz``;
    a selected checkpoint from after it is replaced by the best validation kept (the first on a
    tie, as :class:`ValidationCallback` selects), restored from its checkpoint files
    (``model_<steps>_steps.zip`` and its VecNormalize statistics: train.py checkpoints at every
    validation by default, so each has them; RuntimeError if they are gone); an early-row copy
    (``by_<snapshot_at>``) made after ``resume_step`` is removed, to be made again."""
    eval_dir, checkpoint_dir = Path(eval_dir), Path(checkpoint_dir)
    history = eval_dir / "evaluations.npz"
    means: list[tuple[int, float]] = []
    if history.exists():
        with np.load(history) as log:
            data = {k: log[k] for k in log.files}
        keep = data["timesteps"] <= resume_step
        np.savez(history, **{k: v[keep] for k, v in data.items()})
        means = [(int(t), float(np.mean(r))) for t, r in zip(data["timesteps"][keep], data["results"][keep])]
    per_seed = eval_dir / "validation_returns.npz"
    if per_seed.exists():
        with np.load(per_seed) as log:
            data = {k: log[k] for k in log.files}
        keep = data["timesteps"] <= resume_step
        np.savez(per_seed, timesteps=data["timesteps"][keep], seeds=data["seeds"], returns=data["returns"][keep])
    if snapshot_at is not None and resume_step < snapshot_at:
        shutil.rmtree(eval_dir / f"by_{snapshot_at}", ignore_errors=True)
    info_path = eval_dir / BEST_INFO
    if not info_path.exists():
        return
    info = json.loads(info_path.read_text())
    if info["num_timesteps"] <= resume_step:
        return
    for name in (BEST_MODEL, BEST_VECNORMALIZE, BEST_INFO):
        (eval_dir / name).unlink(missing_ok=True)
    if not means:
        return
    step, mean = means[int(np.argmax([m for _, m in means]))]
    model = checkpoint_dir / f"model_{step}_steps.zip"
    stats = checkpoint_dir / f"model_vecnormalize_{step}_steps.pkl"
    if not (model.exists() and stats.exists()):
        raise RuntimeError(f"resuming from {resume_step:,} steps: the selected checkpoint was validated after it, "
                           f"and the best validation kept ({step:,} steps) has no checkpoint in {checkpoint_dir} to "
                           "restore it from; train the run afresh (without --resume), with --checkpoint-freq equal to "
                           "--eval-freq (the default)")
    shutil.copyfile(model, eval_dir / BEST_MODEL)
    shutil.copyfile(stats, eval_dir / BEST_VECNORMALIZE)
    info.update(mean_validation_return=mean, num_timesteps=step)
    info_path.write_text(json.dumps(info, indent=2))
    print(f"resuming from {resume_step:,} steps: the selected checkpoint restored to {step:,} steps (validation "
          f"return {mean:.1f}); the later validations were on the discarded trajectory", flush=True)


def checkpoint_steps(path: Path) -> int:
    """The env steps of a CheckpointCallback file (``model_<steps>_steps.zip``,
    ``model_replay_buffer_<steps>_steps.pkl``, ...)."""
    return int(Path(path).stem.split("_")[-2])


class ResumePoints(CheckpointCallback):
    """SB3's ``CheckpointCallback`` that keeps only the newest replay buffer (each is the whole
    buffer, tens of MB late in a run; a resume needs the newest) beside every model checkpoint (small;
    kept, so that :func:`restore_selection` can restore any validated checkpoint)."""

    def _on_step(self) -> bool:
        keep_going = super()._on_step()
        if self.save_replay_buffer and self.n_calls % self.save_freq == 0:
            buffers = sorted(Path(self.save_path).glob(f"{self.name_prefix}_replay_buffer_*_steps.pkl"),
                             key=checkpoint_steps)
            for old in buffers[:-1]:
                old.unlink(missing_ok=True)
        return keep_going


class StopBefore(BaseCallback):
    """Pause a run at a resume point when the next one would not be saved before ``deadline``.

    Placed after :class:`ResumePoints` (the same ``every``: calls of ``on_step`` between resume
    points, so it acts on the call at which one was just saved): there it measures the wall time of
    the interval that ended (training and validation), and stops the training if the next
    interval, as long again times ``margin``, would end after ``deadline``. The run then stands
    exactly at its newest checkpoint (model, VecNormalize statistics, replay buffer), which
    ``train.py --resume`` continues. ``paused`` says whether it stopped the training.

    :param deadline: wall-clock time (``time.time()``) by which the run must have stopped.
    :param every: ``on_step`` calls between resume points (ResumePoints' ``save_freq``).
    :param margin: the next interval is budgeted at ``margin`` times the last one.
    """

    def __init__(self, deadline: float, every: int, margin: float = 1.25):
        super().__init__()
        if every < 1:
            raise ValueError(f"every must be >= 1 on_step call, got {every}")
        if margin < 1.0:
            raise ValueError(f"margin must be >= 1 (the next interval budgeted at least as long as the last), got {margin}")
        self.deadline, self.every, self.margin = float(deadline), int(every), float(margin)
        self.paused = False

    def _on_training_start(self) -> None:
        self.last = time.time()

    def _on_step(self) -> bool:
        if self.n_calls % self.every:
            return True
        now = time.time()
        interval, self.last = now - self.last, now
        if now + self.margin * interval > self.deadline:
            self.paused = True
            print(f"pausing at {self.num_timesteps:,} steps: the next resume point (about {interval / 60:.1f} min "
                  "away) would not be saved before the deadline; --resume continues from here", flush=True)
            return False
        return True


def planned_timesteps(model, total_timesteps: int) -> int:
    """The step count at which ``model.learn(total_timesteps)`` will stop, counted like
    ``num_timesteps`` (SB3 stops at the first whole rollout at or past the target: PPO collects
    ``n_steps`` steps per env per rollout, SAC ``train_freq`` steps per env)."""
    n_envs = model.n_envs
    if hasattr(model, "n_steps"):                                  # on-policy (PPO, A2C)
        chunk = model.n_steps * n_envs
    else:                                                         # off-policy (SAC, TD3, DQN)
        freq = getattr(model, "train_freq", None)
        unit = getattr(getattr(freq, "unit", None), "value", "step")
        chunk = freq.frequency * n_envs if freq is not None and unit == "step" else n_envs
    return int(math.ceil(total_timesteps / chunk) * chunk)


class ProgressLines(BaseCallback):
    """Training progress as plain lines (steps, rate, elapsed, time left), at most one every
    ``every_s`` seconds and one at the end: unlike a progress bar, they read well in a log file.

    :param end: the ``num_timesteps`` at which the training will stop (see :func:`planned_timesteps`).
    """

    def __init__(self, end: int, every_s: float = 30.0, label: str = "training"):
        super().__init__()
        self.end, self.every_s, self.label = int(end), float(every_s), label

    def _on_training_start(self) -> None:
        self.t0 = self.last = time.monotonic()
        self.start = int(self.model.num_timesteps)

    def _line(self) -> str:
        done = int(self.num_timesteps)
        el = time.monotonic() - self.t0
        rate = (done - self.start) / el if el > 0 else 0.0
        text = (f"{self.label}: {done:,}/{self.end:,} steps ({100 * done / max(self.end, 1):.0f} %), "
                f"{rate:.0f} steps/s, {el / 60:.1f} min")
        if done < self.end and rate > 0:
            text += f", about {(self.end - done) / rate / 60:.1f} min left"
        return text

    def _on_step(self) -> bool:
        now = time.monotonic()
        if now - self.last >= self.every_s:
            self.last = now
            print(self._line(), flush=True)
        return True

    def _on_training_end(self) -> None:
        print(self._line(), flush=True)


class ProgressBar(ProgressBarCallback):
    """SB3's progress bar with the true total (SB3 sizes it to the requested steps, and the run
    overshoots to the end of its last rollout: 36,352/36,000)."""

    def __init__(self, end: int):
        super().__init__()
        self.end = int(end)

    def _on_training_start(self) -> None:
        from stable_baselines3.common.callbacks import tqdm
        self.pbar = tqdm(total=self.end - self.model.num_timesteps)

