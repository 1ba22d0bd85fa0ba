"""The leaderboard's training runs: every algorithm of the protocol with each of its training
seeds, at the protocol's step budget, one run per command so that each fits a session.

    python -m agents.training.protocol_runs --list               # the runs and which are done
    python -m agents.training.protocol_runs --next               # train the first run not done yet
    python -m agents.training.protocol_runs --next --threads 1   # one numba thread (runs side by side on more cores)
    python -m agents.training.protocol_runs --algo sac --run 0   # train one run
    python -m agents.training.protocol_runs --ship               # copy each algorithm's best run to agents/pretrained/
    python -m agents.training.protocol_runs --protocol 2 --algo tqc --run 2 --until 17:30   # pause by then; carried

A run is ``train.py --algo A --seed S --timesteps STEP_BUDGET_PER_RUN --n-envs 2 --eval-episodes 0
--val-episodes VALIDATION_EPISODES_IN_TRAINING --eval-freq VALIDATION_EVERY_STEPS --out
runs/protocol/A_sS`` (seeds from :func:`agents.protocol.training_seeds`; validation on the
first validation seeds, whose references the store holds; model.zip is the best validation
checkpoint). Its small files are then collected into ``agents/trained/A/seed_S/``
(``model.zip``, ``vec_normalize.pkl``, ``config.json``, ``eval/validation_returns.npz``,
``eval/evaluations.npz``, ``eval/best.json``): committed, so that the leaderboard
(``python -m agents.leaderboard --model agents/trained/*/seed_*``) and the learning curves
(:mod:`agents.leaderboard.learning_curves`) can be rebuilt on another machine. A run is done when its
collected ``config.json`` records the whole budget. A run in progress holds
``runs/protocol/A_sS/.running`` (the process id of its train.py), so a second ``--next`` takes the run after it;
``--threads 1`` gives a run one numba thread (train.py ``--threads``), for running runs side by
side on a machine with more cores than a run uses; the results do not depend on the thread
count (the environments are stepped independently). On the 2-core machine it does not pay: two
SAC runs side by side (2 + 1 threads) made 79 env steps/s together, one run alone about 80-90,
so the protocol's runs go one after another.

**Protocol v2** (``--protocol 2``; agents.protocol's ``V2_*``): every V2 algorithm with each V2
seed, ``train.py --protocol 2`` (its tuned yml, ``V2_STEP_BUDGET_PER_RUN`` steps, validation on
``V2_VALIDATION_EPISODES_IN_TRAINING`` episodes, the shipped start bank of ``V2_START_BANK_STARTS``
starts, the best checkpoint up to ``V2_EARLY_ROW_STEPS`` kept too) in ``runs/protocol_v2/A_sS``;
collected into ``agents/trained_v2/A/seed_S/``: the portable exports of the selected checkpoint
and of the early row (``by_<steps>/``), config and validation logs (:data:`COLLECT_V2`; the SB3
files stay in the work directory).

A run longer than a session is split with ``--until HH:MM`` (train.py pauses it at its last resume
point before then). On the same machine the same command continues it from ``runs/``; for the
next machine, a paused v2 run is packed into ``carry/protocol_v2/<algo>_s<seed>.tar.xz``
(:mod:`agents.training.carry`: the newest checkpoint with its replay buffer, the validation record,
the start bank's draws), which is committed; the same command then unpacks it wherever the work
directory is missing or older, and deletes it once the run is collected.

``--ship`` copies, per algorithm, the run with the best validation return of its selected
checkpoint (validation episodes only: the test seeds choose nothing) to
``agents/pretrained/<algo>/`` (model.zip + vec_normalize.pkl + config.json; protocol 2: the
portable export and config, with the SB3 files from the work directory where they still are:
:func:`ship_v2`), the shipped policies of ``python -m agents.leaderboard --pretrained`` and of the main job.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from bearing_gym.task import DEFAULT_TIER

from agents import protocol as P
from agents.training import carry
from agents.paths import PRETRAINED_DIR, TRAINED_DIR, TRAINED_V2_DIR, checkout_root, require_checkout, runs_dir, start_bank_path


__all__ = ["RUNS", "run_dir", "carry_path", "collected_dir", "is_done", "is_running", "best_checkpoint", "run_summary", "train_run", "collect", "best_run",
           "ship", "ship_v2", "main"]

ROOT = checkout_root()             # None in an installed package: the protocol runs need a checkout
WORK_DIR = runs_dir("protocol")
COLLECT = ("model.zip", "vec_normalize.pkl", "config.json", "eval/validation_returns.npz",
           "eval/evaluations.npz", "eval/best.json")

#: every (algorithm, run index, training seed) of the protocol, the headline algorithm first
RUNS = [(a, k, s) for a in sorted(P.ALGORITHMS, key=lambda a: a != P.HEADLINE_ALGORITHM)
        for k, s in enumerate(P.training_seeds(a))]

# -- protocol v2 (agents.protocol V2_*): its own work and collection directories ------------------
WORK_DIR_V2 = runs_dir("protocol_v2")
TRAINED_DIR_V2 = TRAINED_V2_DIR
#: the early row's files (the best checkpoint up to V2_EARLY_ROW_STEPS) inside a run
EARLY = f"by_{P.V2_EARLY_ROW_STEPS}"
#: what a v2 run keeps in git: its portable exports (the selected checkpoint's and the early
#: row's; the SB3 files stay in the work directory: CrossQ's wide critics and every optimizer
#: state would put tens of MB per run in the repository), config and validation logs
COLLECT_V2 = ("portable_policy.npz", "config.json", "eval/validation_returns.npz", "eval/evaluations.npz",
              "eval/best.json", f"{EARLY}/portable_policy.npz", f"{EARLY}/config.json", f"{EARLY}/best.json")
RUNS_V2 = [(a, k, s) for a in P.V2_ALGORITHMS for k, s in enumerate(P.v2_training_seeds())]
#: paused v2 runs carried between machines through git (agents.training.carry); None outside a checkout
CARRY_DIR = None if ROOT is None else ROOT / "carry" / "protocol_v2"


def run_dir(algo: str, seed: int) -> Path:
    return WORK_DIR / f"{algo}_s{seed}"


def collected_dir(algo: str, seed: int, trained_dir: Path = TRAINED_DIR) -> Path:
    return trained_dir / algo / f"seed_{seed}"


def is_done(algo: str, seed: int, trained_dir: Path = TRAINED_DIR, budget: int = P.STEP_BUDGET_PER_RUN) -> bool:
    cfg = collected_dir(algo, seed, trained_dir) / "config.json"
    return cfg.exists() and json.loads(cfg.read_text()).get("num_timesteps", 0) >= budget


def _holder(lock: Path) -> int | None:
    """The live process named by a ``.running`` file (None: no file, or its process has ended)."""
    try:
        pid = int(lock.read_text())
        os.kill(pid, 0)
    except (FileNotFoundError, ValueError, ProcessLookupError):
        return None
    except PermissionError:            # a process of another user holds the pid
        return pid
    return pid


def is_running(algo: str, seed: int, work_dir: Path | None = None) -> bool:
    """Whether a live process holds this run (its ``.running`` file names a process that exists)."""
    return _holder((work_dir or WORK_DIR) / f"{algo}_s{seed}" / ".running") is not None


def _take_lock(out: Path, what: str) -> Path:
    """Create ``out/.running`` with this process's id, atomically (O_EXCL: of two processes
    starting the same run one gets it); a lock whose process has ended is replaced."""
    out.mkdir(parents=True, exist_ok=True)
    lock = out / ".running"
    for _ in range(3):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            pid = _holder(lock)
            if pid is not None:
                raise SystemExit(f"{what} is being trained by process {pid}")
            lock.unlink(missing_ok=True)           # its process has ended
            continue
        with os.fdopen(fd, "w") as f:
            f.write(str(os.getpid()))
        return lock
    raise SystemExit(f"could not take the lock {lock}")


def best_checkpoint(run: Path) -> dict | None:
    """A collected run's selected checkpoint (``eval/best.json``: ``num_timesteps``,
    ``mean_validation_return``), or None if the run is not collected."""
    path = run / "eval" / "best.json"
    return json.loads(path.read_text()) if path.exists() else None


def run_summary(algo: str, seed: int, trained_dir: Path = TRAINED_DIR) -> str:
    """A done run's selected checkpoint, its mean validation return and the training wall time."""
    d = collected_dir(algo, seed, trained_dir)
    best = best_checkpoint(d)
    if best is None:
        return ""
    cfg = json.loads((d / "config.json").read_text())
    return (f", best checkpoint {best['num_timesteps']:,} steps, validation return {best['mean_validation_return']:.1f}"
            f", {cfg.get('train_wall_s', float('nan')) / 60:.1f} min training")


