"""How large a leaderboard run is (:class:`Settings`): ``FULL`` is the protocol, ``SMOKE`` checks
the pipeline at a tiny budget. The board (:mod:`agents.leaderboard.board`), its references
computed in parts (:mod:`agents.leaderboard.reference_parts`) and the board after training share
them.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from bearing_gym.task import EPISODE_STEPS

from agents import protocol as P
from agents.leaderboard import scoring
from agents.policies.planner import PlannerSettings


@dataclass(frozen=True)
class Settings:
    """How large a leaderboard run is. FULL is the protocol; SMOKE checks the pipeline."""

    smoke: bool
    episodes: int
    episode_steps: int
    hindsight_grid_step_n: float
    #: the upper reference's search on every test episode; None: no planner (the hindsight
    #: constant alone is the upper reference, a deviation from the protocol)
    planner: PlannerSettings | None
    bootstrap_reps: int
    poi_reps: int
    # smoke only: the validation constant and the contextual fit are computed at this size
    validation_episodes: int = 0
    contextual_episodes: int = 0
    contextual_grid_step_n: float = P.CONTEXTUAL_GRID_STEP_N

    def for_tier(self, tier: str) -> "Settings":
        """These settings on ``tier``: on a deterministic tier (every seed gives the same
        episode: ``paper``) one test and validation episode stand for the protocol's
        (:func:`agents.protocol.episodes_for_tier`); elsewhere unchanged."""
        return dataclasses.replace(self, episodes=P.episodes_for_tier(tier, self.episodes),
                                   validation_episodes=P.episodes_for_tier(tier, self.validation_episodes))

    def protocol_sized(self, tier: str) -> bool:
        """Whether these settings run ``tier`` at the protocol's size: not a smoke run, and the
        protocol's test episodes on that tier (:meth:`for_tier`: on a deterministic tier any
        ``--episodes`` is the protocol's one episode) and the protocol's planner. Such a run may
        write docs/results.json and the tier's stored test references by default."""
        mine, protocol = self.for_tier(tier), FULL.for_tier(tier)
        return not self.smoke and mine.episodes == protocol.episodes and mine.planner == protocol.planner

    def planner_settings(self) -> dict[str, Any] | None:
        """The planner's settings as stored with its rows (None: no planner)."""
        return None if self.planner is None else self.planner.as_dict()


FULL = Settings(smoke=False, episodes=P.TEST_EPISODES, episode_steps=EPISODE_STEPS,
                hindsight_grid_step_n=P.HINDSIGHT_GRID_STEP_N, planner=PlannerSettings(),
                bootstrap_reps=scoring.BOOTSTRAP_REPS, poi_reps=scoring.POI_REPS)


_COARSE_N = 850.0       # smoke grids: 300, 1150, 2000 N


SMOKE = Settings(smoke=True, episodes=2, episode_steps=3, hindsight_grid_step_n=_COARSE_N,
                 planner=PlannerSettings(replan_every=1, grid_step_n=_COARSE_N, local_n=(-_COARSE_N, _COARSE_N),
                                         block_n=(), jumps_n=(300.0, 2000.0), start_ramp_intervals=(2,),
                                         block_intervals=(1,), ramp_down_intervals=(2,)),
                 bootstrap_reps=200, poi_reps=50, validation_episodes=2, contextual_episodes=3,
                 contextual_grid_step_n=_COARSE_N)
