"""The reward map: the stationary per-interval reward of every constant preload over a grid of
operating points, the ground truth a preload policy faces.

For each cell (shaft speed, radial load, clearance, rotor unbalance; no waviness) and each
preload of the grid, the env's own physics starts settled at that preload (as ``reset`` does)
and holds it for ``measure_intervals`` control intervals; the reward model scores every
interval. A preload is *period-1* in a cell when no measured interval is quasi-periodic
(index <= ``QPI_THRESHOLD``), *quasi-periodic* when at least one is.

The unbalance is the eccentricity e of the rotor's mass centre (``Scenario.eccentricity_m``, the
force m e omega^2 of eq 35), an axis of its own (``GRID_ECCENTRICITIES_M``: 5, 10 and 20 um, the
ends and the middle of the tiers' 5-20 um): the period-1 windows move with it (issue 31; at
25,000 rpm / 0 N / 4 um the best preload is 500, 900 and 1900 N at 5, 10 and 20 um). The 10 um
slice is the paper's unbalance and was the whole map before the axis (the same code path: its
rows are bit for bit those of that map).

``python -m bearing_gym.envs.reward_map --out docs/reward_map.csv`` writes the grid
(``docs/environment.md`` shows it); :func:`reward_map` is the library call.
"""

from __future__ import annotations

import argparse
import csv
import itertools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .composition import measurement
from .core import PreloadBatch
from .features import F_NS_RMS
from .scenario import Scenario
from .tiers import CONTROL_DT_S, tier_parts

__all__ = ["MapPoint", "reward_map", "GRID_SPEEDS_RPM", "GRID_RADIAL_LOADS_N", "GRID_CLEARANCES_M",
           "GRID_ECCENTRICITIES_M", "GRID_PRELOADS_N", "MEASURE_INTERVALS", "best_preloads", "period1_windows",
           "write_csv", "read_csv", "cells_of", "measure_cell", "ENGINEERING"]

GRID_SPEEDS_RPM = (10000.0, 17500.0, 25000.0)
GRID_RADIAL_LOADS_N = (0.0, 250.0, 500.0)
GRID_CLEARANCES_M = (4e-6, 17e-6, 30e-6)
GRID_ECCENTRICITIES_M = (5e-6, 10e-6, 20e-6)     # the rotor's unbalance (mass-centre eccentricity)
GRID_PRELOADS_N = tuple(float(p) for p in range(300, 2001, 100))
MEASURE_INTERVALS = 25          # 0.5 s of settled motion per point

COLUMNS = ("speed_rpm", "radial_load_n", "clearance_um", "eccentricity_um", "preload_n", "mean_reward",
           "mean_vibration", "mean_heat", "mean_fatigue", "quasi_periodic_fraction", "max_qpi", "mean_qpi",
           "mean_nonsync_rms_um", "terminated")
#: the engineering quantities of a point (env info's, means over the measured intervals)
ENGINEERING = ("radial_stiffness_n_per_m", "axial_stiffness_n_per_m", "life_used_per_s", "friction_torque_n_m")


@dataclass(frozen=True)
class MapPoint:
    speed_rpm: float
    radial_load_n: float
    clearance_um: float
    eccentricity_um: float
    preload_n: float
    mean_reward: float
    mean_vibration: float
    mean_heat: float
    mean_fatigue: float
    quasi_periodic_fraction: float
    max_qpi: float
    mean_qpi: float
    mean_nonsync_rms_um: float
    terminated: bool
    #: means over the measured intervals (NaN in a CSV written before they were recorded)
    radial_stiffness_n_per_m: float = math.nan
    axial_stiffness_n_per_m: float = math.nan
    life_used_per_s: float = math.nan
    friction_torque_n_m: float = math.nan

    @property
    def period1(self) -> bool:
        return not self.terminated and self.quasi_periodic_fraction == 0.0

    @property
    def cell(self) -> tuple[float, float, float, float]:
        """(speed rpm, radial load N, clearance um, eccentricity um): the operating point."""
        return (self.speed_rpm, self.radial_load_n, self.clearance_um, self.eccentricity_um)


