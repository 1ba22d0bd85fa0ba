"""The leaderboard's markdown: the statistics beyond the IQM and the pairwise table read from
results.json's fields, each pair stored once and its other order the complement."""

import numpy as np
import pytest

from agents.leaderboard import scoring
from agents.leaderboard.tables import best_of_kind, improvement, pairwise_improvement, score_fields

REPS = dict(bootstrap_reps=200, poi_reps=200)


def _returns(rng, runs, episodes, shift):
    return rng.normal(-100.0 + shift, 10.0, (runs, episodes))


def test_the_other_order_of_a_pair_is_its_complement_with_the_interval_flipped():
    """Single-run rows: every bootstrap draw resamples only episodes (paired), so P(B > A) computed
    directly equals 1 - P(A > B) and its interval is the flipped one (to rounding, 1e-12)."""
    rng = np.random.default_rng(3)
    r0, r1 = np.full(30, -150.0), np.full(30, -50.0)
    a, b = _returns(rng, 1, 30, 5.0), _returns(rng, 1, 30, 0.0)
    pairwise = pairwise_improvement({"A": a, "B": b}, r0, r1, poi_reps=500)
    assert "B" not in pairwise                                   # each pair once
    direct = scoring.probability_of_improvement(scoring.normalised_scores(b, r0, r1),
                                                scoring.normalised_scores(a, r0, r1), reps=500)
    assert improvement(pairwise, "B", "A") == pytest.approx(list(direct), abs=1e-12)
    assert improvement(pairwise, "A", "B") == pairwise["A"]["B"]
    assert improvement(pairwise, "A", "C") is None


def test_several_runs_the_complement_holds_for_the_point_estimate():
    """With several runs the bootstrap draws runs too (the draws differ with the order), so only
    the point estimate is an exact complement: ties count one half (Mann-Whitney)."""
    rng = np.random.default_rng(4)
    r0, r1 = np.full(20, -150.0), np.full(20, -50.0)
    a, b = np.round(_returns(rng, 3, 20, 3.0)), np.round(_returns(rng, 3, 20, 0.0))     # rounded: some ties
    pairwise = pairwise_improvement({"A": a, "B": b}, r0, r1, poi_reps=100)
    direct = scoring.probability_of_improvement(scoring.normalised_scores(b, r0, r1),
                                                scoring.normalised_scores(a, r0, r1), reps=100)
    assert improvement(pairwise, "B", "A")[0] == pytest.approx(direct[0], abs=1e-12)


def test_the_statistics_table_shows_mean_gap_and_the_best_industry_row():
    rng = np.random.default_rng(5)
    r0, r1 = np.full(20, -150.0), np.full(20, -50.0)
    returns = {"SAC (trained)": _returns(rng, 3, 20, 40.0), "PPO (trained)": _returns(rng, 3, 20, 10.0),
               "switch": _returns(rng, 1, 20, 0.0), "table": _returns(rng, 1, 20, 20.0)}
    kinds = {"SAC (trained)": "learned", "PPO (trained)": "learned", "switch": "industry", "table": "industry"}
    policies = {name: {"kind": kinds[name], "n_seeds": ret.shape[0], "n_episodes": 20,
                       **score_fields(ret, r0, r1, **REPS)} for name, ret in returns.items()}
    assert best_of_kind(policies, "industry") == "table"                   # the higher IQM
    assert best_of_kind(policies, "model-based") is None
    pairwise = pairwise_improvement(returns, r0, r1, poi_reps=200)
    tier = {"policies": policies, "pairwise_improvement": pairwise}
    from agents.leaderboard.tables import _statistics
    text = "\n".join(_statistics(tier))
    sac = policies["SAC (trained)"]
    p_sac_table = improvement(pairwise, "SAC (trained)", "table")
    assert (f"| SAC (trained) | {sac['normalised_score_iqm']:.3f} [{sac['ci_low']:.3f}, {sac['ci_high']:.3f}] "
            f"| {sac['normalised_score_mean']:.3f} [{sac['mean_ci_low']:.3f}, {sac['mean_ci_high']:.3f}] "
            f"| {sac['optimality_gap']:.3f} [{sac['optimality_gap_ci_low']:.3f}, {sac['optimality_gap_ci_high']:.3f}] "
            f"| {p_sac_table[0]:.2f} [{p_sac_table[1]:.2f}, {p_sac_table[2]:.2f}] |") in text
    assert "| table | " in text and "over the best industry row by IQM, table." in text
    p = pairwise["SAC (trained)"]["PPO (trained)"]
    assert f"| SAC (trained) | PPO (trained) | {p[0]:.2f} [{p[1]:.2f}, {p[2]:.2f}] |" in text
    # the optimality gap: the mean shortfall below 1, clipped at 1 (an independent calculation)
    scores = scoring.normalised_scores(returns["SAC (trained)"], r0, r1)
    assert sac["optimality_gap"] == pytest.approx(float(np.mean(1.0 - np.minimum(scores, 1.0))), abs=1e-12)


def test_a_tier_without_learned_or_industry_rows_has_no_statistics_table():
    from agents.leaderboard.tables import _statistics
    assert _statistics({"policies": {"x": {"kind": "reference", "normalised_score_iqm": 0.0}}}) == []


def test_the_results_header_records_each_protocol_version_it_scores():
    """results.json's protocol block: version 1's budget and seeds, version 2's tuned algorithms,
    budget, early row and frozen references; the planner hash equals a hash of the recorded
    planner settings (computed here independently); an unknown version is refused."""
    import hashlib
    import json

    from agents import protocol as P
    from agents.leaderboard.results_file import protocol_summary
    one, two = protocol_summary(1), protocol_summary(2)
    assert one["step_budget_per_run"] == 100_000 and one["validation_rule"] == "best_mean"
    assert two["step_budget_per_run"] == 300_000 and two["early_row_steps"] == 100_000
    assert two["validation_rule"] == "one_se_largest"
    assert set(two["training_seeds"]) == set(P.V2_ALGORITHMS)
    assert all(len(seeds) == 5 for seeds in two["training_seeds"].values())
    planner = json.dumps(two["upper_reference"]["planner"], sort_keys=True).encode()
    assert hashlib.sha256(planner).hexdigest()[:16] == two["planner_settings_sha256"]
    assert protocol_summary()["version"] == P.PROTOCOL_VERSION
    with pytest.raises(ValueError, match="unknown protocol version 3"):
        protocol_summary(3)
