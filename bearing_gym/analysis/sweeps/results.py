"""Reading stability results off sweep rows: the critical preload and the period-1 windows."""

from __future__ import annotations

import math
from typing import Iterable

from .io import truthy

__all__ = ["critical_preload", "stable_windows"]


def _by_preload(rows: Iterable[dict]) -> list[dict]:
    return sorted(rows, key=lambda r: -float(r["axial_preload_n"]))


def critical_preload(rows: Iterable[dict]) -> dict:
    """Critical preload of one sweep (rows of one label): walking down from the highest preload,
    the first point that is not periodic, after at least one that is.

    Returns ``dict(critical_n, bracket_n=(lowest periodic above, highest non-periodic below),
    note)``; ``critical_n`` is the midpoint of the bracket, or NaN with a note when every point
    is periodic ("below the range") or the highest one is not ("at or above the range").
    """
    rs = [r for r in _by_preload(rows) if str(r.get("status", "ok")).startswith(("ok", "floquet"))
          or not truthy(r["periodic"])]
    if not rs:
        return dict(critical_n=math.nan, bracket_n=(math.nan, math.nan), note="no points")
    if not truthy(rs[0]["periodic"]):
        return dict(critical_n=math.nan, bracket_n=(math.nan, float(rs[0]["axial_preload_n"])),
                    note="not periodic at the highest preload: critical preload at or above the range")
    for hi, lo in zip(rs, rs[1:]):
        if not truthy(lo["periodic"]):
            a, b = float(hi["axial_preload_n"]), float(lo["axial_preload_n"])
            return dict(critical_n=0.5 * (a + b), bracket_n=(b, a), note="")
    return dict(critical_n=math.nan, bracket_n=(float(rs[-1]["axial_preload_n"]), math.nan),
                note="periodic at every preload: critical preload below the range")


def stable_windows(rows: Iterable[dict]) -> list[tuple[float, float]]:
    """Intervals [P_lo, P_hi] of consecutive periodic points (rows of one label), highest first."""
    out: list[tuple[float, float]] = []
    cur: list[float] | None = None
    for r in _by_preload(rows):
        p = float(r["axial_preload_n"])
        if truthy(r["periodic"]):
            cur = [p, p] if cur is None else [p, cur[1]]
        elif cur is not None:
            out.append((cur[0], cur[1]))
            cur = None
    if cur is not None:
        out.append((cur[0], cur[1]))
    return out
