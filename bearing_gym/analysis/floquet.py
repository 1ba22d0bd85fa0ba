"""Floquet multipliers by finite differences of the flow map over one period (paper section 3.2;
Nayfeh & Balachandran, *Applied Nonlinear Dynamics*, ch. 7; the paper's ref. [29]).

Machinery
---------
For a flow map Φ: x(t0) -> x(t0 + T) the monodromy matrix is its Jacobian at a point of the
periodic orbit, and its eigenvalues are the Floquet multipliers μ. :func:`fd_monodromy` builds the
Jacobian column by column with central differences, (Φ(x + h_k e_k) − Φ(x − h_k e_k)) / 2h_k
(error O(h²) plus the integration noise divided by h). :func:`ode_flow_map` wraps
``scipy.integrate.solve_ivp`` so that the same code runs on ODEs with known multipliers
(``tests/analysis/test_floquet.py``: a constant-coefficient damped oscillator, whose multipliers
are exp(λ T) exactly, and a damped Mathieu equation checked against the variational equations
integrated by :func:`variational_monodromy` and against Liouville's formula
det M = exp(∫ tr J dt)).

The bearing (:func:`simulator_floquet`)
---------------------------------------
* **Section**: stroboscopic, t = t0 + m T with T = 2π/ω the shaft period (the period of the
  unbalance force m e ω² of eq 35), i.e. shaft angle θ_s = θ_s(t0) mod 2π. T is rounded to a
  whole number of time steps (exact at 2,000, 2,500, 5,000, 10,000, 20,000 rpm with dt = 10 µs;
  the rounding is reported in ``FloquetResult.period_s``).
* **State**: the 10 rotor coordinates (X, V) of eq 35. Each column perturbs one of them in a
  copy of ``Simulator.state`` (the acceleration is recomputed consistently,
  :class:`.simstate.StatePerturber`), runs the Simulator for one period and restores the state.
  The balls are quasi-static (eq 31) and the cage speed is algebraic (eq 7), so they are not
  states. The cage angle ψ_c (eq 8) is: it is the phase of the ball-passage excitation N ω_c,
  which is in general incommensurate with ω, so the forcing is quasi-periodic and a strict
  monodromy matrix exists only when the ball-passage excitation vanishes (no waviness, no
  radial displacement) or locks to ω. In the 10-dim map the cage angle is integrated along each
  perturbed run but its deviation at the section is not fed back: the cage phase is treated
  as a forcing phase, like the shaft angle. The multipliers then depend slightly on where on
  the torus the section is taken (``tests``/reproduction: a few 1e-3 at 800 N).
* **Trivial multiplier**: the 10-dim stroboscopic map of a *forced* system has none (its
  phase is fixed by the unbalance). With ``include_cage_angle=True`` the map is 11-dim
  (X, V, ψ_c); the cage phase has no restoring force, so that map has a multiplier ≈ 1 whose
  eigenvector lies along ψ_c (the direction along the torus). It is identified as the
  eigenvalue whose eigenvector has the largest ψ_c component (after scaling ψ_c by r_p) and
  dropped; ``FloquetResult.dropped`` keeps it, and the remaining 10 agree with the 10-dim map.

Which mode is which: :meth:`FloquetResult.modes` gives, for each multiplier, the decay rate
ln|μ|/T, the frequency candidates (arg μ / 2π + k)/T and the dominant coordinates of its
eigenvector (in the scaled units of :func:`.simstate.state_scale`), so the slow backward rocking
mode (|μ| close to 1, arg μ of a few degrees) is not mistaken for the mode that loses stability.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from .simstate import STATE_LABELS, StatePerturber, shaft_period_steps, state_scale, state_vector

__all__ = ["FloquetResult", "fd_monodromy", "multipliers", "ode_flow_map",
           "variational_monodromy", "simulator_floquet", "liouville_determinant", "match_modes"]


@dataclass
class FloquetResult:
    """Monodromy matrix, multipliers (sorted by decreasing modulus, trivial one removed) and
    eigenvectors (columns, same order) of a map over one period ``period_s``."""

    monodromy: np.ndarray
    multipliers: np.ndarray
    eigenvectors: np.ndarray
    period_s: float
    section: str = ""
    labels: tuple[str, ...] = ()
    scale: np.ndarray | None = None
    dropped: complex | None = None
    info: dict = field(default_factory=dict)

    @property
    def leading_modulus(self) -> float:
        """max |μ| (the orbit is asymptotically stable when < 1)."""
        return float(np.max(np.abs(self.multipliers))) if self.multipliers.size else 0.0

    @property
    def stable(self) -> bool:
        return self.leading_modulus < 1.0

    def modes(self) -> list[dict]:
        """One dict per multiplier: ``mu``, ``modulus``, ``angle_deg`` (arg μ per period),
        ``rate_per_s`` = ln|μ|/T, ``freq_hz`` = |arg μ|/(2π T) (the folded frequency; the true
        one is freq_hz + k/T or k/T − freq_hz), and ``dominant`` (the two state labels with
        the largest share of the scaled eigenvector, leaving out the coordinate of a dropped
        trivial multiplier, whose share is large in every mode)."""
        out = []
        trivial = self.info.get("trivial_index")
        for k, mu in enumerate(self.multipliers):
            v = self.eigenvectors[:, k]
            if self.scale is not None:
                v = v / self.scale
            share = np.abs(v) ** 2
            if trivial is not None:      # shares among the other coordinates
                share[trivial] = 0.0
            share = share / max(share.sum(), 1e-300)
            order = np.argsort(-share)[:2]
            labs = self.labels or tuple(str(i) for i in range(len(v)))
            out.append(dict(index=k, mu=complex(mu), modulus=float(abs(mu)),
                            angle_deg=float(math.degrees(np.angle(mu))),
                            rate_per_s=float(math.log(max(abs(mu), 1e-300)) / self.period_s),
                            freq_hz=float(abs(np.angle(mu)) / (2 * math.pi * self.period_s)),
                            dominant=tuple((labs[i], float(share[i])) for i in order)))
        return out

    def share(self, labels: Sequence[str]) -> np.ndarray:
        """Share of each multiplier's scaled eigenvector in the coordinates ``labels`` (e.g.
        ``("z", "z_dot")`` for the axial mode), leaving out a dropped trivial coordinate."""
        v = self.eigenvectors if self.scale is None else self.eigenvectors / self.scale[:, None]
        e = np.abs(v) ** 2
        trivial = self.info.get("trivial_index")
        if trivial is not None:
            e[trivial] = 0.0
        missing = [lab for lab in labels if lab not in self.labels]
        if missing:
            raise ValueError(f"unknown coordinate(s) {missing}; this result has labels {self.labels} "
                             "(pass labels= to multipliers())")
        idx = [self.labels.index(lab) for lab in labels]
        return e[idx].sum(axis=0) / np.maximum(e.sum(axis=0), 1e-300)

    def pairs(self) -> list[dict]:
        """:meth:`modes` with each complex-conjugate pair listed once (positive angle)."""
        out = []
        for m in self.modes():
            if m["angle_deg"] < -1e-9 and abs(m["mu"].imag) > 1e-12 * max(m["modulus"], 1e-300):
                continue
            out.append(m)
        return out


def fd_monodromy(flow_map: Callable[[np.ndarray], np.ndarray], x0: np.ndarray,
                 steps: np.ndarray | float) -> np.ndarray:
    """Jacobian of ``flow_map`` at ``x0`` by central differences with step ``steps[k]`` along
    coordinate k (2n evaluations)."""
    x0 = np.asarray(x0, dtype=float)
    n = x0.size
    h = np.broadcast_to(np.asarray(steps, dtype=float), (n,))
    if np.any(h <= 0):
        raise ValueError("finite-difference steps must be positive")
    J = np.empty((n, n))
    for k in range(n):
        xp = x0.copy()
        xp[k] += h[k]
        xm = x0.copy()
        xm[k] -= h[k]
        J[:, k] = (np.asarray(flow_map(xp), dtype=float) - np.asarray(flow_map(xm), dtype=float)) / (2.0 * h[k])
    return J


def multipliers(monodromy: np.ndarray, *, period_s: float = 1.0, section: str = "",
                labels: Sequence[str] = (), scale: np.ndarray | None = None,
                drop_along: int | None = None) -> FloquetResult:
    """Eigen-decomposition of a monodromy matrix into a :class:`FloquetResult`.

    ``drop_along``: index of a coordinate along which a trivial (neutral) multiplier is
    expected; the eigenvalue whose (scaled) eigenvector has the largest share on it is removed
    and stored in ``FloquetResult.dropped``.
    """
    M = np.asarray(monodromy, dtype=float)
    mu, vec = np.linalg.eig(M)
    dropped = None
    if drop_along is not None:
        v = vec if scale is None else vec / np.asarray(scale)[:, None]
        share = np.abs(v[drop_along, :]) ** 2 / np.sum(np.abs(v) ** 2, axis=0)
        k = int(np.argmax(share))
        dropped = complex(mu[k])
        mu = np.delete(mu, k)
        vec = np.delete(vec, k, axis=1)
    order = np.lexsort((-np.angle(mu), -np.round(np.abs(mu), 12)))
    return FloquetResult(M, mu[order], vec[:, order], float(period_s), section, tuple(labels),
                         None if scale is None else np.asarray(scale, dtype=float), dropped)


def ode_flow_map(rhs: Callable[[float, np.ndarray], np.ndarray], period: float, t0: float = 0.0,
                 rtol: float = 1e-11, atol: float = 1e-13,
                 method: str = "DOP853") -> Callable[[np.ndarray], np.ndarray]:
    """x(t0) -> x(t0 + period) of dx/dt = rhs(t, x) by ``scipy.integrate.solve_ivp``."""
    from scipy.integrate import solve_ivp

    def flow(x: np.ndarray) -> np.ndarray:
        sol = solve_ivp(rhs, (t0, t0 + period), np.asarray(x, dtype=float), method=method,
                        rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        return sol.y[:, -1]

    return flow


def variational_monodromy(rhs: Callable[[float, np.ndarray], np.ndarray],
                          jac: Callable[[float, np.ndarray], np.ndarray], x0: np.ndarray,
                          period: float, t0: float = 0.0, rtol: float = 1e-12,
                          atol: float = 1e-14) -> np.ndarray:
    """Monodromy matrix from the variational equations dΦ/dt = J(t, x(t)) Φ, Φ(t0) = I,
    integrated together with the orbit (reference for :func:`fd_monodromy`)."""
    from scipy.integrate import solve_ivp

    x0 = np.asarray(x0, dtype=float)
    n = x0.size

    def full(t: float, y: np.ndarray) -> np.ndarray:
        x = y[:n]
        phi = y[n:].reshape(n, n)
        return np.concatenate([rhs(t, x), (jac(t, x) @ phi).ravel()])

    y0 = np.concatenate([x0, np.eye(n).ravel()])
    sol = solve_ivp(full, (t0, t0 + period), y0, method="DOP853", rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"solve_ivp failed: {sol.message}")
    return sol.y[n:, -1].reshape(n, n)


def simulator_floquet(sim, *, h_m: float = 1e-7, include_cage_angle: bool = False,
                      h_cage_rad: float = 1e-6) -> FloquetResult:
    """Floquet multipliers of the Simulator's current trajectory on the stroboscopic section
    (one shaft period from the current state; see the module docstring).

    The Simulator's state is left unchanged. ``h_m`` is the finite-difference step of the
    translations; tilts get h_m / r_p and velocities ω times these. The default 0.1 µm (1 % of
    the contact deflections) balances truncation against the noise of the iterative solutions
    (ball Newton stopped at a 1 nm step with a first-order update, Newmark at 1e-13 m): at
    800 N the product of the multipliers matches Liouville's formula to about 1e-3 with
    h = 0.1 µm, 2-3e-3 with 0.01-0.3 µm and 7e-3 with 1 µm, and the moduli change by < 1e-3
    between 0.03 and 0.3 µm. The current state should be on (or very near) the periodic orbit,
    e.g. the end of a settled run.
    ``include_cage_angle=True`` adds ψ_c as an 11th coordinate and drops its trivial
    multiplier. Cost: 2n runs of one period (≈ 0.06 s simulated at 20,000 rpm, n = 10).
    """
    from bearing_gym.physics.rotor import S_CAGE

    n_steps, period = shaft_period_steps(sim)
    duration = n_steps * sim.dt_s
    base = sim.state
    perturber = StatePerturber(sim)
    scale10 = state_scale(sim)
    x0 = state_vector(base)
    if include_cage_angle:
        rp = 1.0 / scale10[3]
        scale = np.concatenate([scale10, [1.0 / rp]])
        x0 = np.concatenate([x0, [base.scal[S_CAGE]]])
        steps = np.concatenate([h_m / scale10, [h_cage_rad]])
    else:
        scale = scale10
        steps = h_m / scale10

    def flow(x: np.ndarray) -> np.ndarray:
        b = base
        if include_cage_angle:
            b = base.copy()
            b.scal[S_CAGE] = x[10]
        st = perturber.make(b, x[:10])
        sim.state = st
        sim.advance(duration)
        end = sim.state
        out = state_vector(end)
        if include_cage_angle:
            out = np.concatenate([out, [end.scal[S_CAGE]]])
        return out

    try:
        M = fd_monodromy(flow, x0, steps)
    finally:
        sim.state = base
    labels = STATE_LABELS + (("cage_angle",) if include_cage_angle else ())
    section = (f"stroboscopic at the shaft period T = {period:.6g} s ({n_steps} steps), "
               f"state (X, V){' + cage angle' if include_cage_angle else ''}, "
               f"central differences h = {h_m:g} m")
    res = multipliers(M, period_s=period, section=section, labels=labels, scale=scale,
                      drop_along=10 if include_cage_angle else None)
    res.info = dict(trivial_index=10 if include_cage_angle else None, t0_s=base.t, axial_preload_n=sim.axial_preload_n,
                    shaft_speed_rpm=sim.shaft_speed_rpm, h_m=h_m,
                    liouville_det=liouville_determinant(sim, period))
    return res


def liouville_determinant(sim, period_s: float) -> float:
    """exp(−T Σ_k c_k / M_kk): the determinant of the (X, V) monodromy matrix predicted by
    Liouville's formula for eq 35 (the bearing force depends on X only, and the gyroscopic
    matrix is skew with equal radial inertias, so the trace of the Jacobian is −Σ c_k/M_kk).
    A check on :func:`simulator_floquet` (product of all 10 multipliers)."""
    r = sim.params.rotor
    m = np.array([r.mass_kg] * 3 + [r.inertia_radial_kg_m2] * 2)
    return float(math.exp(-period_s * float(np.sum(sim.damping_coefficients / m))))


def match_modes(previous: FloquetResult, current: FloquetResult) -> np.ndarray:
    """Index into ``current.multipliers`` of the mode that continues each mode of ``previous``
    (maximal overlap |<v_prev, v_cur>| of the scaled, normalised eigenvectors, solved as an
    assignment problem). Use it to follow one mode along a parameter sweep."""
    from scipy.optimize import linear_sum_assignment

    def norm(res: FloquetResult) -> np.ndarray:
        v = res.eigenvectors if res.scale is None else res.eigenvectors / res.scale[:, None]
        return v / np.linalg.norm(v, axis=0, keepdims=True)

    a, b = norm(previous), norm(current)
    if a.shape != b.shape:
        raise ValueError("both results must have the same dimension")
    overlap = np.abs(a.conj().T @ b)
    rows, cols = linear_sum_assignment(-overlap)
    out = np.empty(a.shape[1], dtype=int)
    out[rows] = cols
    return out
