"""Building what is not fresh, in dependency order, its parts spread over workers.

:func:`select` decides what to build (the products that are not fresh, or those of ``--only``
with what they need that is not fresh); :func:`build` runs their parts on an executor with the
``concurrent.futures`` interface - this process (one worker), a pool of spawned processes, or
Ray (:class:`bearing_gym.analysis.ray_backend.RayExecutor`, the sweeps' backend) - as soon as
every upstream product is complete, longest remaining chain first. After every part the manifest
is written, so a run stopped at any point (``--until``, Ctrl-C, a crash) resumes with the parts
it had done. With a deadline no part starts that its estimate says would not finish by then.
"""

from __future__ import annotations

import concurrent.futures as cf
import fnmatch
import heapq
import os
import time
from dataclasses import dataclass, field
from datetime import datetime
from typing import Any, Callable

from agents.regenerate.manifest import FRESH, Manifest, State, assess, current_inputs
from agents.regenerate.product import Layout, Part, Product

__all__ = ["Selection", "select", "build", "run_part", "make_executor", "Outcome", "simulate", "hours"]

#: the factor on a part's estimate before one of its product's parts has been timed
MARGIN = 1.5


def hours(core_s: float) -> str:
    return f"{core_s / 3600:.2f} h" if core_s >= 3600 else f"{core_s / 60:.1f} min" if core_s >= 60 else f"{core_s:.0f} s"


@dataclass
class Selection:
    products: dict[str, Product]                  # every product, upstream first
    inputs: dict[str, tuple[dict, str]]           # today's inputs and their hash
    states: dict[str, State]
    to_build: list[str]                           # upstream first

    def parts_left(self, name: str) -> list[Part]:
        return [p for p in self.products[name].parts if p.key not in self.states[name].parts_done]

    def cost_left(self) -> float:
        return sum(p.cost_s for n in self.to_build for p in self.parts_left(n))


def select(products: list[Product], layout: Layout, manifest: Manifest, kernel: str,
           only: list[str] | None = None, force: list[str] = ()) -> Selection:
    """What is fresh and what to build (module docstring). ``only``/``force`` are product names or
    shell patterns (``planner:*``); a forced product counts as changed, so its dependants follow."""
    by = {p.name: p for p in products}

    def names(patterns) -> list[str]:
        out = [n for n in by if any(fnmatch.fnmatchcase(n, pat) for pat in patterns)]
        unknown = [pat for pat in patterns if not any(fnmatch.fnmatchcase(n, pat) for n in by)]
        if unknown:
            raise ValueError(f"no product named {unknown[0]!r}; the products: {', '.join(by)}")
        return out
    forced = set(names(force))
    stamp = datetime.now().isoformat(timespec="seconds")
    nonces = {n: stamp if n in forced else (manifest.entry(n) or {}).get("inputs", {}).get("forced") for n in by}
    inputs = current_inputs(products, kernel, layout, nonces)
    states = {n: assess(by[n], *inputs[n], manifest.entry(n), layout) for n in by}
    for n in forced:              # recorded now: a run stopped before a part ends keeps the force
        manifest.start(n, *inputs[n])
    wanted: set[str] = set()

    def want(n: str) -> None:
        if n in wanted or states[n].state == FRESH:
            return
        wanted.add(n)
        for u in by[n].upstream:
            want(u)
    for n in (names(only) if only else by):
        want(n)
    return Selection(by, inputs, states, [n for n in by if n in wanted])


def run_part(fn: Callable[..., Any], args: tuple, threads: int | None) -> tuple[Any, float]:
    """A part in a worker: ``fn(*args)`` on ``threads`` numba threads (None: as they are)."""
    if threads:
        import numba
        numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))
    t0 = time.perf_counter()
    return fn(*args), time.perf_counter() - t0


def make_executor(processes: int, ray_address: str | None):
    """This process (one worker), a pool of ``processes`` spawned processes, or Ray."""
    if ray_address is not None:
        from bearing_gym.analysis.ray_backend import RayExecutor
        return RayExecutor(None if ray_address == "local" else ray_address)
    from bearing_gym.analysis.sweeps import SerialExecutor, local_process_pool
    return local_process_pool(processes) if processes > 1 else SerialExecutor()


def _bottom_levels(sel: Selection) -> dict[str, float]:
    """Per product to build, the longest chain of part costs from it to the end (its priority)."""
    down: dict[str, list[str]] = {n: [] for n in sel.to_build}
    for n in sel.to_build:
        for u in sel.products[n].upstream:
            if u in down:
                down[u].append(n)
    level: dict[str, float] = {}
    for n in reversed(sel.to_build):
        level[n] = max((p.cost_s for p in sel.products[n].parts), default=0.0) + max((level[d] for d in down[n]), default=0.0)
    return level


@dataclass
class Outcome:
    built: list[str] = field(default_factory=list)
    parts_run: int = 0
    left: list[str] = field(default_factory=list)
    failed: dict[str, str] = field(default_factory=dict)
    stopped_for_deadline: bool = False


