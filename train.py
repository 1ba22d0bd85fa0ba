"""Train a preload controller with Stable-Baselines3 (PPO, SAC) or sb3-contrib (TQC, CrossQ,
RecurrentPPO) and put it on the leaderboard.

    python train.py --timesteps 100000       # the main job: PPO with protocol v2's settings to 100k steps, then its board (README: time)
    python train.py                          # the protocol's whole run (300k steps under protocol 2)
    python train.py --algo sac --timesteps 200000 --n-envs 4 --seed 1 --out runs/sac
    python train.py --out runs/ppo --resume  # continue from the last checkpoint in runs/ppo

Writes to --out: model.zip, vec_normalize.pkl (observation/reward statistics, reloaded with
training=False for evaluation), config.json, checkpoints/ (resumable), tensorboard/ (if
tensorboard is installed), eval/ (validation: every --eval-freq steps the policy runs on the
same --val-episodes scenarios, one per eval env, seeds from --val-seed, distinct from the test
seeds; the best checkpoint and its VecNormalize statistics are kept there, and every
validation's per-episode returns in validation_returns.npz for the learning curves),
last_model.zip and last_vec_normalize.pkl (the final weights), and leaderboard.md/.json
(agents.training.after_training: this run, the shipped policies and every reference on the first
--eval-episodes test seeds, normalised scores). model.zip is the best validation checkpoint
(--select best, the default) or the final weights (--select last).

Training's settled starts come from the start bank shipped for the tier if there is one
(bearing_gym/data/start_bank_<tier>.npz, --start-bank auto): each reset then copies a settled state
(the same bits as settling it) instead of simulating 1.46 s, and training draws the bank's
scenarios, each once before any repeats (a run of the budget meets none twice; --resume keeps the
bank and continues its order). --start-bank none draws every start afresh and settles it, as
protocol 1's runs did (protocol 2's drew from the bank).

It reports as it goes, in plain lines that read the same in a terminal and in a log file
(``python train.py > train.log 2>&1``): whether the numba kernels are being compiled (a one-off),
training progress with the rate and the time left every 30 s (in a terminal without
--no-progress a progress bar instead), each validation, the evaluation's progress, and at the
end the leaderboard table and where the model, the table and the tensorboard logs are, with a
command to look at each.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from pathlib import Path

from agents.extras import require_extra

require_extra("train.py")        # the rl extra: SB3, sb3-contrib, torch (before any of them is imported)

from agents.paths import start_bank_path  # noqa: E402
from agents.training.setup import hyperparams, load_start_bank, make_env  # noqa: E402,F401 (train.<name> for tests)
from agents.training.callbacks import checkpoint_steps  # noqa: E402
from agents import protocol as P  # noqa: E402
from agents.protocol import PROTOCOL_VERSION, STEP_BUDGET_PER_RUN, TEST, VALIDATION, VALIDATION_EPISODES_IN_TRAINING, VALIDATION_EVERY_STEPS  # noqa: E402
from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES  # noqa: E402

PROGRESS_EVERY_S = 30.0     # at most one progress line per this many seconds
#: train.py's --algo: agents.evaluation.trained's algorithms (SB3's PPO and SAC, sb3-contrib's
#: RecurrentPPO, TQC and CrossQ), each with its RL Zoo file in agents/hyperparams/
ALGOS = ("ppo", "sac", "ppo_lstm", "tqc", "crossq")
OFF_POLICY = ("sac", "tqc", "crossq")


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description="Train PPO, SAC, TQC, CrossQ or RecurrentPPO on BearingPreload-v0 and put "
                                             "it on the leaderboard beside the shipped policies and the references.")
    ap.add_argument("--algo", choices=ALGOS, default="ppo",
                    help="ppo, sac (Stable-Baselines3), tqc, crossq or ppo_lstm (sb3-contrib's TQC, CrossQ and "
                         "RecurrentPPO; ppo_lstm is RL Zoo's name)")
    ap.add_argument("--protocol", type=int, choices=(1, 2), default=PROTOCOL_VERSION,
                    help="the protocol whose settings are the defaults (default %(default)s, the board's): 1: the "
                         f"hand-set hyperparameters of agents/hyperparams/, {STEP_BUDGET_PER_RUN:,} steps, "
                         f"{VALIDATION_EPISODES_IN_TRAINING} validation episodes; 2: the tuned ones of "
                         f"agents/hyperparams/v2/, {P.V2_STEP_BUDGET_PER_RUN:,} steps, {P.V2_VALIDATION_EPISODES_IN_TRAINING} "
                         f"validation episodes, the best checkpoint up to {P.V2_EARLY_ROW_STEPS:,} steps kept too "
                         "(eval/by_<steps>/), rewards normalised with the algorithm's discount")
    ap.add_argument("--timesteps", type=int, default=None,
                    help="total environment steps (control intervals; default: the protocol's budget per run); "
                         "with --resume, the run stops at this total")
    ap.add_argument("--n-envs", type=int, default=2, help="environments stepped together by the batched kernel")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=None,
                    help="numba threads stepping the environments (default: one per env, at most numba's threads: the cores, or NUMBA_NUM_THREADS); "
                         "the results do not depend on it")
    ap.add_argument("--out", default="runs/ppo", help="output directory")
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER,
                    help="difficulty tier of BearingPreload-v0 (default: the main benchmark, %(default)s)")
    ap.add_argument("--episode-steps", type=int, default=EPISODE_STEPS,
                    help="control intervals per episode (default %(default)d, the benchmark's horizon; "
                         "another value is announced as not the benchmark)")
    ap.add_argument("--eval-episodes", type=int, default=20, help="held-out episodes per policy at the end (0: skip)")
    ap.add_argument("--eval-freq", type=int, default=VALIDATION_EVERY_STEPS, help="validation period in environment steps")
    ap.add_argument("--val-episodes", type=int, default=None,
                    help="validation episodes per evaluation (the same scenarios each time, one per eval env; "
                         "default: the protocol's)")
    ap.add_argument("--val-seed", type=int, default=VALIDATION.start,
                    help=f"seed of the validation scenarios (agents.protocol: validation {VALIDATION.start}.., "
                         f"test {TEST.start}..)")
    ap.add_argument("--select", choices=("best", "last"), default="best",
                    help="model.zip = the best validation checkpoint or the final weights")
    ap.add_argument("--checkpoint-freq", type=int, default=None,
                    help="checkpoint period in environment steps (default: --eval-freq, so that every validated "
                         "checkpoint can be restored when a resumed run drops validations made after its checkpoint)")
    ap.add_argument("--resume", action="store_true", help="continue from the newest checkpoint in --out")
    ap.add_argument("--start-bank", metavar="NPZ|auto|none",
                    help="where training's settled starts come from. auto (default): the start bank shipped for "
                         "the tier (bearing_gym/data/start_bank_<tier>.npz) if there is one and this kernel made it, "
                         "else every start is settled; NPZ: that bank (python -m bearing_gym.envs.start_bank), "
                         "refused if it does not fit; none: settle every start. With a bank, training draws the "
                         "bank's scenarios (each once before any repeats) and each reset copies its settled start "
                         "instead of simulating 1.46 s; validation is unchanged. --resume keeps the run's choice")
    ap.add_argument("--until", metavar="HH:MM",
                    help="pause the run at its last resume point (checkpoint, VecNormalize statistics, replay buffer) "
                         "that can be saved before this time, at the pace of the run so far; config.json then says "
                         "paused, and --resume continues it (the run's sessions add up to one run of the budget)")
    ap.add_argument("--no-progress", action="store_true",
                    help="no progress bar: plain progress lines, as when the output is not a terminal")
    return ap


def choose_start_bank(option: str | None, tier: str, episode_steps: int):
    """The bank ``--start-bank`` names (``auto`` or None: the shipped one of the tier if it fits,
    else None, saying why; ``none``: None; a path: that bank, SystemExit if it does not fit), as a
    loaded :class:`bearing_gym.envs.start_bank.StartBank` with its ``path``."""
    if option == "none":
        return None
    if option not in (None, "auto"):
        try:
            return load_start_bank(option, tier, episode_steps)
        except ValueError as err:
            raise SystemExit(f"train.py: --start-bank: {err}") from None
    shipped = start_bank_path(tier)
    if not shipped.exists():
        print(f"start bank: none shipped for tier {tier}: every training start is settled (1.46 s simulated each)",
              flush=True)
        return None
    try:
        bank = load_start_bank(shipped, tier, episode_steps)
    except ValueError as err:
        print(f"start bank: the shipped one is not used ({err}); every training start is settled (1.46 s "
              "simulated each)", flush=True)
        return None
    print(f"start bank: {shipped} ({len(bank)} settled starts of tier {tier}): training draws its scenarios, each "
          "once before any repeats, and a reset copies the start instead of settling it (--start-bank none: "
          "fresh draws, each settled)", flush=True)
    return bank


def bank_draws_made(num_timesteps: int, n_envs: int, episode_steps: int) -> int:
    """How many scenarios a run's training envs had drawn after ``num_timesteps`` env steps, every
    episode running its ``episode_steps`` (the envs step in lockstep and reset as soon as an
    episode ends, so each env has drawn one more than it has finished)."""
    return n_envs * (num_timesteps // n_envs // episode_steps + 1)


BANK_RECORD = "start_bank.json"


def start_bank_for_run(args: argparse.Namespace, out: Path, resume_steps: int | None, n_val_envs: int):
    """The start bank of this run and how many of its draws earlier sessions made. A new run
    takes ``--start-bank`` (default auto) and records its choice in ``out/start_bank.json``; a
    resumed run (``resume_steps``: the env steps of its newest checkpoint) keeps the recorded choice (another
    ``--start-bank`` is refused) and skips the draws its checkpoint had made, so that it does not
    train on those scenarios again. Sets ``args.start_bank`` to the bank's path (None: no bank)
    for config.json."""
    record = out / BANK_RECORD
    before = json.loads(record.read_text()) if resume_steps is not None and record.exists() else None
    option = args.start_bank
    if before is not None and option is None:
        option = before["path"] or "none"
    bank = choose_start_bank(option, args.tier, args.episode_steps)
    path = None if bank is None else str(bank.path.resolve())
    if before is not None and path != before["path"]:
        raise SystemExit(f"train.py: --resume: this run trained with --start-bank {before['path'] or 'none'}, not "
                         f"{path or 'none'}; leave --start-bank out to continue it, or start a new run in another --out")
    if bank is not None:
        overlap = set(range(args.val_seed, args.val_seed + n_val_envs)) & set(bank.seeds)
        if overlap:
            raise SystemExit(f"train.py: the validation seeds {args.val_seed}..{args.val_seed + n_val_envs - 1} include "
                             f"{len(overlap)} of the start bank's training scenarios (seeds {bank.seeds[0]}.."
                             f"{bank.seeds[-1]}); pick another --val-seed")
        record.write_text(json.dumps({"path": path, "kernel_hash": bank.kernel_hash, "starts": len(bank),
                                      "seeds": [bank.seeds[0], bank.seeds[-1]]}, indent=2))
    else:
        record.write_text(json.dumps({"path": None}, indent=2))
    args.start_bank = path
    draws = 0
    if bank is not None and resume_steps is not None:
        draws = bank_draws_made(resume_steps, args.n_envs, args.episode_steps)
        print(f"start bank: resuming after {draws} of its {len(bank)} scenarios", flush=True)
    return bank, draws


def warm_up_kernels(n_envs: int) -> None:
    """Compile (or load from the cache) the numba kernels the environment uses, saying which,
    so that a first run does not sit silent for a minute."""
    import numpy as np

    import bearing_gym
    from bearing_gym.envs import BearingPreloadVectorEnv
    import hashlib

    from bearing_gym.envs import kernel as kernel_module
    cache = Path(bearing_gym.NUMBA_CACHE_DIR)
    kernel = "step_batch" if n_envs > 1 else "step_batch_serial"
    # numba files a module's cache under <dir name>_<sha1 of the dir's absolute path>: another
    # checkout's index files do not serve this one
    src_dir = Path(kernel_module.__file__).resolve().parent
    subdir = f"{src_dir.name}_{hashlib.sha1(str(src_dir).encode()).hexdigest()}"
    if any(cache.glob(f"**/{subdir}/kernel.{kernel}-*.nbi")):
        print(f"numba kernels: loading them from the cache {cache}", flush=True)
    else:
        print(f"numba kernels: compiling them (a one-off, about a minute on 2 cores; cached in {cache}, "
              "later runs start in seconds)...", flush=True)
    t = time.time()
    venv = BearingPreloadVectorEnv(num_envs=2 if n_envs > 1 else 1, episode_steps=2, max_episode_steps=2)
    venv.reset(seed=0)
    venv.step(np.zeros((venv.num_envs, 1), dtype=np.float32))
    venv.close()
    print(f"numba kernels: ready after {time.time() - t:.0f} s", flush=True)


def announce_outputs(out: Path, evaluated: bool, tensorboard_dir: Path | None) -> None:
    """Where the results are, and one command to look at each."""
    rows = [("model", out / "model.zip", f"bearing-gym-watch --model {out} --tier paper")]
    if evaluated and (out / "leaderboard.md").exists():
        rows += [("leaderboard", out / "leaderboard.md", f"cat {out / 'leaderboard.md'}   (numbers: leaderboard.json)"),
                 ("baseline report", out, f"python -m agents.evaluate --model {out}   (every scripted baseline, traces)")]
    elif evaluated:
        rows += [("evaluation table", out / "evaluation.md", f"cat {out / 'evaluation.md'}   (numbers: evaluation.csv)"),
                 ("trace figure", out / "evaluation_traces.png",
                  f"{'open' if sys.platform == 'darwin' else 'xdg-open'} {out / 'evaluation_traces.png'}")]
    if tensorboard_dir is not None and tensorboard_dir.exists():
        rows.append(("tensorboard logs", tensorboard_dir, f"tensorboard --logdir {tensorboard_dir}"))
    width = max(len(str(path)) for _, path, _ in rows)
    print(f"outputs in {out}/ (config.json: the settings and wall times):")
    for what, path, cmd in rows:
        print(f"  {what:<17} {str(path):<{width}}   {cmd}")


def protocol_defaults(args: argparse.Namespace) -> argparse.Namespace:
    """Fill the options left out with the chosen protocol's numbers (agents.protocol)."""
    v2 = args.protocol >= 2
    if args.timesteps is None:
        args.timesteps = P.V2_STEP_BUDGET_PER_RUN if v2 else STEP_BUDGET_PER_RUN
    if args.val_episodes is None:
        args.val_episodes = P.V2_VALIDATION_EPISODES_IN_TRAINING if v2 else VALIDATION_EPISODES_IN_TRAINING
    args.snapshot_at = P.V2_EARLY_ROW_STEPS if v2 and args.timesteps > P.V2_EARLY_ROW_STEPS else None
    if args.snapshot_at is not None and (args.snapshot_at % args.eval_freq or (args.eval_freq // max(args.n_envs, 1))
                                         * max(args.n_envs, 1) != args.eval_freq):
        raise SystemExit(f"train.py: protocol 2 keeps the best checkpoint up to {args.snapshot_at:,} steps, which must be "
                         f"a validation point: --eval-freq {args.eval_freq} must divide it and be a multiple of "
                         f"--n-envs {args.n_envs}")
    return args


def tensorboard_installed() -> bool:
    import importlib.util
    return importlib.util.find_spec("tensorboard") is not None


def earlier_wall_s(out: Path, resumed: bool) -> float:
    """The training wall time of a resumed run's earlier sessions (config.json of its last pause or
    end; 0 for a new run or when no session recorded one)."""
    cfg = out / "config.json"
    return json.loads(cfg.read_text()).get("train_wall_s", 0.0) if resumed and cfg.exists() else 0.0


def pause(out: Path, args: argparse.Namespace, model, t0: float, resumed: bool) -> int:
    """A run stopped by --until at its newest checkpoint: config.json records the pause (the steps
    done and the training wall time of every session so far), and no model.zip is written."""
    cfg = dict(vars(args), paused=True, num_timesteps=int(model.num_timesteps),
               train_wall_s=time.time() - t0 + earlier_wall_s(out, resumed))
    (out / "config.json").write_text(json.dumps(cfg, indent=2))
    print(f"paused at {model.num_timesteps:,} of {args.timesteps:,} steps after {cfg['train_wall_s'] / 60:.1f} min of "
          f"training; continue with the same command and --resume (--out {out})", flush=True)
    return 0


def main(argv: list[str] | None = None) -> int:
    args = protocol_defaults(build_parser().parse_args(argv))
    if args.timesteps < 1 or args.n_envs < 1:
        raise SystemExit("train.py: --timesteps and --n-envs must be >= 1")
    import numba
    if args.threads is not None and not 1 <= args.threads <= numba.config.NUMBA_NUM_THREADS:
        raise SystemExit(f"train.py: --threads must be in [1, {numba.config.NUMBA_NUM_THREADS}] (numba's threads, "
                         f"one per core unless NUMBA_NUM_THREADS says otherwise), got {args.threads}")
    if args.val_episodes < 1:
        raise SystemExit("train.py: --val-episodes must be >= 1")
    pause_by = None
    if args.until is not None:
        from agents.clock import deadline
        pause_by = deadline(args.until).timestamp()   # once, before any work (SystemExit on a malformed time)
    from agents.evaluation.episodes import TEST_SEED
    n_val_envs = args.val_episodes      # one episode per env: env i runs the scenario of val_seed + i
    if args.val_seed < TEST_SEED + max(args.eval_episodes, 1) and TEST_SEED < args.val_seed + n_val_envs:
        raise SystemExit(f"train.py: --val-seed {args.val_seed} overlaps the held-out test seeds "
                         f"{TEST_SEED}..{TEST_SEED + max(args.eval_episodes, 1) - 1}; pick another")
    import torch
    from stable_baselines3.common.callbacks import CallbackList
    from stable_baselines3.common.vec_env import VecNormalize

    from agents.training.callbacks import BEST_INFO, BEST_MODEL, BEST_VECNORMALIZE, ProgressBar, ProgressLines, ResumePoints, StopBefore, ValidationCallback, planned_timesteps, restore_selection

    torch.set_num_threads(1)          # the environment kernel uses the cores
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    import importlib

    from agents.evaluation.trained import ALGORITHM_CLASSES
    module, cls_name = ALGORITHM_CLASSES[args.algo]
    algo_cls = getattr(importlib.import_module(module), cls_name)
    policy = "MlpLstmPolicy" if args.algo == "ppo_lstm" else "MlpPolicy"
    off_policy = args.algo in OFF_POLICY   # its replay buffer is checkpointed too, so --resume continues it
    t0 = time.time()
    if args.tier != DEFAULT_TIER or args.episode_steps != EPISODE_STEPS:
        print(f"note: tier {args.tier}, {args.episode_steps}-step episodes: not the benchmark's definition "
              f"(tier {DEFAULT_TIER}, {EPISODE_STEPS} steps), results are not comparable with the leaderboard",
              flush=True)
    print(f"train.py: {args.algo.upper()} (protocol {args.protocol}) on BearingPreload-v0 (tier {args.tier}), {args.timesteps:,} steps on {args.n_envs} "
          f"envs (seed {args.seed}), then {args.eval_episodes} held-out evaluation episodes; output in {out}/",
          flush=True)
    warm_up_kernels(args.n_envs)

    ckpt_dir = out / "checkpoints"
    latest = sorted(ckpt_dir.glob("model_*_steps.zip"), key=checkpoint_steps) if ckpt_dir.exists() else []
    bank, draws_done = start_bank_for_run(args, out, checkpoint_steps(latest[-1]) if args.resume and latest else None,
                                          n_val_envs)
    env = make_env(args.n_envs, args.seed, args.episode_steps, args.tier, args.threads, bank, draws_done)
    eval_env = make_env(n_val_envs, args.val_seed, args.episode_steps, args.tier, args.threads)
    if args.resume and latest:
        last = latest[-1]
        steps = checkpoint_steps(last)
        restore_selection(out / "eval", ckpt_dir, steps, args.snapshot_at)
        env = VecNormalize.load(str(ckpt_dir / f"model_vecnormalize_{steps}_steps.pkl"), env)
        model = algo_cls.load(last, env=env, device="cpu")
        # the saved model names the tensorboard directory of the machine that trained it; here, this run's
        model.tensorboard_log = str(out / "tensorboard") if tensorboard_installed() else None
        print(f"resuming from {last} ({steps} steps)")
        if off_policy:
            buffer = ckpt_dir / f"model_replay_buffer_{steps}_steps.pkl"
            if buffer.exists():
                model.load_replay_buffer(buffer)
            else:
                # SB3 would train at once on a nearly empty buffer: refill it first
                model.learning_starts += model.num_timesteps
                print(f"no replay buffer {buffer.name}: collecting {model.learning_starts - model.num_timesteps} "
                      "steps before the first gradient step")
    else:
        if args.resume:
            print(f"no checkpoint in {ckpt_dir}: starting a new run")
        hp = hyperparams(args.algo, args.protocol)
        # the return it normalises rewards by: from protocol v2 on the algorithm's discount (as RL Zoo
        # does, and protocol v2's search); protocol v1's runs used SB3's default 0.99
        env = VecNormalize(env, norm_obs=True, norm_reward=True, clip_obs=10.0,
                           gamma=hp.get("gamma", 0.99) if args.protocol >= 2 else 0.99)
        model = algo_cls(policy, env, seed=args.seed, device="cpu", verbose=0,
                         tensorboard_log=str(out / "tensorboard") if tensorboard_installed() else None, **hp)
    tb_dir = Path(model.tensorboard_log) if model.tensorboard_log else None
    eval_env = VecNormalize(eval_env, norm_obs=True, norm_reward=False, training=False)
    per_env = max(1, args.n_envs)
    resumed = bool(args.resume and latest)
    callbacks = CallbackList([
        ValidationCallback(eval_env, validation_seed=args.val_seed, resume=resumed, n_eval_episodes=args.val_episodes,
                           progress_every_s=PROGRESS_EVERY_S, snapshot_at=args.snapshot_at,
                           eval_freq=max(1, args.eval_freq // per_env), best_model_save_path=str(out / "eval"),
                           log_path=str(out / "eval"), deterministic=True),
        ResumePoints(save_freq=max(1, (args.checkpoint_freq or args.eval_freq) // per_env), save_path=str(ckpt_dir),
                     name_prefix="model", save_vecnormalize=True, save_replay_buffer=off_policy),
    ])
    stop = None
    if pause_by is not None:
        stop = StopBefore(pause_by, every=max(1, (args.checkpoint_freq or args.eval_freq) // per_env))
        callbacks.callbacks.append(stop)
    # SB3 counts total_timesteps on top of num_timesteps when it does not reset them
    remaining = args.timesteps - model.num_timesteps if resumed else args.timesteps
    if remaining > 0:
        start = int(model.num_timesteps) if resumed else 0
        end = start + planned_timesteps(model, remaining)
        rounded = "" if end == args.timesteps else (
            f" (--timesteps {args.timesteps:,} rounded up to whole rollouts, as SB3 collects them)")
        bar = sys.stdout.isatty() and not args.no_progress
        print(f"training: {start:,} -> {end:,} steps{rounded}; validation every {args.eval_freq:,} steps "
              f"on {args.val_episodes} episodes; {'a progress bar' if bar else f'a line every {PROGRESS_EVERY_S:.0f} s'}",
              flush=True)
        callbacks.callbacks.append(ProgressBar(end) if bar else ProgressLines(end, every_s=PROGRESS_EVERY_S))
        model.learn(total_timesteps=remaining, callback=callbacks, progress_bar=False,
                    reset_num_timesteps=not resumed)
    else:
        print(f"{model.num_timesteps} steps already done (--timesteps {args.timesteps}): no training")
    if stop is not None and stop.paused and model.num_timesteps < args.timesteps:   # not at the budget's end
        return pause(out, args, model, t0, resumed)
    model.save(out / "last_model.zip")
    env.save(str(out / "last_vec_normalize.pkl"))
    best = out / "eval"
    if args.select == "best" and (best / BEST_MODEL).exists() and (best / BEST_VECNORMALIZE).exists():
        sources = (best / BEST_MODEL, best / BEST_VECNORMALIZE)
        info = json.loads((best / BEST_INFO).read_text())
        selected = dict(selected="best validation checkpoint", selected_timesteps=info["num_timesteps"],
                        selected_validation_return=info["mean_validation_return"])
    else:
        sources = (out / "last_model.zip", out / "last_vec_normalize.pkl")
        selected = dict(selected="final weights", selected_timesteps=int(model.num_timesteps))
    for src, dst in zip(sources, ("model.zip", "vec_normalize.pkl")):
        shutil.copyfile(src, out / dst)
    train_s = time.time() - t0 + earlier_wall_s(out, resumed)   # with the earlier sessions of a resumed run
    cfg = dict(vars(args), train_wall_s=train_s, num_timesteps=int(model.num_timesteps), **selected)
    (out / "config.json").write_text(json.dumps(cfg, indent=2))
    print(f"trained {model.num_timesteps:,} steps in {train_s / 60:.1f} min -> {out} "
          f"(model.zip: {selected['selected']}, {selected['selected_timesteps']:,} steps)")
    if args.eval_episodes > 0:
        from agents.training.after_training import evaluate_run
        print(f"evaluating {out / 'model.zip'}, the shipped policies and the references on {args.eval_episodes} "
              f"held-out scenarios (seeds {TEST_SEED}..{TEST_SEED + args.eval_episodes - 1})", flush=True)
        evaluate_run(out, episodes=args.eval_episodes, tier=args.tier, episode_steps=args.episode_steps,
                     progress_every_s=PROGRESS_EVERY_S)
        cfg["total_wall_s"] = time.time() - t0
        (out / "config.json").write_text(json.dumps(cfg, indent=2))
    announce_outputs(out, args.eval_episodes > 0, tb_dir)
    print(f"total wall time {(time.time() - t0) / 60:.1f} min")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
