"""Ridge regression in NumPy, with its penalty chosen by exact leave-one-out error.

``RidgeRegression.fit(X, Y)`` standardises the columns of X (a column without spread is left at
zero and gets no weight), centres Y (the intercept is not penalised) and, for each penalty of
``alphas``, computes the leave-one-out residuals in closed form from one SVD
(e_i / (1 - H_ii), H the hat matrix); it keeps the penalty with the smallest mean squared
leave-one-out error over all outputs. Several outputs (columns of Y) share the penalty.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


__all__ = ["RidgeRegression", "DEFAULT_ALPHAS"]

#: Penalties tried, relative to the number of samples (X standardised: X^T X has n on its diagonal).
DEFAULT_ALPHAS = tuple(float(a) for a in np.logspace(-6, 3, 19))


@dataclass
class RidgeRegression:
    """A fitted ridge map Y = ((X - x_mean) / x_scale) @ coef + intercept."""

    coef: np.ndarray            # (features, outputs), on the standardised columns
    intercept: np.ndarray       # (outputs,)
    x_mean: np.ndarray          # (features,)
    x_scale: np.ndarray         # (features,)
    alpha: float                # the chosen penalty (absolute)
    loo_rmse: float             # its leave-one-out root mean squared error (over all outputs)

    @classmethod
    def fit(cls, X: np.ndarray, Y: np.ndarray, alphas: tuple[float, ...] = DEFAULT_ALPHAS) -> "RidgeRegression":
        """Fit on X (n, features) and Y (n, outputs) or (n,); ``alphas`` relative to n."""
        X = np.asarray(X, dtype=np.float64)
        Y = np.asarray(Y, dtype=np.float64)
        if Y.ndim == 1:
            Y = Y[:, None]
        if X.ndim != 2 or Y.ndim != 2 or X.shape[0] != Y.shape[0]:
            raise ValueError(f"X must be (n, features) and Y (n, outputs) with the same n; got {X.shape} and {Y.shape}")
        n = X.shape[0]
        if n < 3:
            raise ValueError(f"ridge needs at least 3 samples for its leave-one-out choice, got {n}")
        if not (np.all(np.isfinite(X)) and np.all(np.isfinite(Y))):
            raise ValueError("X and Y must be finite (drop episodes with NaN before fitting)")
        if not alphas or min(alphas) <= 0:
            raise ValueError("alphas must be a non-empty tuple of positive penalties")
        x_mean = X.mean(axis=0)
        spread = X.std(axis=0)
        x_scale = np.where(spread > 1e-12, spread, 1.0)
        Z = (X - x_mean) / x_scale
        y_mean = Y.mean(axis=0)
        Yc = Y - y_mean
        U, sv, Vt = np.linalg.svd(Z, full_matrices=False)
        UtY = U.T @ Yc
        best = None
        for rel in alphas:
            alpha = rel * n
            shrink = sv ** 2 / (sv ** 2 + alpha)                       # eigenvalues of H (without 1/n)
            fitted = U @ (shrink[:, None] * UtY)
            leverage = np.sum(U ** 2 * shrink[None, :], axis=1) + 1.0 / n   # + the intercept's
            loo = (Yc - fitted) / (1.0 - leverage)[:, None]
            err = float(np.mean(loo ** 2))
            if best is None or err < best[0]:
                best = (err, alpha, shrink)
        err, alpha, _ = best
        coef = Vt.T @ ((sv / (sv ** 2 + alpha))[:, None] * UtY)
        return cls(coef, y_mean, x_mean, x_scale, float(alpha), float(np.sqrt(err)))

    def predict(self, X: np.ndarray) -> np.ndarray:
        """Predictions (n, outputs) for X (n, features)."""
        X = np.asarray(X, dtype=np.float64)
        if X.ndim != 2 or X.shape[1] != len(self.x_mean):
            raise ValueError(f"X must be (n, {len(self.x_mean)}), got {X.shape}")
        # a product summed in a fixed order, not BLAS (its kernels, and last bits, vary by CPU)
        Z = (X - self.x_mean) / self.x_scale
        out = np.zeros((Z.shape[0], self.coef.shape[1]))
        for k in range(Z.shape[1]):
            out = out + Z[:, k:k + 1] * self.coef[k][None, :]
        return out + self.intercept

    def to_json(self) -> dict:
        """The fitted map as JSON types."""
        return {"coef": self.coef.tolist(), "intercept": self.intercept.tolist(), "x_mean": self.x_mean.tolist(),
                "x_scale": self.x_scale.tolist(), "alpha": self.alpha, "loo_rmse": self.loo_rmse}

    @classmethod
    def from_json(cls, d: dict) -> "RidgeRegression":
        """The map written by :meth:`to_json`."""
        return cls(np.array(d["coef"], dtype=np.float64), np.array(d["intercept"], dtype=np.float64),
                   np.array(d["x_mean"], dtype=np.float64), np.array(d["x_scale"], dtype=np.float64),
                   float(d["alpha"]), float(d["loo_rmse"]))
