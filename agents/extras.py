"""Which optional extra a part of ``agents`` needs, and the error that says so where it is missing."""

from importlib.util import find_spec as _find_spec

#: import name -> distribution of what the ``rl`` extra installs for training and torch inference
RL_EXTRA = {"stable_baselines3": "stable-baselines3", "sb3_contrib": "sb3-contrib", "torch": "torch",
            "rliable": "rliable", "yaml": "pyyaml"}
#: what scoring a policy needs beyond the env (the ``score`` extra, no torch): the statistics
SCORE_EXTRA = {"rliable": "rliable"}


def require_extra(what: str, extra: str = "rl") -> None:
    """Raise ImportError naming the extra to install if ``what`` (a command or feature) cannot run
    here: ``extra`` ``"rl"`` (training, torch inference) or ``"score"`` (scoring, the statistics)."""
    needed = RL_EXTRA if extra == "rl" else SCORE_EXTRA
    missing = [dist for mod, dist in needed.items() if _find_spec(mod) is None]
    if missing:
        raise ImportError(f"{what} needs the '{extra}' extra, which is not installed here (missing: "
                          f"{', '.join(missing)}): pip install \"bearing-gym[{extra}]\""
                          + (" (with the CPU build of torch first, as the README's set-up shows)" if extra == "rl" else
                             " (no torch: the statistics only)")
                          + ". The environment itself (import bearing_gym; gymnasium.make(\"BearingPreload-v0\")) "
                          "needs none of it.")


__all__ = ["RL_EXTRA", "SCORE_EXTRA", "require_extra"]
