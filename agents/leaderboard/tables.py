"""The leaderboard's rows and table: normalised scores aggregated with rliable
(:mod:`agents.leaderboard.scoring`) beside the raw metrics, and the markdown a reader gets."""

from __future__ import annotations

from itertools import zip_longest
from typing import Any

import numpy as np

from agents.leaderboard import scoring
from agents.evaluation.result import EvalResult


__all__ = ["score_fields", "summarise", "pairwise_improvement", "board_pairwise", "improvement", "best_of_kind",
           "to_markdown", "PAIRWISE_KINDS"]

#: the row kinds of the statistics table (every row with intervals of its own; not the references)
STATISTICS_KINDS = ("learned", "industry", "model-based", "submitted")


def _metrics(results: list[EvalResult]) -> dict[str, Any]:
    """Raw metrics over every run and episode of a row (costs per episode, positive)."""
    def mean(get) -> float:
        return float(np.mean(np.concatenate([np.atleast_1d(get(r)) for r in results])))
    out = {"mean_return": mean(lambda r: r.returns),
           "quasi_periodic_fraction": mean(lambda r: r.qp_fraction),
           "vibration_amplitude_um": (None if any(r.vibration_um is None for r in results)
                                      else mean(lambda r: r.vibration_um)),
           "vibration_cost": -mean(lambda r: r.terms["vibration"]),
           "heat_cost": -mean(lambda r: r.terms["heat"]),
           "fatigue_cost": -mean(lambda r: r.terms["fatigue"]),
           "mean_preload_n": mean(lambda r: r.mean_preload),
           "terminated_episodes": int(sum(r.terminated_count for r in results))}
    return out


def score_fields(returns: np.ndarray, r0: np.ndarray, r1: np.ndarray, bootstrap_reps: int, poi_reps: int,
                 versus: dict[str, np.ndarray] | None = None) -> dict[str, Any]:
    """The fields of a row that depend on the score's 0 and 1: the normalised scores of
    ``returns`` (runs x episodes, the episodes of ``r0``/``r1``) aggregated with rliable, the share
    above 1, and the probability of improvement over the validation constant and over each of
    ``versus`` (other rows' returns on the same episodes, runs x episodes)."""
    scores = scoring.normalised_scores(returns, r0, r1)
    point, lo, hi = scoring.iqm_interval(scores, reps=bootstrap_reps)
    poi, poi_lo, poi_hi = scoring.probability_of_improvement(scores, np.zeros((1, scores.shape[1])), reps=poi_reps)
    row: dict[str, Any] = {
        "normalised_score_iqm": point, "ci_low": lo, "ci_high": hi,
        "ci_method": ("stratified bootstrap over training seeds and episodes (rliable, task_bootstrap=True)"
                      if scores.shape[0] > 1 else "bootstrap over episodes (single run; rliable, task_bootstrap=True)"),
        "n_seeds": int(scores.shape[0]), "n_episodes": int(scores.shape[1]),
        "normalised_score_mean": float(np.mean(scores)),
        # how often a (seed, episode) score exceeds the upper reference: where it does, the
        # planner is not yet a bound on that episode (the goal: under 2 % for learned rows)
        "above_one_fraction": float(np.mean(scores > 1.0)),
        "probability_of_improvement": poi, "poi_ci_low": poi_lo, "poi_ci_high": poi_hi}
    _, row["mean_ci_low"], row["mean_ci_high"] = scoring.mean_interval(scores, reps=bootstrap_reps)
    row["optimality_gap"], row["optimality_gap_ci_low"], row["optimality_gap_ci_high"] = \
        scoring.optimality_gap_interval(scores, reps=bootstrap_reps)
    if scores.shape[0] > 1:
        _, row["seed_ci_low"], row["seed_ci_high"] = scoring.seed_interval(scores, reps=bootstrap_reps)
    if versus:
        row["poi_over"] = {name: list(scoring.probability_of_improvement(
            scores, scoring.normalised_scores(other, r0, r1), reps=poi_reps)) for name, other in versus.items()}
    return row


