"""Parameter sweeps: preload continuation, cold starts and stability maps (paper sections
3.2-3.4, Figs 7, 15-17).

Two ways to reach the steady response at a preload P, which give *different* answers near the
stability boundary because a stable period-1 orbit coexists there with large quasi-periodic or
chaotic motion (paper-notes, "Multistability"):

* **continuation** (:func:`continuation_chain`): each point starts from the end state of the
  previous one (``Simulator.state``), so a descending chain follows the period-1 orbit until it
  loses stability. Its critical preload is the bifurcation of the periodic orbit. With
  ``refine_step_n`` the chain, on the first loss of stability, goes back to the last periodic
  state and steps down by the finer step to bracket the boundary more tightly.
* **cold start** (:func:`cold_start_point`): every point starts from the static equilibrium
  (no unbalance response yet), as a machine does when it is run up at that preload. Cold
  starts can wander for a long time before settling; the outcome is the state after
  ``SweepSettings.cold_settle_s``.

Each point is measured over ``measure_s`` after the settling time: quasi-periodicity index of
(x, y, z) (:func:`.signals.quasi_periodicity_index`), peak-to-peak and RMS of x, y, z, mean,
peak-to-peak and maximum of the cage speed, the fewest balls touching the inner race, and (if
``floquet``) the Floquet multipliers of the end state (:func:`.floquet.simulator_floquet`): the
largest modulus, its angle per shaft period and the two coordinates that dominate its
eigenvector (``floquet_max_mode``), and the least stable axial pair (:func:`axial_pair`). A
point is **periodic** when its index is below ``qpi_threshold`` *and*, when the multipliers were
computed, all of them lie inside the unit circle.

**Damping**: each point builds its Simulator from ``base.replace(axial_preload_n=P, ...)``, so
with the default damping model (``params.Damping``: ratio ζ on each rotor DOF's uncoupled,
non-rotating mode) the coefficients are referred to the static stiffness *at that point*; pass
``damping_coefficients`` in ``base`` to keep them fixed over the sweep. The ``damping_ratio``
column records ζ (NaN when fixed coefficients are used).

Points run in parallel (one continuation chain or one cold start per task) on a pluggable
executor with the ``concurrent.futures.Executor`` interface (``submit`` returning an object with
``result()``); the default is a ``ProcessPoolExecutor`` over the local cores, and
:class:`.ray_backend.RayExecutor` runs them on a Ray cluster (several machines). Results are lists
of dicts with the columns of :data:`COLUMNS`, saved with :func:`save_csv` or :func:`save_npz`.
"""

from __future__ import annotations

import concurrent.futures as cf
import csv
import itertools
import math
import os
import time
from dataclasses import asdict, dataclass
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from bearing_gym.params import BearingParams

from .signals import quasi_periodicity_index

__all__ = ["COLUMNS", "SweepSettings", "SerialExecutor", "measure_point", "axial_pair", "continuation_chain",
           "cold_start_point", "run_tasks", "stability_map", "critical_preload",
           "stable_windows", "save_csv", "load_csv", "save_npz", "plot_sweep",
           "plot_stability_map"]

COLUMNS = ("label", "mode", "order", "shaft_speed_rpm", "axial_preload_n", "radial_load_x_n",
           "radial_load_y_n", "clearance_m", "damping_ratio", "eccentricity_m", "qpi",
           "periodic", "ptp_x_m", "ptp_y_m", "ptp_z_m", "rms_x_m", "rms_y_m", "rms_z_m",
           "mean_z_m", "cage_mean_rad_s", "cage_ptp_rad_s", "cage_max_rad_s",
           "min_inner_contacts", "floquet_max_modulus", "floquet_max_angle_deg",
           "floquet_max_mode", "floquet_axial_modulus", "floquet_axial_angle_deg", "refined",
           "status", "wall_s")


