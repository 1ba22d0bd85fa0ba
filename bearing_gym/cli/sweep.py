"""``bearing-gym sweep``: a stability map written to a CSV file that a rerun resumes (the file
logic is :mod:`bearing_gym.analysis.sweeps.store`; this module maps options to it)."""

from __future__ import annotations

import csv
import importlib.util
import math
import re
from pathlib import Path
from typing import Any, Callable

from bearing_gym.analysis import sweeps
from bearing_gym.analysis.sweeps import SweepSettings, store
from bearing_gym.analysis.sweeps.io import truthy

from .errors import CLIError, RunError, check_option, one_line
from .options import LIST_OPTIONS, make_params, params_from_args
from .output import Out, op_text

__all__ = ["cmd_sweep", "sweep_pool", "check_backend"]

# the option behind each run column of the store (a rerun with another value is refused)
_RUN_OPTIONS = {"settle_s": "--settle-s", "cold_settle_s": "--cold-settle-s",
                "measure_s": "--measure-s", "qpi_threshold": "--qpi-threshold",
                "floquet": "--no-floquet", "refine_step_n": "--refine-step", "dt_s": "--dt-us",
                "race_control": "--race-control"}
assert set(_RUN_OPTIONS) == set(store.RUN_COLUMNS)


def _setting_text(col: str, value: Any) -> str:
    if col == "floquet":
        return "Floquet multipliers" if truthy(value) else "--no-floquet"
    if col == "refine_step_n" and value == "none":
        return "no --refine-step"
    if col == "dt_s":
        return f"--dt-us {float(value) * 1e6:g}"
    return f"{_RUN_OPTIONS[col]} {value:g}" if isinstance(value, float) else f"{_RUN_OPTIONS[col]} {value}"


def sweep_pool(args, n_workers: int, quiet: bool) -> Callable[[], Any]:
    """A function making the executor of the tasks to compute (called only if there is one):
    a process pool (one worker: this process) or a RayExecutor."""
    if args.backend == "ray":
        def ray_pool():
            import logging

            from bearing_gym.analysis.ray_backend import RayExecutor
            try:
                return RayExecutor(address=args.address, num_cpus=n_workers,
                                   logging_level=logging.ERROR if quiet else logging.WARNING)
            except Exception as err:  # noqa: BLE001 - ray raises several kinds
                if args.address is not None:
                    raise CLIError(f"--address: cannot connect to the Ray cluster at "
                                   f"{args.address}: {one_line(err)}") from None
                raise RunError(f"could not start a local Ray instance: {one_line(err)}") from None
        return ray_pool

    def local_pool():
        return sweeps.SerialExecutor() if n_workers <= 1 else sweeps.local_process_pool(n_workers)
    return local_pool


def _settings(args) -> SweepSettings:
    try:
        return SweepSettings(settle_s=args.settle_s, measure_s=args.measure_s,
                             cold_settle_s=args.cold_settle_s, qpi_threshold=args.qpi_threshold,
                             floquet=not args.no_floquet, refine_step_n=args.refine_step)
    except ValueError as err:
        msg = one_line(err)
        m = re.match(r"SweepSettings\.(\w+)", msg)
        opt = {"settle_s": "--settle-s", "measure_s": "--measure-s",
               "cold_settle_s": "--cold-settle-s", "refine_step_n": "--refine-step"}.get(
            m.group(1) if m else "", "sweep settings")
        raise CLIError(f"{opt}: {msg}") from None


def check_backend(args) -> None:
    if isinstance(args.workers, bool) or not 1 <= args.workers <= 1024:
        raise CLIError(f"--workers: must be an integer in [1, 1024], got {args.workers}")
    if args.address is not None and args.backend != "ray":
        raise CLIError("--address: only used with --backend ray")
    if args.address is not None and not str(args.address).strip():
        raise CLIError("--address: must not be empty (e.g. auto, HOST:6379 or "
                       "ray://HOST:10001; omit it for a local Ray instance)")
    if args.backend == "ray" and importlib.util.find_spec("ray") is None:
        from bearing_gym.analysis.ray_backend import INSTALL_HINT
        raise CLIError(f"--backend: ray is not installed; {INSTALL_HINT}")


def _open_store(path: Path, settings: SweepSettings, base) -> tuple[list[dict], list[str], dict]:
    """The rows already in ``path``, the field names of the file and this run's run columns;
    CLIError naming --out or the option whose value differs from the stored rows'."""
    if path.is_dir():
        raise CLIError(f"--out: {path} is a directory; give a CSV file name")
    try:
        existing = store.read_sweep_file(path)
    except store.NotASweepFile:
        raise CLIError(f"--out: {path} is not a sweep CSV (no 'label' column); choose "
                       "another file") from None
    except (OSError, csv.Error, UnicodeDecodeError) as err:
        raise CLIError(f"--out: cannot read {path}: {one_line(err)}") from None
    run = store.run_columns(settings, base)
    try:
        fieldnames = store.prepare_file(path, existing, run)
    except store.SettingsMismatch as err:
        raise CLIError(f"{_RUN_OPTIONS[err.column]}: {path} holds points computed with "
                       f"{_setting_text(err.column, err.stored)}, this run has "
                       f"{_setting_text(err.column, err.run)}; rerun with the same value, or "
                       "choose another --out (or delete the file) to start afresh") from None
    except OSError as err:
        raise CLIError(f"--out: cannot write {path}: {err.strerror or err}") from None
    return existing, fieldnames, run


