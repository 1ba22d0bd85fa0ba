"""The controllers: scripted baselines (:mod:`.scripted`) and their stability table
(:mod:`.stability_table`), the map oracle (:mod:`.oracle`), the contextual constant
(:mod:`.contextual`, its ridge regression :mod:`.ridge`), the MPC with the true simulator
(:mod:`.mpc`) and trained SB3 policies in portable float64 (:mod:`.portable`)."""

from agents.policies.scripted import ConstantPreload, FeedbackRule, OraclePreload, Policy, SpeedScheduledPreload

__all__ = ["Policy", "ConstantPreload", "SpeedScheduledPreload", "FeedbackRule", "OraclePreload"]
