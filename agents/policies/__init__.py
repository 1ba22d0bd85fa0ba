"""The controllers: scripted baselines (:mod:`.scripted`) and their stability table
(:mod:`.stability_table`), the map oracle (:mod:`.oracle`), the contextual constant
(:mod:`.contextual`, its ridge regression :mod:`.ridge`), the full-horizon planner that is the
leaderboard's upper reference (:mod:`.planner`), the short-horizon MPC of the tier-design study
(:mod:`.mpc`; both use the true simulator) and trained SB3 policies in portable float64
(:mod:`.portable`)."""

from agents.policies.scripted import ConstantPreload, FeedbackRule, OraclePreload, Policy, SpeedScheduledPreload

__all__ = ["Policy", "ConstantPreload", "SpeedScheduledPreload", "FeedbackRule", "OraclePreload"]
