"""The command line's two kinds of failure and the checks that raise them."""

from __future__ import annotations

import math
from typing import Any

__all__ = ["CLIError", "RunError", "one_line", "check_option"]


class CLIError(Exception):
    """A user error: printed as ``bearing-gym: error: <message>``, exit status 2."""


class RunError(Exception):
    """A failure of the computation itself (integration or equilibrium): exit status 1."""


def one_line(text: Any) -> str:
    """``text`` with every run of whitespace (newlines too) made one space."""
    return " ".join(str(text).split())


def check_option(opt: str, value: Any, low: float, high: float, unit: str = "",
           low_open: bool = False) -> float:
    """``value`` if finite and in range, else CLIError('--opt: must be ... in [low, high] unit')."""
    rng = f"{'(' if low_open else '['}{low:g}, {high:g}]{(' ' + unit) if unit else ''}"
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise CLIError(f"{opt}: must be a finite number in {rng}, got {value!r}")
    if value < low or value > high or (low_open and value == low):
        raise CLIError(f"{opt}: must be in {rng}, got {value:g}")
    return float(value)