@dataclass(frozen=True)
class SweepSettings:
    """Durations (s) and criteria of a sweep point.

    ``settle_s``: time run before measuring in a continuation point; ``cold_settle_s``: the same
    for a cold start (longer: it starts from the static equilibrium); ``measure_s``: the
    measured window (>= 3 shaft periods); ``qpi_threshold``: index above which the motion is
    not period-1 (periodic motion settles at 0.00-0.04, quasi-periodic at 0.2-1);
    ``floquet``: compute the multipliers at points whose index is below the threshold;
    ``refine_step_n``: finer preload step used to bracket the first loss of stability in a
    descending continuation chain (None: no refinement).
    """

    settle_s: float = 0.3
    measure_s: float = 0.1
    cold_settle_s: float = 0.5
    qpi_threshold: float = 0.1
    floquet: bool = True
    refine_step_n: float | None = None

    def __post_init__(self) -> None:
        for name in ("settle_s", "measure_s", "cold_settle_s"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v >= 0 and math.isfinite(v)):
                raise ValueError(f"SweepSettings.{name} must be a finite number >= 0, got {v!r}")
        if not self.measure_s > 0:
            raise ValueError("SweepSettings.measure_s must be > 0 (at least 3 shaft periods)")
        if self.refine_step_n is not None and not self.refine_step_n > 0:
            raise ValueError("SweepSettings.refine_step_n must be > 0 or None")


class SerialExecutor:
    """In-process executor with the ``concurrent.futures`` interface (for tests, debugging and
    profiling): ``submit`` runs the call at once and returns a finished Future."""

    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> cf.Future:
        fut: cf.Future = cf.Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as err:  # noqa: BLE001 - handed to the caller through the Future
            fut.set_exception(err)
        return fut

    def shutdown(self, wait: bool = True) -> None:  # noqa: D401 - interface
        return None

    def __enter__(self) -> "SerialExecutor":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.shutdown()


# ---------------------------------------------------------------------------------------------
# one point
# ---------------------------------------------------------------------------------------------
def _operating_point(params: BearingParams) -> dict:
    g = params.geometry
    coeffs = params.damping.coefficients
    return dict(shaft_speed_rpm=params.shaft_speed_rpm,
                axial_preload_n=params.loads.axial_preload_n,
                radial_load_x_n=params.loads.radial_load_x_n,
                radial_load_y_n=params.loads.radial_load_y_n,
                clearance_m=g.clearance_inner_m if g.clearance_inner_m == g.clearance_outer_m
                else math.nan,
                damping_ratio=params.damping.damping_ratio if coeffs is None else math.nan,
                eccentricity_m=params.rotor.eccentricity_m)


AXIAL_SHARE = 0.2


def axial_pair(res) -> tuple[float, float]:
    """Modulus and angle (deg, 0-180) of the least stable *axial* multiplier pair: the largest
    |μ| among the pairs whose scaled eigenvector has at least ``AXIAL_SHARE`` (20 %) of its
    weight in (z, z_dot) (or, if none has, the pair with the largest such share). In the
    default configuration this mode family loses stability at the critical preload; near it
    two axial pairs exchange character (veering), which is why a share threshold is used
    rather than the single most axial pair."""
    share = res.share(("z", "z_dot"))
    mods = np.abs(res.multipliers)
    cand = np.flatnonzero(share >= AXIAL_SHARE)
    k = int(cand[np.argmax(mods[cand])]) if cand.size else int(np.argmax(share))
    mu = res.multipliers[k]
    return float(abs(mu)), float(abs(math.degrees(np.angle(mu))))


