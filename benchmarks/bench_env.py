"""Environment throughput: single env and native vector env (1 and 2 worker threads).

    python benchmarks/bench_env.py [--quick] [--json]

Prints env steps per second (one step = one control interval of the "paper" preset at the
default 20 ms and at 10 ms) for the single env and for the vector env with 2 envs on 1 and on 2
threads, after a warm-up that compiles the kernels.
"""

from __future__ import annotations

import argparse
import json
import platform
import time

import numba
import numpy as np

from bearing_gym.envs import BearingPreloadEnv, BearingPreloadVectorEnv


def single_rate(control_dt_s: float, steps: int) -> float:
    env = BearingPreloadEnv(scenario="paper", control_dt_s=control_dt_s)
    env.reset(seed=0)
    a = np.array([0.0], dtype=np.float32)
    env.step(a)
    t0 = time.perf_counter()
    for _ in range(steps):
        env.step(a)
    return steps / (time.perf_counter() - t0)


def vector_rate(control_dt_s: float, steps: int, threads: int, num_envs: int = 2) -> float:
    venv = BearingPreloadVectorEnv(num_envs=num_envs, scenario="paper", control_dt_s=control_dt_s,
                                   num_threads=threads, max_episode_steps=None)
    venv.reset(seed=0)
    a = np.zeros((num_envs, 1), dtype=np.float32)
    venv.step(a)
    t0 = time.perf_counter()
    for _ in range(steps):
        venv.step(a)
    return steps * num_envs / (time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer steps (same keys)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args()
    steps = 10 if args.quick else 60
    res = {"machine": platform.processor() or platform.machine(), "cores": numba.config.NUMBA_NUM_THREADS}
    for dt in (0.02, 0.01):
        key = f"{int(dt * 1000)}ms"
        res[f"single_env_steps_per_s_{key}"] = single_rate(dt, steps)
        res[f"vector_env_steps_per_s_1_thread_{key}"] = vector_rate(dt, steps, 1)
        if numba.config.NUMBA_NUM_THREADS >= 2:
            res[f"vector_env_steps_per_s_2_threads_{key}"] = vector_rate(dt, steps, 2)
            res[f"vector_env_speedup_2_cores_{key}"] = (res[f"vector_env_steps_per_s_2_threads_{key}"]
                                                        / res[f"single_env_steps_per_s_{key}"])
    if args.json:
        print(json.dumps(res))
        return
    print(f"{'measure':45s} {'value':>10s}")
    for k, v in res.items():
        print(f"{k:45s} {v:>10.4g}" if isinstance(v, float) else f"{k:45s} {v!s:>10s}")


if __name__ == "__main__":
    main()
