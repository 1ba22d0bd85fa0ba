"""The evaluation protocol's seed ranges, written down before any evaluation on them.

Every env seed a script uses comes from one of these disjoint ranges (``check_disjoint`` and
``tests/agents/test_protocol.py`` hold them apart):

* ``TRAIN``: training envs (``train.py --seed s`` seeds env i with s + i; their later episodes
  draw from the envs' own generators);
* ``VALIDATION``: checkpoint selection and every choice made while developing (hyperparameters,
  the best constant preload);
* ``TIER_DESIGN``: measurements that shaped the benchmark itself (``agents.tier_gap``: does a
  tier need closed-loop control?);
* ``TEST``: the held-out evaluation of the leaderboard; fresh, never used while developing.
  (The earlier test range, 100000+, was looked at during development and is retired:
  ``RETIRED``.)
"""

from __future__ import annotations

__all__ = ["TRAIN", "VALIDATION", "TIER_DESIGN", "TEST", "RETIRED", "RANGES", "check_disjoint"]

TRAIN = range(0, 50_000)
VALIDATION = range(50_000, 60_000)
RETIRED = range(100_000, 110_000)
TIER_DESIGN = range(200_000, 210_000)
TEST = range(300_000, 310_000)

RANGES = {"train": TRAIN, "validation": VALIDATION, "retired": RETIRED, "tier_design": TIER_DESIGN,
          "test": TEST}


def check_disjoint(ranges: dict[str, range] = RANGES) -> None:
    """Raise ValueError naming the first two ranges that overlap."""
    items = sorted(ranges.items(), key=lambda kv: kv[1].start)
    for (name_a, a), (name_b, b) in zip(items, items[1:]):
        if a.stop > b.start:
            raise ValueError(f"seed ranges {name_a} [{a.start}, {a.stop}) and {name_b} "
                             f"[{b.start}, {b.stop}) overlap")


def range_of(seed: int) -> str | None:
    """The name of the range that holds ``seed`` (None if none does)."""
    for name, r in RANGES.items():
        if seed in r:
            return name
    return None


check_disjoint()
