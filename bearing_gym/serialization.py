"""One conversion of results to JSON-safe Python values, used by every JSON file the package
writes (the command line's outputs and the reproduction's ``summary.json``)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["to_jsonable"]


def to_jsonable(x: Any) -> Any:
    """``x`` with every container and number made JSON-safe, recursively: dict keys as strings,
    tuples and NumPy arrays as lists, NumPy scalars as Python ones, non-finite floats as None
    (JSON has no NaN or infinity), complex numbers as ``[re, im]`` (each part by the float
    rule). Anything else is returned as it is."""
    if isinstance(x, dict):
        return {str(k): to_jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [to_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return to_jsonable(x.tolist())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, (complex, np.complexfloating)):
        return [to_jsonable(float(x.real)), to_jsonable(float(x.imag))]
    return x
