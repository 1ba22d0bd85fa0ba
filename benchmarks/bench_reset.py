"""What a reset costs, in env steps: settling on the fly against a start bank.

    python benchmarks/bench_reset.py [--quick] [--json] [--out FILE] [--tier transient]

A reset with a new training seed settles the rotor at the episode's initial operating point
(1.46 s simulated, :meth:`bearing_gym.envs.core.PreloadBatch.settle`); with a start bank
(:mod:`bearing_gym.envs.start_bank`) it copies the settled state instead. For ``--resets``
training seeds never reset before in this process (so the in-process settle cache cannot serve
them), on one env and one numba thread:

``reset_settled_s``
    median wall time of ``reset(seed=s)`` settling on the fly;
``reset_banked_s``
    median wall time of ``reset(seed=s)`` for seeds whose starts a bank holds (built in a separate
    interpreter, ``python -m bearing_gym.envs.start_bank``, so this process has not settled them:
    the settled resets above use the next ``--resets`` seeds, as the in-process cache is looked
    up before the bank); ``banked_resets_from_the_bank`` counts those whose settle key the bank
    holds (all of them, or the figure is not a banked reset's);
``step_s``
    mean wall time of the env steps of those episodes (``--steps`` after each banked reset,
    action 0);
``reset_shipped_s``
    median wall time of ``reset(seed=s)`` of ``gymnasium.make("BearingPreload-v0",
    start_bank="shipped")`` (the package's bank of the tier, its scenarios drawn uniformly; the
    seeds of the settled resets, none of whose scenarios this process has settled), if the tier
    ships a bank;
``reset_{settled,banked,shipped}_env_steps``
    the reset times divided by ``step_s``: a reset's price in env steps (issue target for
    the banked ones: at most 3).

The seeds are training seeds (``agents.protocol.TRAIN``: 40,000 onwards is the contextual fit's,
so this uses 30,000 + k), the tier's own scenario distribution.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")     # one env on one thread: steps and resets alike

import numpy as np  # noqa: E402

try:
    from benchmarks.bench_cli import emit, machine_info, parser   # imported from the benchmarks package
except ImportError:
    from bench_cli import emit, machine_info, parser              # run as a script: its directory is on sys.path

FIRST_SEED = 30_000


def measure(tier: str, resets: int, steps: int) -> dict:
    from bearing_gym.envs import BearingPreloadEnv
    from bearing_gym.envs import start_bank

    seeds = list(range(FIRST_SEED, FIRST_SEED + resets))
    warm = BearingPreloadEnv(tier=tier)                       # kernel compile / cache load, untimed
    warm.reset(seed=FIRST_SEED - 1)
    warm.step(np.zeros(1, dtype=np.float32))
    warm.close()

    env = BearingPreloadEnv(tier=tier)
    settled = []
    for s in seeds:
        t0 = time.perf_counter()
        env.reset(seed=s + resets)                            # other seeds: nothing banked or cached
        settled.append(time.perf_counter() - t0)

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bank.npz"
        subprocess.run([sys.executable, "-m", "bearing_gym.envs.start_bank", "--tier", tier, "--seeds",
                        str(seeds[0]), str(seeds[-1] + 1), "--out", str(path)], check=True,
                       stdout=subprocess.DEVNULL)
        bank = start_bank.load(path).install()
    banked, step_times, hits = [], [], 0
    a = np.zeros(1, dtype=np.float32)
    for s in seeds:
        t0 = time.perf_counter()
        env.reset(seed=s)
        banked.append(time.perf_counter() - t0)
        hits += env.task.batch.settle_digest(0) in bank.states
        t0 = time.perf_counter()
        for _ in range(steps):
            env.step(a)
        step_times.append((time.perf_counter() - t0) / steps)
    step_s = statistics.fmean(step_times)
    shipped = {}
    if start_bank.shipped_path(tier).exists():
        import gymnasium as gym
        made = gym.make("BearingPreload-v0", tier=tier, start_bank="shipped")
        times = []
        for s in seeds:
            t0 = time.perf_counter()
            made.reset(seed=s + resets)
            times.append(time.perf_counter() - t0)
        shipped = {"reset_shipped_s": statistics.median(times),
                   "reset_shipped_env_steps": statistics.median(times) / step_s}
    return {"tier": tier, "resets": resets, "steps_per_episode": steps,
            "reset_settled_s": statistics.median(settled), "reset_banked_s": statistics.median(banked),
            "banked_resets_from_the_bank": hits,
            "step_s": step_s,
            "reset_settled_env_steps": statistics.median(settled) / step_s,
            "reset_banked_env_steps": statistics.median(banked) / step_s, **shipped}


def print_table(res: dict) -> None:
    for k, v in res.items():
        if k != "machine":
            print(f"{k:30s} {v:>10.4g}" if isinstance(v, float) else f"{k:30s} {v!s:>10s}")
    m = res["machine"]
    print(f"machine: {m['cpu_model']}, {m['logical_cpus']} logical CPUs, Python {m['python']}, "
          f"commit {m.get('git_commit')}, 1-min load {m['load_average_1min_at_start']} at start, "
          f"{res['load_1min_at_end']:.2f} at end")


def main(argv: list[str] | None = None) -> None:
    ap = parser(__doc__, "fewer resets and steps (same keys)")
    ap.add_argument("--tier", default="transient")
    args = ap.parse_args(argv)
    res = {"machine": machine_info(), **measure(args.tier, 3 if args.quick else 12, 5 if args.quick else 30)}
    res["load_1min_at_end"] = round(os.getloadavg()[0], 2)
    emit(res, args, print_table)


if __name__ == "__main__":
    main()