def build(sel: Selection, layout: Layout, manifest: Manifest, executor, workers: int, threads: int | None,
          deadline: datetime | None = None, log: Callable[[str], None] = print) -> Outcome:
    """Build ``sel.to_build`` (module docstring); returns what was built and what is left."""
    todo = list(sel.to_build)
    level = _bottom_levels(sel)
    pending = {n: sel.parts_left(n) for n in todo}
    done: set[str] = set()
    running: dict[cf.Future, tuple[str, Part, float]] = {}
    timed: dict[str, float] = {}                  # per product: the slowest part's wall seconds per estimated second
    started: dict[str, float] = {}
    out = Outcome()
    speed = max(1, threads or os.cpu_count() or 1)

    def ready(n: str) -> bool:
        return n not in out.failed and all(u in done or u not in pending for u in sel.products[n].upstream)

    def estimate(n: str, part: Part) -> float:
        """The part's cost at the pace its product's parts have kept in this run (the slowest),
        or its cost on ``speed`` threads with a margin before one was timed."""
        return part.cost_s * timed[n] if n in timed else MARGIN * part.cost_s / speed

    def finish(n: str) -> None:
        p = sel.products[n]
        if p.finish is not None:
            p.finish()
        manifest.complete(n, *sel.inputs[n], p.output_digest(layout.root), datetime.now().isoformat(timespec="seconds"),
                          time.time() - started.get(n, time.time()))
        done.add(n)
        out.built.append(n)
        log(f"[{datetime.now():%H:%M:%S}] {n}: built")

    while True:
        for n in todo:
            if n not in done and ready(n) and not pending[n] and not any(r[0] == n for r in running.values()):
                try:
                    finish(n)
                except Exception as err:           # noqa: BLE001 - reported, its dependants wait
                    out.failed[n] = f"{type(err).__name__}: {err}"
                    log(f"[{datetime.now():%H:%M:%S}] {n}: FAILED finishing: {out.failed[n]}")
        queue = sorted(((n, part) for n in todo if n not in done and ready(n) for part in pending[n]),
                       key=lambda np_: (-level[np_[0]], todo.index(np_[0])))
        for n, part in queue:
            if len(running) >= workers:
                break
            est = estimate(n, part)
            if deadline is not None and time.time() + est > deadline.timestamp():
                out.stopped_for_deadline = True
                continue
            for f in sel.products[n].outputs:
                f.parent.mkdir(parents=True, exist_ok=True)
            started.setdefault(n, time.time())
            pending[n].remove(part)
            k = len(sel.products[n].parts) - len(pending[n])
            log(f"[{datetime.now():%H:%M:%S}] {n}: part {part.key} ({k}/{len(sel.products[n].parts)}) started, "
                f"~{hours(est)}")
            running[executor.submit(run_part, part.fn, part.args, threads)] = (n, part, time.time())
        if not running:
            break
        finished, _ = cf.wait(list(running), return_when=cf.FIRST_COMPLETED)
        for fut in finished:
            n, part, t0 = running.pop(fut)
            try:
                result, wall = fut.result()
                if part.commit is not None:
                    part.commit(result)
            except Exception as err:               # noqa: BLE001 - reported, its dependants wait
                out.failed[n] = f"{type(err).__name__}: {err}"
                log(f"[{datetime.now():%H:%M:%S}] {n}: part {part.key} FAILED: {out.failed[n]}")
                continue
            manifest.part_done(n, *sel.inputs[n], part.key)
            out.parts_run += 1
            timed[n] = max(timed.get(n, 0.0), (time.time() - t0) / max(part.cost_s, 1e-9))
            left = sum(p.cost_s for m in todo if m not in done for p in pending[m])
            log(f"[{datetime.now():%H:%M:%S}] {n}: part {part.key} done in {hours(wall)}; "
                f"{sum(len(pending[m]) for m in todo)} parts left (~{hours(left)} of one core)")
    out.left = [n for n in todo if n not in done]
    return out


def simulate(sel: Selection, workers: int, threads: int | None) -> float:
    """The wall seconds :func:`build` would take on ``workers`` workers of ``threads`` threads
    each if every part took its estimate divided by ``threads`` (the same order: a part starts
    when a worker is free and its product's upstream is complete, longest remaining chain first)."""
    speed = max(1, threads or 1)
    level = _bottom_levels(sel)
    pending = {n: sorted((p.cost_s / speed for p in sel.parts_left(n)), reverse=True) for n in sel.to_build}
    unfinished = {n: len(pending[n]) for n in sel.to_build}
    done: set[str] = set()
    running: list[tuple[float, str]] = []
    now = 0.0
    while True:
        ready = [n for n in sel.to_build if n not in done
                 and all(u in done or u not in pending for u in sel.products[n].upstream)]
        complete = [n for n in ready if unfinished[n] == 0]
        if complete:
            done.update(complete)
            continue
        for n in sorted(ready, key=lambda m: -level[m]):
            while pending[n] and len(running) < workers:
                heapq.heappush(running, (now + pending[n].pop(0), n))
        if not running:
            return now
        now, n = heapq.heappop(running)
        unfinished[n] -= 1