def measure_cell(speed_rpm: float, radial_n: float, clearance_m: float, eccentricity_m: float,
                 preloads: tuple[float, ...], measure_intervals: int, reward, params) -> list[MapPoint]:
    """Every preload of one operating point (no waviness), one batch: settled at the preload as
    ``reset`` does, then held ``measure_intervals`` control intervals, each scored by ``reward``
    (a reward model of the env; its terms and the interval's index averaged). ``params``: the base
    physics (None: the env's)."""
    parts = tier_parts("stationary")
    batch = PreloadBatch(len(preloads), params, CONTROL_DT_S, parts["actuator"])
    for b, p in enumerate(preloads):
        batch.load(b, Scenario(speed_profile=((0.0, speed_rpm),), radial_load_profile=((0.0, radial_n),),
                               clearance_m=clearance_m, eccentricity_m=eccentricity_m, initial_preload_n=p))
    idx = np.arange(len(preloads))
    batch.settle(idx)
    setpoints = np.array(preloads, dtype=float)
    terms_sum = {k: np.zeros(len(preloads)) for k in ("vibration", "heat", "fatigue")}
    total = np.zeros(len(preloads))
    qp = np.zeros(len(preloads))
    qpi_max = np.zeros(len(preloads))
    qpi_sum = np.zeros(len(preloads))
    ns_sum = np.zeros(len(preloads))
    eng = {k: np.zeros(len(preloads)) for k in ENGINEERING}
    failed = batch.start_failed.copy()
    for k in range(measure_intervals):
        before = batch.preload.copy()
        batch.step(setpoints, ~failed)
        failed |= batch.status != 0
        m = measurement(batch, idx, before, np.full(len(idx), measure_intervals - k - 1), failed)
        r, terms = reward(m)
        total += r
        for name in terms_sum:
            terms_sum[name] += terms[name]
        qp += m.quasi_periodic
        qpi_max = np.maximum(qpi_max, m.qpi)
        qpi_sum += m.qpi
        ns_sum += batch.feats[:, F_NS_RMS]
        for k in ENGINEERING:
            eng[k] += getattr(m, k)
    n = measure_intervals
    return [MapPoint(speed_rpm, radial_n, clearance_m * 1e6, eccentricity_m * 1e6, float(p),
                     float(total[b] / n), float(terms_sum["vibration"][b] / n), float(terms_sum["heat"][b] / n),
                     float(terms_sum["fatigue"][b] / n), float(qp[b] / n), float(qpi_max[b]),
                     float(qpi_sum[b] / n), float(ns_sum[b] / n * 1e6), bool(failed[b]),
                     *(float(eng[k][b] / n) for k in ENGINEERING))
            for b, p in enumerate(preloads)]


def reward_map(speeds_rpm=GRID_SPEEDS_RPM, radial_loads_n=GRID_RADIAL_LOADS_N,
               clearances_m=GRID_CLEARANCES_M, preloads_n=GRID_PRELOADS_N,
               measure_intervals: int = MEASURE_INTERVALS, reward=None, progress=None,
               params=None, eccentricities_m=GRID_ECCENTRICITIES_M) -> list[MapPoint]:
    """The map over the grid (every preload of a cell in one batch: numba threads over them).
    ``params``: the env's base physics (default :func:`~bearing_gym.envs.env_params`; another
    integrator step gives the map that ``benchmarks/bench_accuracy.py`` compares with).
    ``eccentricities_m``: the rotor unbalance axis in metres (each in (0, 1e-3], the range of
    ``Scenario.eccentricity_m``; e.g. ``(10e-6,)`` for the paper's slice alone)."""
    from bearing_gym.validation import check_real_tuple
    eccentricities = check_real_tuple("reward_map eccentricities_m (metres)", eccentricities_m, 0.0, 1e-3)
    if not eccentricities or min(eccentricities) <= 0.0:
        raise ValueError(f"reward_map eccentricities_m must be one or more eccentricities in (0, 1e-3] m, "
                         f"got {eccentricities_m!r}")
    reward = reward if reward is not None else tier_parts("stationary")["reward"]
    points: list[MapPoint] = []
    cells = list(itertools.product(speeds_rpm, radial_loads_n, clearances_m, eccentricities))
    for k, (v, f, c, e) in enumerate(cells):
        points += measure_cell(float(v), float(f), float(c), e, tuple(preloads_n), measure_intervals,
                               reward, params)
        if progress is not None:
            progress(k + 1, len(cells))
    return points


def cells_of(points: list[MapPoint]) -> dict[tuple, list[MapPoint]]:
    out: dict[tuple, list[MapPoint]] = {}
    for p in points:
        out.setdefault(p.cell, []).append(p)
    return {k: sorted(v, key=lambda p: p.preload_n) for k, v in out.items()}


def best_preloads(points: list[MapPoint]) -> dict[tuple, MapPoint]:
    """Per cell, the preload of the highest stationary reward."""
    return {cell: max(pts, key=lambda p: p.mean_reward) for cell, pts in cells_of(points).items()}


