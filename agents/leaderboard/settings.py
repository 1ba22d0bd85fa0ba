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
from agents.policies.mpc import RecedingHorizonMPC


@dataclass(frozen=True)
class Settings:
    """How large a leaderboard run is. FULL is the protocol; SMOKE checks the pipeline."""

    smoke: bool
    episodes: int
    episode_steps: int
    mpc_episodes: int
    hindsight_grid_step_n: float
    mpc: RecedingHorizonMPC
    bootstrap_reps: int
    poi_reps: int
    # smoke only: the validation constant and the contextual fit are computed at this size
    validation_episodes: int = 0
    contextual_episodes: int = 0
    contextual_grid_step_n: float = P.CONTEXTUAL_GRID_STEP_N

    def for_tier(self, tier: str) -> "Settings":
        """These settings on ``tier``: on a deterministic tier (every seed gives the same
        episode: ``paper``) one test, MPC and validation episode stand for the protocol's
        (:func:`agents.protocol.episodes_for_tier`); elsewhere unchanged."""
        return dataclasses.replace(self, episodes=P.episodes_for_tier(tier, self.episodes),
                                   mpc_episodes=P.episodes_for_tier(tier, self.mpc_episodes),
                                   validation_episodes=P.episodes_for_tier(tier, self.validation_episodes))

    def protocol_sized(self, tier: str) -> bool:
        """Whether these settings run ``tier`` at the protocol's size: not a smoke run, and the
        protocol's test and MPC episodes on that tier (:meth:`for_tier`: on a deterministic tier
        any ``--episodes`` is the protocol's one episode). Such a run may write docs/results.json
        and the tier's stored test references by default."""
        mine, protocol = self.for_tier(tier), FULL.for_tier(tier)
        return not self.smoke and (mine.episodes, mine.mpc_episodes) == (protocol.episodes, protocol.mpc_episodes)

    def mpc_settings(self) -> dict[str, Any]:
        """The MPC reference's settings as stored with its rows."""
        return {"horizon": self.mpc.horizon, "replan_every": self.mpc.replan_every,
                "candidates_n": list(self.mpc.candidates_n)}


FULL = Settings(smoke=False, episodes=P.TEST_EPISODES, episode_steps=EPISODE_STEPS, mpc_episodes=P.MPC_EPISODES,
                hindsight_grid_step_n=P.HINDSIGHT_GRID_STEP_N, mpc=RecedingHorizonMPC(),
                bootstrap_reps=scoring.BOOTSTRAP_REPS, poi_reps=scoring.POI_REPS)


_COARSE_N = 850.0       # smoke grids: 300, 1150, 2000 N


SMOKE = Settings(smoke=True, episodes=2, episode_steps=3, mpc_episodes=1, hindsight_grid_step_n=_COARSE_N,
                 mpc=RecedingHorizonMPC(candidates_n=(300.0, 2000.0), horizon=2, replan_every=2),
                 bootstrap_reps=200, poi_reps=50, validation_episodes=2, contextual_episodes=3,
                 contextual_grid_step_n=_COARSE_N)