def summarise(kind: str, results: list[EvalResult], r0: np.ndarray, r1: np.ndarray,
              bootstrap_reps: int, poi_reps: int, versus: dict[str, EvalResult] | None = None,
              **extra: Any) -> dict[str, Any]:
    """One row of results.json: the normalised scores of ``results`` (one EvalResult per run,
    all on the episodes of ``r0``/``r1``) aggregated with rliable, the raw metrics and every
    return (``episode_returns``, runs x episodes, the tier's test seeds in order).
    ``versus``: other rows' results on the same episodes, each given as the probability that
    this row improves on it (``poi_over``: P, 95 % low, high; e.g. over the contextual constant,
    the test of whether a policy does more than pick one preload from the first observation)."""
    returns = np.array([r.returns for r in results])                     # (runs, episodes)
    row: dict[str, Any] = {"kind": kind}
    row.update(score_fields(returns, r0, r1, bootstrap_reps, poi_reps,
                            None if versus is None else {k: np.atleast_2d(v.returns) for k, v in versus.items()}))
    row.update(_metrics(results))
    row["episode_returns"] = returns.tolist()        # (runs, episodes): for statistics of your own
    row.update(extra)
    return row


def pairwise_improvement(returns: dict[str, np.ndarray], r0: np.ndarray, r1: np.ndarray,
                         poi_reps: int) -> dict[str, dict[str, list[float]]]:
    """For every pair of rows (``returns``: name -> runs x episodes, the episodes of ``r0``/``r1``),
    in the given order, the probability that the first improves on the second, with its 95 %
    interval (:func:`scoring.probability_of_improvement`): ``{a: {b: [P(a > b), low, high]}}``.
    P(b > a) is 1 - P(a > b) (ties count one half), so each pair appears once."""
    names = list(returns)
    scores = {k: scoring.normalised_scores(np.atleast_2d(v), r0, r1) for k, v in returns.items()}
    return {a: {b: list(scoring.probability_of_improvement(scores[a], scores[b], reps=poi_reps))
                for b in names[i + 1:]} for i, a in enumerate(names[:-1])}


#: the row kinds compared pair by pair on a tier (results.json's pairwise_improvement); learned rows
#: only with learned rows of the same budget (a protocol-v2 early row with the other early rows)
PAIRWISE_KINDS = ("learned", "industry", "model-based")


def board_pairwise(rows: dict[str, dict], r0: np.ndarray, r1: np.ndarray, poi_reps: int) -> dict[str, dict[str, list[float]]]:
    """Every pair of the rows of PAIRWISE_KINDS, paired by episode: the industry and model-based rows
    with each other and with every learned row, learned rows with the learned rows of their own
    budget (``early_row_steps``: the selected checkpoints together, the early rows together)."""
    fixed = {n: np.asarray(r["episode_returns"]) for n, r in rows.items() if r["kind"] in PAIRWISE_KINDS
             and r["kind"] != "learned"}
    budgets = dict.fromkeys(r.get("early_row_steps") for r in rows.values() if r["kind"] == "learned")
    out: dict[str, dict[str, list[float]]] = {}
    for budget in budgets or [None]:
        compared = {**fixed, **{n: np.asarray(r["episode_returns"]) for n, r in rows.items()
                                if r["kind"] == "learned" and r.get("early_row_steps") == budget}}
        if len(compared) > 1:
            for a, versus in pairwise_improvement(compared, r0, r1, poi_reps).items():
                out.setdefault(a, {}).update(versus)
    return out


def improvement(pairwise: dict[str, dict[str, list[float]]], a: str, b: str) -> list[float] | None:
    """P(row ``a`` improves on row ``b``) with its 95 % interval from a tier's ``pairwise_improvement``
    (:func:`pairwise_improvement` stores each pair once; the other order is its complement, ties
    counting one half, and the interval flips with it); None if the pair was not compared."""
    if b in pairwise.get(a, {}):
        return list(pairwise[a][b])
    if a in pairwise.get(b, {}):
        p, lo, hi = pairwise[b][a]
        return [1.0 - p, 1.0 - hi, 1.0 - lo]
    return None


def best_of_kind(policies: dict[str, dict], kind: str) -> str | None:
    """The row of ``kind`` with the highest normalised-score IQM (the first on a tie), or None."""
    rows = [(name, r) for name, r in policies.items() if r["kind"] == kind]
    return max(rows, key=lambda nr: nr[1]["normalised_score_iqm"])[0] if rows else None