def train_args(algo: str, seed: int, out: Path, budget: int = P.STEP_BUDGET_PER_RUN,
               threads: int | None = None, protocol: int = 1) -> list[str]:
    """train.py's arguments for one protocol run. Protocol 1 draws every training start afresh
    (no start bank); protocol 2 draws the shipped bank's (V2_START_BANK_STARTS starts, each once)."""
    val = P.VALIDATION_EPISODES_IN_TRAINING if protocol == 1 else P.V2_VALIDATION_EPISODES_IN_TRAINING
    bank = "none" if protocol == 1 else str(start_bank_path(DEFAULT_TIER))
    return ["--protocol", str(protocol), "--algo", algo, "--seed", str(seed), "--timesteps", str(budget),
            "--n-envs", "2", "--tier", DEFAULT_TIER, "--eval-episodes", "0",
            "--val-episodes", str(val), "--val-seed", str(P.VALIDATION.start),
            "--eval-freq", str(P.VALIDATION_EVERY_STEPS), "--out", str(out), "--no-progress",
            "--start-bank", bank] + (["--threads", str(threads)] if threads is not None else [])


def check_v2_bank() -> None:
    """SystemExit unless the shipped start bank holds protocol v2's starts (a run must not meet a
    start twice)."""
    from bearing_gym.envs import start_bank as banks
    path = start_bank_path(DEFAULT_TIER)
    n = len(banks.load(path)) if path.exists() else 0
    if n < P.V2_START_BANK_STARTS:
        raise SystemExit(f"protocol v2 trains on a start bank of {P.V2_START_BANK_STARTS} starts; {path} holds {n}: "
                         f"python -m agents.regenerate --only start_bank")


