"""Any policy behind the board's interface (``predict(obs, state, episode_start, deterministic) ->
(actions, state)`` on a batch of observations): a plain callable, an SB3 model, a train.py
directory, an RLlib module, or anything that already has ``predict``.

:func:`as_policies` is what the scoring API (:func:`agents.submit.score`) calls on its argument;
each element of a list is one training seed's policy.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

import numpy as np

from agents.policies.scripted import Policy
from agents.submit.actions import check_action_batch

__all__ = ["CallablePolicy", "TimeAwarePolicy", "as_policy", "as_policies", "check_action_batch"]


class CallablePolicy(Policy):
    """A function of observations as a board policy. ``batched`` (default): ``fn(obs)`` takes the
    batch ``(n, 15)`` float32 and returns ``n`` actions; else ``fn`` takes one observation ``(15,)``
    and returns one action, and is called once per row. Deterministic and memoryless by
    construction (``state`` is passed through)."""

    def __init__(self, fn: Callable[[np.ndarray], Any], name: str = "submitted policy", batched: bool = True):
        super().__init__()
        if not callable(fn):
            raise TypeError(f"a policy must be callable or have predict(); got {type(fn).__name__}")
        self.fn, self.name, self.batched = fn, name, bool(batched)

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        o = np.asarray(obs, dtype=np.float32)
        o = o[None, :] if o.ndim == 1 else o
        if self.batched:
            try:
                raw = self.fn(o)
            except (IndexError, TypeError, ValueError) as err:
                raise type(err)(f"policy {self.name!r} failed on a batch of observations of shape {o.shape} "
                                f"({err}); if it is a function of one observation, pass batched=False") from err
        else:
            raw = [np.asarray(self.fn(row), dtype=np.float32).reshape(-1) for row in o]
            if any(r.size != 1 for r in raw):
                k = next(i for i, r in enumerate(raw) if r.size != 1)
                raise ValueError(f"policy {self.name!r} (batched=False) returned {raw[k].size} numbers for one "
                                 "observation: it must return one action")
            raw = np.concatenate(raw)
        return check_action_batch(raw, len(o), self.name), state


class _CheckedPolicy(Policy):
    """An object with ``predict`` whose actions are checked like a callable's."""

    def __init__(self, inner: Any, name: str):
        super().__init__()
        self.inner, self.name = inner, name

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        act, state = self.inner.predict(obs, state=state, episode_start=episode_start, deterministic=deterministic)
        return check_action_batch(act, len(np.atleast_2d(obs)), self.name), state


class TimeAwarePolicy(Policy):
    """A policy trained with Gymnasium's ``TimeAwareObservation`` (time-to-go is allowed: the rules,
    docs/benchmark.md) on the board: each observation gets the env steps taken in its episode
    appended as the wrapper appends them (its default: the count, not normalised), counted from
    the board's ``episode_start`` flags, then goes to ``inner`` (anything :func:`as_policy` takes)."""

    def __init__(self, inner: Any, name: str = "submitted policy", batched: bool = True):
        super().__init__()
        self.inner, self.name = as_policy(inner, name, batched), name
        self.steps: np.ndarray | None = None

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        o = np.atleast_2d(np.asarray(obs, dtype=np.float32))
        if self.steps is None or len(self.steps) != len(o):
            self.steps = np.zeros(len(o))
        if episode_start is not None:
            self.steps[np.asarray(episode_start, dtype=bool)] = 0
        timed = np.concatenate([o, self.steps[:, None].astype(np.float32)], axis=1)
        act, state = self.inner.predict(timed, state=state, episode_start=episode_start, deterministic=deterministic)
        self.steps += 1
        return act, state


def _is_sb3_model(obj: Any) -> bool:
    return hasattr(obj, "policy") and hasattr(obj, "predict") and hasattr(obj, "get_vec_normalize_env")


def as_policy(obj: Any, name: str = "submitted policy", batched: bool = True) -> Policy:
    """One policy as the board runs it:

    * a train.py run directory (``str`` or ``Path`` holding model.zip), or a shipped or collected
      run's directory holding its portable export alone (``portable_policy.npz`` and
      ``config.json``): loaded as the board loads it, through the portable float64 path where it
      covers the architecture (the same actions bit for bit on every CPU; no torch needed once
      ``portable_policy.npz`` is exported), else through torch;
    * an SB3 model (PPO, SAC, ...; torch): its deterministic actions, with the observation
      normalisation of its VecNormalize env if it has one (a model loaded from a file has none:
      pass its train.py directory instead, which keeps ``vec_normalize.pkl``);
    * an RLlib Algorithm or RLModule (new API stack): :class:`agents.submit.rllib.RLlibPolicy`;
    * an object with ``predict(obs, state=None, episode_start=None, deterministic=True)`` (SB3's
      interface: recurrent policies keep their state this way);
    * a callable: :class:`CallablePolicy` (``batched``: a batch of observations at once, else one).
    """
    if isinstance(obj, (str, Path)):
        from agents.evaluation.trained import is_model_dir, load_trained
        d = Path(obj)
        if not is_model_dir(d):
            raise FileNotFoundError(f"{d}: no model.zip and no portable_policy.npz; a path names a train.py run "
                                    "directory (model.zip, vec_normalize.pkl, config.json) or a shipped one "
                                    "(portable_policy.npz, config.json)")
        pol = load_trained(d, portable="auto")
        pol.name = name
        return pol
    if _is_sb3_model(obj):
        from agents.evaluation.trained import SB3Policy
        venv = obj.get_vec_normalize_env()
        if venv is not None and venv.norm_obs:
            return SB3Policy(obj, venv.obs_rms, venv.clip_obs, venv.epsilon, name=name)
        return SB3Policy(obj, name=name)
    if hasattr(obj, "forward_inference") or (hasattr(obj, "get_module") and not hasattr(obj, "predict")):
        from agents.submit.rllib import RLlibPolicy
        return RLlibPolicy(obj, name=name)
    if hasattr(obj, "predict"):
        return _CheckedPolicy(obj, name)
    return CallablePolicy(obj, name, batched)


def as_policies(policy: Any, name: str = "submitted policy", batched: bool = True) -> list[Policy]:
    """``policy`` as a list of board policies, one per training seed: a list or tuple gives one
    each (at least one), anything else one (:func:`as_policy`)."""
    items = list(policy) if isinstance(policy, (list, tuple)) else [policy]
    if not items:
        raise ValueError("no policy to score: pass a policy, or a list of them (one per training seed)")
    return [as_policy(p, name if len(items) == 1 else f"{name} (run {k})", batched) for k, p in enumerate(items)]
