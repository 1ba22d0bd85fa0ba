"""The offline datasets' recipes: per dataset the tier, the behaviour policy, the training
scenarios it is run on and how the work is cut into parts. A recipe is all a dataset is: the
kernel gives the same bits on every CPU, so anyone rebuilds a dataset from its recipe and checks
it against the committed checksum (:mod:`agents.offline.build`).

Every dataset runs on the same block of training scenarios (``agents.protocol``:
OFFLINE_DATASET_SEED on), so the same episode seed is the same scenario (speed course, loads,
unbalance, clearance, waviness) under each behaviour:

* ``random``: uniform actions in [-1, 1], drawn per episode from ``numpy.random.default_rng(seed)``
  (integer arithmetic and a conversion: the same on every CPU);
* ``constant``: the tier's validation constant under protocol v2's rule (a value in the recipe,
  checked against the store by the tests, so the recipe does not move when the store does);
* ``medium``: a shipped learned policy (``agents/pretrained/sac``: protocol 2's shipped SAC, the
  seed-2000 run's selected checkpoint), run through its portable inference (the same bits on
  every CPU, no torch);
* ``expert``: the planner (the true simulator and the episode's whole future, the board's "1"),
  its plans stored per episode (``agents/data/offline/planner_<tier>/``, the dear part: about
  100 s of a core per episode) and replayed;
* ``mixed``: the episodes of the four on the expert's scenarios, one after another.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from agents import protocol as P
from agents.paths import DATA_DIR, PRETRAINED_DIR, file_digest

__all__ = ["Recipe", "RECIPES", "recipe", "dataset_id", "KINDS", "MEDIUM_PRETRAINED", "PLANS_DIR", "pretrained_dir",
           "VALIDATION_CONSTANT_N"]

KINDS = ("random", "constant", "portable", "planner", "mixed")
#: the shipped learned policy behind ``medium`` (agents/pretrained/<name>; its portable export is
#: hashed into the recipe)
MEDIUM_PRETRAINED = "sac"
#: where the expert's plans are stored, one JSON file per episode (agents.references.planner_runs' format)
PLANS_DIR = DATA_DIR / "offline"
#: protocol v2's validation constant of ``transient`` (V2_VALIDATION_RULE on the stored validation
#: returns; tests/agents/offline checks it against agents/data/reference_constants.json)
VALIDATION_CONSTANT_N = {"transient": 2000.0}


@dataclass(frozen=True)
class Recipe:
    """One dataset: ``episodes`` episodes of ``tier`` from training seed ``first_seed`` on, under
    the behaviour ``kind`` (module docstring) with its ``policy`` settings, built in parts of
    ``part_episodes`` episodes. ``sources``: a ``mixed`` dataset's (dataset, episodes) taken in
    order from each source's first episode."""

    name: str
    tier: str
    kind: str
    episodes: int
    first_seed: int = P.OFFLINE_DATASET_SEED
    part_episodes: int = 100
    policy: dict[str, Any] = field(default_factory=dict)
    sources: tuple[tuple[str, int], ...] = ()
    description: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"dataset {self.name}: kind must be one of {KINDS}, got {self.kind!r}")
        block = range(P.OFFLINE_DATASET_SEED, P.OFFLINE_DATASET_SEED + P.OFFLINE_DATASET_SEEDS)
        if self.kind != "mixed" and (self.first_seed not in block or self.first_seed + self.episodes - 1 not in block):
            raise ValueError(f"dataset {self.name}: seeds {self.first_seed}..{self.first_seed + self.episodes - 1} must "
                             f"lie in the offline datasets' training block {block.start}..{block.stop - 1}")
        if self.episodes < 1 or self.part_episodes < 1:
            raise ValueError(f"dataset {self.name}: episodes and part_episodes must be >= 1")

    @property
    def dataset_id(self) -> str:
        return dataset_id(self.tier, self.name)

    def parts(self) -> list[tuple[int, int]]:
        """(first seed, episodes) of every part, in order (a mixed dataset has one: the join)."""
        if self.kind == "mixed":
            return [(self.first_seed, self.episodes)]
        return [(self.first_seed + k, min(self.part_episodes, self.episodes - k))
                for k in range(0, self.episodes, self.part_episodes)]

    def as_json(self) -> dict[str, Any]:
        d = asdict(self)
        d["sources"] = [list(s) for s in self.sources]
        return d

    def digest(self) -> str:
        """SHA-256 (16 hex digits) of what the data depend on: the recipe (not its description),
        the medium policy's weights, a mixed dataset's sources' digests."""
        d = self.as_json()
        d.pop("description")
        if self.kind == "mixed":
            d["sources_sha"] = [recipe(f"{self.tier}/{name}").digest() for name, _ in self.sources]
        if self.kind == "portable":
            d["policy_weights_sha256"] = file_digest(pretrained_dir(self.policy["pretrained"]) / "portable_policy.npz")
        return hashlib.sha256(json.dumps(d, sort_keys=True).encode()).hexdigest()[:16]


def pretrained_dir(name: str) -> Path:
    return PRETRAINED_DIR / name


def dataset_id(tier: str, name: str) -> str:
    """Minari's id: ``bearing_gym/<tier>/<name>-v0`` (namespace bearing_gym/<tier>)."""
    return f"bearing_gym/{tier}/{name}-v0"


def _recipes() -> dict[str, Recipe]:
    from agents.policies.planner import PlannerSettings
    tier = "transient"
    expert_episodes = 200
    out = [
        Recipe("sample", tier, "random", 10, part_episodes=10,
               description="the random dataset's first 10 episodes (a build checked end to end in a minute: the tests)"),
        Recipe("random", tier, "random", 1000,
               description="uniform random actions in [-1, 1] (the actuator's whole range, every interval)"),
        Recipe("constant", tier, "constant", 1000, policy={"preload_n": VALIDATION_CONSTANT_N[tier]},
               description="the validation-chosen constant preload (protocol v2's rule)"),
        Recipe("medium", tier, "portable", 1000, policy={"pretrained": MEDIUM_PRETRAINED},
               description="protocol 2's shipped SAC (seed 2000's selected checkpoint), deterministic, portable inference"),
        Recipe("expert", tier, "planner", expert_episodes, part_episodes=20,
               policy={"planner": PlannerSettings().as_dict()},
               description="the planner: the true simulator and the episode's whole future (the board's 1)"),
        Recipe("mixed", tier, "mixed", 4 * expert_episodes,
               sources=(("random", expert_episodes), ("constant", expert_episodes), ("medium", expert_episodes),
                        ("expert", expert_episodes)),
               description="random, constant, medium and expert on the expert's scenarios, one after another"),
    ]
    return {r.dataset_id: r for r in out}


#: every dataset, by Minari id
RECIPES: dict[str, Recipe] = _recipes()


def recipe(name: str) -> Recipe:
    """The recipe of ``name``: a Minari id (``bearing_gym/transient/expert-v0``) or ``tier/name``
    (``transient/expert``)."""
    if name in RECIPES:
        return RECIPES[name]
    tier, _, short = name.partition("/")
    key = dataset_id(tier, short)
    if key not in RECIPES:
        raise KeyError(f"no dataset {name!r}; the datasets: {', '.join(RECIPES)}")
    return RECIPES[key]
