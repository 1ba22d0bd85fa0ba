"""Reading and writing sweep rows (lists of dicts with the columns of :data:`.points.COLUMNS`):
CSV and NPZ files, and the cell conventions they share."""

from __future__ import annotations

import csv
import math
import os
from typing import Any, Sequence

import numpy as np

from .points import COLUMNS

__all__ = ["save_csv", "load_csv", "save_npz", "format_cell", "truthy", "fieldnames"]


def truthy(v: Any) -> bool:
    """A boolean cell as written to CSV ("True", "1", "yes"; any case) or as computed."""
    if isinstance(v, str):
        return v.strip().lower() in ("true", "1", "yes")
    return bool(v)


def format_cell(v: Any) -> Any:
    """A value as written to a CSV cell: floats with 10 significant digits, others as they are."""
    return f"{v:.10g}" if isinstance(v, float) else v


def fieldnames(rows: Sequence[dict]) -> list[str]:
    """:data:`COLUMNS` first, then every other key of the rows, sorted."""
    return list(COLUMNS) + sorted({k for r in rows for k in r} - set(COLUMNS))


def save_csv(rows: Sequence[dict], path: str | os.PathLike) -> None:
    """Write the rows (columns :data:`COLUMNS` first, then any extra keys) to a CSV file."""
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fieldnames(rows), restval="")
        w.writeheader()
        for r in rows:
            w.writerow({k: format_cell(v) for k, v in r.items()})


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
    arrays = {}
    for k in fieldnames(rows):
        vals = [r.get(k, math.nan) for r in rows]
        if all(isinstance(v, (bool, np.bool_)) for v in vals):
            arrays[k] = np.array(vals, dtype=bool)
        elif all(isinstance(v, (int, float, np.integer, np.floating)) for v in vals):
            arrays[k] = np.array(vals, dtype=float)
        else:
            arrays[k] = np.array([str(v) for v in vals])
    np.savez(path, **arrays)
