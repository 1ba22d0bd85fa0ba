"""How large a regeneration is: ``full`` rebuilds the stored numbers at the protocol's sizes
(what the repository ships), ``tiny`` the same products on a few episodes of a few steps, tiny
grids and sweeps, into a scratch directory (``--root``), for the tests.

A profile fixes every setting a product is built with, so the settings are recorded with the
products (a change of one rebuilds that product and its dependants). ``None`` leaves a product
out of a profile: ``tiny`` leaves out the learning curves (they score the trained runs' 20
validation episodes, which a tiny validation constant does not cover), the integrator's accuracy
benchmark and the paper's reproduction (a minute or more even at their smallest).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from bearing_gym.task import TIER_NAMES

from agents import protocol as P
from agents.leaderboard.settings import FULL as FULL_BOARD, SMOKE, Settings
from agents.paths import PACKAGE_DIR, TRAINED_DIR, TRAINED_V2_DIR
from agents.policies.contextual import MIN_FIT_EPISODES

__all__ = ["Profile", "FULL", "FULL_BASELINES", "TINY", "PROFILES", "trained_runs"]


def trained_runs(version: int | None = None, early: bool = True) -> tuple[str, ...]:
    """The protocol's trained runs shipped in the checkout: protocol 1's ``agents/trained/<algo>/seed_<s>``;
    protocol 2's ``agents/trained_v2/<algo>/seed_<s>`` and each run's early row
    (``.../by_<V2_EARLY_ROW_STEPS>``, the best checkpoint up to that step; not with ``early=False``:
    the learning curves read the runs' logs). ``version``: the protocol (default:
    agents.protocol.PROTOCOL_VERSION)."""
    version = P.PROTOCOL_VERSION if version is None else version
    root, pattern = (TRAINED_DIR, "*/seed_*") if version < 2 else (TRAINED_V2_DIR, "*/seed_*")
    runs = [p for p in root.glob(pattern) if p.is_dir()]
    if version >= 2 and early:
        runs += [p / f"by_{P.V2_EARLY_ROW_STEPS}" for p in runs if (p / f"by_{P.V2_EARLY_ROW_STEPS}").is_dir()]
    return tuple(sorted(p.relative_to(PACKAGE_DIR.parent).as_posix() for p in runs))


@dataclass(frozen=True)
class Profile:
    """Every setting of a regeneration (module docstring); run directories are relative to the checkout."""

    name: str
    tiers: tuple[str, ...]
    board: Settings                       # test episodes, their length, hindsight grid, planner, statistics
    validation_episodes: int              # per random tier (one on a deterministic tier)
    contextual_episodes: int
    contextual_grid_step_n: float
    reward_map: dict[str, Any]            # bearing_gym.envs.reward_map.reward_map's grid
    stability_table: dict[str, Any]       # agents.policies.stability_table.build's grid
    start_bank: dict[str, Any]            # tier, first and stop seed
    model_dirs: tuple[str, ...]           # the board's learned rows
    breakdown_tiers: tuple[str, ...]
    chaos: dict[str, Any]                 # tier, replicas, episodes
    tier_gap: dict[str, Any]              # tier_gap's options
    traces: dict[str, Any]                # agents.evaluate --pretrained: episodes, grid
    learning_curves: tuple[str, ...] | None
    bench_accuracy: bool
    reproduction: bool
    breakdown_row: str = "SAC (trained)"
    #: the open board's worked examples (examples/*.py) scored and shown beside the board's rows
    #: (they read the checkout's stored references, so the full profile only)
    examples: bool = False
    #: the industry and model-based baselines' products (protocol v2; agents.regenerate.catalogue):
    #: feedback_episodes/_rounds (validation seeds), schedule_episodes/_rounds (training seeds), the
    #: speed schedules' kinds. None: not products of this profile (the full profile's are
    #: FULL_BASELINES; each tier's were first made by their hand-run commands, resumable, and
    #: adopted)
    baselines: dict[str, Any] | None = None

    def board_for(self, tier: str) -> Settings:
        return self.board.for_tier(tier)

    def validation_for(self, tier: str) -> int:
        return P.episodes_for_tier(tier, self.validation_episodes)

    def contextual_for(self, tier: str) -> int:
        return P.episodes_for_tier(tier, self.contextual_episodes, minimum=MIN_FIT_EPISODES)


#: protocol v2's baseline fits at the protocol's sizes
FULL_BASELINES: dict[str, Any] = {
    "feedback_episodes": P.V2_FEEDBACK_TUNE_EPISODES, "feedback_rounds": P.V2_FEEDBACK_TUNE_ROUNDS,
    "schedule_episodes": P.SCHEDULE_FIT_EPISODES, "schedule_rounds": P.SCHEDULE_FIT_ROUNDS,
    "kinds": ("2-level", "3-level", "table")}

FULL = Profile(
    name="full", tiers=TIER_NAMES, board=FULL_BOARD,
    validation_episodes=P.VALIDATION_CONSTANT_EPISODES,
    contextual_episodes=P.CONTEXTUAL_FIT_EPISODES, contextual_grid_step_n=P.CONTEXTUAL_GRID_STEP_N,
    reward_map={},                        # the module's grid (81 cells x 18 preloads, 25 intervals)
    stability_table={},                   # the module's grid
    start_bank={"tier": "transient", "first": 0, "stop": P.V2_START_BANK_STARTS},   # protocol v2: a run meets no start twice
    model_dirs=trained_runs(), breakdown_tiers=("transient", "stationary", "field"),
    chaos={"tier": "transient", "replicas": 5, "episodes": P.TEST_EPISODES},
    tier_gap={"tier": "transient", "seed": P.TIER_DESIGN.start, "episodes": 20, "grid_step": 50.0, "horizon": 10,
              "replan_every": 5},
    traces={"episodes": 2, "grid_step_n": P.HINDSIGHT_GRID_STEP_N},
    learning_curves=trained_runs(early=False), bench_accuracy=True, reproduction=True, examples=True,
    baselines=FULL_BASELINES)

_COARSE = SMOKE.hindsight_grid_step_n     # 300, 1150, 2000 N

TINY = Profile(
    name="tiny", tiers=("transient",),
    # 3 test episodes (the breakdown's thirds) of 3 steps, the smoke planner
    board=dataclasses.replace(SMOKE, smoke=False, episodes=3),
    validation_episodes=2, contextual_episodes=MIN_FIT_EPISODES, contextual_grid_step_n=_COARSE,
    reward_map={"speeds_rpm": (17500.0,), "radial_loads_n": (250.0,), "clearances_m": (17e-6,),
                "eccentricities_m": (10e-6,), "preloads_n": (300.0, 1150.0, 2000.0), "measure_intervals": 2},
    stability_table={"speeds": (20000.0,), "radial_loads": (0.0,), "clearances": (4e-6,), "preloads": (800.0, 600.0)},
    start_bank={"tier": "transient", "first": 0, "stop": 2},
    model_dirs=("agents/trained/sac/seed_0",), breakdown_tiers=("transient",),
    chaos={"tier": "transient", "replicas": 2, "episodes": 2},
    tier_gap={"tier": "transient", "seed": P.TIER_DESIGN.start, "episodes": 2, "grid_step": _COARSE, "horizon": 1,
              "replan_every": 150},
    traces={"episodes": 2, "grid_step_n": _COARSE},
    learning_curves=None, bench_accuracy=False, reproduction=False,
    baselines={"feedback_episodes": 2, "feedback_rounds": 1, "schedule_episodes": 2, "schedule_rounds": 1,
               "kinds": ("2-level",)})

PROFILES = {p.name: p for p in (FULL, TINY)}
