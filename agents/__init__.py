"""Preload controllers for BearingPreload-v0: scripted baselines, evaluation, SB3 training.

Every policy has the Stable-Baselines3 interface ``predict(obs, state=None, episode_start=None,
deterministic=True) -> (actions, state)`` on batched observations, so one evaluation loop
(:mod:`agents.evaluate`) runs scripted and learned controllers alike.
"""

__all__ = ["Policy", "ConstantPreload", "SpeedScheduledPreload", "FeedbackRule", "OraclePreload"]


def __getattr__(name):  # lazy, so `python -m agents.stability_table` imports nothing twice
    if name in __all__:
        from . import policies
        return getattr(policies, name)
    raise AttributeError(name)
