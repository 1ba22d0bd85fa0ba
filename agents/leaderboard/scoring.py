"""Normalised scores and their aggregation (rliable: IQM, stratified-bootstrap intervals,
probability of improvement).

Per episode, a policy's return R becomes

    score = (R - R_0) / max(R_1 - R_0, DENOMINATOR_FLOOR)

with R_0 the return of the validation-chosen constant preload (score 0) and R_1 the planner's
return on that episode (score 1; :mod:`agents.policies.planner`, the true simulator and the
episode's future, which starts from the hindsight best constant and never ends below it; the
hindsight constant alone where the planner did not run, a protocol deviation).

**The denominator floor.** R_1 - R_0 is >= 0 (the validation constant is one of the hindsight
grid's candidates) and is ~0 on episodes where the validation constant already is the best
constant and the planner finds nothing better. Dividing by it would turn a return difference of a
fraction of one interval's cost into a score of hundreds. The floor is
``DENOMINATOR_FLOOR = 1.0`` reward units: the smallest cost of one quasi-periodic control
interval in the default reward (``VibrationFirstReward``: q (1 + a / a_ref) >= 1), i.e. a gap
smaller than one quasi-periodic interval per episode is not treated as room to improve. On
such an episode the score is the return difference in units of that interval's cost (so the
upper reference itself scores (R_1 - R_0) / floor < 1 there). Scores are never clipped: a
policy can score below 0 (worse than the validation constant) or above 1 (better than the
planner: then the planner is not yet a bound on that episode, and the board counts how often);
the number of floored episodes is reported with every tier.

**Aggregation.** Scores are arranged as rliable's (runs x tasks) matrix: training seeds x test
episodes. ``iqm_interval`` gives the interquartile mean with a 95 % stratified-bootstrap
interval with ``task_bootstrap=True``: each bootstrap sample redraws the seeds within every
episode *and* the episodes, so the interval covers both the training-seed spread and the
sampling of scenarios. For a single-run row (a deterministic reference, or one shipped policy)
this is a bootstrap over episodes. ``seed_interval`` is rliable's default (seeds redrawn within
each episode, the episodes held fixed), reported as well for rows with several seeds.
The probability of improvement (over the validation constant, the contextual constant, ...) is
rliable's (P(X_m > Y_m) averaged over episodes, ties counting one half); its interval redraws
the episodes (paired) and the seeds within them (:func:`probability_of_improvement`), so it is
defined for a single-run row too.

rliable's bootstrap draws its indices from NumPy's global generator; every function here seeds
it (and restores its state afterwards), so the intervals are reproducible.
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator

import numpy as np


__all__ = ["DENOMINATOR_FLOOR", "upper_reference", "normalised_scores", "floored_episodes", "iqm",
           "iqm_interval", "mean_interval", "seed_interval", "optimality_gap_interval", "probability_of_improvement",
           "BOOTSTRAP_REPS", "POI_REPS", "seeded_global_rng"]

#: Reward units: the smallest cost of one quasi-periodic interval (module docstring: the reason).
DENOMINATOR_FLOOR = 1.0
#: Bootstrap replications for the IQM intervals (rliable's default) and for the probability of
#: improvement (rliable's examples: one Mann-Whitney test per episode per replication).
BOOTSTRAP_REPS = 50_000
POI_REPS = 2_000
BOOTSTRAP_SEED = 0


def _rliable():
    try:
        from rliable import library, metrics
    except Exception as err:    # arch fails to import with pandas 3; rliable's bootstrap with arch 8
        raise ImportError("the leaderboard's statistics need rliable with a compatible arch: "
                          "pip install 'rliable>=1.2' 'arch>=5,<8' 'pandas<3' "
                          f"(import failed: {type(err).__name__}: {err})") from err
    return library, metrics


@contextmanager
def seeded_global_rng(seed: int) -> Iterator[None]:
    state = np.random.get_state()
    np.random.seed(seed)
    try:
        yield
    finally:
        np.random.set_state(state)


def upper_reference(hindsight: np.ndarray, planner: np.ndarray | None = None) -> np.ndarray:
    """R_1 per episode: the planner's return (None: the planner did not run, the hindsight
    constant's). Raises if the planner ends below the hindsight constant on an episode: it starts
    from it and accepts only improvements, so that would mean a broken store."""
    h = np.asarray(hindsight, dtype=np.float64)
    if planner is None:
        return h.copy()
    p = np.asarray(planner, dtype=np.float64)
    if p.shape != h.shape:
        raise ValueError(f"planner returns {p.shape} must match the hindsight's {h.shape} (it runs on every episode)")
    below = np.flatnonzero(~(p >= h))
    if below.size:
        k = int(below[0])
        raise ValueError(f"the planner returns {p[k]!r} on episode {k}, below the hindsight constant's {h[k]!r}: "
                         "it cannot (it starts from it); its stored runs are broken")
    return p.copy()


def normalised_scores(returns: np.ndarray, r0: np.ndarray, r1: np.ndarray,
                      floor: float = DENOMINATOR_FLOOR) -> np.ndarray:
    """(R - R_0) / max(R_1 - R_0, floor) per episode; ``returns`` (episodes,) or (runs, episodes),
    ``r0`` and ``r1`` (episodes,). Not clipped."""
    if not floor > 0:
        raise ValueError(f"the denominator floor must be > 0 reward units, got {floor}")
    r = np.asarray(returns, dtype=np.float64)
    r0 = np.asarray(r0, dtype=np.float64)
    r1 = np.asarray(r1, dtype=np.float64)
    if r0.shape != r1.shape or r0.ndim != 1 or r.shape[-1] != r0.shape[0]:
        raise ValueError(f"returns {r.shape} must end in the episodes of r0 {r0.shape} and r1 {r1.shape}")
    return (r - r0) / np.maximum(r1 - r0, floor)


def floored_episodes(r0: np.ndarray, r1: np.ndarray, floor: float = DENOMINATOR_FLOOR) -> int:
    """How many episodes have R_1 - R_0 below the floor (their denominator is the floor)."""
    return int(np.count_nonzero(np.asarray(r1) - np.asarray(r0) < floor))


def _as_runs_by_tasks(scores: np.ndarray) -> np.ndarray:
    s = np.asarray(scores, dtype=np.float64)
    s = s[None, :] if s.ndim == 1 else s
    if s.ndim != 2 or s.size == 0 or not np.all(np.isfinite(s)):
        raise ValueError(f"scores must be a finite (runs, episodes) array, got shape {s.shape}")
    return s


def iqm(scores: np.ndarray) -> float:
    """rliable's interquartile mean over every run and episode."""
    _, metrics = _rliable()
    return float(metrics.aggregate_iqm(_as_runs_by_tasks(scores)))


