"""The preload map: for a grid of operating points, which constant preload keeps the rotor
period-1, which of those the reward's secondary costs prefer, and with how much margin.

A spindle engineer's first question - *for my speeds and loads, which preload keeps the rotor out
of trouble, and with how much margin?* - answered from the env's own physics. Per operating point
(shaft speed, radial load, clearance, rotor unbalance; no waviness) every preload of the grid is
started settled and held (:func:`bearing_gym.envs.reward_map.measure_cell`: the reward map's
measurement, ``MEASURE_INTERVALS`` control intervals of 20 ms each), and the row reports

* ``lowest_period1_n``: the lowest preload of the grid at which no measured interval is
  quasi-periodic (index <= ``QPI_THRESHOLD``);
* ``preferred_n``: among the period-1 preloads, the one whose secondary costs (the reward's heat
  and fatigue terms, :class:`~bearing_gym.envs.reward.VibrationFirstReward`) are lowest - the
  vibration term is zero-ish on every period-1 point, so this is what the reward prefers there
  (ties: the lower preload);
* ``margin_below_n`` / ``margin_above_n``: the distance from ``preferred_n`` to the nearest
  quasi-periodic preload of the grid below / above it (empty where the grid has none on that side:
  no window within the actuator's range); a margin is known to the grid step (the true edge lies
  between the last period-1 and the first quasi-periodic preload);
* at ``preferred_n``: the bearing's radial and axial stiffness (N/um: (K_xx + K_yy) / 2 and K_zz
  of :func:`bearing_gym.physics.static_equilibrium` at the operating point without unbalance, the
  stiffness a catalogue quotes), its L10 life in hours there (Lundberg-Palmgren from the measured
  contact loads, the balls' centrifugal force included: the reward's fatigue term) and Palmgren's
  friction torque M_1 (N m).

With ``min_margin_n`` > 0 the preferred preload is the cheapest period-1 preload with at least that
margin to a quasi-periodic preload on each side (the cheapest period-1 preload is usually the
lowest, one grid step above a quasi-periodic window: a choice on a knife edge); NaN where none has.

:func:`preload_map` computes the rows (the cells as tasks of :func:`bearing_gym.analysis.sweeps.run_tasks`:
a process pool or a Ray cluster, progress shown); ``bearing-gym preload-map`` is the command.
"""

from __future__ import annotations

import csv
import itertools
import math
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any, Sequence

from bearing_gym.envs.reward_map import MEASURE_INTERVALS, MapPoint, measure_cell

__all__ = ["PreloadMapRow", "cell_row", "static_stiffness", "preload_map", "map_points", "write_csv", "read_csv", "plot", "DEFAULT_PRELOADS_N",
           "COLUMNS"]

#: the actuator's whole range on a 50 N grid (the protocol's hindsight grid)
DEFAULT_PRELOADS_N = tuple(float(p) for p in range(300, 2001, 50))


@dataclass(frozen=True)
class PreloadMapRow:
    """One operating point of the map (module docstring); NaN where nothing qualifies."""

    speed_rpm: float
    radial_load_n: float
    clearance_um: float
    eccentricity_um: float
    lowest_period1_n: float
    preferred_n: float
    margin_below_n: float
    margin_above_n: float
    radial_stiffness_n_per_um: float
    axial_stiffness_n_per_um: float
    l10_life_h: float
    friction_torque_n_m: float
    period1_preloads: int
    grid_preloads: int
    grid_step_n: float


COLUMNS = tuple(f.name for f in fields(PreloadMapRow))


def _secondary_cost(p: MapPoint) -> float:
    """The reward's secondary costs per interval (positive): heat and fatigue."""
    return -(p.mean_heat + p.mean_fatigue)


