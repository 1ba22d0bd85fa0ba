"""A tier's upper reference ("1") on the board: the planner's row, what the planner adds to the
hindsight constant, and the tier fields and protocol deviations that follow from which upper
reference the stored references hold. Shared by the board (:mod:`agents.leaderboard.board`),
which runs the policies, and the re-scoring (:mod:`agents.leaderboard.rescore`), which scores
their stored per-episode returns against new references without running them again.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from agents.leaderboard import scoring
from agents.leaderboard.tables import summarise
from agents.references.store import StoredReferences
from agents.references.tier_gap import paired_ci

__all__ = ["PLANNER_ROW", "score_bounds", "require_planner_settings", "planner_row", "planner_gain", "upper_fields",
           "is_upper_deviation"]

#: the planner's row on the board (the upper reference)
PLANNER_ROW = "planner (true simulator, the episode's future)"

_ROLE = ("the upper reference: 1 by definition (below 1 only where the gap to the validation constant is under the "
         "denominator floor)")
_NO_PLANNER = "no planner: the upper reference is the hindsight constant alone (the protocol: the planner)"
_OTHER_SEARCH = "the planner searched with "


def score_bounds(refs: StoredReferences) -> tuple[np.ndarray, np.ndarray]:
    """R_0 (the validation constant) and R_1 (the planner, else the hindsight constant) per test
    episode: the score's 0 and 1 (:func:`agents.leaderboard.scoring.upper_reference` refuses a
    planner below the hindsight constant)."""
    r0 = np.asarray(refs.validation_constant.returns, dtype=np.float64)
    r1 = scoring.upper_reference(refs.hindsight.returns, None if refs.planner is None else refs.planner.returns)
    return r0, r1


def require_planner_settings(refs: StoredReferences, settings: dict[str, Any] | None) -> None:
    """Raise if the stored planner searched with other settings than ``settings`` (a run's
    :meth:`PlannerSettings.as_dict`), naming the commands that plan the tier again."""
    if refs.planner is not None and refs.planner_settings != settings:
        raise ValueError(f"the stored planner of tier {refs.tier} searched with {refs.planner_settings}, these "
                         f"settings name {settings}: plan again (`python -m agents.references.planner_runs --tier "
                         f"{refs.tier} --until HH:MM`, then `python -m agents.leaderboard.reference_parts --tier "
                         f"{refs.tier} --merge`)")


def planner_row(refs: StoredReferences, r0: np.ndarray, r1: np.ndarray, bootstrap_reps: int,
                poi_reps: int) -> dict[str, Any]:
    """The planner's row of results.json (``refs.planner`` must exist)."""
    if refs.planner is None or refs.planner_settings is None:
        raise ValueError(f"tier {refs.tier}: the stored references hold no planner: no planner row")
    return summarise("reference", [refs.planner], r0, r1, bootstrap_reps=bootstrap_reps, poi_reps=poi_reps,
                     **refs.planner_settings, wall_s_per_episode=refs.planner_wall_s_per_episode, role=_ROLE)


def planner_gain(refs: StoredReferences) -> dict[str, Any] | None:
    """The planner minus the hindsight constant, paired over the test episodes: what closed-loop
    scheduling with the episode's future adds to the best constant (a tier's closed-loop gap)."""
    if refs.planner is None:
        return None
    diff = np.asarray(refs.planner.returns) - np.asarray(refs.hindsight.returns)
    out: dict[str, Any] = {"mean": float(np.mean(diff)), "median": float(np.median(diff)),
                           "improved_episodes": int(np.sum(diff > 0)), "episodes": int(diff.size)}
    if diff.size > 1:
        _, out["ci_low"], out["ci_high"] = paired_ci(diff)
        out["ci_method"] = "paired Student-t 95 % over the test episodes"
    return out


def upper_fields(refs: StoredReferences, r0: np.ndarray, r1: np.ndarray,
                 protocol_planner: dict[str, Any] | None) -> tuple[dict[str, Any], list[str]]:
    """The tier fields of results.json that describe the upper reference (``r0``, ``r1``: the
    score's bounds, :func:`score_bounds`), and the deviations from the protocol it implies (no
    planner; a planner that searched with other settings than ``protocol_planner``, the
    protocol's :meth:`PlannerSettings.as_dict`)."""
    deviations = []
    if refs.planner is None:
        deviations.append(_NO_PLANNER)
    elif refs.planner_settings != protocol_planner:
        deviations.append(f"{_OTHER_SEARCH}{refs.planner_settings} (the protocol: {protocol_planner})")
    upper = ("the planner (true simulator, the episode's future) on every test episode; it starts from the "
             "hindsight constant and never ends below it" if refs.planner is not None else
             "the hindsight constant alone (the planner did not run)")
    return ({"upper_reference": upper, "planner_episodes": 0 if refs.planner is None else len(refs.seeds),
             "planner_minus_hindsight": planner_gain(refs), "hindsight_grid_step_n": refs.hindsight_grid_step_n,
             "denominator_floor": scoring.DENOMINATOR_FLOOR, "floored_episodes": scoring.floored_episodes(r0, r1)},
            deviations)


def is_upper_deviation(deviation: str) -> bool:
    """Whether a recorded deviation is one :func:`upper_fields` makes (the re-scoring replaces those)."""
    return deviation == _NO_PLANNER or deviation.startswith(_OTHER_SEARCH)