def measure_point(sim, settings: SweepSettings, settle_s: float) -> tuple[dict, Any]:
    """Advance ``sim`` by ``settle_s``, record ``settings.measure_s`` and return the metrics
    (the measured columns of :data:`COLUMNS`) and the record."""
    from bearing_gym.physics import SimulationError

    t0 = time.perf_counter()
    row: dict = dict(status="ok")
    try:
        if settle_s > 0:
            sim.advance(settle_s)
        rec = sim.advance(settings.measure_s)
    except SimulationError as err:
        row.update(status=str(err), qpi=math.nan, periodic=False, wall_s=time.perf_counter() - t0)
        return row, None
    w = sim.shaft_speed_rpm * math.pi / 30.0
    xyz = np.column_stack([rec.x, rec.y, rec.z])
    q = quasi_periodicity_index(rec.t, xyz, w)
    ptp = np.ptp(xyz, axis=0)
    rmsv = np.std(xyz, axis=0)
    row.update(qpi=q, ptp_x_m=ptp[0], ptp_y_m=ptp[1], ptp_z_m=ptp[2], rms_x_m=rmsv[0],
               rms_y_m=rmsv[1], rms_z_m=rmsv[2], mean_z_m=float(np.mean(rec.z)),
               cage_mean_rad_s=float(np.mean(rec.cage_speed)),
               cage_ptp_rad_s=float(np.ptp(rec.cage_speed)),
               cage_max_rad_s=float(np.max(rec.cage_speed)),
               min_inner_contacts=int(np.min(rec.n_inner_contacts)))
    periodic = bool(q < settings.qpi_threshold)
    row.update(floquet_max_modulus=math.nan, floquet_max_angle_deg=math.nan, floquet_max_mode="",
               floquet_axial_modulus=math.nan, floquet_axial_angle_deg=math.nan)
    if settings.floquet and periodic and w > 0:
        from .floquet import simulator_floquet
        try:
            res = simulator_floquet(sim)
        except Exception as err:  # noqa: BLE001 - a failed FD run is reported, not fatal
            row["status"] = f"floquet failed: {err}"
        else:
            lead = res.multipliers[0]
            row.update(floquet_max_modulus=abs(lead),
                       floquet_max_angle_deg=abs(math.degrees(np.angle(lead))),
                       floquet_max_mode="+".join(lab for lab, _ in res.modes()[0]["dominant"]))
            am, aa = axial_pair(res)
            row.update(floquet_axial_modulus=am, floquet_axial_angle_deg=aa)
            periodic = periodic and res.stable
    row["periodic"] = periodic
    row["wall_s"] = time.perf_counter() - t0
    return row, rec


def _simulator(params: BearingParams, state=None):
    from bearing_gym.physics import Simulator

    sim = Simulator(params)
    if state is not None:
        sim.state = state
    return sim


def cold_start_point(params: BearingParams, settings: SweepSettings = SweepSettings(),
                     label: str = "") -> dict:
    """One point started from the static equilibrium (see the module docstring)."""
    sim = _simulator(params)
    row, _ = measure_point(sim, settings, settings.cold_settle_s)
    return {**dict(label=label, mode="cold", order=0, refined=False),
            **_operating_point(params), **row}


def continuation_chain(base: BearingParams, preloads: Sequence[float],
                       settings: SweepSettings = SweepSettings(), label: str = "",
                       start_state=None, first_settle_s: float | None = None) -> list[dict]:
    """Preload continuation: point k starts from the end state of point k-1.

    The first point starts from ``start_state`` or, by default, from the static equilibrium and
    is settled for ``first_settle_s`` (default ``settings.cold_settle_s``). A point whose
    integration fails is reported with its ``status`` and the next one starts from its own
    static equilibrium. Rows come in chain order (``order`` column); rows added by the
    refinement of the first loss of stability have ``refined=True``.
    """
    rows: list[dict] = []
    state = start_state
    prev_periodic_state = None
    prev_periodic_p = None
    refined_done = False
    order = 0

    def run(p: float, st, settle: float, refined: bool) -> tuple[dict, Any]:
        nonlocal order
        params = base.replace(axial_preload_n=float(p))
        sim = _simulator(params, st)
        row, _ = measure_point(sim, settings, settle)
        out = {**dict(label=label, mode="continuation", order=order, refined=refined),
               **_operating_point(params), **row}
        order += 1
        return out, (sim.state if row["status"] == "ok" or row["status"].startswith("floquet") else None)

    for k, p in enumerate(preloads):
        settle = settings.settle_s if (k > 0 or start_state is not None) else \
            (settings.cold_settle_s if first_settle_s is None else first_settle_s)
        if state is None and k > 0:
            settle = settings.cold_settle_s
        row, state = run(p, state, settle, False)
        lost = not row["periodic"]
        if (lost and not refined_done and settings.refine_step_n and prev_periodic_state is not None
                and prev_periodic_p > p):
            # bracket the first loss of stability: back to the last periodic state, finer steps
            refined_done = True
            q = prev_periodic_p - settings.refine_step_n
            st = prev_periodic_state
            while q > p + 1e-9:
                r2, st2 = run(q, st, settings.settle_s, True)
                rows.append(r2)
                if not r2["periodic"] or st2 is None:
                    break
                st = st2
                q -= settings.refine_step_n
        rows.append(row)
        if row["periodic"] and state is not None:
            prev_periodic_state, prev_periodic_p = state, p
    return rows


