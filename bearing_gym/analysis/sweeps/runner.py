"""Running many sweep points: an in-process executor, the task runner with a progress bar, and
the stability map over a grid of operating points.

Points run in parallel (one continuation chain or one cold start per task) on a pluggable
executor with the ``concurrent.futures.Executor`` interface (``submit`` returning an object with
``result()``); the default is a ``ProcessPoolExecutor`` over the local cores, and
:class:`..ray_backend.RayExecutor` runs them on a Ray cluster (several machines).
"""

from __future__ import annotations

import concurrent.futures as cf
import itertools
import os
import time
from typing import Any, Callable, Sequence

from bearing_gym.params import BearingParams

from .points import SweepSettings, cold_start_point, continuation_chain

__all__ = ["SerialExecutor", "local_process_pool", "run_tasks", "stability_map"]


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


def local_process_pool(max_workers: int) -> cf.ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` whose workers are *spawned*, not forked: a process that has
    loaded GNU OpenMP (torch does) must not fork (libgomp terminates the child: "fork() called
    from a process already using GNU OpenMP, this is unsafe"), and a spawned worker inherits no
    thread state. Workers load the kernels from numba's cache, so spawning costs about a
    second per worker, once per pool."""
    import multiprocessing

    return cf.ProcessPoolExecutor(max_workers=max_workers, mp_context=multiprocessing.get_context("spawn"))


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
    level function of an importable module: not one defined in a notebook or a package's
    ``__main__``) for process executors; the default pool spawns its workers, so a script that
    calls this needs the ``if __name__ == "__main__":`` guard. Default executor: :func:`local_process_pool` with
    ``max_workers`` (default: ``os.cpu_count()``) workers; with one task or one worker the
    calls run in this process."""
    arg_list = list(arg_list)
    own = executor is None
    if own:
        n = min(max_workers or os.cpu_count() or 1, len(arg_list))
        executor = SerialExecutor() if n <= 1 else local_process_pool(n)
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