def period1_windows(pts: list[MapPoint], step_n: float = 100.0) -> list[tuple[float, float]]:
    """The contiguous preload ranges (N) of one cell in which the motion is period-1."""
    windows: list[tuple[float, float]] = []
    for p in sorted(pts, key=lambda p: p.preload_n):
        if not p.period1:
            continue
        if windows and math.isclose(p.preload_n - windows[-1][1], step_n):
            windows[-1] = (windows[-1][0], p.preload_n)
        else:
            windows.append((p.preload_n, p.preload_n))
    return windows


def write_csv(points: list[MapPoint], path: str | Path) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS + ENGINEERING)
        for p in points:
            w.writerow([getattr(p, c) if not isinstance(getattr(p, c), float) else f"{getattr(p, c):.6g}"
                        for c in COLUMNS + ENGINEERING])


def read_csv(path: str | Path) -> list[MapPoint]:
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return [MapPoint(**{c: (r[c] == "True") if c == "terminated" else float(r[c])
                        for c in COLUMNS + ENGINEERING if c in r}) for r in rows]


def plot(points: list[MapPoint], path: str | Path) -> None:
    """One panel per (eccentricity, speed): a row of panels per eccentricity, a column per
    speed; in each, preload (x) against the 9 (radial load, clearance) cells (y), coloured by
    the stationary reward, quasi-periodic points crossed, each cell's best ringed."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    speeds = sorted({p.speed_rpm for p in points})
    eccentricities = sorted({p.eccentricity_um for p in points})
    cells = cells_of(points)
    best = best_preloads(points)
    fig = Figure(figsize=(4.2 * len(speeds) + 2.4, 3.3 * len(eccentricities) + 1.0), layout="constrained")
    FigureCanvasAgg(fig)
    axes = np.atleast_2d(fig.subplots(len(eccentricities), len(speeds), sharex=True, sharey=True, squeeze=False))
    vmin = min(p.mean_reward for p in points if not p.terminated)
    norm = matplotlib.colors.Normalize(vmin=max(vmin, -6.0), vmax=0.0)
    sc = None
    for i, e in enumerate(eccentricities):
        for j, v in enumerate(speeds):
            ax = axes[i, j]
            rows = sorted(c for c in cells if c[0] == v and c[3] == e)
            for y, cell in enumerate(rows):
                pts = cells[cell]
                x = [p.preload_n for p in pts]
                sc = ax.scatter(x, [y] * len(x), c=[p.mean_reward for p in pts], cmap="viridis", norm=norm, s=40)
                qx = [p.preload_n for p in pts if not p.period1]
                ax.scatter(qx, [y] * len(qx), marker="x", color="red", s=22, lw=1.1)
                ax.scatter([best[cell].preload_n], [y], facecolors="none", edgecolors="black", s=110, lw=1.3)
            ax.set_yticks(range(len(rows)), [f"{c[1]:.0f} N, {c[2]:.0f} um" for c in rows], fontsize=8)
            ax.tick_params(axis="x", labelsize=8)
            ax.set_title(f"{v:,.0f} rpm, unbalance e = {e:g} um", fontsize=10)
            if i == len(eccentricities) - 1:
                ax.set_xlabel("constant preload (N)")
        axes[i, 0].set_ylabel("radial load, clearance")
    if sc is not None:
        fig.colorbar(sc, ax=axes, label="stationary reward per 20 ms interval", shrink=0.6)
    fig.suptitle("Reward map: rows = rotor unbalance (eccentricity), columns = shaft speed\n"
                 "x = quasi-periodic (some interval with index > 0.1), ring = best preload of the cell")
    fig.savefig(path, dpi=80)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="docs/reward_map.csv", help="CSV to write (a PNG beside it)")
    ap.add_argument("--plot-only", action="store_true", help="redraw the PNG from an existing CSV")
    ap.add_argument("--eccentricities-um", nargs="+", type=float, metavar="UM",
                    help="the rotor unbalance axis (mass-centre eccentricity, um; default "
                         f"{' '.join(f'{e * 1e6:g}' for e in GRID_ECCENTRICITIES_M)}; e.g. 0.4 1 2.5: G0.4 at 10,000 rpm "
                         "to G6.5 at 25,000 rpm)")
    args = ap.parse_args(argv)
    if args.plot_only:
        pts = read_csv(args.out)
    else:
        ecc = GRID_ECCENTRICITIES_M if not args.eccentricities_um else tuple(e * 1e-6 for e in args.eccentricities_um)
        pts = reward_map(progress=lambda k, n: print(f"cell {k}/{n}", flush=True), eccentricities_m=ecc)
        write_csv(pts, args.out)
    plot(pts, Path(args.out).with_suffix(".png"))
    print(f"wrote {args.out} and {Path(args.out).with_suffix('.png')}")


if __name__ == "__main__":
    main()