def cmd_sweep(args, say: Out) -> int:
    if not args.preloads:
        raise CLIError("--preloads: at least one axial preload (N) is required, e.g. "
                       "--preloads 1000 900 800 700")
    base = params_from_args(args, exclude=("preload",))
    lists: dict[str, list[float]] = {}
    for dest, single in LIST_OPTIONS.items():
        values = getattr(args, dest)
        if values is None:
            continue
        opt = f"--{dest.replace('_', '-')}"
        for v in values:      # every value checked before anything runs
            make_params([(opt, single, v)], base)
        lists[dest] = [float(v) for v in values]
    settings = _settings(args)
    check_option("--qpi-threshold", args.qpi_threshold, 0.0, 2.0, low_open=True)
    check_backend(args)
    speeds = lists.get("rpms", [base.shaft_speed_rpm])
    if min(speeds) > 0:
        longest = 60.0 / min(speeds)
        if settings.measure_s < 3 * longest:
            raise CLIError(f"--measure-s: must be at least 3 shaft periods ({3 * longest:.3g} s "
                           f"at {min(speeds):g} rpm), got {settings.measure_s:g}")

    path = Path(args.out)
    existing, fieldnames, run = _open_store(path, settings, base)
    n_combo = 1
    for k, v in lists.items():
        if k != "preloads":
            n_combo *= len(v)
    n_tasks = n_combo if args.mode == "continuation" else n_combo * len(args.preloads)
    say(f"bearing-gym sweep ({args.mode}): {len(args.preloads)} preloads x {n_combo} "
        f"combination(s) = {n_tasks} task(s); base {op_text(base)}")
    ex = store.ResumingExecutor(sweep_pool(args, min(args.workers, n_tasks), say.quiet), existing,
                                path, fieldnames, args.preloads, run)
    try:
        rows = sweeps.stability_map(
            base, args.preloads, shaft_speeds_rpm=lists.get("rpms"),
            radial_loads_n=lists.get("radial_loads"),
            clearances_m=[c / 1e6 for c in lists["clearances_um"]] if "clearances_um" in lists
            else None,
            damping_ratios=lists.get("damping_ratios"), mode=args.mode, settings=settings,
            executor=ex, progress=not say.quiet)
        ex.wait_for_appends()                # every task has finished: only callbacks are left
    except (CLIError, RunError):
        raise
    except Exception as err:  # noqa: BLE001 - a failed task stops the map; finished rows stay
        cause = getattr(err, "cause", None)      # a Ray task's error: the exception it wraps
        err = cause if isinstance(cause, Exception) else err
        raise RunError(f"sweep stopped: {type(err).__name__}: {one_line(err)}; the finished "
                       f"points are in {path}, rerun the same command to resume") from None
    finally:
        ex.shutdown()
    if ex.write_error is not None:
        raise RunError(f"could not append to {path}: {ex.write_error}")
    # final file: rows of other grids kept, this grid's rows in grid order
    other, rows = store.merge_rows(existing, ex.submitted, rows, run)
    sweeps.save_csv(other + rows, path)
    n_reused = len(ex.reused)
    say(f"{n_tasks - n_reused} task(s) computed, {n_reused} reused from {path}; "
        f"{len(rows)} rows for this grid, {len(other) + len(rows)} in the file")
    _say_critical(rows, say)
    if args.plot:
        _sweep_plot(rows, lists, Path(args.plot), args.mode, args.qpi_threshold, base)
        say(f"  figure: {args.plot}")
    return 0


def _say_critical(rows: list[dict], say: Out) -> None:
    by_label: dict[str, list[dict]] = {}
    for r in rows:
        by_label.setdefault(str(r["label"]), []).append(r)
    for label, rs in by_label.items():
        c = sweeps.critical_preload(rs)
        failed = [r for r in rs if not str(r.get("status", "ok")).startswith(("ok", "floquet"))]
        crit = (f"critical preload {c['critical_n']:g} N (between {c['bracket_n'][0]:g} and "
                f"{c['bracket_n'][1]:g} N)" if math.isfinite(c["critical_n"]) else c["note"])
        fails = f"; {len(failed)} point(s) failed" if failed else ""
        periodic = sum(truthy(r["periodic"]) for r in rs)
        say(f"  {label}: {periodic}/{len(rs)} points period-1; {crit}{fails}")


def _sweep_plot(rows: list[dict], lists: dict, path: Path, mode: str, qpi_threshold: float,
                base) -> None:
    varied = [k for k, v in lists.items() if k != "preloads" and len(v) > 1]
    column = {"rpms": "shaft_speed_rpm", "radial_loads": "radial_load_x_n",
              "clearances_um": "clearance_m", "damping_ratios": "damping_ratio"}
    fixed = op_text(base).replace(f"P_z = {base.loads.axial_preload_n:g} N, ", "")
    how = ("descending continuation" if mode == "continuation" else "cold starts from the "
           "static equilibrium")
    if varied:
        ylabel = sweeps.column_label(column[varied[0]])[0]
        fig = sweeps.plot_stability_map(
            rows, y=column[varied[0]], qpi_threshold=qpi_threshold,
            title=f"bearing-gym sweep: stability map over axial preload and {ylabel} "
                  f"({how}); other parameters as in {fixed}")
    else:
        fig = sweeps.plot_sweep(
            rows, qpi_threshold=qpi_threshold,
            title=f"bearing-gym sweep: response vs axial preload ({how}); {fixed}")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
