"""A sweep CSV file that a rerun resumes: the finished tasks it holds, the settings they were
computed with, and an executor that returns stored results at once and appends new rows as
their tasks finish.

A task is one continuation chain, keyed by ``("continuation", label)``, or one cold start,
keyed by ``("cold", label, preload)``. A stored task is reused only if its operating point and
(chains) its preloads are the new task's; a file whose rows were computed with other settings
(durations, criteria, time step, race control: :data:`RUN_COLUMNS`) is refused
(:class:`SettingsMismatch`), so that one file never mixes two kinds of points.
"""

from __future__ import annotations

import concurrent.futures as cf
import csv
import math
import os
import threading
from pathlib import Path
from typing import Any, Callable, Sequence

from bearing_gym.params import BearingParams

from .io import format_cell, load_csv, save_csv
from .points import COLUMNS, SweepSettings, operating_point

__all__ = ["RUN_COLUMNS", "CONTINUATION_ONLY", "NotASweepFile", "SettingsMismatch",
           "run_columns", "read_sweep_file", "check_run_columns", "prepare_file",
           "stored_tasks", "ResumingExecutor", "merge_rows"]

# settings of a sweep written into every computed row; cold starts do not use the
# continuation-only ones
RUN_COLUMNS = ("settle_s", "cold_settle_s", "measure_s", "qpi_threshold", "floquet",
               "refine_step_n", "dt_s", "race_control")
CONTINUATION_ONLY = ("settle_s", "refine_step_n")


class NotASweepFile(ValueError):
    """The file exists but holds no sweep rows (no ``label`` column)."""


class SettingsMismatch(ValueError):
    """A row of the file was computed with another value of a run column."""

    def __init__(self, path: str | os.PathLike, column: str, stored: Any, run: Any):
        super().__init__(f"{path} holds points computed with {column} = {stored!r}, this run "
                         f"has {run!r}")
        self.path, self.column, self.stored, self.run = path, column, stored, run


def run_columns(settings: SweepSettings, params: BearingParams) -> dict:
    """The :data:`RUN_COLUMNS` of a sweep with these settings and base parameters."""
    return dict(settle_s=settings.settle_s, cold_settle_s=settings.cold_settle_s,
                measure_s=settings.measure_s, qpi_threshold=settings.qpi_threshold,
                floquet=settings.floquet,
                refine_step_n="none" if settings.refine_step_n is None else settings.refine_step_n,
                dt_s=params.integrator.dt_s, race_control=params.race_control)


def _pkey(p: Any) -> float:
    try:
        return round(float(p), 6)
    except (TypeError, ValueError):
        return math.nan


def _same(a: Any, b: Any) -> bool:
    try:
        fa, fb = float(a), float(b)
    except (TypeError, ValueError):
        return a == b
    if math.isnan(fa) and math.isnan(fb):
        return True
    return math.isclose(fa, fb, rel_tol=1e-8, abs_tol=1e-15)


def read_sweep_file(path: str | os.PathLike) -> list[dict]:
    """The rows of an existing sweep CSV (none if the file does not exist). Raises OSError,
    csv.Error or UnicodeDecodeError if it cannot be read, :class:`NotASweepFile` if it is not
    a sweep file."""
    path = Path(path)
    if not path.exists():
        return []
    rows = load_csv(path)
    if rows and "label" not in rows[0]:
        raise NotASweepFile(f"{path} is not a sweep CSV (no 'label' column)")
    return rows


def check_run_columns(existing: Sequence[dict], run: dict, path: str | os.PathLike) -> None:
    """:class:`SettingsMismatch` if a row of the file was computed with other settings (rows
    written before the settings were recorded have empty cells and are not checked)."""
    for r in existing:
        if r.get("measure_s") in (None, ""):
            continue
        for col in RUN_COLUMNS:
            if r.get("mode") == "cold" and col in CONTINUATION_ONLY:
                continue
            if not _same(r.get(col), run[col]):
                raise SettingsMismatch(path, col, r.get(col), run[col])


def prepare_file(path: str | os.PathLike, existing: list[dict], run: dict) -> list[str]:
    """Check the stored rows against ``run`` (:func:`check_run_columns`), rewrite the file in
    the canonical form (header, number formatting) so that finished rows can be appended, and
    return its field names. Rows written before the settings were recorded get empty run
    cells (in ``existing`` too). Raises OSError if the file cannot be written."""
    path = Path(path)
    check_run_columns(existing, run, path)
    for r in existing:
        for col in RUN_COLUMNS:
            r.setdefault(col, "")
    names = list(COLUMNS) + sorted(({k for r in existing for k in r} | set(run)) - set(COLUMNS))
    path.parent.mkdir(parents=True, exist_ok=True)
    if existing:
        save_csv(existing, path)
    else:
        with open(path, "w", newline="") as fh:
            csv.DictWriter(fh, fieldnames=names).writeheader()
    return names


