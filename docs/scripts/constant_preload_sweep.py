"""Best constant preload vs. lowest stable preload under the default reward.

For each operating point and each constant preload P the env starts at the static equilibrium
at P, holds the set-point at P for ``--steps`` control intervals, and reports the mean reward and
the mean quasi-periodicity index over the second half. Writes docs/environment_sweep.csv and
prints a table.   python docs/scripts/constant_preload_sweep.py [--steps 100]
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from bearing_gym.envs import BearingPreloadVectorEnv, Scenario

POINTS = {
    "paper (20,000 rpm, c = 4 um, no radial load)": Scenario(),
    "15,000 rpm, c = 10 um, radial 200 N": Scenario(speed_start_rpm=15000.0, speed_end_rpm=15000.0,
                                                    clearance_m=10e-6, radial_load_before_n=200.0,
                                                    radial_load_after_n=200.0),
}
PRELOADS = np.arange(400.0, 1601.0, 100.0)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=100)
    args = ap.parse_args()
    rows = []
    venv = BearingPreloadVectorEnv(num_envs=len(PRELOADS), max_episode_steps=None)
    for name, sc in POINTS.items():
        venv.reset(seed=0, options={"scenario": sc})
        for i, p in enumerate(PRELOADS):
            mask = np.zeros(len(PRELOADS), dtype=bool)
            mask[i] = True
            venv.reset(options={"scenario": sc, "initial_preload_n": float(p), "reset_mask": mask})
        actions = np.array([[venv.actuator.action_for(p)] for p in PRELOADS], dtype=np.float32)
        rew, qpi = [], []
        for _ in range(args.steps):
            _, r, term, _, info = venv.step(actions)
            rew.append(r)
            qpi.append(info["qpi"])
        rew = np.array(rew)[args.steps // 2:].mean(axis=0)
        qpi = np.array(qpi)[args.steps // 2:].mean(axis=0)
        stable = qpi < 0.3
        lowest_stable = PRELOADS[np.argmax(stable)] if stable.any() else float("nan")
        best = PRELOADS[np.argmax(rew)]
        print(f"\n{name}: best constant preload {best:.0f} N, lowest stable {lowest_stable:.0f} N")
        print(" preload (N)   mean reward   mean qpi")
        for p, r, q in zip(PRELOADS, rew, qpi):
            print(f"  {p:8.0f}   {r:11.3f}   {q:8.3f}")
            rows.append({"operating_point": name, "preload_n": p, "mean_reward": r, "mean_qpi": q})
    out = Path(__file__).resolve().parents[1] / "environment_sweep.csv"
    with out.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()
