"""Learning curves score each validation episode against its own scenario's references."""

import json

import numpy as np
import pytest

from agents.leaderboard import learning_curves
from agents.leaderboard import scoring
from agents.references.store import ValidationChoice, save_choice


def _store(tmp_path, returns):
    """A store entry: 3 candidates x 4 validation episodes (seeds 50000..50003)."""
    grid = (300.0, 1000.0, 2000.0)
    means = tuple(float(np.mean(r)) for r in returns)
    choice = ValidationChoice(tier="transient", preload_n=grid[int(np.argmax(means))], seeds=(50000, 50001, 50002, 50003),
                              grid_step_n=50.0, grid_n=grid, mean_returns=means, episode_steps=150,
                              episode_returns=tuple(tuple(r) for r in returns))
    path = tmp_path / "store.json"
    save_choice(choice, path)
    return path


def _run(tmp_path, name, algo, seed, timesteps, returns):
    d = tmp_path / name
    (d / "eval").mkdir(parents=True)
    (d / "config.json").write_text(json.dumps({"algo": algo, "seed": seed, "tier": "transient"}))
    np.savez(d / "eval" / "validation_returns.npz", timesteps=np.array(timesteps), seeds=50000 + np.arange(2),
             returns=np.array(returns, dtype=float))
    return d


def test_scores_use_each_episodes_own_references(tmp_path):
    # candidate returns per episode: the 1000 N constant is best on average, 2000 N best on episode 1
    store = _store(tmp_path, [[-50.0, -60.0, -40.0, -40.0], [-20.0, -30.0, -20.0, -20.0], [-30.0, -10.0, -30.0, -30.0]])
    run = _run(tmp_path, "a", "sac", 0, [10000, 20000], [[-20.0, -30.0], [-15.0, -20.0]])
    c = learning_curves.read_run(run, store)
    # episode 0: R0 = -20 (1000 N), R1 = -20 (hindsight) -> denominator floor 1.0
    # episode 1: R0 = -30, R1 = -10 -> denominator 20
    np.testing.assert_allclose(c.scores, [[0.0, 0.0], [5.0 / 1.0, 10.0 / 20.0]])
    assert list(c.timesteps) == [10000, 20000]


def test_curves_aggregate_seeds_at_shared_steps(tmp_path):
    store = _store(tmp_path, [[-50.0, -60.0, -40.0, -40.0], [-20.0, -30.0, -20.0, -20.0], [-30.0, -10.0, -30.0, -30.0]])
    runs = [learning_curves.read_run(_run(tmp_path, f"s{k}", "sac", k, [10000, 20000, 30000][:2 + k],
                                          [[-20.0 - k, -30.0]] * (2 + k)), store) for k in range(2)]
    curves = learning_curves.algorithm_curves(runs, reps=200)
    sac = curves["sac"]
    assert sac["timesteps"] == [10000, 20000] and sac["seeds"] == [0, 1]       # only the steps both runs have
    expected = scoring.iqm(np.array([[0.0, 0.0], [-1.0, 0.0]]))
    assert sac["iqm"][0] == pytest.approx(expected, abs=1e-12)
    assert sac["ci_low"][0] <= sac["iqm"][0] <= sac["ci_high"][0]
    learning_curves.plot(curves, tmp_path / "lc.png")
    assert (tmp_path / "lc.png").stat().st_size > 0


def test_an_episode_outside_the_stored_validation_set_is_refused(tmp_path):
    store = _store(tmp_path, [[-1.0] * 4, [-2.0] * 4, [-3.0] * 4])
    d = _run(tmp_path, "x", "ppo", 0, [10000], [[-1.0, -1.0]])
    np.savez(d / "eval" / "validation_returns.npz", timesteps=np.array([10000]), seeds=np.array([50003, 50004]),
             returns=np.array([[-1.0, -1.0]]))
    with pytest.raises(ValueError, match="seed 50004 is not one of the stored validation episodes"):
        learning_curves.read_run(d, store)
