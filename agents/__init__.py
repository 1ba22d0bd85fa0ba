"""Preload controllers for BearingPreload-v0 and the leaderboard that compares them (the ``rl`` extra:
``pip install "bearing-gym[rl]"``).

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

from importlib.util import find_spec as _find_spec

#: import name -> distribution of what the ``rl`` extra installs and agents needs
RL_EXTRA = {"stable_baselines3": "stable-baselines3", "sb3_contrib": "sb3-contrib", "torch": "torch",
            "rliable": "rliable", "yaml": "pyyaml"}

_missing = [dist for mod, dist in RL_EXTRA.items() if _find_spec(mod) is None]
if _missing:
    raise ImportError(f"agents needs the 'rl' extra, which is not installed here (missing: {', '.join(_missing)}): "
                      "pip install \"bearing-gym[rl]\" (with the CPU build of torch first, as the README's set-up "
                      "shows). The environment itself (import bearing_gym; gymnasium.make(\"BearingPreload-v0\")) "
                      "needs none of it.")

__all__ = ["Policy", "ConstantPreload", "SpeedScheduledPreload", "FeedbackRule", "OraclePreload", "RL_EXTRA"]


def __getattr__(name):  # lazy, so `python -m agents.<module>` imports nothing twice
    if name in __all__:
        from .policies import scripted
        return getattr(scripted, name)
    raise AttributeError(name)
