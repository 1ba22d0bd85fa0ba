"""What race waviness costs an env step, and the env step's throughput (one thread).

    python benchmarks/bench_waviness.py [--repeats 5] [--steps 40] [--json]
    python benchmarks/bench_waviness.py --baseline <other checkout> [--rounds 3] [--json]

Times ``env.step`` (one 20 ms control interval, one thread) at one operating point (20,000 rpm,
1200 N, c = 4 um, no radial load), once without waviness and once with the tiers' kind of it
(0.5 um radial waviness of order 18 on both races), interleaved, best of ``--repeats``; a
``stationary`` draw (seed 300000) and a ``transient`` draw (seed 0, the benchmark's tier: the
figure of issue 42's gate, at most 0.5x f716269's). The ratio with/without is the figure of issue 29 (target
<= 1.2). Uses only the public env API, so the same file times another checkout: with
``--baseline DIR`` it runs itself ``--rounds`` times for this checkout and for DIR alternately
(each in a fresh process, DIR first on ``PYTHONPATH``), keeps each variant's best figures and
prints both with the ratio baseline / this: a side-by-side measurement in one run. The baseline
checkout needs its own numba cache (``--baseline-cache``), because numba's cache keys do not
tell two checkouts of one package apart.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from bearing_gym.envs import BearingPreloadEnv  # noqa: E402

POINT = {"shaft_speed_rpm": 20000.0, "radial_load_n": 0.0, "clearance_m": 4e-6, "initial_preload_n": 1200.0}


def make(waviness_m: float | None, tier: str = "stationary") -> BearingPreloadEnv:
    if tier == "transient":                                 # a transient draw (training seed 0)
        env = BearingPreloadEnv(tier="transient")
        env.reset(seed=0)
        return env
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


def side_by_side(baseline: str, baseline_cache: str | None, rounds: int, repeats: int, steps: int) -> dict:
    """Best figures of this checkout and of ``baseline``, measured alternately in fresh processes."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    cmd = [sys.executable, os.path.abspath(__file__), "--json", "--repeats", str(repeats), "--steps", str(steps)]
    best: dict[str, dict[str, float]] = {"this": {}, "baseline": {}}
    for _ in range(rounds):
        for label, root in (("baseline", baseline), ("this", here)):
            env = dict(os.environ, PYTHONPATH=os.path.abspath(root))
            if label == "baseline" and baseline_cache:
                env["NUMBA_CACHE_DIR"] = baseline_cache
            out = subprocess.run(cmd, env=env, cwd=os.path.abspath(root), capture_output=True, text=True, check=True)
            res = json.loads(out.stdout.strip().splitlines()[-1])
            for k, v in res.items():
                if k.startswith("ms_per_step"):
                    best[label][k] = min(best[label].get(k, float("inf")), v)
    table = {}
    for k in best["this"]:
        table[f"{k} (baseline)"] = best["baseline"][k]
        table[f"{k} (this)"] = best["this"][k]
        table[f"{k} speed-up"] = best["baseline"][k] / best["this"][k]
    for label in ("baseline", "this"):
        table[f"waviness_ratio ({label})"] = best[label]["ms_per_step 0.5 um waviness"] / best[label]["ms_per_step no waviness"]
    return table


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--baseline", help="another checkout of bearing_gym to time alternately with this one")
    ap.add_argument("--baseline-cache", help="NUMBA_CACHE_DIR for the baseline (default: the environment's)")
    ap.add_argument("--rounds", type=int, default=3, help="with --baseline: alternations")
    args = ap.parse_args()
    if args.baseline:
        res = side_by_side(args.baseline, args.baseline_cache, args.rounds, args.repeats, args.steps)
        if args.json:
            print(json.dumps(res))
        else:
            print(f"{'measure':48s} {'value':>10s}")
            for k, v in res.items():
                print(f"{k:48s} {v:>10.4g}")
        return
    envs = {"no waviness": make(0.0), "0.5 um waviness": make(0.5e-6), "stationary draw": make(None),
            "transient draw": make(None, tier="transient")}
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
