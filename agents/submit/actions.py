"""The check every submitted policy's actions pass: one finite action in [-1, 1] per observation."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["check_action_batch"]


def check_action_batch(actions: Any, n: int, name: str) -> np.ndarray:
    """``actions`` of ``n`` observations as float32 ``(n, 1)``; ValueError naming the policy if they
    are not ``n`` finite numbers in the action space [-1, 1] (the env does not clip)."""
    try:
        a = np.asarray(actions, dtype=np.float32)
    except (TypeError, ValueError):
        raise ValueError(f"policy {name!r} returned {type(actions).__name__}, not numbers: it must return one "
                         "action in [-1, 1] per observation") from None
    if a.size != n:
        raise ValueError(f"policy {name!r} returned {a.size} action(s) (shape {a.shape}) for {n} observation(s): it "
                         f"must return one per observation, shape ({n}, 1) or ({n},); for a function of one "
                         "observation pass batched=False")
    a = a.reshape(n, 1)
    bad = np.flatnonzero(~np.isfinite(a[:, 0]) | (a[:, 0] < -1.0) | (a[:, 0] > 1.0))
    if bad.size:
        k = int(bad[0])
        raise ValueError(f"policy {name!r} returned the action {float(a[k, 0])!r} for observation {k}: actions must be "
                         "finite and in the action space [-1, 1] (the preload set-point, 300-2000 N mapped "
                         "linearly); the env does not clip, so scale or clip it in your policy")
    return a
