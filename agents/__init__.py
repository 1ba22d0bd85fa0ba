"""Preload controllers for BearingPreload-v0 and the leaderboard that compares them.

Scoring a policy (:mod:`agents.submit`) and the scripted baselines need only the ``score`` extra
(``pip install "bearing-gym[score]"``: rliable's statistics, no torch); training, torch inference
and train.py the ``rl`` extra (``pip install "bearing-gym[rl]"``): :func:`require_extra` says which
is missing where it is needed.

Grouped by job, each subpackage importing only those above it in this list (tests/test_architecture.py):

    agents.paths, agents.protocol   where files live; the frozen protocol (seeds, budgets)
    agents.policies                 scripted baselines, the oracle, the contextual constant, the
                                    planner (the upper reference), the MPC (the tier-gap study),
                                    the portable float64 inference of trained SB3 policies
    agents.evaluation               running policies on episodes (one loop for all), their results,
                                    loading trained models, watching one play
    agents.references               computing the references (validation constant, hindsight,
                                    planner runs, contextual fit, tier gap) and their one store
    agents.leaderboard              the board: settings, scoring, tables, results file, breakdowns,
                                    learning curves, chaos replicas, side-by-side comparisons
    agents.training                 what train.py and the protocol's runs share (callbacks, the
                                    board after training, running the protocol)

Every policy has the Stable-Baselines3 interface ``predict(obs, state=None, episode_start=None,
deterministic=True) -> (actions, state)`` on batched observations, so one evaluation loop
(:mod:`agents.evaluation.episodes`) runs scripted and learned controllers alike.
"""

from agents.extras import RL_EXTRA, SCORE_EXTRA, require_extra

__all__ = ["Policy", "ConstantPreload", "SpeedScheduledPreload", "FeedbackRule", "OraclePreload", "RL_EXTRA",
           "SCORE_EXTRA", "require_extra"]


def __getattr__(name):  # lazy, so `python -m agents.<module>` imports nothing twice
    if name in __all__:
        from .policies import scripted
        return getattr(scripted, name)
    raise AttributeError(name)
