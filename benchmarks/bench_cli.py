"""The command line the benchmark scripts share: a table by default, ``--json`` for one JSON
object instead, ``--quick`` for a shorter run with the same keys, ``--out FILE`` (where
offered) to also write the JSON object to FILE."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Callable


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