def _interval(scores: np.ndarray, task_bootstrap: bool, reps: int, seed: int) -> tuple[float, float, float]:
    library, metrics = _rliable()
    s = _as_runs_by_tasks(scores)
    with seeded_global_rng(seed):
        point, ci = library.get_interval_estimates({"x": s}, lambda x: np.array([metrics.aggregate_iqm(x)]),
                                                   reps=reps, task_bootstrap=task_bootstrap)
    return float(point["x"][0]), float(ci["x"][0][0]), float(ci["x"][1][0])


def iqm_interval(scores: np.ndarray, reps: int = BOOTSTRAP_REPS, seed: int = BOOTSTRAP_SEED) -> tuple[float, float, float]:
    """(IQM, 95 % low, high): stratified bootstrap over seeds and episodes (a bootstrap over
    episodes for a single run)."""
    return _interval(scores, True, reps, seed)


def mean_interval(values: np.ndarray, reps: int = BOOTSTRAP_REPS, seed: int = BOOTSTRAP_SEED) -> tuple[float, float, float]:
    """(mean, 95 % low, high) of a (runs, episodes) array with the same stratified bootstrap as
    :func:`iqm_interval` (seeds and episodes redrawn): for raw quantities such as the constrained
    variant's return and cost, where the IQM of a normalised score does not apply."""
    library, _ = _rliable()
    s = _as_runs_by_tasks(values)
    with seeded_global_rng(seed):
        point, ci = library.get_interval_estimates({"x": s}, lambda x: np.array([np.mean(x)]), reps=reps,
                                                   task_bootstrap=True)
    return float(point["x"][0]), float(ci["x"][0][0]), float(ci["x"][1][0])


