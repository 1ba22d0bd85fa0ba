"""Reproduction of Bai & Xu (2006), section 3 (claims 1-7 of ``docs/model.md``).

    python -m bearing_gym.reproduction [--quick] [--out docs/reproduction] [--report PATH]
                                       [--workers N] [--no-progress] [--cache FILE [--redo PREFIX ...]]
                                       [--report-only]

(``bearing-gym reproduce`` is the same.) Regenerates from scratch every figure the
paper describes, as PNG files under ``--out``:

* claim 1 (section 3.1, Fig. 5): cage speed against shaft speed, e = 2e-5 m;
* claim 2 (section 3.1, Fig. 6): x-displacement at 2,000 rpm, 800 N, for the full model, the
  model without centrifugal force and gyroscopic moment, and with the centrifugal force only;
* claims 3-4 (section 3.2, Figs 7-14): the preload sweep, response, orbit, spectra, Poincare
  sections, Floquet multipliers and largest Lyapunov exponent at 800 N and 600 N;
* claim 5 (section 3.3, Figs 15-16): the clearance sweep (4, 10, 20, 30 um);
* claim 6 (section 3.4, Figs 17-19): the radial-load sweeps (P_x = P_y = 200 and 500 N);
* claim 7 (section 3.5, Fig. 20): races with waviness of order 18, balls of order 2, 1 um;
* beyond the paper: stability map over preload and shaft speed, the effect of the damping
  ratio, and the linear stability of the static equilibrium (e = 0);

and writes ``summary.json`` (numbers), ``data/sweeps.csv`` (every sweep point) and the report
(default ``<out>/../reproduction.md``): for each claim the paper's statement, our number and a
verdict with the reason for every difference. The verdicts follow fixed criteria written in the
report; nothing is tuned to the paper's numbers. The reproduction's own figures in ``--out``
that the run did not write (from a run with another plan) are removed, so the folder matches
the report; other files there are left alone. ``--cache FILE`` keeps the raw task results
(``--redo PREFIX ...`` recomputes some of them); ``--report-only`` rewrites the report from
``summary.json``.

Every stability result is stated with its damping model and with how the point was reached:
**continuation** (each preload starts from the end state of the previous one: the bifurcation of
the periodic orbit) or **cold start** (from the static equilibrium). ``--quick`` runs coarse
grids with short durations (about 1 minute on 2 free cores) to check the pipeline; its numbers
are rougher than the full run's (about 8 minutes on 2 free cores, 15 when they are shared).

The steps live in :mod:`.plan` (grids), :mod:`.experiments` (worker tasks), :mod:`.figures`,
:mod:`.summary` (the numbers), :mod:`.claims` (checks and verdicts), :mod:`.report` and
:mod:`.sections` (the report text per claim).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pickle
import time
from pathlib import Path

from bearing_gym.analysis.sweeps import run_tasks, save_csv
from bearing_gym.serialization import to_jsonable

from .claims import check_claims
from .experiments import run_task, tasks
from .figures import remove_stale_figures, write_figures
from .plan import FULL, QUICK
from .report import write_report
from .summary import physics_hash, summarize

__all__ = ["main"]


def _load_cache(path: Path) -> dict:
    """The pickled results of an earlier run, or {} if the file cannot be used (made by
    another version of the package)."""
    try:
        with open(path, "rb") as fh:
            blob = pickle.load(fh)
    except (pickle.UnpicklingError, AttributeError, ModuleNotFoundError, EOFError, ImportError):
        return {}
    return blob if isinstance(blob, dict) else {}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m bearing_gym.reproduction",
                                 description="Regenerate the figures, summary.json and report of the "
                                             "reproduction of Bai & Xu (2006).")
    ap.add_argument("--quick", action="store_true", help="coarse grids, short runs (~3 min)")
    ap.add_argument("--out", default="docs/reproduction", help="directory for PNG, summary.json, data/")
    ap.add_argument("--report", default=None, help="report path (default: <out>/../reproduction.md)")
    ap.add_argument("--workers", type=int, default=min(2, os.cpu_count() or 1),
                    help="parallel worker processes (default: min(2, cores))")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    ap.add_argument("--cache", default=None,
                    help="pickle of the raw task results: reused when present, updated after the run")
    ap.add_argument("--redo", nargs="*", default=[],
                    help="with --cache: task-key prefixes to recompute (e.g. waviness_ detail_)")
    ap.add_argument("--report-only", action="store_true",
                    help="only rewrite the report from an existing <out>/summary.json")
    args = ap.parse_args(argv)
    if args.workers < 1:
        ap.error("--workers must be >= 1")
    plan = QUICK if args.quick else FULL
    out = Path(args.out)
    (out / "data").mkdir(parents=True, exist_ok=True)
    report = Path(args.report) if args.report else out.parent / "reproduction.md"
    if args.report_only:
        summary_path = out / "summary.json"
        if not summary_path.exists():
            ap.error(f"{summary_path} does not exist: run without --report-only first")
        write_report(json.loads(summary_path.read_text()), report, out)
        print(f"report rewritten: {report}")
        return 0

    t0 = time.perf_counter()
    task_list = tasks(plan)
    physics = physics_hash()
    cached: dict = {}
    compute_s = 0.0
    if args.cache and Path(args.cache).exists():
        blob = _load_cache(Path(args.cache))
        if blob.get("plan") == plan and blob.get("physics_source_sha256") == physics:
            cached = {k: v for k, v in blob["results"].items()
                      if not any(k.startswith(p) for p in args.redo)}
            compute_s = blob.get("compute_s", math.nan) if cached else 0.0
        else:
            print(f"cache {args.cache} was made with another plan or other physics sources: "
                  "recomputing everything")
    todo = [t for t in task_list if t[0] not in cached]
    values = run_tasks(run_task, [(kind, kw) for _, kind, kw in todo], max_workers=args.workers,
                       progress=not args.no_progress, desc=f"reproduction ({plan.name})")
    results = {**cached, **{key: v for (key, _, _), v in zip(todo, values)}}
    results = {key: results[key] for key, _, _ in task_list}
    wall = compute_s + (time.perf_counter() - t0)
    if args.cache:
        Path(args.cache).parent.mkdir(parents=True, exist_ok=True)
        with open(args.cache, "wb") as fh:
            pickle.dump(dict(plan=plan, results=results, physics_source_sha256=physics,
                             compute_s=wall), fh)

    written = write_figures(results, plan, out)
    remove_stale_figures(out, written)
    sweep_rows = [r for k, v in results.items() if isinstance(v, list) and v and isinstance(v[0], dict)
                  and "qpi" in v[0] for r in v] + [v for v in results.values() if isinstance(v, dict)
                                                   and v.get("mode") == "cold"]
    save_csv(sweep_rows, out / "data" / "sweeps.csv")
    summary = summarize(results, plan, wall, physics)
    summary["claims"] = check_claims(results, summary, plan)
    summary["figures"] = written
    (out / "summary.json").write_text(json.dumps(to_jsonable(summary), indent=1) + "\n")
    write_report(json.loads(json.dumps(to_jsonable(summary))), report, out)
    print(f"reproduction ({plan.name}) done in {time.perf_counter() - t0:.0f} s: {len(written)} figures "
          f"in {out}, summary {out / 'summary.json'}, report {report}")
    print(f"critical preload (continuation) {summary['critical_preload_n']} N, cold start "
          f"{summary['critical_preload_n_cold']} N")
    return 0