def export_v2(src: Path) -> None:
    """The portable exports of a finished v2 run in ``src``: the selected checkpoint's (beside its
    model.zip) and the early row's (``src/by_<steps>/``: its best checkpoint copied as model.zip,
    vec_normalize.pkl and config.json, then exported)."""
    from agents.evaluation.trained import export
    early = src / "eval" / EARLY
    if not (early / "best_model.zip").exists():
        raise FileNotFoundError(f"{early}: no best checkpoint up to {P.V2_EARLY_ROW_STEPS:,} steps (the run is not "
                                "finished)")
    dst = src / EARLY
    dst.mkdir(exist_ok=True)
    shutil.copyfile(early / "best_model.zip", dst / "model.zip")
    shutil.copyfile(early / "best_vec_normalize.pkl", dst / "vec_normalize.pkl")
    shutil.copyfile(early / "best.json", dst / "best.json")
    cfg = json.loads((src / "config.json").read_text())
    info = json.loads((early / "best.json").read_text())
    cfg.update(early_row_steps=P.V2_EARLY_ROW_STEPS,
               selected=f"best validation checkpoint up to {P.V2_EARLY_ROW_STEPS:,} steps",
               selected_timesteps=info["num_timesteps"], selected_validation_return=info["mean_validation_return"])
    (dst / "config.json").write_text(json.dumps(cfg, indent=2))
    export(src)
    export(dst)