def _interval(point: float | None, lo: float | None, hi: float | None) -> str:
    if point is None:
        return "-"
    return f"{point:.3f}" + ("" if lo is None or hi is None else f" [{lo:.3f}, {hi:.3f}]")


def _statistics(t: dict[str, Any]) -> list[str]:
    """A tier's statistics beyond the IQM, for the rows with intervals of their own: the mean and
    the optimality gap (rliable; the gap is the mean shortfall below 1, scores above 1 counting
    as 1), the probability of improvement over the tier's best industry row, and every pair of
    learned rows."""
    rows = [(name, r) for name, r in t["policies"].items() if r["kind"] in STATISTICS_KINDS]
    if not rows:
        return []
    pairwise = t.get("pairwise_improvement", {})
    industry = t.get("best_industry_row", best_of_kind(t["policies"], "industry"))
    lines = ["Beyond the IQM (rliable, 95 % intervals as above): the mean normalised score, the optimality gap "
             "(the mean shortfall below 1, a score above 1 counting as 1: lower is better)"
             + (f" and P(> best industry): the probability of improvement over the best industry row by IQM, "
                f"{industry}." if industry else "."), "",
             "| policy | IQM [95 % CI] | mean [95 % CI] | optimality gap [95 % CI] | P(> best industry) [95 % CI] |",
             "|---|---|---|---|---|"]
    for name, r in rows:
        versus = None
        if industry and name != industry:      # from the pairwise set, or a submitted row's own comparison
            versus = improvement(pairwise, name, industry) or r.get("poi_over", {}).get(industry)
        lines.append(f"| {name} | {_interval(r['normalised_score_iqm'], r.get('ci_low'), r.get('ci_high'))} "
                     f"| {_interval(r.get('normalised_score_mean'), r.get('mean_ci_low'), r.get('mean_ci_high'))} "
                     f"| {_interval(r.get('optimality_gap'), r.get('optimality_gap_ci_low'), r.get('optimality_gap_ci_high'))} "
                     f"| {_poi(versus)} |")
    lines.append("")
    learned = [name for name, r in rows if r["kind"] == "learned"]
    pairs = [(a, b, improvement(pairwise, a, b)) for i, a in enumerate(learned) for b in learned[i + 1:]]
    pairs = [(a, b, p) for a, b, p in pairs if p is not None]
    if pairs:
        lines += ["Learned rows pair by pair: P(A > B), the probability that A's normalised score beats B's on a "
                  "test episode (paired by episode, seeds within it drawn; rliable), 95 % interval; P(B > A) is "
                  "1 - P(A > B).", "", "| A | B | P(A > B) [95 % CI] |", "|---|---|---|"]
        lines += [f"| {a} | {b} | {_poi(p)} |" for a, b, p in pairs]
        lines.append("")
    return lines


def _fmt(x: float | None, spec: str = ".2f") -> str:
    return "-" if x is None else format(x, spec)


def _poi(p: list | None) -> str:
    if p is None:
        return "-"
    return f"{p[0]:.2f}" + (f" [{p[1]:.2f}, {p[2]:.2f}]" if p[1] is not None else "")


