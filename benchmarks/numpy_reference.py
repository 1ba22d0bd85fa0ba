"""Plain-NumPy reference implementation of one step of the Bai & Xu (2006) rotor / ball-bearing
model, written independently of the numba kernels in :mod:`bearing_gym.physics`.

It is meant as (a) a readable statement of what the kernels compute and (b) a yardstick for the
benchmark in ``bench_integrator.py``. Everything is vectorised over the balls; no numba is used
(``bearing_gym`` is only imported to read the parameter dataclasses and, in the conversion
helpers at the bottom, to convert a :class:`bearing_gym.physics.SimulatorState` to and from this
module's state).

Model (same equations and the same algorithmic choices as the package, so that the results agree
to rounding error when started from the same state):

* Hertz constant K(R_x, R_y) from the Brewe-Hamrock fits (App. A, eqs A.1-A.7) and dK/dR_x.
* Race-control kinematics (App. B): orbital speed omega_m, spin omega_b, gyroscopic moment M_g
  under outer- or inner-race control and their derivatives in alpha_i, alpha_o.
* Ball equilibrium (eq 28) solved per ball by Newton-Raphson (eq 31) with the analytic Jacobian
  (App. C), warm-started from the previous ball displacement (v_r, v_z). The Newton step is
  taken in polar coordinates about the outer-groove centre, (l_o, alpha_o), so that the ball
  moves along the groove arc. The iteration stops when the step s = max(|dl_o|, l_o |dalpha_o|)
  is below ``newton_tol_m``, or, with every loaded deflection above QUADRATIC_REGIME_M and any
  gap wider than 2 s, when s^2 / d_min (d_min the smaller loaded deflection) is below
  ``newmark_tol_m`` (that last step is taken and the contact state is moved to
  the new point to first order with the derivatives of the last evaluation instead of
  evaluating the model again); steps are clipped to 0.1 L_o; a step that makes the residual
  (max-norm) grow is halved along the arc (up to 30 times in a row); a ball without outer
  contact that is pushed outwards (centrifugal force plus inner load > 0) is first put against
  the outer race where the Hertz load balances that push; a ball touching neither race at rest
  is left alone (no load).
* Race-control friction lambda (eqs 28, 32) multiplied by a smooth contact factor that rises from
  0 at delta = 0 to 1 at delta = FRICTION_ONSET_M = 0.1 um (smoothstep), in the Jacobian too.
* Race control "outer", "inner" or "auto" (Jones/Harris criterion, re-solving a ball whose
  preferred control differs from the one it was solved with).
* Race and ball waviness (eqs 9-14, ring-angle form) and ball oversize are implemented; with
  the default parameters all of them are zero.
* Bearing force F = sum_j T_j^T Q_j (eqs 3-5, 32-33).
* Newmark-beta step with fixed-point (equilibrium) iterations on the displacement, viscous
  damping and the gyroscopic coupling of eq 35; the first guess of a_{n+1} is extrapolated
  quadratically from the last three steps, and so is every ball's (v_r, v_z); the cage angle, shaft angle and
  ball spin angles advance explicitly with the speeds of the previous step (eqs 7, 8, 15).

Usage::

    import bearing_gym
    from bearing_gym.physics import Simulator
    from numpy_reference import NumpyModel, state_from_simulator

    sim = Simulator(bearing_gym.default_params())
    model = NumpyModel(sim.params, damping=sim.damping_coefficients)
    state = state_from_simulator(sim.state)
    model.advance(state, 100)          # 100 Newmark steps, state updated in place
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["NumpyModel", "BallState", "RotorState", "state_from_simulator", "state_to_simulator",
           "ball_state_from_arrays", "STATUS_TEXT"]

# the race-control friction of a contact fades in over this deflection (package:
# bearing_gym.physics.ball.FRICTION_ONSET_M; the test checks that the two agree)
FRICTION_ONSET_M = 1.0e-7
QUADRATIC_REGIME_M = 2.0 * FRICTION_ONSET_M   # ball.solve_ball's quadratic regime
MAX_HALVINGS = 30         # consecutive step halvings allowed in the ball Newton iteration

# status codes (same meaning and values as the package)
OK, NOT_CONVERGED, SINGULAR, NEWMARK_NOT_CONVERGED, DIVERGED = 0, 1, 2, 3, 4
STATUS_TEXT = {OK: "ok", NOT_CONVERGED: "ball Newton did not converge",
               SINGULAR: "ball Jacobian singular",
               NEWMARK_NOT_CONVERGED: "Newmark iterations did not converge",
               DIVERGED: "diverged"}


# ---------------------------------------------------------------------------------------------
# state containers
# ---------------------------------------------------------------------------------------------
@dataclass
class BallState:
    """Per-ball quantities (arrays of length N). ``v`` (N, 2) = (v_r, v_z) is the Newton warm
    start; the rest is the contact state of the last bearing-force evaluation."""

    v: np.ndarray                 # (N, 2) ball-centre displacement (v_r, v_z)
    inner_control: np.ndarray     # (N,) bool, race control used for the ball
    q_i: np.ndarray = None        # contact loads (N)
    q_o: np.ndarray = None
    cos_ai: np.ndarray = None     # contact-angle cosines / sines
    sin_ai: np.ndarray = None
    cos_ao: np.ndarray = None
    sin_ao: np.ndarray = None
    omega_m: np.ndarray = None    # orbital speed (rad/s)
    omega_b: np.ndarray = None    # spin speed (rad/s)
    m_g: np.ndarray = None        # gyroscopic moment (N m)
    delta_i: np.ndarray = None    # deflections (m, negative = gap)
    delta_o: np.ndarray = None
    lam_i: np.ndarray = None      # effective race-control factor on the inner race (eq 32)

    _FIELDS = ("q_i", "q_o", "cos_ai", "sin_ai", "cos_ao", "sin_ao", "omega_m", "omega_b", "m_g",
               "delta_i", "delta_o", "lam_i")

    def __post_init__(self):
        n = self.v.shape[0]
        for name in self._FIELDS:
            if getattr(self, name) is None:
                setattr(self, name, np.zeros(n))

    def copy(self) -> "BallState":
        return BallState(self.v.copy(), self.inner_control.copy(),
                         *(getattr(self, f).copy() for f in self._FIELDS))


@dataclass
class RotorState:
    """Complete dynamic state of the reference integrator."""

    X: np.ndarray                 # (5,) x, y, z, theta_x, theta_y
    V: np.ndarray
    A: np.ndarray
    t: float
    shaft_angle: float
    cage_angle: float
    cage_speed: float
    psi_b: np.ndarray             # (N,) ball spin angles (eq 15)
    balls: BallState
    A_prev: np.ndarray            # (5,) acceleration of the previous step (predictor)
    v_prev: np.ndarray            # (N, 2) ball displacements of the previous step (warm start)
    F: np.ndarray = field(default_factory=lambda: np.zeros(5))   # last bearing force
    A_prev2: np.ndarray | None = None   # (5,) acceleration two steps back (None: = A_prev)
    v_prev2: np.ndarray | None = None   # (N, 2) ball displacements two steps back (None: = v_prev)
    eta: float = 0.0              # last measured theta/(1-theta) of the Newmark iteration (0: none)

    def copy(self) -> "RotorState":
        return RotorState(self.X.copy(), self.V.copy(), self.A.copy(), self.t, self.shaft_angle,
                          self.cage_angle, self.cage_speed, self.psi_b.copy(), self.balls.copy(),
                          self.A_prev.copy(), self.v_prev.copy(), self.F.copy(),
                          None if self.A_prev2 is None else self.A_prev2.copy(),
                          None if self.v_prev2 is None else self.v_prev2.copy(), self.eta)


# ---------------------------------------------------------------------------------------------
# the model
# ---------------------------------------------------------------------------------------------
class NumpyModel:
    """Bearing force and Newmark integration in plain NumPy.

    ``params``: a :class:`bearing_gym.params.BearingParams`; ``damping``: the 5 viscous damping
    coefficients (x, y, z, theta_x, theta_y). The Simulator derives these from the static
    stiffness, so pass ``sim.damping_coefficients`` to reproduce a Simulator run. When omitted,
    ``params.damping.coefficients`` is used, or zero damping.

    Loads and speed are plain attributes (``P`` (5,), ``omega``) and may be changed between steps.
    ``counters`` accumulates work statistics: force evaluations, ball residual evaluations
    (Newton iterations summed over balls), vectorised Newton passes (one pass evaluates the
    residual of every ball still iterating, so passes per solve = the most iterations any ball
    needs), Newmark iterations and steps.
    """

    def __init__(self, params, damping=None):
        g, mat, rot, integ = params.geometry, params.material, params.rotor, params.integrator
        # geometry (Table 1) and material
        self.n = g.n_balls
        self.db = g.ball_diameter_m
        self.dp = g.pitch_diameter_m
        self.r_i = g.inner_groove_radius_m
        self.r_o = g.outer_groove_radius_m
        self.alpha0 = g.contact_angle_rad
        self.e_eff = mat.youngs_modulus_pa / (1.0 - mat.poisson_ratio ** 2)
        self.m_b = params.ball_mass_kg
        self.i_b = params.ball_inertia_kg_m2
        self.gamma = self.db / self.dp
        # nominal centre distances of eqs 16-17 (ring geometry, clearance included)
        self.L_i = self.r_i - self.db / 2.0 - g.clearance_inner_m
        self.L_o = self.r_o - self.db / 2.0 - g.clearance_outer_m
        # inner-groove centre locus (eq 4): on the nominal contact line outside the ball centre
        self.r_p = self.dp / 2.0 + self.L_i * math.cos(self.alpha0)
        self.z_p = self.L_i * math.sin(self.alpha0)
        # transverse effective radii (A.6, A.7); R_y does not depend on the contact angle
        self.ry_i = self.r_i / (2.0 * self.r_i / self.db - 1.0)
        self.ry_o = self.r_o / (2.0 * self.r_o / self.db - 1.0)
        self.race_control = params.race_control
        self.phi0 = params.initial_cage_angle_rad
        # rotor, loads, speed
        self.mass = rot.mass_kg
        self.i_r = rot.inertia_radial_kg_m2
        self.i_z = rot.inertia_polar_kg_m2
        self.ecc = rot.eccentricity_m
        ld = params.loads
        self.P = np.array([ld.radial_load_x_n, ld.radial_load_y_n, ld.axial_preload_n, 0.0, 0.0])
        self.omega = params.shaft_speed_rad_s
        if damping is None:
            damping = params.damping.coefficients if params.damping.coefficients is not None \
                else np.zeros(5)
        self.C = np.diag(np.asarray(damping, dtype=float))
        # integrator
        self.dt = integ.dt_s
        self.beta = integ.newmark_beta
        self.nm_gamma = integ.newmark_gamma
        self.nm_tol = integ.newmark_tol_m
        self.nm_maxit = integ.newmark_max_iter
        self.nt_tol = integ.newton_tol_m
        self.nt_maxit = integ.newton_max_iter
        self.div_limit = integ.divergence_limit_m
        # rotations are compared as displacements at the inner-groove radius
        self.dof_scale = np.array([1.0, 1.0, 1.0, self.r_p, self.r_p])
        self._init_waviness(params)
        self.reset_counters()

    # --- waviness (eqs 9-14) ------------------------------------------------------------------
    def _init_waviness(self, params):
        w = params.waviness

        def race_terms(rw, radial):
            amps = rw.radial_amplitudes_m if radial else rw.axial_amplitudes_m
            phases = rw.radial_phases_rad if radial else rw.axial_phases_rad
            return (np.asarray(rw.orders, float), np.asarray(amps, float),
                    np.asarray(phases, float))

        self.wav_p_i = race_terms(w.inner, True)
        self.wav_q_i = race_terms(w.inner, False)
        self.wav_p_o = race_terms(w.outer, True)
        self.wav_q_o = race_terms(w.outer, False)
        bw = w.balls
        self.ball_orders = np.asarray(bw.orders, float)
        self.ball_amps = np.asarray(bw.amplitudes_m, float)
        ph = np.asarray(bw.phases_rad, float).reshape(-1, len(bw.orders)) if bw.orders \
            else np.zeros((1, 0))
        self.ball_phases = np.broadcast_to(ph, (self.n, len(bw.orders)))  # (N, n_orders)
        self.ball_oversize = np.asarray(bw.oversize_m, float) if bw.oversize_m else np.zeros(self.n)
        self.has_waviness = not (w.inner.is_zero and w.outer.is_zero and not self.ball_amps.any())

    @staticmethod
    def _wave(terms, angle):
        """sum_n A_n cos(n angle + phase_n), angle (N,) -> (N,)."""
        orders, amps, phases = terms
        if orders.size == 0:
            return np.zeros_like(angle)
        return np.cos(np.outer(angle, orders) + phases) @ amps

    def waviness(self, phi, shaft_angle, psi_b):
        """(p_i, q_i, p_o, q_o, w_i, w_o) per ball; the inner race turns with the shaft."""
        if not self.has_waviness:
            z = np.zeros(self.n)
            return z, z, z, z, z, z
        ring_i = phi - shaft_angle
        p_i = self._wave(self.wav_p_i, ring_i)
        q_i = self._wave(self.wav_q_i, ring_i)
        p_o = self._wave(self.wav_p_o, phi)
        q_o = self._wave(self.wav_q_o, phi)
        arg = np.outer(psi_b, self.ball_orders)
        w_i = np.cos(arg + self.ball_phases) @ self.ball_amps
        w_o = np.cos(arg + self.ball_orders * math.pi + self.ball_phases) @ self.ball_amps
        return p_i, q_i, p_o, q_o, w_i, w_o

    # --- Hertz (App. A) -----------------------------------------------------------------------
    def hertz(self, r_x, r_y):
        """Load-deflection constant K (A.1) with the fits A.2-A.5, and dK/dR_x."""
        ratio = r_y / r_x
        k_bar = 1.0339 * ratio ** 0.6360
        e_bar = 1.0003 + 0.5968 / ratio
        f_bar = 1.5277 + 0.6023 * np.log(ratio)
        r_bar = r_x * r_y / (r_x + r_y)
        K = np.pi * self.e_eff * k_bar * np.sqrt(r_bar * e_bar / (4.5 * f_bar ** 3))
        # logarithmic derivative: d ln K = d ln k_bar + (d ln r_bar + d ln e_bar - 3 d ln f_bar)/2
        dlnk_dratio = 0.6360 / ratio - 0.5 * 0.5968 / (ratio ** 2 * e_bar) \
            - 1.5 * 0.6023 / (ratio * f_bar)
        dlnrbar_drx = r_y / (r_x * (r_x + r_y))
        dK_drx = K * (dlnk_dratio * (-ratio / r_x) + 0.5 * dlnrbar_drx)
        return K, dK_drx

    # --- race-control kinematics (App. B) -----------------------------------------------------
    def kinematics(self, ci, si, co, so, inner):
        """omega_m, M_g (with d/dalpha_i, d/dalpha_o), omega_b for outer/inner race control.

        ``inner`` is a boolean array; both hypotheses are evaluated and selected per ball.
        """
        w, g = self.omega, self.gamma
        cmg = self.i_b * w * w / g
        cd = ci * co + si * so                  # cos(alpha_i - alpha_o)
        sd = si * co - ci * so                  # sin(alpha_i - alpha_o)
        den = 1.0 + cd                          # d(den)/dalpha_i = -sd, d/dalpha_o = +sd
        # outer-race control (B.6-B.8)
        a = 1.0 - g * ci                        # da/dalpha_i = g si
        wm_out = w * a / den
        dwm_out_i = w * (g * si / den + a * sd / den ** 2)
        dwm_out_o = -w * a * sd / den ** 2
        mg_out = -cmg * a ** 2 * so / den ** 2
        dmg_out_i = -cmg * (2 * a * g * si * so / den ** 2 + 2 * a ** 2 * so * sd / den ** 3)
        dmg_out_o = -cmg * (a ** 2 * co / den ** 2 - 2 * a ** 2 * so * sd / den ** 3)
        wb_out = -w * np.sqrt(1.0 + 2.0 * g * co + g * g) * a / (g * den)
        # inner-race control (B.2-B.4)
        num = cd - g * co                       # dnum/dalpha_i = -sd, dnum/dalpha_o = sd + g so
        wm_in = w * num / den
        dwm_in_i = w * (-sd / den + num * sd / den ** 2)
        dwm_in_o = w * ((sd + g * so) / den - num * sd / den ** 2)
        b = 1.0 + g * co                        # db/dalpha_o = -g so
        prod = b * num
        dprod_i = -b * sd
        dprod_o = -g * so * num + b * (sd + g * so)
        mg_in = -cmg * prod * si / den ** 2
        dmg_in_i = -cmg * (dprod_i * si / den ** 2 + prod * ci / den ** 2
                           + 2 * prod * si * sd / den ** 3)
        dmg_in_o = -cmg * (dprod_o * si / den ** 2 - 2 * prod * si * sd / den ** 3)
        wb_in = -w * np.sqrt(1.0 - 2.0 * g * ci + g * g) * b / (g * den)
        pick = lambda x_in, x_out: np.where(inner, x_in, x_out)  # noqa: E731
        return (pick(wm_in, wm_out), pick(dwm_in_i, dwm_out_i), pick(dwm_in_o, dwm_out_o),
                pick(mg_in, mg_out), pick(dmg_in_i, dmg_out_i), pick(dmg_in_o, dmg_out_o),
                pick(wb_in, wb_out))

    # --- one ball: residual of eq 28 and Jacobian (eq 31, App. C) ------------------------------
    def ball_residual(self, v, u, dist_i, dist_o, inner):
        """Residual g (M, 2) and Jacobian J (M, 2, 2), J[:, a, b] = dg_a/dv_b, for M balls.

        ``v`` (M, 2) ball displacement, ``u`` (M, 2) inner-groove-centre displacement (u_r, u_z),
        ``dist_i``/``dist_o`` unloaded centre distances r - (D_b + h)/2 - w.
        Returns (g, J, contact dict).
        """
        c0, s0 = math.cos(self.alpha0), math.sin(self.alpha0)
        # contact geometry, eqs 18-21: vectors between ball centre and groove centres
        d_i = np.stack([self.L_i * c0 + u[:, 0] - v[:, 0], self.L_i * s0 + u[:, 1] - v[:, 1]], 1)
        d_o = np.stack([self.L_o * c0 + v[:, 0], self.L_o * s0 + v[:, 1]], 1)
        l_i = np.sqrt(d_i[:, 0] ** 2 + d_i[:, 1] ** 2)
        l_o = np.sqrt(d_o[:, 0] ** 2 + d_o[:, 1] ** 2)
        n_i = d_i / l_i[:, None]                 # (cos a_i, sin a_i)
        n_o = d_o / l_o[:, None]                 # (cos a_o, sin a_o)
        ci, si = n_i[:, 0], n_i[:, 1]
        co, so = n_o[:, 0], n_o[:, 1]
        delta_i = l_i - dist_i                   # eqs 22-23
        delta_o = l_o - dist_o
        # gradients w.r.t. v = (v_r, v_z) (C.5, C.6): the inner vector moves with -v, outer with +v
        t_i = np.stack([-si, ci], 1)             # d n_i / d alpha_i
        t_o = np.stack([-so, co], 1)
        grad_ai = -t_i / l_i[:, None]            # d alpha_i / dv
        grad_ao = t_o / l_o[:, None]             # d alpha_o / dv
        grad_li = -n_i                           # d l_i / dv
        grad_lo = n_o
        # Hertz loads (eqs 24-27); R_x depends on the contact angle (A.6, A.7)
        db, dp = self.db, self.dp
        rx_i = db * (dp - db * ci) / (2.0 * dp)
        rx_o = db * (dp + db * co) / (2.0 * dp)
        drx_i = db * db * si / (2.0 * dp)        # dR_x/dalpha
        drx_o = -db * db * so / (2.0 * dp)
        K_i, dK_i = self.hertz(rx_i, self.ry_i)
        K_o, dK_o = self.hertz(rx_o, self.ry_o)
        in_i = delta_i > 0.0
        in_o = delta_o > 0.0
        dpos_i = np.where(in_i, delta_i, 0.0)
        dpos_o = np.where(in_o, delta_o, 0.0)
        q_i = K_i * dpos_i ** 1.5
        q_o = K_o * dpos_o ** 1.5
        grad_qi = ((dpos_i ** 1.5 * dK_i * drx_i)[:, None] * grad_ai
                   + (1.5 * K_i * np.sqrt(dpos_i))[:, None] * grad_li)
        grad_qo = ((dpos_o ** 1.5 * dK_o * drx_o)[:, None] * grad_ao
                   + (1.5 * K_o * np.sqrt(dpos_o))[:, None] * grad_lo)
        # race control (App. B) and the friction multipliers of eq 28: lambda_i = 0, lambda_o = 2
        # (outer control) or 1, 1 (inner control), times a contact factor that fades the friction
        # out smoothly as a contact is lost
        wm, dwm_i, dwm_o, mg, dmg_i, dmg_o, wb = self.kinematics(ci, si, co, so, inner)
        s_i, ds_i = contact_factor(delta_i)
        s_o, ds_o = contact_factor(delta_o)
        lam_i = np.where(inner, s_i, 0.0)
        lam_o = np.where(inner, 1.0, 2.0) * s_o
        grad_lam_i = np.where(inner, ds_i, 0.0)[:, None] * grad_li
        grad_lam_o = (np.where(inner, 1.0, 2.0) * ds_o)[:, None] * grad_lo
        grad_wm = dwm_i[:, None] * grad_ai + dwm_o[:, None] * grad_ao
        grad_mg = dmg_i[:, None] * grad_ai + dmg_o[:, None] * grad_ao
        # centrifugal force (eq 29) at orbit radius D_p/2 + v_r
        rad = dp + 2.0 * v[:, 0]
        fe = 0.5 * self.m_b * rad * wm ** 2
        grad_fe = (self.m_b * wm * rad)[:, None] * grad_wm
        grad_fe[:, 0] += self.m_b * wm ** 2
        # eq 28: g = Q_i n_i - Q_o n_o - (M_g/D_b) (lam_i t_i - lam_o t_o) + F_e e_r
        fric = lam_i[:, None] * t_i - lam_o[:, None] * t_o          # (M, 2)
        g = q_i[:, None] * n_i - q_o[:, None] * n_o - (mg / db)[:, None] * fric
        g[:, 0] += fe
        # Jacobian J[:, a, b] = dg_a/dv_b by the product rule (d n/dalpha = t, d t/dalpha = -n);
        # outer(a, b) is the per-ball outer product a_i b_j
        outer = lambda a, b: a[:, :, None] * b[:, None, :]  # noqa: E731
        d_fric = (-outer(lam_i[:, None] * n_i, grad_ai) + outer(lam_o[:, None] * n_o, grad_ao)
                  + outer(t_i, grad_lam_i) - outer(t_o, grad_lam_o))
        J = (outer(n_i, grad_qi) + outer(q_i[:, None] * t_i, grad_ai)
             - outer(n_o, grad_qo) - outer(q_o[:, None] * t_o, grad_ao)
             - outer(fric, grad_mg) / db - (mg / db)[:, None, None] * d_fric)
        J[:, 0, :] += grad_fe
        contact = dict(q_i=q_i, q_o=q_o, cos_ai=ci, sin_ai=si, cos_ao=co, sin_ao=so, omega_m=wm,
                       omega_b=wb, m_g=mg, delta_i=delta_i, delta_o=delta_o, lam_i=lam_i, K_o=K_o,
                       fe=fe, grad_qi=grad_qi, grad_qo=grad_qo, grad_ai=grad_ai, grad_ao=grad_ao,
                       grad_wm=grad_wm, grad_mg=grad_mg, grad_lam_i=grad_lam_i)
        return g, J, contact

    # --- Newton-Raphson for all balls (eq 31) -------------------------------------------------
    def arc_point(self, l_o, cos_ao, sin_ao, d_alpha):
        """Ball displacement v (M, 2) at distance ``l_o`` from the outer-groove centre and angle
        alpha_o + d_alpha (eq 19 solved for v)."""
        c, s = np.cos(d_alpha), np.sin(d_alpha)
        return np.stack([l_o * (cos_ao * c - sin_ao * s) - self.L_o * math.cos(self.alpha0),
                         l_o * (sin_ao * c + cos_ao * s) - self.L_o * math.sin(self.alpha0)], 1)

    def solve_balls(self, idx, balls: BallState, u, dist_i, dist_o):
        """Solve the balls ``idx`` (index array) in place, warm-started from ``balls.v[idx]``.

        Each ball iterates independently; balls that are done drop out of the active set.
        Returns the per-ball status array (len(idx)).
        """
        max_step = 0.1 * (self.L_o + 1e-9)
        m = idx.size
        status = np.full(m, NOT_CONVERGED)
        # last accepted point, in polar coordinates about the outer-groove centre, and the step
        # (dl_o, dalpha_o) taken from it (halved when backtracking)
        prev_norm = np.full(m, np.inf)
        prev_l = np.zeros(m)
        prev_c = np.ones(m)
        prev_s = np.zeros(m)
        step_l = np.zeros(m)
        step_a = np.zeros(m)
        halvings = np.zeros(m, dtype=int)
        active = np.arange(m)                   # positions in idx still iterating
        for _ in range(self.nt_maxit + 1):
            if active.size == 0:
                break
            j = idx[active]
            g, J, con = self.ball_residual(balls.v[j], u[j], dist_i[j], dist_o[j],
                                           balls.inner_control[j])
            self.counters["ball_residuals"] += active.size
            self.counters["newton_passes"] += 1
            for name in BallState._FIELDS:
                getattr(balls, name)[j] = con[name]
            # no outer contact: a ball pushed outwards (centrifugal force + inner load) is put
            # against the outer race, where the Hertz load balances that push; a ball touching
            # neither race at rest is done and carries nothing
            no_outer = con["delta_o"] <= 0.0
            push = con["fe"] + con["q_i"]
            throw = no_outer & (push > 0.0)
            if throw.any():
                k = active[throw]
                reach = dist_o[j[throw]] + (push[throw] / con["K_o"][throw]) ** (2.0 / 3.0)
                balls.v[j[throw]] = self.arc_point(reach, con["cos_ao"][throw],
                                                   con["sin_ao"][throw], 0.0)
                prev_norm[k] = np.inf
            at_rest = no_outer & ~throw & (con["delta_i"] <= 0.0)
            status[active[at_rest]] = OK
            # backtracking: the residual grew, so go back and try half of the last step
            norm = np.abs(g).max(axis=1)
            rest = ~throw & ~at_rest
            back = rest & (norm > prev_norm[active]) & (halvings[active] < MAX_HALVINGS)
            if back.any():
                k = active[back]
                halvings[k] += 1
                step_l[k] *= 0.5
                step_a[k] *= 0.5
                balls.v[j[back]] = self.arc_point(prev_l[k] + step_l[k], prev_c[k], prev_s[k],
                                                  step_a[k])
            # Newton step for the others, in (l_o, alpha_o): J_p = J [dv/dl_o, dv/dalpha_o]
            newton = rest & ~back
            halvings[active[newton]] = 0
            l_o = con["delta_o"] + dist_o[j]
            co, so = con["cos_ao"], con["sin_ao"]
            dv_dpolar = np.stack([np.stack([co, so], 1),
                                  l_o[:, None] * np.stack([-so, co], 1)], 2)  # (M, 2, 2)
            Jp = J @ dv_dpolar
            det = Jp[:, 0, 0] * Jp[:, 1, 1] - Jp[:, 0, 1] * Jp[:, 1, 0]
            singular = newton & ~((det != 0.0) & np.isfinite(det))
            status[active[singular]] = SINGULAR
            newton &= ~singular
            with np.errstate(divide="ignore", invalid="ignore"):
                dl = -(Jp[:, 1, 1] * g[:, 0] - Jp[:, 0, 1] * g[:, 1]) / det
                da = -(-Jp[:, 1, 0] * g[:, 0] + Jp[:, 0, 0] * g[:, 1]) / det
            size = np.maximum(np.abs(dl), np.abs(l_o * da))
            # the package's stopping rule (ball.solve_ball): the step below newton_tol_m, or in
            # the quadratic regime the error estimate step^2 / d_min below newmark_tol_m
            d_i, d_o = con["delta_i"], con["delta_o"]
            d_min = np.where(d_i > 0.0, np.minimum(d_o, d_i), np.where(-d_i <= 2.0 * size, 0.0, d_o))
            quadratic = (d_min > QUADRATIC_REGIME_M) & (size * size < self.nm_tol * d_min)
            converged = newton & ((size < self.nt_tol) | quadratic)
            status[active[converged]] = OK
            if converged.any():
                self._take_last_step(balls, j[converged], dl[converged], da[converged],
                                     l_o[converged],
                                     {key: val[converged] for key, val in con.items()})
            move = newton & ~converged
            if move.any():
                k = active[move]
                shrink = np.where(size[move] > max_step, max_step / size[move], 1.0)
                step_l[k] = dl[move] * shrink
                step_a[k] = da[move] * shrink
                prev_norm[k] = norm[move]
                prev_l[k], prev_c[k], prev_s[k] = l_o[move], co[move], so[move]
                balls.v[j[move]] = self.arc_point(l_o[move] + step_l[k], co[move], so[move],
                                                  step_a[k])
            active = active[move | throw | back]
        return status

    @staticmethod
    def _take_last_step(balls: BallState, j, dl, da, l_o, con):
        """Converged balls: take the last (sub-tolerance) Newton step (dl_o, dalpha_o) to first
        order and move the contact state to the new point with the derivatives of the last
        evaluation instead of evaluating the model again (in the quadratic regime the error
        left is ~step^2 / delta). omega_b is not moved."""
        co, so = con["cos_ao"], con["sin_ao"]
        dv = np.stack([dl * co - l_o * da * so, dl * so + l_o * da * co], 1)
        balls.v[j] += dv
        along = lambda grad: np.sum(grad * dv, axis=1)  # noqa: E731  (directional derivative)
        balls.q_i[j] = np.maximum(con["q_i"] + along(con["grad_qi"]), 0.0)
        balls.q_o[j] = np.maximum(con["q_o"] + along(con["grad_qo"]), 0.0)
        da_i = along(con["grad_ai"])
        ci, si = con["cos_ai"] - con["sin_ai"] * da_i, con["sin_ai"] + con["cos_ai"] * da_i
        balls.cos_ai[j], balls.sin_ai[j] = ci, si
        balls.cos_ao[j], balls.sin_ao[j] = co - so * da, so + co * da
        balls.omega_m[j] = con["omega_m"] + along(con["grad_wm"])
        balls.m_g[j] = con["m_g"] + along(con["grad_mg"])
        balls.lam_i[j] = con["lam_i"] + along(con["grad_lam_i"])
        balls.delta_i[j] = con["delta_i"] - (ci * dv[:, 0] + si * dv[:, 1])
        balls.delta_o[j] = con["delta_o"] + dl

    # --- bearing force (eqs 3-6, 32-33) -------------------------------------------------------
    def bearing_force(self, U, cage_angle, shaft_angle, psi_b, balls: BallState):
        """Force and moments (F_x, F_y, F_z, M_x, M_y) of the balls on the inner race.

        ``balls`` supplies the warm start and receives the solution. Returns (F, status) with
        status the worst ball status (0 = all converged)."""
        self.counters["force_evals"] += 1
        n = self.n
        phi = 2.0 * np.pi * np.arange(n) / n + cage_angle + self.phi0       # eq 6
        c, s = np.cos(phi), np.sin(phi)
        p_i, q_i, p_o, q_o, w_i, w_o = self.waviness(phi, shaft_angle, psi_b)
        zp = self.z_p + q_i
        rp = self.r_p + p_i
        # eqs 3-5: displacement of the inner-groove centre in the ball's (r, z) plane
        u = np.stack([U[0] * c + U[1] * s + zp * (U[4] * c - U[3] * s) + (p_i - p_o),
                      U[2] + rp * (U[3] * s - U[4] * c) + (q_i - q_o)], 1)
        size = 0.5 * self.db + 0.5 * self.ball_oversize
        dist_i = self.r_i - size - w_i
        dist_o = self.r_o - size - w_o
        if self.race_control != "auto":
            balls.inner_control[:] = self.race_control == "inner"
        all_balls = np.arange(n)
        status = self.solve_balls(all_balls, balls, u, dist_i, dist_o)
        if self.race_control == "auto":
            ok = status == OK
            want_outer = self.prefers_outer_control(balls)
            flip = np.flatnonzero(ok & (want_outer == balls.inner_control))
            if flip.size:
                balls.inner_control[flip] = ~balls.inner_control[flip]
                status[flip] = self.solve_balls(flip, balls, u, dist_i, dist_o)
        # eq 32: force and moment of each ball on the inner race (friction only under inner
        # control, faded out with the inner contact)
        fr = balls.lam_i * balls.m_g / self.db
        Q_r = -balls.q_i * balls.cos_ai - fr * balls.sin_ai
        Q_z = -balls.q_i * balls.sin_ai + fr * balls.cos_ai
        Q_phi = fr * self.r_i
        # eq 33: F = sum_j T_j^T Q_j
        F = np.array([np.sum(c * Q_r), np.sum(s * Q_r), np.sum(Q_z),
                      np.sum(s * (-zp * Q_r + rp * Q_z - Q_phi)),
                      np.sum(c * (zp * Q_r - rp * Q_z + Q_phi))])
        return F, int(status.max())

    def prefers_outer_control(self, balls: BallState):
        """Jones/Harris: outer control when Q_o a_o E_o cos(a_i - a_o) > Q_i a_i E_i."""
        db, dp = self.db, self.dp

        def semi_axis(q, r_x, r_y):
            ratio = r_y / r_x
            e_bar = 1.0003 + 0.5968 / ratio
            k_bar = 1.0339 * ratio ** 0.6360
            r_bar = r_x * r_y / (r_x + r_y)
            load = np.maximum(q, 0.0)
            return np.cbrt(6.0 * k_bar ** 2 * e_bar * load * r_bar / (np.pi * self.e_eff)), e_bar

        a_i, e_i = semi_axis(balls.q_i, db * (dp - db * balls.cos_ai) / (2 * dp), self.ry_i)
        a_o, e_o = semi_axis(balls.q_o, db * (dp + db * balls.cos_ao) / (2 * dp), self.ry_o)
        cos_d = balls.cos_ai * balls.cos_ao + balls.sin_ai * balls.sin_ao
        return balls.q_o * a_o * e_o * cos_d > balls.q_i * a_i * e_i

    # --- rotor (eq 35) and Newmark ------------------------------------------------------------
    def system_matrix(self):
        """M + gamma dt (C + G) of the implicit acceleration equation, and C + G."""
        M = np.diag([self.mass] * 3 + [self.i_r] * 2)
        G = np.zeros((5, 5))
        G[3, 4] = self.i_z * self.omega          # I_r tx'' + I_z omega ty' = M_x
        G[4, 3] = -self.i_z * self.omega         # I_r ty'' - I_z omega tx' = M_y
        CG = self.C + G
        return M + self.nm_gamma * self.dt * CG, CG

    def external_force(self, shaft_angle):
        unb = self.mass * self.ecc * self.omega ** 2
        return self.P + unb * np.array([math.cos(shaft_angle), math.sin(shaft_angle), 0, 0, 0])

    def cage_speed(self, balls: BallState, previous: float) -> float:
        """Eq 7: mean orbital speed of the balls touching the inner race (else keep coasting)."""
        touching = balls.q_i > 0.0
        return float(np.mean(balls.omega_m[touching])) if touching.any() else previous

    def newmark_step(self, st: RotorState) -> int:
        """One Newmark-beta step with fixed-point equilibrium iterations; updates ``st``."""
        dt, beta, gam = self.dt, self.beta, self.nm_gamma
        # explicit kinematics (eqs 8, 15) with the speeds of the previous step
        st.t += dt
        st.shaft_angle += self.omega * dt
        st.cage_angle += st.cage_speed * dt
        st.psi_b += st.balls.omega_b * dt
        # ball Newton warm starts: quadratic extrapolation of each ball's last three solutions
        v_now = st.balls.v.copy()
        v_prev2 = st.v_prev if st.v_prev2 is None else st.v_prev2
        st.balls.v[:] = 3.0 * v_now - 3.0 * st.v_prev + v_prev2
        st.v_prev2 = st.v_prev
        st.v_prev = v_now
        S, CG = self.system_matrix()
        v_pred = st.V + (1.0 - gam) * dt * st.A
        x_base = st.X + dt * st.V + (0.5 - beta) * dt * dt * st.A
        a_prev2 = st.A_prev if st.A_prev2 is None else st.A_prev2
        a_guess = 3.0 * st.A - 3.0 * st.A_prev + a_prev2  # predictor: quadratic in a_n, a_n-1, a_n-2
        st.A_prev2 = st.A_prev.copy()
        st.A_prev = st.A.copy()
        X_new = x_base + beta * dt * dt * a_guess
        rhs0 = self.external_force(st.shaft_angle) - CG @ v_pred
        # a-posteriori stop (Hairer & Wanner IV.8): accept when eta |dX| < tol, eta = theta/(1-theta)
        # of the observed contraction theta; the first pass uses max(eta_old, eps)^0.8
        eta = 1.0 if st.eta <= 0.0 else max(st.eta, np.finfo(float).eps) ** 0.8
        change_prev = 0.0
        for it in range(self.nm_maxit):
            self.counters["newmark_iters"] += 1
            F, status = self.bearing_force(X_new, st.cage_angle, st.shaft_angle, st.psi_b,
                                           st.balls)
            st.F = F
            if status != OK:
                return status
            a_new = np.linalg.solve(S, F + rhs0)
            x_next = x_base + beta * dt * dt * a_new
            change = np.max(np.abs(x_next - X_new) * self.dof_scale)
            X_new = x_next
            if it > 0 and change_prev > 0.0:
                theta = min(change / change_prev, 0.99)
                eta = theta / (1.0 - theta)
            change_prev = change
            if eta * change < self.nm_tol:
                st.eta = eta
                break
        else:
            return NEWMARK_NOT_CONVERGED
        st.X = X_new
        st.A = a_new
        st.V = v_pred + gam * dt * a_new
        if not (np.all(np.isfinite(st.X)) and np.all(np.isfinite(st.V))) \
                or np.any(np.abs(st.X) * self.dof_scale > self.div_limit):
            return DIVERGED
        st.cage_speed = self.cage_speed(st.balls, st.cage_speed)
        self.counters["steps"] += 1
        return OK

    def advance(self, st: RotorState, n_steps: int, record: bool = False):
        """Run ``n_steps`` Newmark steps. Returns (status, steps_done, X history or None)."""
        hist = np.empty((n_steps, 5)) if record else None
        for k in range(n_steps):
            status = self.newmark_step(st)
            if status != OK:
                return status, k, (hist[:k] if record else None)
            if record:
                hist[k] = st.X
        return OK, n_steps, hist

    def reset_counters(self):
        self.counters = dict(force_evals=0, ball_residuals=0, newton_passes=0, newmark_iters=0,
                             steps=0)


def contact_factor(delta):
    """Smooth 0 -> 1 contact factor of the race-control friction and its derivative in delta:
    smoothstep x^2 (3 - 2x) of x = delta / FRICTION_ONSET_M clipped to [0, 1]."""
    x = np.clip(delta / FRICTION_ONSET_M, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x), 6.0 * x * (1.0 - x) / FRICTION_ONSET_M


# ---------------------------------------------------------------------------------------------
# conversion from / to the package's state arrays (uses the package's column layout)
# ---------------------------------------------------------------------------------------------
_BALL_COLUMNS = dict(q_i="B_QI", q_o="B_QO", cos_ai="B_CI", sin_ai="B_SI", cos_ao="B_CO",
                     sin_ao="B_SO", omega_m="B_WM", omega_b="B_WB", m_g="B_MG", delta_i="B_DI",
                     delta_o="B_DO", lam_i="B_LAMI")


def ball_state_from_arrays(ball_v: np.ndarray, ball_out: np.ndarray) -> BallState:
    """BallState from the package's ``ball_v`` (N, 2) and ``ball_out`` (N, N_BALL_OUT)."""
    from bearing_gym.physics import ball as B
    return BallState(np.array(ball_v, float), ball_out[:, B.B_CTRL] > 0.5,
                     **{k: ball_out[:, getattr(B, c)].copy() for k, c in _BALL_COLUMNS.items()})


