"""What the benchmark scripts share: the command line (a table by default, ``--json`` for one
JSON object instead, ``--quick`` for a shorter run with the same keys, ``--out FILE`` (where
offered) to also write the JSON object to FILE) and the description of the machine a result
was measured on (:func:`machine_info`)."""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
from pathlib import Path
from typing import Callable

HERE = Path(__file__).resolve().parent


def machine_info(packages: bool = True) -> dict:
    """CPU model, logical CPUs, load, platform and Python; with ``packages`` also the NumPy,
    numba and bearing_gym versions and the git commit (and whether bearing_gym/ has uncommitted
    changes) of the checkout these scripts are in."""
    cpu = "unknown"
    try:
        cpu = next((ln.split(":", 1)[1].strip() for ln in Path("/proc/cpuinfo").read_text().splitlines()
                    if ln.startswith("model name")), cpu)
    except OSError:
        pass
    info = {"cpu_model": cpu, "logical_cpus": os.cpu_count(),
            "load_average_1min_at_start": round(os.getloadavg()[0], 2),
            "platform": platform.platform(), "python": platform.python_version()}
    if not packages:
        return info
    import numba
    import numpy as np

    import bearing_gym
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, text=True,
                                capture_output=True, timeout=5).stdout.strip() or None
        dirty = bool(subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no", "--", "bearing_gym"],
            cwd=HERE.parent, text=True, capture_output=True, timeout=5).stdout.strip())
    except (OSError, subprocess.SubprocessError):
        commit, dirty = None, None
    return {**info, "numpy": np.__version__, "numba": numba.__version__, "bearing_gym": bearing_gym.__version__,
            "git_commit": commit, "package_has_uncommitted_changes": dirty}


def parser(doc: str, quick_help: str, out: bool = True) -> argparse.ArgumentParser:
    """An argument parser described by the first paragraph of ``doc``, with the shared options."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    ap.add_argument("--quick", action="store_true", help=quick_help)
    if out:
        ap.add_argument("--out", metavar="FILE", help="also write the JSON object to FILE")
    return ap


def emit(result: dict, args: argparse.Namespace, print_table: Callable[[dict], None]) -> None:
    """Write ``result`` to ``--out`` if given; print it as JSON or as the table."""
    if getattr(args, "out", None):
        Path(args.out).write_text(json.dumps(result, indent=2) + "\n")
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        print_table(result)
