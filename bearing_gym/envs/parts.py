"""Swappable parts of the environment and how they survive ``env.spec.to_json()``.

The env is composed of parts: a scenario distribution, an actuator, a sensor (observation
model) and a reward model (see :mod:`.scenario`, :mod:`.actuator`, :mod:`.observation`,
:mod:`.reward` for the protocols each must follow). Pass your own object to ``gym.make``::

    gym.make("BearingPreload-v0", reward=MyReward(), observation=MySensor())

Gymnasium serialises ``env.spec`` with :func:`dataclasses.asdict`, which turns a dataclass
into a plain dict and loses its type. A part that is a dataclass with an ``entry_point`` field
(``field(default="", init=False)``, filled in ``__post_init__`` by :func:`part_entry_point`)
carries ``"module:QualName"`` into that dict, and :func:`resolve_part` rebuilds the object from
it: ``gym.make(gym.envs.registration.EnvSpec.from_json(env.spec.to_json()))`` gives the same env.
A part that is not such a dataclass still works; only its spec does not round-trip.
"""

from __future__ import annotations

import dataclasses
import importlib
from collections.abc import Mapping
from typing import Any

__all__ = ["part_entry_point", "resolve_part", "rebuild_dataclass", "ENTRY_POINT"]

ENTRY_POINT = "entry_point"


def part_entry_point(part: Any) -> None:
    """Record ``"module:QualName"`` of ``part``'s class in its ``entry_point`` field (frozen
    dataclasses allowed); call it from ``__post_init__``."""
    object.__setattr__(part, ENTRY_POINT, f"{type(part).__module__}:{type(part).__qualname__}")


def _import(entry_point: str) -> type:
    module_name, _, qualname = entry_point.partition(":")
    if not module_name or not qualname:
        raise ValueError(f"entry_point must look like 'package.module:ClassName', got {entry_point!r}")
    obj: Any = importlib.import_module(module_name)
    for name in qualname.split("."):
        obj = getattr(obj, name)
    return obj


def _rebuild(value: Any) -> Any:
    """Rebuild dataclasses (dicts with an entry_point) recursively; lists become tuples."""
    if isinstance(value, Mapping):
        if ENTRY_POINT in value:
            cls = _import(str(value[ENTRY_POINT]))
            init = {f.name for f in dataclasses.fields(cls) if f.init} if dataclasses.is_dataclass(cls) else None
            kwargs = {k: _rebuild(v) for k, v in value.items()
                      if k != ENTRY_POINT and (init is None or k in init)}
            return cls(**kwargs)
        return {k: _rebuild(v) for k, v in value.items()}
    if isinstance(value, list):
        return tuple(_rebuild(v) for v in value)
    return value


def rebuild_dataclass(cls: type, data: Mapping[str, Any]) -> Any:
    """``cls`` rebuilt from the dict :func:`dataclasses.asdict` made of it (nested dataclass
    fields recursively, lists back to tuples): how a spec's JSON gets ``params`` back."""
    import typing
    hints = typing.get_type_hints(cls)
    kwargs = {}
    for f in dataclasses.fields(cls):
        if not f.init or f.name not in data:
            continue
        value, hint = data[f.name], hints.get(f.name)
        if isinstance(value, Mapping) and dataclasses.is_dataclass(hint):
            value = rebuild_dataclass(hint, value)
        elif isinstance(value, list):
            value = _rebuild(value)
        kwargs[f.name] = value
    return cls(**kwargs)


def resolve_part(name: str, value: Any, default: Any, required: tuple[str, ...]) -> Any:
    """The part to use for argument ``name``: ``default`` for None, an object rebuilt from a
    dict with an ``entry_point`` (what ``spec.to_json`` produced), else ``value`` itself. The
    result must have the attributes ``required``; a TypeError names what is missing."""
    if value is None:
        return default
    if isinstance(value, Mapping):
        if ENTRY_POINT not in value:
            raise TypeError(f"{name}: a dict must carry an {ENTRY_POINT!r} ('package.module:ClassName') "
                            f"to be rebuilt into a part, got keys {sorted(value)}")
        value = _rebuild(value)
    missing = [attr for attr in required if not hasattr(value, attr)]
    if missing:
        raise TypeError(f"{name} must provide {', '.join(required)} (see bearing_gym.envs.parts); "
                        f"{type(value).__name__} lacks {', '.join(missing)}")
    return value
