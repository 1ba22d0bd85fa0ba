"""The ridge regression and the contextual constant on synthetic data with a known answer."""

import numpy as np
import pytest

from agents.policies.contextual import ContextualConstant
from agents.references.contextual_fit import collect_fit_data
from agents.policies.ridge import RidgeRegression

GRID = (300.0, 800.0, 1300.0, 2000.0)


def test_ridge_recovers_a_known_linear_map():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(200, 6)) * [1.0, 5.0, 0.1, 2.0, 1.0, 3.0] + [0, 10, -1, 0, 4, 0]
    W = rng.normal(size=(6, 3))
    b = np.array([1.0, -2.0, 0.5])
    Y = X @ W + b + rng.normal(scale=1e-3, size=(200, 3))
    fit = RidgeRegression.fit(X, Y)
    X_new = rng.normal(size=(50, 6)) * 2.0
    # the map itself, per standardised column (the noise leaves ~1e-3 / sqrt(200) there; the
    # feature of spread 0.1 would amplify it tenfold in X's units), and predictions off the data
    np.testing.assert_allclose(fit.coef, W * fit.x_scale[:, None], atol=1e-3)
    np.testing.assert_allclose(fit.predict(X_new), X_new @ W + b, atol=1e-2)
    assert fit.loo_rmse < 5e-3                       # ~ the 1e-3 noise, not the signal (O(1))


def test_ridge_chooses_a_larger_penalty_for_pure_noise_and_ignores_constant_columns():
    rng = np.random.default_rng(1)
    X = np.column_stack([rng.normal(size=(60, 4)), np.full(60, 7.0)])
    noise = RidgeRegression.fit(X, rng.normal(size=60))
    signal = RidgeRegression.fit(X, X[:, 0] * 3.0 + rng.normal(scale=0.01, size=60))
    assert noise.alpha > 100 * signal.alpha
    assert noise.coef[4, 0] == 0.0 and signal.coef[4, 0] == 0.0
    with pytest.raises(ValueError, match="at least 3 samples"):
        RidgeRegression.fit(X[:2], np.zeros(2))


def _synthetic(n: int, rng) -> tuple[np.ndarray, np.ndarray]:
    """First observations (15 features) and grid returns linear in two of them."""
    obs = rng.normal(size=(n, 15))
    W = np.zeros((15, len(GRID)))
    W[11] = [-3.0, -1.0, 1.0, 3.0]          # faster -> a higher preload pays
    W[12] = [2.0, 1.0, -1.0, -2.5]          # more radial offset -> a lower one
    return obs, obs @ W - 40.0


def test_contextual_constant_picks_the_best_grid_constant_on_new_episodes():
    rng = np.random.default_rng(2)
    obs, returns = _synthetic(300, rng)
    pol = ContextualConstant.fit(obs, returns, GRID, squares=False)
    new_obs, new_returns = _synthetic(100, rng)
    chosen = pol.choose(new_obs)
    best = np.asarray(GRID)[np.argmax(new_returns, axis=1)]
    assert np.mean(chosen == best) >= 0.97               # noiseless linear truth: near-perfect
    # it holds the first choice for the episode, and chooses again at a new episode's start
    act, state = pol.predict(new_obs[:4], episode_start=np.ones(4, bool))
    np.testing.assert_array_equal(state, chosen[:4])
    act2, state2 = pol.predict(new_obs[4:8], state=state, episode_start=np.zeros(4, bool))
    np.testing.assert_array_equal(state2, chosen[:4])
    np.testing.assert_array_equal(act2, act)
    _, state3 = pol.predict(new_obs[4:8], state=state2, episode_start=np.array([True, False, False, False]))
    assert state3[0] == chosen[4] and np.array_equal(state3[1:], chosen[1:4])
    assert act.shape == (4, 1) and act.dtype == np.float32 and np.all(np.abs(act) <= 1.0)


def test_auto_features_take_squares_when_the_truth_is_quadratic(tmp_path):
    rng = np.random.default_rng(4)
    obs = rng.normal(size=(300, 15))
    returns = np.column_stack([-(obs[:, 3] ** 2), obs[:, 3] ** 2, np.zeros(300), -np.ones(300)])
    pol = ContextualConstant.fit(obs, returns, GRID)
    assert pol.squares and pol.meta["loo_rmse"]["squares"] < 0.5 * pol.meta["loo_rmse"]["linear"]
    pol.save(tmp_path / "c.json")
    again = ContextualConstant.load(tmp_path / "c.json")
    np.testing.assert_allclose(again.predict_returns(obs[:10]), pol.predict_returns(obs[:10]), atol=1e-12)
    with pytest.raises(FileNotFoundError, match="python -m agents.references.contextual_fit --tier field"):
        ContextualConstant.load(tmp_path / "contextual_field.json")


def test_the_fit_refuses_seeds_outside_the_training_range():
    from agents.protocol import TEST, VALIDATION
    for seed in (TEST.start, VALIDATION.start):
        with pytest.raises(ValueError, match="training seeds"):
            collect_fit_data("transient", 3, seed=seed, episode_steps=2)