# ---------------------------------------------------------------------------------------------
# running many points
# ---------------------------------------------------------------------------------------------
def _progress(total: int, desc: str, enabled: bool):
    if not enabled:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return _PlainProgress(total, desc)
    return tqdm(total=total, desc=desc, unit="task")


class _PlainProgress:
    def __init__(self, total: int, desc: str):
        self.total, self.desc, self.n, self.t0 = total, desc, 0, time.perf_counter()

    def update(self, k: int = 1) -> None:
        self.n += k
        print(f"{self.desc}: {self.n}/{self.total} tasks, {time.perf_counter() - self.t0:.0f} s",
              flush=True)

    def close(self) -> None:
        pass


def run_tasks(fn: Callable, arg_list: Sequence[tuple], executor=None, max_workers: int | None = None,
              progress: bool = True, desc: str = "sweep") -> list:
    """``[fn(*args) for args in arg_list]`` on ``executor`` (any object with the
    ``concurrent.futures.Executor.submit`` interface), in input order, with a progress bar
    (tqdm if installed, else one line per finished task). ``fn`` must be picklable (a module
    level function) for process executors. Default executor: ``ProcessPoolExecutor`` with
    ``max_workers`` (default: ``os.cpu_count()``) workers; with one task or one worker the
    calls run in this process."""
    arg_list = list(arg_list)
    own = executor is None
    if own:
        n = min(max_workers or os.cpu_count() or 1, len(arg_list))
        executor = SerialExecutor() if n <= 1 else cf.ProcessPoolExecutor(max_workers=n)
    bar = _progress(len(arg_list), desc, progress)
    try:
        futures = [executor.submit(fn, *args) for args in arg_list]
        if all(isinstance(f, cf.Future) for f in futures):
            for _ in cf.as_completed(futures):
                if bar is not None:
                    bar.update(1)
        results = []
        for f in futures:
            results.append(f.result())
            if bar is not None and not isinstance(f, cf.Future):
                bar.update(1)
        return results
    finally:
        if bar is not None:
            bar.close()
        if own:
            executor.shutdown()


def stability_map(base: BearingParams, preloads: Sequence[float], *,
                  shaft_speeds_rpm: Sequence[float] | None = None,
                  radial_loads_n: Sequence[float] | None = None,
                  clearances_m: Sequence[float] | None = None,
                  damping_ratios: Sequence[float] | None = None,
                  mode: str = "continuation", settings: SweepSettings = SweepSettings(),
                  executor=None, max_workers: int | None = None, progress: bool = True) -> list[dict]:
    """Sweep ``preloads`` for every combination of shaft speed, radial load (P_x = P_y, as in
    the paper's section 3.4), clearance (c_i = c_o) and damping ratio (None: keep ``base``).

    ``mode="continuation"``: one chain per combination, in the order of ``preloads`` (give them
    descending to follow the period-1 orbit down to its loss of stability); ``"cold"``: every
    point from its static equilibrium. Returns the rows of all points (columns :data:`COLUMNS`),
    grouped by combination; the ``label`` column names the combination.
    """
    if mode not in ("continuation", "cold"):
        raise ValueError(f"mode must be 'continuation' or 'cold', got {mode!r}")
    combos = []
    for w, pr, c, z in itertools.product(shaft_speeds_rpm or [None], radial_loads_n or [None],
                                         clearances_m or [None], damping_ratios or [None]):
        over: dict = {}
        parts = []
        if w is not None:
            over["shaft_speed_rpm"] = float(w)
            parts.append(f"{w:g}rpm")
        if pr is not None:
            over.update(radial_load_x_n=float(pr), radial_load_y_n=float(pr))
            parts.append(f"Pr{pr:g}N")
        if c is not None:
            over.update(clearance_inner_m=float(c), clearance_outer_m=float(c))
            parts.append(f"c{c * 1e6:g}um")
        if z is not None:
            over["damping_ratio"] = float(z)
            parts.append(f"zeta{z:g}")
        combos.append((base.replace(**over), "_".join(parts) or "base"))
    if mode == "continuation":
        args = [(p, list(preloads), settings, lab) for p, lab in combos]
        chains = run_tasks(continuation_chain, args, executor, max_workers, progress,
                           desc="continuation chains")
        return [row for chain in chains for row in chain]
    args = [(p.replace(axial_preload_n=float(P)), settings, lab) for p, lab in combos for P in preloads]
    rows = run_tasks(cold_start_point, args, executor, max_workers, progress, desc="cold starts")
    for k, r in enumerate(rows):
        r["order"] = k % max(len(preloads), 1)
    return rows


