"""The constrained variant's scoring: the same trajectory as the benchmark's run (the reward does not
act on the physics), its return the benchmark's minus the vibration term, its cost the
quasi-periodic intervals, counted as the env's cost channel counts them."""

import numpy as np
import pytest

from agents.leaderboard import scoring
from agents.submit import score
from agents.submit.constrained import constrained_row, reference_rows

from tests.agents.helpers import eval_result
from tests.agents.submit.test_api import REPS, qp_rule

EPISODES = 3


@pytest.fixture(scope="module")
def both():
    std = score(qp_rule, tier="transient", episodes=EPISODES, progress=False, **REPS)
    con = score(qp_rule, tier="transient", episodes=EPISODES, variant="constrained", progress=False, **REPS)
    return std, con


def test_the_constrained_run_is_the_benchmark_run_without_the_vibration_term(both):
    std, con = both
    s, c = std.results[0], con.results[0]
    assert not s.terminated.any()
    np.testing.assert_array_equal(c.cost, s.cost)                   # the same trajectory
    np.testing.assert_array_equal(c.cost, np.rint(s.qp_fraction * 150))
    np.testing.assert_allclose(c.returns, s.returns - s.terms["vibration"], rtol=0, atol=1e-9)
    assert np.all(c.terms["vibration"] == 0.0)


def test_the_constrained_row_reports_cost_return_and_budget(both):
    _, con = both
    row = con.row
    costs = np.asarray(row["episode_costs"])
    assert row["variant"] == "constrained" and row["cost_budget"] == 15.0
    assert row["cost_mean"] == pytest.approx(costs.mean()) and row["cost_ci_low"] <= row["cost_mean"] <= row["cost_ci_high"]
    assert row["within_budget_fraction"] == pytest.approx(np.mean(costs <= 15.0))
    assert row["constrained_return_mean"] == pytest.approx(np.mean(row["episode_returns"]))
    refs = con.reference_rows()
    assert len(refs) == 3 and any(n.startswith("planner") for n in refs)    # validation, hindsight, planner
    for r in refs.values():
        assert r["n_episodes"] + r["terminated_episodes_left_out"] == EPISODES
    assert "constrained return" in con.markdown() and "budget 15" in con.markdown()


def test_a_row_without_costs_and_references_that_all_terminated():
    r = eval_result("x", [-5.0, -6.0])
    with pytest.raises(ValueError, match="cost"):
        constrained_row([r])
    r.cost = np.array([0.0, 20.0])
    row = constrained_row([r], 15.0, bootstrap_reps=200)
    assert row["within_budget_fraction"] == 0.5 and row["cost_mean"] == 10.0


def test_reference_rows_leave_out_terminated_episodes_and_a_reference_with_none_left():
    from agents.references.store import StoredReferences
    vc = eval_result("validation", [-10.0, -12.0], qp=[0.1, 0.0])
    vc.terminated = np.array([False, True])
    hs = eval_result("hindsight", [-9.0, -11.0])
    hs.terminated = np.array([True, True])
    refs = StoredReferences("transient", (300000, 300001), 150, 1000.0, 50.0, vc, hs, None, None)
    rows = reference_rows(refs, bootstrap_reps=200)
    assert list(rows) == ["validation constant (1000 N)"]                  # the hindsight row: all terminated
    r = rows["validation constant (1000 N)"]
    assert r["terminated_episodes_left_out"] == 1 and r["episode_costs"] == [[15.0]]
    heat_fatigue_actuation = sum(vc.terms[k][0] for k in ("heat", "fatigue", "actuation"))
    assert r["episode_returns"] == [[heat_fatigue_actuation]]


def test_the_mean_interval_brackets_the_mean():
    x = np.arange(20.0).reshape(2, 10)
    m, lo, hi = scoring.mean_interval(x, reps=500)
    assert m == pytest.approx(9.5) and lo < m < hi