def cell_row(points: Sequence[MapPoint], min_margin_n: float = 0.0, stiffness=None) -> PreloadMapRow:
    """The map's row of one operating point from its measured preloads. ``stiffness``: a function
    of the preload giving (radial, axial) stiffness in N/m (default: the measured means)."""
    pts = sorted(points, key=lambda p: p.preload_n)
    if not pts:
        raise ValueError("cell_row needs the measured points of one operating point")
    speed, radial, clearance, ecc = pts[0].cell
    grid = [p.preload_n for p in pts]
    step = min((b - a for a, b in zip(grid, grid[1:])), default=math.nan)
    good = [p for p in pts if p.period1]
    nan = math.nan
    if not good:
        return PreloadMapRow(speed, radial, clearance, ecc, nan, nan, nan, nan, nan, nan, nan, nan, 0, len(pts), step)
    bad = [p.preload_n for p in pts if not p.period1]

    def margins(x: float) -> tuple[float, float]:
        below, above = [b for b in bad if b < x], [b for b in bad if b > x]
        return (x - max(below) if below else math.inf), (min(above) - x if above else math.inf)

    wide = [p for p in good if min(margins(p.preload_n)) >= min_margin_n]
    if not wide:
        return PreloadMapRow(speed, radial, clearance, ecc, good[0].preload_n, nan, nan, nan, nan, nan, nan, nan,
                             len(good), len(pts), step)
    best = min(wide, key=lambda p: (_secondary_cost(p), p.preload_n))
    lo, hi = margins(best.preload_n)
    k_radial, k_axial = (stiffness(best.preload_n) if stiffness is not None
                         else (best.radial_stiffness_n_per_m, best.axial_stiffness_n_per_m))
    life = best.life_used_per_s
    return PreloadMapRow(
        speed, radial, clearance, ecc, good[0].preload_n, best.preload_n,
        nan if math.isinf(lo) else lo, nan if math.isinf(hi) else hi, k_radial * 1e-6, k_axial * 1e-6,
        1.0 / (3600.0 * life) if life > 0.0 else math.inf, best.friction_torque_n_m, len(good), len(pts), step)


def static_stiffness(speed_rpm: float, radial_n: float, clearance_m: float, preload_n: float,
                     params=None) -> tuple[float, float]:
    """(radial, axial) stiffness (N/m) of the bearing at its quasi-static equilibrium at this
    operating point: (K_xx + K_yy) / 2 and K_zz of :func:`bearing_gym.physics.static_equilibrium`."""
    from bearing_gym.physics import static_equilibrium
    from bearing_gym.envs.core import env_params, scenario_params
    from bearing_gym.envs.scenario import Scenario
    sc = Scenario(speed_profile=((0.0, speed_rpm),), radial_load_profile=((0.0, radial_n),), clearance_m=clearance_m,
                  eccentricity_m=0.0, initial_preload_n=preload_n)
    K = static_equilibrium(scenario_params(params if params is not None else env_params(), sc)).stiffness
    return 0.5 * (float(K[0, 0]) + float(K[1, 1])), float(K[2, 2])


def _cell_task(speed_rpm: float, radial_n: float, clearance_m: float, eccentricity_m: float,
               preloads: tuple[float, ...], measure_intervals: int, params,
               min_margin_n: float) -> tuple[PreloadMapRow, list[MapPoint]]:
    import numba
    from bearing_gym.envs.tiers import tier_parts
    threads = numba.get_num_threads()
    numba.set_num_threads(1)                    # one task per core (restored: a task may run in the caller)
    try:
        pts = measure_cell(speed_rpm, radial_n, clearance_m, eccentricity_m, preloads, measure_intervals,
                           tier_parts("stationary")["reward"], params)
    finally:
        numba.set_num_threads(threads)
    row = cell_row(pts, min_margin_n,
                   lambda p: static_stiffness(speed_rpm, radial_n, clearance_m, p, params))
    return row, pts


def preload_map(speeds_rpm: Sequence[float], radial_loads_n: Sequence[float] = (0.0,),
                clearances_m: Sequence[float] = (4e-6,), eccentricities_m: Sequence[float] = (10e-6,),
                preloads_n: Sequence[float] = DEFAULT_PRELOADS_N, measure_intervals: int = MEASURE_INTERVALS,
                params=None, executor=None, workers: int | None = None, progress: bool = True,
                min_margin_n: float = 0.0) -> tuple[list[PreloadMapRow], list[MapPoint]]:
    """(the map's rows, every measured point) over the grid (module docstring). ``executor``: a
    ``concurrent.futures``-style executor (e.g. :class:`bearing_gym.analysis.ray_backend.RayExecutor`);
    default a pool of ``workers`` processes. ``params``: the bearing and rotor (default: the env's)."""
    from bearing_gym.validation import check_real_tuple
    speeds = check_real_tuple("preload map speeds (rpm)", speeds_rpm, 1000.0, 60000.0)
    loads = check_real_tuple("preload map radial loads (N)", radial_loads_n, 0.0, 5000.0)
    clear = check_real_tuple("preload map clearances (m)", clearances_m, 0.0, 1e-4)
    ecc = check_real_tuple("preload map unbalances (eccentricity, m)", eccentricities_m, 0.0, 1e-3)
    pre = check_real_tuple("preload map preloads (N)", preloads_n, 0.0, 1e5)
    if not (speeds and loads and clear and ecc) or len(pre) < 2:
        raise ValueError("preload map: give at least one speed, radial load, clearance and unbalance, and at "
                         "least two preloads")
    if list(pre) != sorted(set(pre)):
        raise ValueError(f"preload map preloads must be increasing, got {list(pre)}")
    if isinstance(measure_intervals, bool) or not isinstance(measure_intervals, int) or measure_intervals < 1:
        raise ValueError(f"preload map measure_intervals must be an integer >= 1, got {measure_intervals!r}")
    from bearing_gym.validation import check_real
    margin = check_real("preload map min_margin_n (N)", min_margin_n, 0.0, 1e5)
    return map_points(list(itertools.product(speeds, loads, clear, ecc)), pre, measure_intervals, params, executor,
                      workers, progress, margin)