# ---------------------------------------------------------------------------------------------
# reading sweeps
# ---------------------------------------------------------------------------------------------
def _by_preload(rows: Iterable[dict]) -> list[dict]:
    return sorted(rows, key=lambda r: -float(r["axial_preload_n"]))


def critical_preload(rows: Iterable[dict]) -> dict:
    """Critical preload of one sweep (rows of one label): walking down from the highest preload,
    the first point that is not periodic, after at least one that is.

    Returns ``dict(critical_n, bracket_n=(lowest periodic above, highest non-periodic below),
    note)``; ``critical_n`` is the midpoint of the bracket, or NaN with a note when every point
    is periodic ("below the range") or the highest one is not ("at or above the range").
    """
    rs = [r for r in _by_preload(rows) if str(r.get("status", "ok")).startswith(("ok", "floquet"))
          or not _truthy(r["periodic"])]
    if not rs:
        return dict(critical_n=math.nan, bracket_n=(math.nan, math.nan), note="no points")
    if not _truthy(rs[0]["periodic"]):
        return dict(critical_n=math.nan, bracket_n=(math.nan, float(rs[0]["axial_preload_n"])),
                    note="not periodic at the highest preload: critical preload at or above the range")
    for hi, lo in zip(rs, rs[1:]):
        if not _truthy(lo["periodic"]):
            a, b = float(hi["axial_preload_n"]), float(lo["axial_preload_n"])
            return dict(critical_n=0.5 * (a + b), bracket_n=(b, a), note="")
    return dict(critical_n=math.nan, bracket_n=(float(rs[-1]["axial_preload_n"]), math.nan),
                note="periodic at every preload: critical preload below the range")


def stable_windows(rows: Iterable[dict]) -> list[tuple[float, float]]:
    """Intervals [P_lo, P_hi] of consecutive periodic points (rows of one label), highest first."""
    out: list[tuple[float, float]] = []
    cur: list[float] | None = None
    for r in _by_preload(rows):
        p = float(r["axial_preload_n"])
        if _truthy(r["periodic"]):
            cur = [p, p] if cur is None else [p, cur[1]]
        elif cur is not None:
            out.append((cur[0], cur[1]))
            cur = None
    if cur is not None:
        out.append((cur[0], cur[1]))
    return out


def _truthy(v: Any) -> bool:
    if isinstance(v, str):
        return v.strip().lower() in ("true", "1", "yes")
    return bool(v)


def save_csv(rows: Sequence[dict], path: str | os.PathLike) -> None:
    """Write the rows (columns :data:`COLUMNS` first, then any extra keys) to a CSV file."""
    keys = list(COLUMNS) + sorted({k for r in rows for k in r} - set(COLUMNS))
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, restval="")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in r.items()})


def load_csv(path: str | os.PathLike) -> list[dict]:
    """Read a CSV written by :func:`save_csv` (numbers back to float/int, booleans to bool)."""
    out = []
    with open(path, newline="") as fh:
        for r in csv.DictReader(fh):
            row: dict = {}
            for k, v in r.items():
                if v in ("True", "False"):
                    row[k] = v == "True"
                else:
                    try:
                        row[k] = int(v) if v.lstrip("-").isdigit() else float(v)
                    except ValueError:
                        row[k] = v
            out.append(row)
    return out