def optimality_gap_interval(scores: np.ndarray, gamma: float = 1.0, reps: int = BOOTSTRAP_REPS,
                            seed: int = BOOTSTRAP_SEED) -> tuple[float, float, float]:
    """(optimality gap, 95 % low, high): rliable's ``aggregate_optimality_gap``, the mean of
    max(gamma - score, 0) over every run and episode (how far below the upper reference a row
    stays, with no credit for beating it), with the stratified bootstrap of :func:`iqm_interval`."""
    library, metrics = _rliable()
    s = _as_runs_by_tasks(scores)
    with seeded_global_rng(seed):
        point, ci = library.get_interval_estimates(
            {"x": s}, lambda x: np.array([metrics.aggregate_optimality_gap(x, gamma)]), reps=reps, task_bootstrap=True)
    return float(point["x"][0]), float(ci["x"][0][0]), float(ci["x"][1][0])


def seed_interval(scores: np.ndarray, reps: int = BOOTSTRAP_REPS, seed: int = BOOTSTRAP_SEED) -> tuple[float, float, float]:
    """(IQM, 95 % low, high): rliable's default, seeds redrawn within each episode, episodes fixed."""
    return _interval(scores, False, reps, seed)


def probability_of_improvement(x: np.ndarray, y: np.ndarray, reps: int = POI_REPS,
                               seed: int = BOOTSTRAP_SEED) -> tuple[float, float, float]:
    """(P(X > Y), 95 % low, high): rliable's probability of improvement of X over Y (runs,
    episodes) on the same episodes, with a percentile interval from a stratified bootstrap that
    redraws the **episodes** (the same draw for X and Y: they stay paired) and, within each drawn
    episode, each one's runs independently. rliable's own interval for this metric
    (``StratifiedIndependentBootstrap``) redraws runs only, so it is blind to which scenarios the
    test set happens to hold and undefined for single runs; this one covers both."""
    _, metrics = _rliable()
    x, y = _as_runs_by_tasks(x), _as_runs_by_tasks(y)
    if x.shape[1] != y.shape[1]:
        raise ValueError(f"x and y must share their episodes: {x.shape} vs {y.shape}")
    p = float(metrics.probability_of_improvement(x, y))
    rng = np.random.default_rng(seed)
    (nx, m), ny = x.shape, y.shape[0]
    episodes = rng.integers(0, m, (reps, 1, m))
    xs = x[rng.integers(0, nx, (reps, nx, m)), episodes]            # (reps, runs, episodes)
    ys = y[rng.integers(0, ny, (reps, ny, m)), episodes]
    draws = _improvement(xs, ys)
    low, high = np.percentile(draws, [2.5, 97.5])
    return p, float(low), float(high)


def _improvement(xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """rliable's probability of improvement (per episode the Mann-Whitney U of X over Y divided
    by runs_x * runs_y - wins plus half the ties - then the mean over episodes) of each leading
    replicate of (reps, runs, episodes) arrays, vectorised over the replicates."""
    diff = xs[:, :, None, :] - ys[:, None, :, :]                   # (reps, nx, ny, m)
    per_episode = ((diff > 0).sum(axis=(1, 2)) + 0.5 * (diff == 0).sum(axis=(1, 2))) / (xs.shape[1] * ys.shape[1])
    return per_episode.mean(axis=1)