def collect(src: Path, dst: Path, files: tuple[str, ...] = COLLECT) -> None:
    """Copy a finished run's small files (:data:`COLLECT`; :data:`COLLECT_V2` for protocol 2)
    from ``src`` to ``dst``."""
    for name in files:
        if not (src / name).exists():
            raise FileNotFoundError(f"{src / name}: the run is not finished (train.py writes it at the end)")
    for name in files:
        (dst / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(src / name, dst / name)


def carry_path(algo: str, seed: int, carry_dir: Path | None = CARRY_DIR) -> Path | None:
    """Where a paused v2 run is carried to the next machine (:mod:`agents.training.carry`), or None
    outside a checkout."""
    return None if carry_dir is None else carry_dir / f"{algo}_s{seed}.tar.xz"


def train_run(algo: str, seed: int, budget: int = P.STEP_BUDGET_PER_RUN, trained_dir: Path = TRAINED_DIR,
              work_dir: Path | None = None, threads: int | None = None, protocol: int = 1,
              until: str | None = None, carry_dir: Path | None = CARRY_DIR) -> Path | None:
    """Train one run with train.py (resuming its checkpoints if an earlier attempt left them, or,
    for protocol 2, its carry from another machine if that is newer) and collect it; returns the
    collected directory. With ``until`` (HH:MM) train.py pauses the run at its last resume point
    before then; a paused v2 run is packed into its carry (``carry_dir``, committed so that the next
    machine continues it) and None is returned. A finished run's carry is deleted."""
    out = (work_dir or (WORK_DIR if protocol == 1 else WORK_DIR_V2)) / f"{algo}_s{seed}"
    if protocol >= 2:
        check_v2_bank()
    carried = carry_path(algo, seed, carry_dir) if protocol >= 2 else None
    lock = _take_lock(out, f"{algo} seed {seed}")
    try:
        args = train_args(algo, seed, out, budget, threads, protocol)
        if carried is not None and carried.exists():
            try:
                carry.unpack(carried, out, start_bank_path(DEFAULT_TIER))
                print(f"protocol run: continuing from its carry {carry.describe(carried)}", flush=True)
            except carry.CarryNotNewer as err:
                print(f"protocol run: the carry is not used: {err}", flush=True)
            except carry.CarryError as err:     # a fresh start would discard the carried progress
                raise SystemExit(f"protocol run: {algo} seed {seed} has a carry that cannot be used: {err}") from None
        if (out / "checkpoints").exists():
            args.append("--resume")
        if until is not None:
            args += ["--until", until]
        t0 = time.time()
        print(f"protocol run: {algo} seed {seed}, {budget:,} steps -> {out}", flush=True)
        # train.py as its own process (the library does not import the script above it); the lock
        # names that process, so a run whose launcher was killed still counts as running
        root = ROOT or require_checkout("train.py", "a source checkout (git clone)")
        proc = subprocess.Popen([sys.executable, str(root / "train.py"), *args], cwd=root)
        tmp = lock.with_name(".running.tmp")
        tmp.write_text(str(proc.pid))
        os.replace(tmp, lock)
        rc = proc.wait()
    finally:
        lock.unlink(missing_ok=True)
    if rc:
        raise SystemExit(f"train.py failed ({rc}) for {algo} seed {seed}")
    if json.loads((out / "config.json").read_text()).get("paused"):
        if carried is None:
            print(f"protocol run: {algo} seed {seed} paused in {out}; the same command continues it", flush=True)
            return None
        try:
            carry.pack(out, carried)
        except carry.CarryError as err:
            raise SystemExit(f"protocol run: {algo} seed {seed} paused in {out}, not carried: {err}") from None
        print(f"protocol run: {algo} seed {seed} paused; carried to {carry.describe(carried)}: commit it, and the "
              "same command continues the run on any machine", flush=True)
        return None
    dst = collected_dir(algo, seed, trained_dir)
    if protocol >= 2:
        export_v2(out)
    collect(out, dst, COLLECT if protocol == 1 else COLLECT_V2)
    print(f"collected into {dst} ({(time.time() - t0) / 60:.1f} min)", flush=True)
    if carried is not None and carried.exists():
        carried.unlink()
        print(f"its carry {carried} is deleted (the run is collected): commit the deletion", flush=True)
    return dst


def best_run(trained_dir: Path, algo: str) -> Path | None:
    """``algo``'s collected run with the best validation return of its selected checkpoint
    (validation episodes only; the first on a tie), or None if none is collected."""
    runs = {d: b for d in sorted((trained_dir / algo).glob("seed_*")) if (b := best_checkpoint(d)) is not None}
    return max(runs, key=lambda d: runs[d]["mean_validation_return"]) if runs else None


def ship(trained_dir: Path = TRAINED_DIR, pretrained_dir: Path = PRETRAINED_DIR) -> dict[str, Path]:
    """Per algorithm, copy the collected run with the best validation return of its selected
    checkpoint to ``pretrained_dir/<algo>/``."""
    shipped = {}
    for algo in P.ALGORITHMS:
        best = best_run(trained_dir, algo)
        if best is None:
            continue
        dst = pretrained_dir / algo
        dst.mkdir(parents=True, exist_ok=True)
        for name in ("model.zip", "vec_normalize.pkl", "config.json"):
            shutil.copyfile(best / name, dst / name)
        shipped[algo] = best
        print(f"{algo}: shipped {best} -> {dst}")
    return shipped


def ship_v2(trained_dir: Path = TRAINED_DIR_V2, work_dir: Path | None = None,
            pretrained_dir: Path = PRETRAINED_DIR) -> dict[str, Path]:
    """Protocol v2's shipped policies: per algorithm, the collected run with the best validation
    return of its selected checkpoint (validation episodes only), copied to
    ``pretrained_dir/<algo>/``: its portable export and config, and its SB3 files (model.zip,
    vec_normalize.pkl) from the run's work directory where this machine still has them. A shipped
    directory keeps no SB3 file of another run (the portable export would no longer be current)."""
    work_dir = WORK_DIR_V2 if work_dir is None else work_dir
    shipped = {}
    for algo in P.V2_ALGORITHMS:
        best = best_run(trained_dir, algo)
        if best is None:
            continue
        dst = pretrained_dir / algo
        dst.mkdir(parents=True, exist_ok=True)
        for name in ("portable_policy.npz", "config.json"):
            shutil.copyfile(best / name, dst / name)
        src = work_dir / f"{algo}_s{json.loads((best / 'config.json').read_text())['seed']}"
        both = all((src / name).exists() for name in ("model.zip", "vec_normalize.pkl"))
        for name in ("model.zip", "vec_normalize.pkl"):
            if both:
                shutil.copyfile(src / name, dst / name)
            else:
                (dst / name).unlink(missing_ok=True)
        shipped[algo] = best
        print(f"{algo}: shipped {best} -> {dst}" + ("" if both else f" (portable export only: its SB3 files are not in {src})"))
    return shipped


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="The leaderboard's training runs, one per command.")
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--list", action="store_true", help="the protocol's runs and which are done")
    g.add_argument("--next", action="store_true", help="train the first run not done yet")
    g.add_argument("--algo", choices=sorted(set(P.ALGORITHMS) | set(P.V2_ALGORITHMS)),
                   help="train this algorithm's run --run")
    g.add_argument("--ship", action="store_true", help="copy each algorithm's best run to agents/pretrained/")
    ap.add_argument("--run", type=int, default=0, help="run index (0 .. seeds-1) with --algo")
    ap.add_argument("--threads", type=int, help="numba threads per run (train.py --threads; default one per env, at most the cores)")
    ap.add_argument("--until", metavar="HH:MM",
                    help="pause the run at its last resume point before this time (train.py --until); protocol 2 "
                         "packs a paused run into carry/protocol_v2/<algo>_s<seed>.tar.xz, to commit: the same "
                         "command continues it on any machine")
    ap.add_argument("--protocol", type=int, choices=(1, 2), default=P.PROTOCOL_VERSION,
                    help="1: protocol v1's runs (agents/trained/); 2: protocol v2's (agents/trained_v2/) "
                         "(default %(default)s, the board's)")
    a = ap.parse_args(argv)
    v2 = a.protocol >= 2
    runs = RUNS_V2 if v2 else RUNS
    trained = TRAINED_DIR_V2 if v2 else TRAINED_DIR
    budget = P.V2_STEP_BUDGET_PER_RUN if v2 else P.STEP_BUDGET_PER_RUN
    work = WORK_DIR_V2 if v2 else WORK_DIR
    kw = dict(budget=budget, trained_dir=trained, work_dir=work, threads=a.threads, protocol=a.protocol, until=a.until)
    if a.until is not None:
        from agents.clock import deadline
        deadline(a.until)                # SystemExit naming --until on a malformed time
    if a.threads is not None and a.threads < 1:
        ap.error(f"--threads must be >= 1, got {a.threads}")
    if a.list:
        for algo, k, seed in runs:
            carried = carry_path(algo, seed) if v2 else None
            state = ("done" if is_done(algo, seed, trained, budget) else "training" if is_running(algo, seed, work)
                     else f"paused ({carry.describe(carried)})" if carried is not None and carried.exists() else "to do")
            print(f"{algo:9s} run {k} seed {seed:6d}: {state}{run_summary(algo, seed, trained)}")
        print(f"protocol {a.protocol}: budget {budget:,} env steps per run")
        return 0
    if a.ship:
        ship_v2() if v2 else ship()
        return 0
    if a.next:
        todo = [(algo, seed) for algo, _, seed in runs if not is_done(algo, seed, trained, budget)]
        if not todo:
            print("every protocol run is done")
            return 0
        free = [r for r in todo if not is_running(*r, work)]
        if not free:
            print("every protocol run not done is being trained")
            return 0
        train_run(*free[0], **kw)
        return 0
    if v2 and a.algo not in P.V2_ALGORITHMS or not v2 and a.algo not in P.ALGORITHMS:
        raise SystemExit(f"--algo {a.algo} is not one of protocol {a.protocol}'s algorithms")
    seeds = P.v2_training_seeds() if v2 else P.training_seeds(a.algo)
    if not 0 <= a.run < len(seeds):
        raise SystemExit(f"--run must be in 0..{len(seeds) - 1} for {a.algo}")
    train_run(a.algo, seeds[a.run], **kw)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
