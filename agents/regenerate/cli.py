"""``python -m agents.regenerate``: status, plan and build of every stored data product.

    python -m agents.regenerate --status                 # each product fresh / stale / partial / missing, and why
    python -m agents.regenerate --dry-run --processes 32 # what would be built, its cost, a rough wall time
    python -m agents.regenerate --until 18:30            # build what is stale while it can finish by 18:30
    python -m agents.regenerate --processes 8            # ... on 8 worker processes (or --ray ADDRESS)
    python -m agents.regenerate --only 'planner:*'       # some products (and what they need that is stale)
    python -m agents.regenerate --list                   # the product table (docs/regeneration.md)
    python -m agents.regenerate --adopt 'planner:*'      # record files in place fresh, where their records prove it
    python -m agents.regenerate --profile tiny --root /tmp/regen   # every product, tiny, in a scratch tree
"""

from __future__ import annotations

import argparse
import fnmatch
import os
from datetime import datetime

from agents.clock import deadline
from pathlib import Path
from typing import Callable

from agents.paths import require_checkout
from agents.regenerate.catalogue import products as catalogue
from agents.regenerate.manifest import Manifest, source_name
from agents.regenerate.product import Layout
from agents.regenerate.profiles import PROFILES, Profile
from agents.regenerate.scheduler import Outcome, Selection, build, hours, make_executor, select, simulate

__all__ = ["plan", "regenerate", "worker_threads", "print_status", "product_table", "main"]


def plan(profile: Profile, root: Path, only: list[str] | None = None, force: list[str] = (),
         kernel: str | None = None) -> tuple[Selection, Layout, Manifest]:
    """Today's state of every product of ``profile`` under ``root`` and what to build."""
    if kernel is None:
        from bearing_gym.envs.provenance import kernel_hash
        kernel = kernel_hash()
    layout = Layout(Path(root))
    manifest = Manifest(layout.manifest, profile.name)
    return select(catalogue(profile, layout), layout, manifest, kernel, only, list(force)), layout, manifest


def regenerate(profile: Profile, root: Path, only: list[str] | None = None, force: list[str] = (),
               processes: int = 1, ray: str | None = None, threads: int | None = None,
               until: datetime | None = None, kernel: str | None = None,
               log: Callable[[str], None] = print) -> Outcome:
    """Build what is not fresh (the library call behind the command)."""
    sel, layout, manifest = plan(profile, root, only, force, kernel)
    if not sel.to_build:
        log("every product is fresh: nothing to build")
        return Outcome()
    threads = worker_threads(processes, ray, threads)
    executor = make_executor(processes, ray)
    workers = processes
    if ray is not None and processes <= 1:             # as many parts in flight as the cluster has room for
        import ray as ray_module
        workers = max(1, int(ray_module.cluster_resources().get("CPU", 1)) // (threads or 1))
    log(f"building {len(sel.to_build)} products ({sum(len(sel.parts_left(n)) for n in sel.to_build)} parts, "
        f"~{hours(sel.cost_left())} of one core) on {workers} worker(s)"
        + (f" until {until:%Y-%m-%d %H:%M}" if until else "") + f": {', '.join(sel.to_build)}")
    try:
        out = build(sel, layout, manifest, executor, workers, threads, until, log)
    finally:
        executor.shutdown(wait=True)
    if out.failed:
        log("failed: " + "; ".join(f"{n}: {e}" for n, e in out.failed.items()))
    if out.left:
        left = plan(profile, root, only, (), kernel)[0]
        log(f"left: {len(left.to_build)} products, ~{hours(left.cost_left())} of one core: {', '.join(left.to_build)}"
            + ("; run the same command again to continue" if out.stopped_for_deadline else ""))
    else:
        log(f"done: {len(out.built)} products built")
    return out


def worker_threads(processes: int, ray: str | None, threads: int | None) -> int | None:
    """Numba threads per worker: ``threads`` if given; one per Ray task; the cores shared among
    ``processes`` processes; None (all, as numba has them) in this process."""
    if threads is not None:
        return threads
    if ray is not None:
        return 1
    return max(1, (os.cpu_count() or 1) // processes) if processes > 1 else None


def print_status(sel: Selection, layout: Layout, log: Callable[[str], None] = print) -> None:
    log(f"root {layout.root}, manifest {layout.rel(layout.manifest)}")
    width = max(len(n) for n in sel.products)
    for n, st in sel.states.items():
        log(f"{n:{width}s}  {st.state:8s} {'; '.join(st.reasons)}".rstrip())
    counts = {s: sum(1 for st in sel.states.values() if st.state == s) for s in ("fresh", "stale", "partial", "missing")}
    log(", ".join(f"{v} {k}" for k, v in counts.items() if v)
        + ("" if not sel.to_build else f": rebuilding costs ~{hours(sel.cost_left())} of one core "
                                         "(`python -m agents.regenerate --dry-run --processes N`: a wall time)"))


def product_table(sel: Selection) -> str:
    """The products as a markdown table (name, what, depends on, parts, cost, command)."""
    lines = ["| product | what | depends on | parts | cost (one core) | by hand |", "|---|---|---|---|---|---|"]
    for p in sel.products.values():
        names = [source_name(s) for s in p.sources]
        sources = names if len(names) < 2 else [f"{names[0].rsplit('/', 2)[0]}/ ({len(names)} runs)"]
        deps = ", ".join((["kernel"] if p.kernel else []) + list(p.upstream) + sources)
        lines.append(f"| `{p.name}` | {p.what} | {deps or '-'} | {len(p.parts)} | {hours(p.cost_s)} | `{p.command}` |")
    return "\n".join(lines)


def _deadline(text: str) -> datetime:
    return deadline(text)


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="python -m agents.regenerate",
                                 description="Rebuild every stored data product that is not fresh for today's kernel "
                                             "and settings, in dependency order, resumable.")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--status", action="store_true", help="each product fresh/stale/partial/missing and why; builds nothing")
    g.add_argument("--dry-run", action="store_true", help="what would be built, its cost and a rough wall time")
    g.add_argument("--list", action="store_true", help="the product table (markdown)")
    g.add_argument("--adopt", nargs="+", metavar="NAME",
                   help="record these products (names or patterns) fresh under today's inputs without building "
                        "them, where their check of the files in place finds nothing that differs (a "
                        "definition change that cannot change their files); upstream first")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="these products (names or patterns like 'planner:*') "
                                                               "and what they need that is not fresh")
    ap.add_argument("--force", nargs="+", default=[], metavar="NAME",
                    help="count these products as changed (a code change the hashes do not see): they and their "
                         "dependants are rebuilt")
    ap.add_argument("--until", metavar="HH:MM", help="start no part that would not finish by then; exit 0 with what is left")
    ap.add_argument("--processes", type=int, default=1, help="worker processes (default 1: this process)")
    ap.add_argument("--ray", nargs="?", const="auto", metavar="ADDRESS",
                    help="run the parts on a Ray cluster (auto, HOST:6379, ray://HOST:10001; 'local': a private "
                         "instance); every node must see --root. --processes N: N parts in flight (default: the "
                         "cluster's CPUs)")
    ap.add_argument("--threads", type=int, help="numba threads per worker (default: the cores shared among "
                                                "--processes; 1 on Ray; all in this process)")
    ap.add_argument("--profile", choices=sorted(PROFILES), default="full",
                    help="full: the protocol's sizes (the committed data); tiny: every product small, for tests")
    ap.add_argument("--root", help="where to write (default: this checkout, full profile only)")
    return ap


