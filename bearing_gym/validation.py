"""Checks of user-supplied numbers, shared by the parameters, the physics and the environment.

Each check returns the value converted to ``float`` or ``int`` and raises :class:`ValueError`
naming the quantity and its allowed range otherwise, e.g.
``axial_preload_n must be in [0, 1e+06], got -5``.
"""

from __future__ import annotations

import math
from typing import Any, Iterable

import numpy as np

__all__ = ["check_real", "check_int", "check_bool", "check_real_tuple"]


def check_real(name: str, value: Any, low: float | None = None, high: float | None = None,
               low_open: bool = False, high_open: bool = False) -> float:
    """Return ``value`` as float; raise ValueError naming ``name`` unless finite and in range
    (``low``/``high`` None: unbounded; ``low_open``/``high_open``: the bound is excluded)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    v = float(value)
    lo_txt = "-inf" if low is None else f"{low:g}"
    hi_txt = "inf" if high is None else f"{high:g}"
    rng = (f"{'(' if low_open or low is None else '['}{lo_txt}, "
           f"{hi_txt}{')' if high_open or high is None else ']'}")
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite and in {rng}, got {value!r}")
    if low is not None and (v < low or (low_open and v == low)):
        raise ValueError(f"{name} must be in {rng}, got {v:g}")
    if high is not None and (v > high or (high_open and v == high)):
        raise ValueError(f"{name} must be in {rng}, got {v:g}")
    return v


def check_int(name: str, value: Any, low: int, high: int) -> int:
    """Return ``value`` as int; raise ValueError naming ``name`` unless an integer (not a bool)
    in [low, high]."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer in [{low}, {high}], got {value!r}")
    v = int(value)
    if v < low or v > high:
        raise ValueError(f"{name} must be an integer in [{low}, {high}], got {v}")
    return v


def check_bool(name: str, value: Any) -> bool:
    """Return ``value`` as bool; raise ValueError naming ``name`` unless True or False (or a
    NumPy bool): 0, 1 or "yes" are refused, so that a misplaced number is not read as a switch."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def check_real_tuple(name: str, value: Iterable[Any], low: float | None = None,
                     high: float | None = None) -> tuple[float, ...]:
    """Tuple of floats, each checked by :func:`check_real` as ``name[k]``."""
    try:
        items = tuple(value)
    except TypeError:
        raise ValueError(f"{name} must be a sequence of real numbers, got {value!r}") from None
    return tuple(check_real(f"{name}[{k}]", x, low, high) for k, x in enumerate(items))
