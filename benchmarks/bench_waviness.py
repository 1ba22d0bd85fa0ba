"""What race waviness costs an env step, and the env step's throughput (one thread).

    python benchmarks/bench_waviness.py [--repeats 5] [--steps 40] [--json]

Times ``env.step`` (one 20 ms control interval, one thread) at one operating point (20,000 rpm,
1200 N, c = 4 um, no radial load), once without waviness and once with the tiers' kind of it
(0.5 um radial waviness of order 18 on both races), interleaved, best of ``--repeats``; and a
``stationary`` draw (seed 300000). The ratio with/without is the figure of issue 29 (target
<= 1.2). Uses only the public env API, so the same file times another checkout side by side:
``PYTHONPATH=<other checkout> python benchmarks/bench_waviness.py --json``.
"""

from __future__ import annotations

import argparse
import json
import os
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from bearing_gym.envs import BearingPreloadEnv  # noqa: E402

POINT = {"shaft_speed_rpm": 20000.0, "radial_load_n": 0.0, "clearance_m": 4e-6, "initial_preload_n": 1200.0}


def make(waviness_m: float | None) -> BearingPreloadEnv:
    if waviness_m is None:                                  # a stationary draw
        env = BearingPreloadEnv(tier="stationary")
        env.reset(seed=300000)
        return env
    env = BearingPreloadEnv(tier="stationary")
    env.reset(seed=0, options={**POINT, "waviness_amplitude_m": waviness_m, "waviness_order": 18})
    return env


def seconds_per_step(env: BearingPreloadEnv, steps: int) -> float:
    a = np.array([env.actuator.action_for(1200.0)], dtype=np.float32)
    t0 = time.perf_counter()
    for _ in range(steps):
        env.step(a)
    return (time.perf_counter() - t0) / steps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args()
    envs = {"no waviness": make(0.0), "0.5 um waviness": make(0.5e-6), "stationary draw": make(None)}
    for env in envs.values():                               # compile and warm up
        seconds_per_step(env, 2)
    best = {k: float("inf") for k in envs}
    for _ in range(args.repeats):                           # interleaved: drift hits all alike
        for k, env in envs.items():                         # no time limit: the point holds
            best[k] = min(best[k], seconds_per_step(env, args.steps))
    res = {f"ms_per_step {k}": 1e3 * v for k, v in best.items()}
    res["steps_per_s no waviness"] = 1.0 / best["no waviness"]
    res["waviness_ratio"] = best["0.5 um waviness"] / best["no waviness"]
    res["stationary_ratio"] = best["stationary draw"] / best["no waviness"]
    if args.json:
        print(json.dumps(res))
        return
    print(f"{'measure':32s} {'value':>10s}")
    for k, v in res.items():
        print(f"{k:32s} {v:>10.4g}")


if __name__ == "__main__":
    main()
