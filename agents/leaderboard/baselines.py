"""The board's industry-practice and model-based rows (protocol v2): what a spindle maker runs and
what the true model without the future gives, each from its stored fit or runs.

* ``industry``: the speed schedules fitted on training seeds (a 2-level and a 3-level speed
  switch, a speed table: :mod:`agents.references.speed_schedule_fit`) and the feedback rule tuned
  on validation seeds (:mod:`agents.references.feedback_fit`), evaluated on the test episodes like
  any policy;
* ``model-based``: the causal MPC (:mod:`agents.policies.causal_mpc`), its stored per-episode
  set-points replayed bit for bit (:mod:`agents.references.causal_mpc_runs`).

A fit or run missing for a tier (or made by another kernel) leaves its row out, named in
:func:`missing`; the board lists those as protocol deviations.
"""

from __future__ import annotations

import json
from pathlib import Path

from bearing_gym.envs.provenance import kernel_hash

from agents.evaluation.result import EvalResult
from agents.paths import DATA_DIR
from agents.policies.scripted import Policy
from agents.policies.speed_schedule import SpeedSchedule
from agents.references import causal_mpc_runs
from agents.references.feedback_fit import feedback_path, load_feedback
from agents.references.speed_schedule_fit import KINDS, schedule_path

__all__ = ["industry_policies", "causal_mpc_row", "missing", "not_the_protocols", "INDUSTRY_KIND", "MODEL_BASED_KIND"]

INDUSTRY_KIND = "industry"
MODEL_BASED_KIND = "model-based"


def _fresh(path: Path) -> dict | None:
    try:
        d = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return None
    return d if d.get("kernel_hash") == kernel_hash() else None


def industry_policies(tier: str, data_dir: Path = DATA_DIR) -> list[Policy]:
    """The tier's fitted speed schedules and tuned feedback rule that are stored for this kernel,
    each named for its row."""
    out: list[Policy] = []
    for kind in KINDS:
        d = _fresh(schedule_path(tier, kind, data_dir))
        if d is not None:
            p = SpeedSchedule.from_json(d["schedule"])
            p.name = f"{p.name} (fitted on training seeds)"
            out.append(p)
    if _fresh(feedback_path(tier, data_dir)) is not None:
        out.append(load_feedback(tier, data_dir))
    return out


def causal_mpc_row(tier: str, episodes: int, episode_steps: int, data_dir: Path = DATA_DIR) -> EvalResult | None:
    """The causal MPC's row on the first ``episodes`` test episodes, replayed from its stored runs
    (None if any is missing)."""
    if causal_mpc_runs.missing(tier, episodes, episode_steps=episode_steps, data_dir=data_dir):
        return None
    return causal_mpc_runs.replay(tier, causal_mpc_runs.load_runs(tier, episodes, episode_steps=episode_steps,
                                                                  data_dir=data_dir), episode_steps)


def missing(tier: str, episodes: int, episode_steps: int, data_dir: Path = DATA_DIR) -> list[str]:
    """What of the tier's industry and model-based rows is not stored for this kernel, each with
    the command that makes it."""
    out = [f"speed schedule {kind}: python -m agents.references.speed_schedule_fit --tier {tier} --kind {kind}"
           for kind in KINDS if _fresh(schedule_path(tier, kind, data_dir)) is None]
    if _fresh(feedback_path(tier, data_dir)) is None:
        out.append(f"feedback rule: python -m agents.references.feedback_fit --tier {tier}")
    gone = causal_mpc_runs.missing(tier, episodes, episode_steps=episode_steps, data_dir=data_dir)
    if gone:
        out.append(f"causal MPC ({len(gone)} episodes): python -m agents.references.causal_mpc_runs --tier {tier} "
                   "--until HH:MM")
    return out


def not_the_protocols(tier: str, data_dir: Path = DATA_DIR, store: Path | None = None) -> list[str]:
    """The tier's stored fits (present for this kernel, so rows of the board) that are not what
    the protocol's fit would write today (other episodes, rounds, candidates, start - the
    validation constant in ``store`` - or an older record): each named with its first problem.
    Protocol-sized boards list them as deviations."""
    from bearing_gym.task import EPISODE_STEPS

    from agents import protocol as P
    from agents.references import feedback_fit, speed_schedule_fit
    out = []
    for kind in KINDS:
        path = schedule_path(tier, kind, data_dir)
        if _fresh(path) is not None:
            problems = speed_schedule_fit.fit_problems(
                tier, kind, path, P.episodes_for_tier(tier, P.SCHEDULE_FIT_EPISODES), P.SCHEDULE_FIT_ROUNDS,
                EPISODE_STEPS, store)
            if problems:
                out.append(f"speed schedule {kind} is not the protocol's fit ({problems[0]}): "
                           f"python -m agents.references.speed_schedule_fit --tier {tier} --kind {kind}")
    path = feedback_path(tier, data_dir)
    if _fresh(path) is not None:
        problems = feedback_fit.fit_problems(tier, path, P.episodes_for_tier(tier, P.V2_FEEDBACK_TUNE_EPISODES),
                                             P.V2_FEEDBACK_TUNE_ROUNDS, EPISODE_STEPS)
        if problems:
            out.append(f"feedback rule is not the protocol's fit ({problems[0]}): "
                       f"python -m agents.references.feedback_fit --tier {tier}")
    return out
