"""A submitted row: a policy's runs scored against the stored references as the board scores a
learned row. One function for the API (:func:`agents.submit.score`) and for a submission file
joining a board (:func:`agents.submit.submission.add_submission`), so both give the same numbers."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.task import EPISODE_STEPS

from agents import protocol as P
from agents.evaluation.result import EvalResult
from agents.leaderboard.settings import FULL
from agents.leaderboard.tables import summarise
from agents.leaderboard.upper import require_planner_settings, score_bounds
from agents.paths import DATA_DIR
from agents.references.store import StoredReferences, load_references

__all__ = ["CONTEXTUAL", "test_references", "submitted_row"]

#: the board's row (and the probability of improvement) a submitted row is compared with
CONTEXTUAL = "contextual constant"


def test_references(tier: str, episodes: int, references_dir: Path = DATA_DIR) -> StoredReferences:
    """The stored references of ``tier``'s first ``episodes`` test episodes, checked as the board
    checks them (this kernel's, the protocol's planner, the protocol's test seeds and horizon)."""
    refs = load_references(tier, references_dir)
    refs.check_kernel(f"python -m agents.regenerate --only 'references:{tier}'")
    require_planner_settings(refs, FULL.planner_settings())
    refs = refs.first(episodes)
    seeds = P.held_out_seeds(episodes)
    if refs.seeds != tuple(seeds) or refs.episode_steps != EPISODE_STEPS:
        raise ValueError(f"the stored test references of tier {tier} are for seeds {refs.seeds[0]}.. of "
                         f"{refs.episode_steps} steps, not the protocol's {seeds.start}.. of {EPISODE_STEPS}")
    return refs


def submitted_row(results: list[EvalResult], contextual_returns: np.ndarray, refs: StoredReferences,
                  bootstrap_reps: int, poi_reps: int, versus: dict[str, np.ndarray] | None = None,
                  **extra: Any) -> dict[str, Any]:
    """A submitted row of a board's tier: ``results`` (one per training seed, on the references'
    test episodes) scored against ``refs`` as the board scores a learned row (normalised-score
    IQM and intervals, the share above 1, the probabilities of improvement over the validation
    and the contextual constant - and over each of ``versus``, other rows' returns (runs x episodes)
    on the same episodes, e.g. the board's best industry row -, the physical metrics, every
    return), marked ``"submitted"``.
    The same function builds the row when the API scores a policy and when a submission file
    joins a board."""
    r0, r1 = score_bounds(refs)
    contextual = EvalResult(CONTEXTUAL, np.asarray(contextual_returns, dtype=np.float64).reshape(-1), {},
                            np.zeros(0), np.zeros(0))
    others = {name: EvalResult(name, np.atleast_2d(np.asarray(ret, dtype=np.float64)), {}, np.zeros(0), np.zeros(0))
              for name, ret in (versus or {}).items()}
    return summarise("submitted", results, r0, r1, bootstrap_reps=bootstrap_reps, poi_reps=poi_reps,
                     versus={CONTEXTUAL: contextual, **others}, **extra)