def to_markdown(results: dict[str, Any]) -> str:
    """The leaderboard table of each tier, with the notes a reader needs to read it."""
    lines = [f"# Leaderboard ({results['mode']})", "",
             f"Generated by `{results['command']}`. Normalised score: 0 = the validation-chosen constant "
             "preload, 1 = the planner (the true simulator and the episode's future; never below the hindsight "
             "best constant) on the episode; "
             "IQM with 95 % stratified-bootstrap intervals (rliable; over training seeds and episodes, over "
             "episodes for single-run rows); P(> constant): the probability of improvement over the validation "
             "constant, P(> contextual): over the contextual constant - whether a row does more than pick one "
             "preload from the first observation (rliable's statistic; 95 % intervals redraw training seeds "
             "and episodes); > 1: the share of (seed, episode) scores above the upper reference.", ""]
    for tier, t in results["tiers"].items():
        lines += [f"## Tier `{tier}`", "",
                  f"{t['episodes']} test episodes (seeds {t['seeds'][0]}..{t['seeds'][1]}) of {t['episode_steps']} "
                  f"intervals; upper reference: {t['upper_reference']}; denominator floor "
                  f"{t['denominator_floor']:g} reward units, reached on {t['floored_episodes']} episodes.", ""]
        gain = t.get("planner_minus_hindsight")
        if gain:
            ci = f" [{gain['ci_low']:.1f}, {gain['ci_high']:.1f}]" if "ci_low" in gain else ""
            lines += [f"Planner minus hindsight constant, paired: {gain['mean']:+.1f}{ci} reward units per episode "
                      f"(median {gain['median']:+.1f}; better on {gain['improved_episodes']} of {gain['episodes']} "
                      "episodes): the closed-loop gap with the episode's future known.", ""]
        if t.get("command", results["command"]) != results["command"]:
            lines += [f"Rows of this tier made by `{t['command']}` (kept by --keep-other-tiers).", ""]
        if t.get("rescored_by"):
            lines += [f"Scores re-computed from the rows' stored per-episode returns against today's stored references "
                      f"by `{t['rescored_by']}` (no policy ran again).", ""]
        if t.get("deterministic_note"):
            lines += ["Deterministic tier: " + t["deterministic_note"] + ".", ""]
        if not t["protocol"]:
            lines += ["**Not the protocol:** " + "; ".join(t["protocol_deviations"]) + ".", ""]
        lines += ["| policy | seeds | episodes | normalised score IQM [95 % CI] | > 1 | P(> constant) [95 % CI] "
                  "| P(> contextual) [95 % CI] | mean return "
                  "| time quasi-periodic | vibration (um) | heat cost | fatigue cost | terminated |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for name, r in t["policies"].items():
            above = r.get("above_one_fraction")
            score = (f"{r['normalised_score_iqm']:.3f} [{r['ci_low']:.3f}, {r['ci_high']:.3f}]" if "role" not in r
                     else f"1 by definition ({r['normalised_score_iqm']:.3f} with the floor)")
            lines.append(f"| {name} | {r['n_seeds']} | {r['n_episodes']} | {score} "
                         f"| {'-' if above is None else f'{100 * above:.0f} %'} "
                         f"| {_poi([r['probability_of_improvement'], r.get('poi_ci_low'), r.get('poi_ci_high')])} "
                         f"| {_poi(r.get('poi_over', {}).get('contextual constant'))} "
                         f"| {r['mean_return']:.2f} | {100 * r['quasi_periodic_fraction']:.1f} % "
                         f"| {_fmt(r['vibration_amplitude_um'])} | {r['heat_cost']:.2f} | {r['fatigue_cost']:.2f} "
                         f"| {r['terminated_episodes']} |")
        lines.append("")
        lines += _statistics(t)
        submitted = [(name, r) for name, r in t["policies"].items() if r["kind"] == "submitted"]
        if submitted:
            lines += ["Submitted rows (python -m agents.submit; scored by the board from their per-episode returns): "
                      "algorithm, env steps of training, training seeds, library, code; what they leave out of "
                      "the rules' report.", ""]
            lines += [f"- {name}: {r.get('algorithm') or '-'}; "
                      f"{'-' if r.get('training_steps') is None else format(r['training_steps'], ',')} steps; "
                      f"seeds {r.get('training_seeds') or '-'}; {r.get('library') or '-'} {r.get('library_version') or ''}"
                      f"; {r.get('code') or '-'}"
                      + (f" (**{'; '.join(r['submission_notes'])}**)" if r.get("submission_notes") else "")
                      for name, r in submitted]
            lines.append("")
        learned = [(name, r) for name, r in t["policies"].items() if r["kind"] == "learned"]
        if learned:
            lines += ["Learned rows: training seed, selected checkpoint (env steps), training wall time.", ""]
            lines += [f"- {name}: " + "; ".join(_run(*x) for x in zip_longest(r.get("training_seeds", []),
                                                                               r.get("timesteps", []),
                                                                               r.get("train_wall_s", [])))
                      for name, r in learned]
            lines.append("")
    return "\n".join(lines)


def _run(seed: int | None, steps: int | None, wall_s: float | None) -> str:
    return (f"seed {'-' if seed is None else seed}, {'-' if steps is None else f'{steps:,}'} steps, "
            f"{'-' if wall_s is None else f'{wall_s / 60:.1f} min'}")