def save_npz(rows: Sequence[dict], path: str | os.PathLike) -> None:
    """Write the rows as one array per column (strings as unicode arrays)."""
    keys = list(COLUMNS) + sorted({k for r in rows for k in r} - set(COLUMNS))
    arrays = {}
    for k in keys:
        vals = [r.get(k, math.nan) for r in rows]
        if all(isinstance(v, (bool, np.bool_)) for v in vals):
            arrays[k] = np.array(vals, dtype=bool)
        elif all(isinstance(v, (int, float, np.integer, np.floating)) for v in vals):
            arrays[k] = np.array(vals, dtype=float)
        else:
            arrays[k] = np.array([str(v) for v in vals])
    np.savez(path, **arrays)


# ---------------------------------------------------------------------------------------------
# plots (matplotlib imported lazily; the functions return a Figure and draw nothing on screen)
# ---------------------------------------------------------------------------------------------
def plot_sweep(rows: Sequence[dict], quantities: Sequence[str] = ("ptp_x_m", "ptp_z_m", "cage_ptp_rad_s"),
               group: str = "label", title: str = ""):
    """Quantities vs axial preload, one line per ``group`` value; non-periodic points hollow."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 2.2 * len(quantities) + 0.6), layout="constrained")
    axes = fig.subplots(len(quantities), 1, sharex=True, squeeze=False)[:, 0]
    groups: dict = {}
    for r in rows:
        groups.setdefault(r[group], []).append(r)
    for ax, qname in zip(axes, quantities):
        f, unit = (1e6, "um") if qname.endswith("_m") else (1.0, "")
        for k, (g, rs) in enumerate(groups.items()):
            rs = sorted(rs, key=lambda r: float(r["axial_preload_n"]))
            p = np.array([float(r["axial_preload_n"]) for r in rs])
            v = np.array([float(r.get(qname, math.nan)) for r in rs]) * f
            per = np.array([_truthy(r["periodic"]) for r in rs])
            line, = ax.plot(p, v, "-", lw=1, label=str(g))
            ax.plot(p[per], v[per], "o", ms=3.5, color=line.get_color())
            ax.plot(p[~per], v[~per], "o", ms=4, mfc="none", color=line.get_color())
        ax.set_ylabel(qname.replace("_m", f" ({unit})") if unit else qname)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("axial preload P_z (N)")
    axes[0].legend(fontsize=7, ncol=2)
    if title:
        import textwrap
        axes[0].set_title("\n".join(textwrap.wrap(title, 80)), fontsize=9)
    return fig


def plot_stability_map(rows: Sequence[dict], y: str = "shaft_speed_rpm", title: str = ""):
    """Preload (x) against ``y`` (a column, e.g. shaft speed, radial load or clearance): filled
    circles periodic, crosses non-periodic, coloured by the quasi-periodicity index."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    ax = fig.subplots()
    p = np.array([float(r["axial_preload_n"]) for r in rows])
    yv = np.array([float(r[y]) for r in rows])
    if y.endswith("_m"):
        yv = yv * 1e6
    q = np.array([float(r["qpi"]) for r in rows])
    per = np.array([_truthy(r["periodic"]) for r in rows])
    sc = ax.scatter(p[per], yv[per], c=q[per], vmin=0, vmax=1, cmap="viridis", marker="o", s=30,
                    label="period-1 (stable)")
    ax.scatter(p[~per], yv[~per], c=q[~per], vmin=0, vmax=1, cmap="viridis", marker="x", s=30,
               label="not period-1")
    fig.colorbar(sc, ax=ax, label="quasi-periodicity index")
    ax.set_xlabel("axial preload P_z (N)")
    ax.set_ylabel(y.replace("_m", " (um)") if y.endswith("_m") else y)
    ax.legend(fontsize=7, loc="lower left", framealpha=0.9)
    ax.grid(alpha=0.3)
    if title:
        import textwrap
        ax.set_title("\n".join(textwrap.wrap(title, 80)), fontsize=9)
    return fig


def settings_dict(settings: SweepSettings) -> dict:
    """The settings as a plain dict (for reports)."""
    return asdict(settings)