def state_from_simulator(s) -> RotorState:
    """RotorState from a :class:`bearing_gym.physics.SimulatorState`."""
    from bearing_gym.physics import ball as B
    from bearing_gym.physics import rotor as R
    return RotorState(s.X.copy(), s.V.copy(), s.A.copy(), float(s.scal[R.S_T]),
                      float(s.scal[R.S_SHAFT]), float(s.scal[R.S_CAGE]),
                      float(s.scal[R.S_CAGE_SPEED]), s.psi_b.copy(),
                      ball_state_from_arrays(s.ball_v, s.ball_out),
                      s.scal[R.S_A_PREV:R.S_A_PREV + 5].copy(),
                      s.ball_out[:, [B.B_VR_PREV, B.B_VZ_PREV]].copy(),
                      A_prev2=s.scal[R.S_A_PREV2:R.S_A_PREV2 + 5].copy(),
                      v_prev2=s.ball_out[:, [B.B_VR_PREV2, B.B_VZ_PREV2]].copy(),
                      eta=float(s.scal[R.S_ETA]))


def state_to_simulator(st: RotorState, like):
    """SimulatorState (shaped like ``like``) holding the RotorState ``st``."""
    from bearing_gym.physics import ball as B
    from bearing_gym.physics import rotor as R
    out = like.copy()
    out.X[:], out.V[:], out.A[:] = st.X, st.V, st.A
    out.scal[R.S_T], out.scal[R.S_SHAFT] = st.t, st.shaft_angle
    out.scal[R.S_CAGE], out.scal[R.S_CAGE_SPEED] = st.cage_angle, st.cage_speed
    out.psi_b[:] = st.psi_b
    out.scal[R.S_A_PREV:R.S_A_PREV + 5] = st.A_prev
    out.scal[R.S_A_PREV2:R.S_A_PREV2 + 5] = st.A_prev if st.A_prev2 is None else st.A_prev2
    out.scal[R.S_ETA] = st.eta
    out.ball_v[:] = st.balls.v
    out.ball_out[:, B.B_VR_PREV] = st.v_prev[:, 0]
    out.ball_out[:, B.B_VZ_PREV] = st.v_prev[:, 1]
    v_prev2 = st.v_prev if st.v_prev2 is None else st.v_prev2
    out.ball_out[:, B.B_VR_PREV2] = v_prev2[:, 0]
    out.ball_out[:, B.B_VZ_PREV2] = v_prev2[:, 1]
    for name, col in _BALL_COLUMNS.items():
        out.ball_out[:, getattr(B, col)] = getattr(st.balls, name)
    out.ball_out[:, B.B_CTRL] = st.balls.inner_control.astype(float)
    return out