def main(argv: list[str] | None = None) -> int:
    ap = build_parser()
    a = ap.parse_args(argv)
    profile = PROFILES[a.profile]
    if a.root is None and profile.name != "full":
        ap.error(f"--profile {a.profile} needs --root (a scratch directory): it would overwrite the committed data")
    if a.processes < 1:
        ap.error("--processes must be >= 1")
    try:
        root = Path(a.root) if a.root else require_checkout("the stored data", "--root")
        sel, layout, manifest = plan(profile, root, a.only, a.force)
    except ValueError as err:
        raise SystemExit(f"regenerate: {err}") from None
    if a.list:
        print(product_table(sel))
        return 0
    if a.status:
        print_status(sel, layout)
        return 0
    if a.adopt:
        from agents.regenerate.adopt import AdoptError, adopt
        try:
            names = [n for n in sel.products if any(fnmatch.fnmatchcase(n, pat) for pat in a.adopt)]
            unknown = [pat for pat in a.adopt if not any(fnmatch.fnmatchcase(n, pat) for n in sel.products)]
            if unknown:
                raise AdoptError(f"no product named {unknown[0]!r}")
            adopt(sel, names, layout, manifest)
        except AdoptError as err:
            raise SystemExit(f"regenerate --adopt: {err}") from None
        return 0
    if a.dry_run:
        print_status(sel, layout)
        workers = a.processes
        threads = worker_threads(workers, a.ray, a.threads) or os.cpu_count()
        for n in sel.to_build:
            print(f"would build {n}: {len(sel.parts_left(n))} parts, ~{hours(sum(p.cost_s for p in sel.parts_left(n)))}")
        print(f"~{hours(sel.cost_left())} of one core; on {workers} worker(s) of {threads} thread(s): about "
              f"{hours(simulate(sel, workers, threads))} if the estimates hold")
        return 0
    out = regenerate(profile, root, a.only, a.force, a.processes, a.ray, a.threads,
                     _deadline(a.until) if a.until else None)
    return 1 if out.failed else 0
