"""``python -m agents.offline``: list, plan, build and verify the offline datasets.

    python -m agents.offline list                                   # every dataset: recipe, size, cost, checksum
    python -m agents.offline status                                 # what is recorded and planned here
    python -m agents.offline plan --until 18:00 [--processes 2]     # the expert's plans, resumable
    python -m agents.offline build transient/sample                 # record, join, check against the checksum
    python -m agents.offline build --all --processes 2              # every dataset (Ray: --ray ADDRESS)
    python -m agents.offline verify transient/expert                # a local dataset against its checksum
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from agents.offline.recipes import PLANS_DIR, RECIPES, recipe

__all__ = ["main"]


def _list() -> None:
    from agents.offline.build import load_catalogue
    cat = load_catalogue()["datasets"]
    print("| dataset | behaviour | episodes | steps | size | cost (one core) | checksum |")
    print("|---|---|---|---|---|---|---|")
    for did, r in RECIPES.items():
        e = cat.get(did)
        cells = [f"`{did}`", r.description, str(r.episodes), f"{e['steps']:,}" if e else "-",
                 f"{e['bytes'] / 1e6:.1f} MB" if e else "-",
                 f"{e['parts_core_s'] / 60:.1f} min" if e and e.get("parts_core_s") else "-",
                 f"`{e['checksum'][:16]}`" if e else "not built"]
        print("| " + " | ".join(cells) + " |")


def _status(work_dir: Path, plans_dir: Path) -> None:
    from agents.offline.build import parts_left
    from agents.offline.collect import plans_missing
    for did, r in RECIPES.items():
        left = parts_left(r, work_dir)
        line = f"{did}: {len(r.parts()) - len(left) if r.kind != 'mixed' else '-'} of {len(r.parts())} parts recorded"
        if r.kind == "mixed":
            line = f"{did}: joined from {', '.join(n for n, _ in r.sources)}; {len(left)} source parts missing"
        if r.kind == "planner":
            gone = plans_missing(r, list(range(r.first_seed, r.first_seed + r.episodes)), plans_dir)
            line += f"; {r.episodes - len(gone)} of {r.episodes} episodes planned"
        print(line)


def _executor(a):
    if a.ray is None:
        return None
    from bearing_gym.analysis.ray_backend import RayExecutor
    return RayExecutor(address=None if a.ray == "local" else a.ray)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m agents.offline", description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("list", help="every dataset: its behaviour, size, cost and committed checksum (markdown)")
    st = sub.add_parser("status", help="what is recorded and planned in this checkout")
    pl = sub.add_parser("plan", help="plan the expert's episodes (about a minute of a core each), resumable")
    pl.add_argument("--until", metavar="HH:MM", help="start no episode that would not finish by then")
    pl.add_argument("--processes", type=int, default=1, help="worker processes (each plans its own episodes)")
    pl.add_argument("--dataset", default="transient/expert")
    b = sub.add_parser("build", help="record what is missing, write the Minari dataset, check its checksum")
    b.add_argument("names", nargs="*", metavar="TIER/NAME")
    b.add_argument("--all", action="store_true", help="every dataset (upstream first: mixed last)")
    b.add_argument("--processes", type=int, help="worker processes for the parts (default: the cores)")
    b.add_argument("--ray", nargs="?", const="auto", metavar="ADDRESS", help="record the parts on a Ray cluster")
    b.add_argument("--record", action="store_true",
                   help="write this build's checksum into agents/data/offline_datasets.json (a new or changed recipe)")
    v = sub.add_parser("verify", help="check a local Minari dataset against its committed checksum")
    v.add_argument("names", nargs="+", metavar="TIER/NAME")
    for p in (st, b):
        p.add_argument("--work-dir", help="where the parts are recorded (default: runs/offline)")
    for p in (b, v):
        p.add_argument("--datasets-path", help="Minari's datasets directory (default: $MINARI_DATASETS_PATH or "
                                               "~/.minari/datasets)")
    a = ap.parse_args(argv)
    from agents.offline import build as B
    work_dir = Path(a.work_dir) if getattr(a, "work_dir", None) else B.WORK_DIR
    try:
        if a.cmd == "list":
            _list()
        elif a.cmd == "status":
            _status(work_dir, PLANS_DIR)
        elif a.cmd == "plan":
            return _plan(a)
        elif a.cmd == "build":
            names = list(RECIPES) if a.all else a.names
            if not names:
                ap.error("build: name a dataset (TIER/NAME) or give --all")
            if a.processes is not None and a.processes < 1:
                ap.error("--processes must be >= 1")
            for name in names:
                B.build(name, work_dir, PLANS_DIR, Path(a.datasets_path) if a.datasets_path else None,
                        _executor(a), a.processes, a.record)
        elif a.cmd == "verify":
            if a.datasets_path:
                import os
                os.environ["MINARI_DATASETS_PATH"] = a.datasets_path
            for name in a.names:
                print(f"{recipe(name).dataset_id}: checksum {B.verify(name)[:16]} equals the committed one")
    except (KeyError, FileNotFoundError, ValueError) as err:
        print(f"python -m agents.offline {a.cmd}: {err}", file=sys.stderr)
        return 1
    return 0


def _plan(a) -> int:
    from agents.clock import deadline
    from agents.offline.collect import plan_expert, plans_missing
    r = recipe(a.dataset)
    if r.kind != "planner":
        raise ValueError(f"{r.dataset_id} is not planned (its behaviour: {r.kind})")
    if a.processes < 1:
        raise ValueError("--processes must be >= 1")
    seeds = list(range(r.first_seed, r.first_seed + r.episodes))
    until = deadline(a.until) if a.until else None
    if a.processes == 1:
        plan_expert(r, seeds, PLANS_DIR, until)
    else:                                   # each process plans every processes-th missing episode
        from bearing_gym.analysis.sweeps import run_tasks
        todo = plans_missing(r, seeds, PLANS_DIR)
        from agents.offline.collect import plan_chunk
        chunks = [(r.dataset_id, todo[k::a.processes], str(PLANS_DIR), a.until) for k in range(a.processes)]
        run_tasks(plan_chunk, [c for c in chunks if c[1]], max_workers=a.processes, desc="expert plans")
    left = plans_missing(r, seeds, PLANS_DIR)
    print(f"{r.dataset_id}: {r.episodes - len(left)} of {r.episodes} episodes planned in {PLANS_DIR}"
          + ("" if left else f"; build it: `python -m agents.offline build {r.tier}/{r.name}`"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
