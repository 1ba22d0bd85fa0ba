"""Quasi-static 5-DOF equilibrium of the rotor on the bearing (Jones/Harris quasi-static model
built from eqs 3-33 with the loads of eq 35, no unbalance, at t = 0).

The rotor displacement U solves F(U) + P = 0, where F is the bearing force of eq 33 (each ball
in its own equilibrium, eq 28) and P = (P_x, P_y, P, 0, 0). It is found by a damped Newton
iteration whose Jacobian, the bearing stiffness K = -dF/dU, is taken by central differences of
the converged bearing force (each ball to a 1 nm Newton step plus a first-order update). The
Newton step is a least-squares solve of our own (:func:`.portable_linalg.lstsq`, not LAPACK), so
the equilibrium, and the settled start built on it, are the same bits on every CPU; the contact
angles it reports (``alpha_i``, ``alpha_o``, outputs only) use NumPy's ``arctan2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from .ball import (B_CI, B_CO, B_CTRL, B_DI, B_DO, B_MG, B_QI, B_QO, B_SI, B_SO, B_WB, B_WM,
                   N_BALL_OUT)
from .bearing import bearing_force, cage_speed
from .kinematics import race_control_kinematics
from .layout import (CONTROL_INNER, I_CONTROL, I_GAM, I_IB, I_NM_TOL, I_RP, O_OMEGA,
                     PackedParams, pack_params)
from .portable_linalg import lstsq
from .portable_math import pow, sin

__all__ = ["StaticEquilibrium", "static_equilibrium", "EquilibriumError"]


class EquilibriumError(RuntimeError):
    """The static equilibrium iteration did not converge."""


@dataclass(frozen=True)
class StaticEquilibrium:
    """Result of :func:`static_equilibrium`. Per-ball arrays have length N (ball j at
    angle 2 pi j / N + phi_0)."""

    U: np.ndarray                 # (5,) x, y, z (m), theta_x, theta_y (rad)
    alpha_i: np.ndarray           # inner contact angles (rad)
    alpha_o: np.ndarray           # outer contact angles (rad)
    q_i: np.ndarray               # inner contact loads (N)
    q_o: np.ndarray               # outer contact loads (N)
    delta_i: np.ndarray           # inner deflections (m; negative = gap)
    delta_o: np.ndarray           # outer deflections (m)
    ball_displacement_r: np.ndarray  # v_r (m)
    ball_displacement_z: np.ndarray  # v_z (m)
    orbital_speed: np.ndarray     # omega_m (rad/s)
    spin_speed: np.ndarray        # omega_b (rad/s)
    gyroscopic_moment: np.ndarray  # M_g (N m)
    inner_race_control: np.ndarray  # True where the ball is under inner-race control
    stiffness: np.ndarray         # (5, 5) K = -dF/dU (N/m, N/rad, N m/m, N m/rad)
    cage_speed_ratio: float       # omega_c / omega (eq 7; kinematic ratio at zero speed)
    bearing_force: np.ndarray     # (5,) F at the solution (= -P to the tolerance)
    residual: float               # max |F + P| (N; moments divided by r_p)
    iterations: int
    shaft_speed_rad_s: float = 0.0

    @property
    def cage_speed_rad_s(self) -> float:
        """Cage speed omega_c (rad/s) of eq 7 at the equilibrium."""
        return float(self.cage_speed_ratio * self.shaft_speed_rad_s)


@njit(cache=True)
def _force_at(U, prm, omega, race_wav, ball_wav, ball_phase, ball_size, ball_v, ball_out, F, cage_angle,
              psi_b):
    return bearing_force(U, cage_angle, 0.0, psi_b, prm, omega, race_wav, ball_wav, ball_phase,
                         ball_size, ball_v, ball_out, F)


class _ForceEvaluator:
    """Bearing force at t = 0 with warm-started ball states (Python-side helper)."""

    def __init__(self, packed: PackedParams, cage_angle: float = 0.0):
        self.p = packed
        n = packed.ball_size.shape[0]
        self.ball_v = np.zeros((n, 2))
        self.ball_out = np.zeros((n, N_BALL_OUT))
        if int(packed.prm[I_CONTROL]) == CONTROL_INNER:
            self.ball_out[:, B_CTRL] = 1.0
        self.psi_b = np.zeros(n)
        self.cage_angle = cage_angle
        self.F = np.zeros(5)

    def __call__(self, U: np.ndarray) -> np.ndarray:
        st = _force_at(np.ascontiguousarray(U, dtype=np.float64), self.p.prm, self.p.op[O_OMEGA], self.p.race_wav,
                       self.p.ball_wav, self.p.ball_phase, self.p.ball_size, self.ball_v,
                       self.ball_out, self.F, self.cage_angle, self.psi_b)
        if st != 0:
            raise EquilibriumError(f"ball equilibrium (eq 31) failed with status {st} at U = {U}")
        return self.F.copy()


def _stiffness(force, U: np.ndarray, rp: float, h: float = 1e-9) -> np.ndarray:
    """K = -dF/dU by central differences (step h for translations, h / r_p for rotations)."""
    K = np.zeros((5, 5))
    saved_v = force.ball_v.copy()
    saved_out = force.ball_out.copy()
    for k in range(5):
        hk = h if k < 3 else h / rp
        Up = U.copy()
        Up[k] += hk
        Um = U.copy()
        Um[k] -= hk
        force.ball_v[:] = saved_v
        force.ball_out[:] = saved_out
        Fp = force(Up)
        force.ball_v[:] = saved_v
        force.ball_out[:] = saved_out
        Fm = force(Um)
        K[:, k] = -(Fp - Fm) / (2.0 * hk)
    force.ball_v[:] = saved_v
    force.ball_out[:] = saved_out
    force(U)
    return K


def _initial_guess(params) -> np.ndarray:
    """Low-speed estimate of the displacement under the axial and radial loads, erring on the
    large side (the Hertz contact hardens, so Newton then approaches from above)."""
    g = params.geometry
    U = np.zeros(5)
    n = g.n_balls
    p_ax = params.loads.axial_preload_n
    k_guess = 4.0e10
    sa = max(sin(g.contact_angle_rad), 0.2)
    if p_ax > 0:
        q = p_ax / (n * sa)
        delta = pow(q / k_guess, 2.0 / 3.0)
        U[2] = (2.0 * delta + g.clearance_inner_m + g.clearance_outer_m) / sa
    return U


def static_equilibrium(params, *, max_iter: int = 200, tol_n: float = 1e-4) -> StaticEquilibrium:
    """5-DOF quasi-static equilibrium of ``params`` at its speed and loads, no unbalance.

    Converged when max |F + P| (moments divided by r_p) is below ``tol_n`` newtons; the default
    1e-4 N sits just above the noise of the ball solutions (each stopped by its step rule,
    ``newton_tol_m``, and the first-order last step).

    Returns per-ball contact angles, loads and displacements, the rotor displacement U, the
    bearing stiffness matrix (central differences) and the cage/shaft speed ratio.
    Raises :class:`EquilibriumError` if the iteration does not converge (for instance when the
    loads exceed what the bearing can carry).
    """
    packed = pack_params(params)
    prm = packed.prm
    # each ball to its step rule alone (newton_tol_m): the quadratic stop of ball.solve_ball
    # trusts the rotor's Newmark tolerance, and there is no Newmark iteration here; the
    # stiffness's central differences want every ball solved to the same depth
    prm[I_NM_TOL] = 0.0
    rp = prm[I_RP]
    # cage angle 0 at t = 0; the initial cage angle phi_0 is in prm (ball angles, eq 6)
    force = _ForceEvaluator(packed, 0.0)
    P = np.array([params.loads.radial_load_x_n, params.loads.radial_load_y_n,
                  params.loads.axial_preload_n, 0.0, 0.0])
    scale = np.array([1.0, 1.0, 1.0, 1.0 / rp, 1.0 / rp])     # moments -> N at r_p
    U = _initial_guess(params)
    max_step = 2.0e-6
    trust = max_step
    it = 0
    R = force(U) + P
    res = float(np.max(np.abs(R * scale)))
    while res > tol_n and it < max_iter:
        it += 1
        K = _stiffness(force, U, rp)
        if not np.any(K):
            # no contact anywhere: push the rotor along the load until the balls engage
            dU = P / (np.max(np.abs(P[:3])) + 1e-300) * max_step
        else:
            dU = lstsq(K, R, 1e-12)                             # Newton: K dU = F + P
        step = np.max(np.abs(dU * np.array([1, 1, 1, rp, rp])))
        if step > trust:
            dU *= trust / step
            step = trust
        # backtracking on the residual
        lam = 1.0
        saved_v = force.ball_v.copy()
        saved_out = force.ball_out.copy()
        while True:
            Ut = U + lam * dU
            try:
                Rt = force(Ut) + P
                rt = float(np.max(np.abs(Rt * scale)))
            except EquilibriumError:          # a ball without equilibrium there: step shorter
                Rt, rt = R, math.inf
            if rt < res or lam < 1e-3:
                break
            force.ball_v[:] = saved_v
            force.ball_out[:] = saved_out
            lam *= 0.5
        if not math.isfinite(rt):
            force.ball_v[:] = saved_v
            force.ball_out[:] = saved_out
            break
        U, R, res = Ut, Rt, rt
        # trust region on the step: grow after full steps, shrink after backtracking
        trust = min(2.0 * trust, 1e-4) if lam == 1.0 else max(0.5 * trust, 1e-9)
        if step * lam < 1e-16:
            break
    if not res <= tol_n:
        raise EquilibriumError(
            f"static equilibrium did not converge: residual {res:.3g} N after {it} iterations "
            f"(loads {P[:3]} N at {params.shaft_speed_rpm:g} rpm)")
    K = _stiffness(force, U, rp)
    bo = force.ball_out
    n = bo.shape[0]
    alpha_i = np.arctan2(bo[:, B_SI], bo[:, B_CI])
    alpha_o = np.arctan2(bo[:, B_SO], bo[:, B_CO])
    omega = packed.op[O_OMEGA]
    if omega > 0:
        ratio = cage_speed(bo, n, math.nan) / omega
        if math.isnan(ratio):   # no ball on the inner race: kinematic mean over all balls
            ratio = float(np.mean(bo[:, B_WM])) / omega
    else:
        wm = [race_control_kinematics(bo[j, B_CI], bo[j, B_SI], bo[j, B_CO], bo[j, B_SO], 1.0,
                                      prm[I_GAM], prm[I_IB], bool(bo[j, B_CTRL] > 0.5))[0]
              for j in range(n)]
        loaded = bo[:, B_QI] > 0
        ratio = float(np.mean(np.asarray(wm)[loaded])) if loaded.any() else float(np.mean(wm))
    return StaticEquilibrium(
        U=U.copy(), alpha_i=alpha_i, alpha_o=alpha_o, q_i=bo[:, B_QI].copy(),
        q_o=bo[:, B_QO].copy(), delta_i=bo[:, B_DI].copy(), delta_o=bo[:, B_DO].copy(),
        ball_displacement_r=force.ball_v[:, 0].copy(), ball_displacement_z=force.ball_v[:, 1].copy(),
        orbital_speed=bo[:, B_WM].copy(), spin_speed=bo[:, B_WB].copy(),
        gyroscopic_moment=bo[:, B_MG].copy(), inner_race_control=bo[:, B_CTRL] > 0.5,
        stiffness=K, cage_speed_ratio=float(ratio), bearing_force=force(U), residual=res,
        iterations=it, shaft_speed_rad_s=float(omega))
