"""The board's learned rows: train.py run directories grouped into one row per (algorithm, tier
trained on, shipped or not, budget), each run's policy loaded through the portable float64 path
where it covers the architecture."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from bearing_gym.task import DEFAULT_TIER

from agents import protocol as P
from agents.evaluation.trained import PRETRAINED_DIR, SB3Policy, load_trained, shipped_dirs

__all__ = ["LearnedGroup", "learned_groups", "missing_v2_rows", "inference"]


@dataclass
class LearnedGroup:
    """One algorithm's runs (one policy per training seed) trained on ``tier``: a row on the board
    of every tier evaluated (:meth:`row_name`)."""

    name: str
    algo: str
    tier: str
    policies: list[SB3Policy]
    seeds: list[int | None]
    timesteps: list[int | None]
    dirs: list[str] = field(default_factory=list)
    shipped: bool = False
    train_wall_s: list[float | None] = field(default_factory=list)
    #: a protocol-v2 early row: the best checkpoint up to this many env steps (None: the run's selection)
    early_row_steps: int | None = None
    #: the protocol each run trained under (train.py's config; 1 if it does not say)
    protocols: list[int] = field(default_factory=list)

    def row_name(self, tier: str) -> str:
        """The row's name on the board of ``tier`` (saying so where it was trained on another)."""
        return self.name if tier == self.tier else f"{self.name} - trained on {self.tier}"


def _config(d: Path) -> dict:
    cfg = d / "config.json"
    return json.loads(cfg.read_text()) if cfg.exists() else {}


def learned_groups(model_dirs: list[str | Path], pretrained: bool,
                   pretrained_dir: Path = PRETRAINED_DIR) -> list[LearnedGroup]:
    """The learned rows: ``model_dirs`` grouped by (algorithm, tier) from their config.json
    (one directory per training seed), then one row per shipped policy in
    ``pretrained_dir/<algo>/`` if ``pretrained``."""
    groups: dict[tuple[str, str, bool, int | None], LearnedGroup] = {}

    def add(d: Path, algo: str | None, shipped: bool) -> None:
        cfg = _config(d)
        algo = algo or cfg.get("algo")
        if algo is None:
            raise ValueError(f"{d}: no config.json names the algorithm; train it with train.py or put the "
                             "model in agents/pretrained/<algo>/")
        tier = cfg.get("tier", DEFAULT_TIER)
        early = cfg.get("early_row_steps")          # a protocol-v2 run's row at its early budget
        key = (algo, tier, shipped, early)
        if key not in groups:
            label = "shipped" if shipped else "trained" if early is None else f"trained, best up to {early // 1000}k steps"
            groups[key] = LearnedGroup(f"{algo.upper()} ({label})", algo, tier, [], [], [], shipped=shipped,
                                       early_row_steps=early)
        g = groups[key]
        g.policies.append(load_trained(d, algo=algo, portable="auto"))   # the same bits on every CPU where covered
        g.seeds.append(cfg.get("seed"))
        g.timesteps.append(cfg.get("selected_timesteps", cfg.get("num_timesteps")))
        g.dirs.append(str(d))
        g.train_wall_s.append(None if early else cfg.get("train_wall_s"))    # an early row: the run's is not its
        g.protocols.append(cfg.get("protocol", 1))

    for d in model_dirs:
        add(Path(d), None, False)
    if pretrained:
        for d in shipped_dirs(pretrained_dir):
            add(d, d.name, True)
    return list(groups.values())


def missing_v2_rows(groups: list[LearnedGroup]) -> list[str]:
    """Protocol v2's learned rows that no run gives: per algorithm its selected checkpoint's row
    and its early row (runs trained on the board's tiers or not)."""
    have = {(g.algo, g.early_row_steps) for g in groups if not g.shipped}
    return [f"{algo.upper()}: no {'early row' if early else 'trained run'} (protocol v2's runs: "
            f"python -m agents.training.protocol_runs --protocol 2 --list)"
            for algo in P.V2_ALGORITHMS for early in (None, P.V2_EARLY_ROW_STEPS) if (algo, early) not in have]


def inference(policies: list) -> str:
    """How a group's actions were computed: bit-identical on every CPU, or through torch."""
    from agents.policies.portable import PortablePolicy
    if all(isinstance(p, PortablePolicy) for p in policies):
        return "portable float64 (agents/policies/portable.py): the same bits on every CPU"
    return "torch: its last bits differ between CPUs"
