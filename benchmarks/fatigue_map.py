"""How the physical fatigue term moves the reward map: best preloads and rankings, old against new.

    python benchmarks/fatigue_map.py [--csv docs/reward_map.csv] [--dynamic] [--json OUT]

The reward map (``docs/reward_map.csv``, :mod:`bearing_gym.envs.reward_map`: 81 cells of speed x
radial load x clearance x unbalance, 18 constant preloads each) was made with the first fatigue
term (ISO 281's bearing-level load, ``0.5 (P_eq / P_eq,max)^3 n / n_max``). Without running the
dynamic map again, this rescores it with the Lundberg-Palmgren term of
:class:`~bearing_gym.envs.VibrationFirstReward`: the vibration term, the heat and any
termination as stored, the new fatigue from the contact loads of the quasi-static equilibrium
(:func:`bearing_gym.physics.static_equilibrium`, no unbalance) at each (cell, preload). A
period-1 interval's time-averaged loads are close to those (``--dynamic`` checks a few points
against the env's accumulated loads; the unbalance's rotating force adds a little); in a
quasi-periodic interval they are not, but there the vibration term (>= 1) outweighs any
fatigue (<= 1), so the ranking does not hinge on it.

The CSV must be a map made with the old term (``docs/reward_map.csv`` up to commit 40728c8:
``git show 40728c8:docs/reward_map.csv > old.csv``); a map made with the new term compares it
with itself. Per cell it prints the best preload under the old and the new reward, Spearman's rho and
Kendall's tau of the 18 preloads' rewards (old against new), and a summary: the share of cells
whose best preload moves. ``--json`` writes the per-cell numbers.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bearing_gym.envs import VibrationFirstReward  # noqa: E402
from bearing_gym.envs.reward import corner_life_used_per_s  # noqa: E402
from bearing_gym.envs.reward_map import cells_of, read_csv  # noqa: E402
from bearing_gym.units import rpm_to_rad_s  # noqa: E402

#: period-1 points of the map checked against the dynamic accumulated loads (--dynamic):
#: (speed rpm, radial load N, clearance um, unbalance um, preload N)
DYNAMIC_POINTS = ((10000.0, 500.0, 30.0, 10.0, 800.0), (17500.0, 250.0, 17.0, 10.0, 1500.0),
                  (25000.0, 0.0, 4.0, 5.0, 1200.0), (25000.0, 500.0, 30.0, 10.0, 2000.0),
                  (25000.0, 0.0, 4.0, 20.0, 1900.0))
DYNAMIC_INTERVALS = 10


def static_life(speed_rpm: float, radial_n: float, clearance_um: float, preload_n: float) -> float:
    """u (1/s) at the static equilibrium of the default bearing at that operating point (the
    reward's own :func:`~bearing_gym.envs.reward.corner_life_used_per_s`, cached)."""
    return corner_life_used_per_s(preload_n, speed_rpm, radial_n, clearance_um * 1e-6)


def rescore(points, reward: VibrationFirstReward) -> dict[tuple, dict]:
    """Per cell: the old and the new mean reward of each preload (new = old - old fatigue + new)."""
    out = {}
    for cell, pts in cells_of(points).items():
        speed, radial, clearance, _ = cell
        old, new, fat = [], [], []
        for p in pts:
            u = static_life(speed, radial, clearance, p.preload_n)
            _, fatigue = reward.secondary_costs(np.array([p.preload_n]), np.array([rpm_to_rad_s(speed)]), np.array([u]))
            old.append(p.mean_reward)
            new.append(p.mean_reward - p.mean_fatigue - float(fatigue[0]))    # stored terms are <= 0
            fat.append(float(fatigue[0]))
        out[cell] = {"preloads_n": [p.preload_n for p in pts], "old": old, "new": new, "new_fatigue": fat}
    return out


def compare(scored: dict[tuple, dict], points) -> dict[tuple, dict]:
    """Per cell: best preloads, rank correlations, the new fatigue's range, and the reward map's
    two required properties under the new reward (``tests/envs/test_reward_map.py``): every
    quasi-periodic preload below the best period-1 one, period-1 rewards falling with preload."""
    from scipy.stats import kendalltau, spearmanr
    cells = cells_of(points)
    rows = {}
    for cell, d in scored.items():
        period1 = [p.period1 for p in cells[cell]]
        new_p1 = [r for r, ok in zip(d["new"], period1) if ok]
        best_p1 = max(new_p1, default=None)
        old, new, pre = np.array(d["old"]), np.array(d["new"]), d["preloads_n"]
        rho = spearmanr(old, new).statistic
        tau = kendalltau(old, new).statistic
        rows[cell] = {"best_old_n": pre[int(np.argmax(old))], "best_new_n": pre[int(np.argmax(new))],
                      "spearman": float(rho), "kendall": float(tau),
                      "new_fatigue_range": (float(min(d["new_fatigue"])), float(max(d["new_fatigue"]))),
                      "quasi_periodic_above_period1": best_p1 is not None and any(
                          r >= best_p1 for r, ok in zip(d["new"], period1) if not ok),
                      "period1_not_falling": any(a <= b for a, b in zip(new_p1, new_p1[1:]))}
    return rows


def markdown(rows: dict[tuple, dict]) -> str:
    """One line per (speed, radial load, clearance); per unbalance: best old -> new (N), tau."""
    ecc = sorted({c[3] for c in rows})
    head = ("| speed (rpm) | radial (N) | clearance (um) | "
            + " | ".join(f"e = {e:g} um: best old -> new (tau)" for e in ecc) + " |")
    lines = [head, "|" + "---|" * (3 + len(ecc))]
    for v, f, c in sorted({c[:3] for c in rows}):
        cols = []
        for e in ecc:
            r = rows[(v, f, c, e)]
            moved = "**" if r["best_old_n"] != r["best_new_n"] else ""
            cols.append(f"{moved}{r['best_old_n']:.0f} -> {r['best_new_n']:.0f}{moved} ({r['kendall']:.2f})")
        lines.append(f"| {v:,.0f} | {f:.0f} | {c:.0f} | " + " | ".join(cols) + " |")
    return "\n".join(lines)


def summary(rows: dict[tuple, dict]) -> dict:
    moved = [c for c, r in rows.items() if r["best_old_n"] != r["best_new_n"]]
    return {"cells": len(rows), "best_moved": len(moved),
            "share_moved": len(moved) / len(rows),
            "spearman_median": float(np.median([r["spearman"] for r in rows.values()])),
            "spearman_min": float(min(r["spearman"] for r in rows.values())),
            "kendall_median": float(np.median([r["kendall"] for r in rows.values()])),
            "kendall_min": float(min(r["kendall"] for r in rows.values())),
            "cells_quasi_periodic_above_period1": sum(r["quasi_periodic_above_period1"] for r in rows.values()),
            "cells_period1_not_falling": sum(r["period1_not_falling"] for r in rows.values()),
            "mean_shift_n": (float(np.mean([rows[c]["best_new_n"] - rows[c]["best_old_n"] for c in moved]))
                             if moved else 0.0)}


def dynamic_check(points=DYNAMIC_POINTS, intervals: int = DYNAMIC_INTERVALS) -> list[dict]:
    """Static against dynamic life used at a few period-1 points: the env settled at the
    point, the mean of ``info["life_used_per_s"]`` over ``intervals`` control intervals."""
    from bearing_gym.envs import BearingPreloadEnv
    out = []
    for speed, radial, clearance, ecc, preload in points:
        env = BearingPreloadEnv(tier="stationary")
        _, info = env.reset(seed=0, options={"shaft_speed_rpm": speed, "radial_load_n": radial,
                                             "clearance_m": clearance * 1e-6, "eccentricity_m": ecc * 1e-6,
                                             "initial_preload_n": preload, "waviness_amplitude_m": 0.0})
        a = env.actuator.action_for(preload)
        lives, qp = [], False
        for _ in range(intervals):
            _, _, term, _, info = env.step(np.array([a], dtype=np.float32))
            lives.append(info["life_used_per_s"])
            qp |= info["quasi_periodic"]
        dyn = math.fsum(lives) / len(lives)
        stat = static_life(speed, radial, clearance, preload)
        out.append({"point": [speed, radial, clearance, ecc, preload], "static": stat, "dynamic": dyn,
                    "rel_diff": dyn / stat - 1.0, "quasi_periodic": bool(qp)})
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--csv", default=str(ROOT / "docs" / "reward_map.csv"))
    ap.add_argument("--dynamic", action="store_true", help="check static against dynamic loads at a few points")
    ap.add_argument("--json", help="write per-cell results and the summary here")
    args = ap.parse_args(argv)
    reward = VibrationFirstReward()
    points = read_csv(args.csv)
    rows = compare(rescore(points, reward), points)
    print(markdown(rows))
    s = summary(rows)
    print(json.dumps(s, indent=1))
    by_speed = {}
    for (v, *_), r in rows.items():
        lo, hi = by_speed.get(v, (math.inf, -math.inf))
        by_speed[v] = (min(lo, r["new_fatigue_range"][0]), max(hi, r["new_fatigue_range"][1]))
    for v, (lo, hi) in sorted(by_speed.items()):
        print(f"new fatigue cost at {v:,.0f} rpm: {lo:.4f} .. {hi:.4f}")
    checks = dynamic_check() if args.dynamic else []
    for c in checks:
        print(f"dynamic check {c['point']}: static {c['static']:.4e}, dynamic {c['dynamic']:.4e} /s "
              f"({100 * c['rel_diff']:+.2f} %){' quasi-periodic' if c['quasi_periodic'] else ''}")
    if args.json:
        Path(args.json).write_text(json.dumps({"summary": s, "dynamic_check": checks,
                                               "cells": [{"cell": list(k), **v} for k, v in rows.items()]}, indent=1))


if __name__ == "__main__":
    main()