def stored_tasks(rows: Sequence[dict]) -> dict[tuple, list[dict]]:
    """Finished tasks in a file: continuation chains by ("continuation", label) (the last chain
    of a label if the file holds several) and cold points by ("cold", label, preload)."""
    out: dict[tuple, list[dict]] = {}
    for r in rows:
        mode, label = r.get("mode"), str(r.get("label"))
        if mode == "continuation":
            key = ("continuation", label)
            if r.get("order") == 0 or key not in out:
                out[key] = []
            out[key].append(r)
        elif mode == "cold":
            out[("cold", label, _pkey(r.get("axial_preload_n")))] = [r]
    return out


def _row_task(row: dict) -> tuple:
    label = str(row.get("label"))
    if row.get("mode") == "continuation":
        return ("continuation", label)
    return ("cold", label, _pkey(row.get("axial_preload_n")))


def _matches(stored: list[dict], params: BearingParams, preloads: Sequence[float] | None) -> bool:
    """A stored task is reused only if its operating point and (chains) preloads are this
    task's."""
    if not stored:
        return False
    op = operating_point(params)
    op.pop("axial_preload_n")
    r0 = stored[0]
    if not all(_same(r0.get(k), v) for k, v in op.items()):
        return False
    if preloads is not None:
        have = sorted(_pkey(r["axial_preload_n"]) for r in stored if not r.get("refined"))
        return have == sorted(_pkey(p) for p in preloads)
    return True


class ResumingExecutor:
    """concurrent.futures-style executor for :func:`.runner.stability_map`: a task whose result
    is already in the file returns it at once; the others run on the executor made by
    ``make_pool`` (a process pool, this process or Ray; made only if there is something to
    compute) and their rows, with the ``run`` columns, are appended to the file as soon as they
    finish. ``reused`` and ``submitted`` hold the task keys."""

    def __init__(self, make_pool: Callable[[], Any], existing: Sequence[dict], path: str | os.PathLike,
                 fieldnames: list[str], preloads: Sequence[float], run: dict):
        self.make_pool, self.stored, self.path = make_pool, stored_tasks(existing), Path(path)
        self.fieldnames, self.preloads, self.run = fieldnames, list(preloads), run
        self.reused: set[tuple] = set()
        self.submitted: set[tuple] = set()
        self._pool: Any = None
        self._lock = threading.Lock()
        self._appended = threading.Condition()
        self._pending = 0                     # submitted tasks whose rows are not appended yet
        self.write_error: Exception | None = None

    def _key(self, fn: Callable, args: tuple) -> tuple[tuple, Any, Any]:
        if fn.__name__ == "continuation_chain":
            params, preloads, _settings, label = args[:4]
            return ("continuation", str(label)), params, preloads
        params, _settings, label = args[:3]
        return ("cold", str(label), _pkey(params.loads.axial_preload_n)), params, None

    def submit(self, fn: Callable, /, *args: Any) -> cf.Future:
        key, params, preloads = self._key(fn, args)
        self.submitted.add(key)
        stored = self.stored.get(key)
        if stored is not None and _matches(stored, params, preloads):
            self.reused.add(key)
            fut: cf.Future = cf.Future()
            fut.set_result([dict(r) for r in stored] if key[0] == "continuation" else dict(stored[0]))
            return fut
        if self._pool is None:
            self._pool = self.make_pool()
        fut = self._pool.submit(fn, *args)
        with self._appended:
            self._pending += 1
        fut.add_done_callback(self._append)
        return fut

    def wait_for_appends(self) -> None:
        """Block until every finished task's rows are in the file. A future's result is visible
        to the waiting thread before its done-callbacks have run (they run in the thread that
        set the result: the pool's or Ray's), so the final rewrite of the file must wait for
        them or a late append would duplicate rows."""
        with self._appended:
            self._appended.wait_for(lambda: self._pending == 0)

    def _append(self, fut: cf.Future) -> None:
        try:
            self._write_rows(fut)
        finally:
            with self._appended:
                self._pending -= 1
                self._appended.notify_all()

    def _write_rows(self, fut: cf.Future) -> None:
        if fut.cancelled() or fut.exception() is not None:
            return
        res = fut.result()
        rows = res if isinstance(res, list) else [res]
        for r in rows:
            if r.get("mode") == "cold":      # stability_map sets it after the run; same value
                ps = [_pkey(p) for p in self.preloads]
                pk = _pkey(r.get("axial_preload_n"))
                r["order"] = ps.index(pk) if pk in ps else 0
        try:
            with self._lock, open(self.path, "a", newline="") as fh:
                w = csv.DictWriter(fh, fieldnames=self.fieldnames, restval="", extrasaction="ignore")
                for r in rows:
                    w.writerow({k: format_cell(v) for k, v in {**self.run, **r}.items()})
        except OSError as err:
            self.write_error = err

    def shutdown(self, wait: bool = True) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=wait)


def merge_rows(existing: Sequence[dict], submitted: set[tuple], rows: Sequence[dict],
               run: dict) -> tuple[list[dict], list[dict]]:
    """The final content of the file: (rows of other grids, kept as they were; this grid's rows
    in grid order, with the run columns where a row has none of its own)."""
    other = [r for r in existing if _row_task(r) not in submitted]
    return other, [{**run, **r} for r in rows]