def map_points(cells: Sequence[tuple[float, float, float, float]], preloads_n: Sequence[float],
               measure_intervals: int = MEASURE_INTERVALS, params=None, executor=None, workers: int | None = None,
               progress: bool = True, min_margin_n: float = 0.0) -> tuple[list[PreloadMapRow], list[MapPoint]]:
    """The map's rows of any list of operating points (speed rpm, radial load N, clearance m,
    eccentricity m), in order, one task each (:func:`preload_map` checks its arguments and passes
    the grid's product here)."""
    from bearing_gym.analysis.sweeps.runner import run_tasks
    tasks = [(float(v), float(f), float(c), float(e), tuple(preloads_n), measure_intervals, params, float(min_margin_n))
             for v, f, c, e in cells]
    done = run_tasks(_cell_task, tasks, executor=executor, max_workers=workers, progress=progress,
                     desc="preload map")
    return [row for row, _ in done], [p for _, pts in done for p in pts]


def write_csv(rows: Sequence[PreloadMapRow], path: str | Path) -> Path:
    path = Path(path)
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS)
        for r in rows:
            w.writerow(["" if isinstance(v, float) and math.isnan(v) else f"{v:.6g}" if isinstance(v, float) else v
                        for v in asdict(r).values()])
    return path


def read_csv(path: str | Path) -> list[PreloadMapRow]:
    with Path(path).open(newline="") as fh:
        out = []
        for r in csv.DictReader(fh):
            vals: dict[str, Any] = {}
            for f in fields(PreloadMapRow):
                v = r[f.name]
                vals[f.name] = int(v) if f.type in (int, "int") else (math.nan if v == "" else float(v))
            out.append(PreloadMapRow(**vals))
    return out


def plot(rows: Sequence[PreloadMapRow], points: Sequence[MapPoint], path: str | Path) -> Path:
    """One panel per (clearance, unbalance): preload (x) against speed and radial load (y), each
    grid preload a dot (green period-1, red quasi-periodic), the preferred preload a black ring
    and its margins as a bar to the nearest quasi-periodic preloads."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    panels = sorted({(r.clearance_um, r.eccentricity_um) for r in rows})
    fig = Figure(figsize=(7.5, 0.5 + 0.42 * len(rows) / max(len(panels), 1) * len(panels) + 1.2 * len(panels)),
                 layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(panels), 1, squeeze=False)[:, 0]
    for ax, (c, e) in zip(axes, panels):
        mine = sorted((r for r in rows if (r.clearance_um, r.eccentricity_um) == (c, e)),
                      key=lambda r: (r.speed_rpm, r.radial_load_n))
        for y, r in enumerate(mine):
            pts = [p for p in points if p.cell == (r.speed_rpm, r.radial_load_n, r.clearance_um, r.eccentricity_um)]
            ax.scatter([p.preload_n for p in pts if p.period1], [y] * sum(p.period1 for p in pts), s=9, color="tab:green")
            ax.scatter([p.preload_n for p in pts if not p.period1], [y] * sum(not p.period1 for p in pts), s=9,
                       color="tab:red", marker="x")
            if not math.isnan(r.preferred_n):
                lo = r.preferred_n - (r.margin_below_n if not math.isnan(r.margin_below_n) else 0.0)
                hi = r.preferred_n + (r.margin_above_n if not math.isnan(r.margin_above_n) else 0.0)
                ax.plot([lo, hi], [y, y], color="black", lw=0.8)
                ax.scatter([r.preferred_n], [y], s=70, facecolors="none", edgecolors="black", lw=1.3)
        ax.set_yticks(range(len(mine)), [f"{r.speed_rpm:,.0f} rpm, {r.radial_load_n:.0f} N" for r in mine], fontsize=8)
        ax.set_title(f"clearance {c:g} um, unbalance {e:g} um", fontsize=9)
        ax.grid(axis="x", alpha=0.3)
    axes[-1].set_xlabel("constant preload (N): green = period-1, red x = quasi-periodic, ring = preferred, "
                        "bar = its margins", fontsize=8)
    fig.savefig(path, dpi=100)
    return Path(path)
