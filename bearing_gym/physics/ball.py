"""Quasi-static equilibrium of one ball (paper eqs 16-31) by Newton-Raphson (eq 31) with the
analytic Jacobian of App. C (C.1-C.33, with the C.16/C.18 errata corrected).

Conventions (paper Fig. 3, eqs 18-21): in the ball's (r, z) plane the inner-groove curvature
centre lies on the contact line *outside* the ball centre and the outer-groove centre *inside*
it. With ``u`` the displacement of the inner-groove centre and ``v`` that of the ball centre,

    inner: (L_i cos a0 + u_r - v_r, L_i sin a0 + u_z - v_z) = l_i (cos a_i, sin a_i)   (18, 20)
    outer: (L_o cos a0 + v_r,       L_o sin a0 + v_z)       = l_o (cos a_o, sin a_o)   (19, 21)

where L_i, L_o are the *nominal* distances of eqs 16-17 (ring geometry). The deflections are
delta = l - (r - (D_b + h_j)/2 - w_j) (eqs 16-17 and 22-23: the per-ball oversize h_j and ball
waviness w_j enter here; a gap of c at each contact at U = 0).

Loss of contact (delta <= 0) gives zero Hertz force at that race (eqs 24-27) and, because a
race out of contact cannot carry friction, zero race-control friction there too: the lambda of
eq 28 is multiplied by a contact factor that rises smoothly from 0 at delta = 0 to 1 at
delta = ``FRICTION_ONSET_M`` (0.1 um, about 1 % of a working deflection; under
outer-race control at speed the outer contacts sit far above it). A hard on/off factor
would make g jump by lambda M_g / D_b (hundreds of newtons under inner-race control at speed)
and leave Newton cycling around a contact that has no equilibrium on either side. A ball with
no contact at either race is moved against the outer race, where at speed its centrifugal force
holds it (likewise a ball touching only the inner race at speed is first moved out against the
outer race before Newton goes on); at zero speed it is left where it is, carrying no load.
"""

from __future__ import annotations

import math

from numba import njit

from .hertz import contact_semi_major_axis, hertz_constant_poly
from .kinematics import race_control_kinematics
from .layout import (I_COSA0, I_DB, I_DP, I_EEFF, I_GAM, I_IB, I_KI, I_KO, I_LI0, I_LO0, I_MB,
                     I_NM_TOL, I_NT_MAXIT, I_NT_TOL, I_RYI, I_RYO, I_SINA0)
from .portable_math import pow, sincos

BALL_OK = 0
BALL_NOT_CONVERGED = 1
BALL_SINGULAR = 2

# columns of the per-ball output array ``ball_out``
B_QI = 0      # inner contact load Q_i (N)
B_QO = 1      # outer contact load Q_o (N)
B_CI = 2      # cos(alpha_i)
B_SI = 3      # sin(alpha_i)
B_CO = 4      # cos(alpha_o)
B_SO = 5      # sin(alpha_o)
B_WM = 6      # orbital speed omega_m (rad/s)
B_WB = 7      # spin speed omega_b (rad/s)
B_MG = 8      # gyroscopic moment M_g (N m)
B_CTRL = 9    # race control used: 0 outer, 1 inner
B_DI = 10     # inner deflection delta_i (m, negative = gap)
B_DO = 11     # outer deflection delta_o (m)
B_LAMI = 12   # effective race-control factor lambda_i of eq 32 (friction on the inner race)
B_NITER = 13  # Newton iterations used, accumulated over solves (diagnostics; reset by the caller)
B_VR_PREV = 14  # v_r at the previous time step (warm-start extrapolation in rotor.integrate)
B_VZ_PREV = 15  # v_z at the previous time step
B_VR_PREV2 = 16  # v_r two time steps back (the warm start is extrapolated quadratically)
B_VZ_PREV2 = 17  # v_z two time steps back
N_BALL_OUT = 18

FRICTION_ONSET_M = 1.0e-7
ARC_SERIES_RAD = 1.0e-2    # |d_alpha| below which _arc_point takes sine and cosine from their series
_SIN3, _SIN5, _SIN7 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0
_COS2, _COS4, _COS6, _COS8 = -0.5, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0
#: Smallest loaded deflection (m) at which the Newton iteration counts on its quadratic
#: convergence to estimate its error (:func:`solve_ball`): twice the friction's onset, above
#: which the contact factor is 1 and only the Hertz law bends the residual.
QUADRATIC_REGIME_M = 2.0 * FRICTION_ONSET_M


@njit(cache=True, inline="always")
def contact_factor(delta):
    """Smooth 0 -> 1 contact indicator for the race-control friction and its derivative."""
    if delta <= 0.0:
        return 0.0, 0.0
    if delta >= FRICTION_ONSET_M:
        return 1.0, 0.0
    x = delta / FRICTION_ONSET_M
    return x * x * (3.0 - 2.0 * x), 6.0 * x * (1.0 - x) / FRICTION_ONSET_M


@njit(cache=True, inline="always")
def _dg(dai, dao, dqi, dqo, dmg, dfe, dlam_i, dlam_o, qi, qo, ci, si, co, so, lam_i, lam_o, mg,
        inv_db):
    """Derivative of (g_r, g_z) (eq 28) along one ball coordinate (C.1-C.4); ``inv_db`` = 1/D_b."""
    dci = -si * dai
    dsi = ci * dai
    dco = -so * dao
    dso = co * dao
    mgd = mg * inv_db
    dmgd = dmg * inv_db
    dgr = (dqi * ci + qi * dci - dqo * co - qo * dco
           + (lam_i * si - lam_o * so) * dmgd + mgd * (lam_i * dsi - lam_o * dso)
           + (dlam_i * si - dlam_o * so) * mgd + dfe)
    dgz = (dqi * si + qi * dsi - dqo * so - qo * dso
           - (lam_i * ci - lam_o * co) * dmgd - mgd * (lam_i * dci - lam_o * dco)
           - (dlam_i * ci - dlam_o * co) * mgd)
    return dgr, dgz


@njit(cache=True, inline="always")
def ball_residual(vr, vz, ur, uz, dist_i, dist_o, omega, inner_control, prm):
    """Residual g = (g_r, g_z) of eq 28 and its Jacobian (eq 31, App. C) at ball displacement v.

    Returns (g_r, g_z, J_rr, J_rz, J_zr, J_zz, Q_i, Q_o, ci, si, co, so, omega_m, omega_b,
    M_g, delta_i, delta_o, K_o, lambda_i); see :func:`ball_model` for the derivatives too.
    """
    r = ball_model(vr, vz, ur, uz, dist_i, dist_o, omega, inner_control, prm)
    return (r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12],
            r[13], r[14], r[15], r[16], r[17], r[18])


@njit(cache=True, inline="always")
def hertz_load(delta, k, dk_dalpha):
    """Hertz contact load Q = K delta^1.5 (eqs 24-25) of a deflection ``delta`` (0 without
    contact), with dQ/d(alpha) = delta^1.5 dK/d(alpha) and dQ/d(delta) = 1.5 K delta^0.5
    (App. C); delta^1.5 as delta sqrt(delta), with IEEE operations only."""
    if delta > 0.0:
        sq = math.sqrt(delta)
        return k * delta * sq, delta * sq * dk_dalpha, 1.5 * k * sq
    return 0.0, 0.0, 0.0


@njit(cache=True, inline="always")
def ball_model(vr, vz, ur, uz, dist_i, dist_o, omega, inner_control, prm):
    """Eqs 18-30 for one ball at displacement v: residual of eq 28, its Jacobian (App. C) and
    the contact state with its derivatives along (v_r, v_z).

    ``dist_i``, ``dist_o`` are the unloaded centre distances r - (D_b + h_j)/2 - w_j.
    Returns (g_r, g_z, J_rr, J_rz, J_zr, J_zz, Q_i, Q_o, ci, si, co, so, omega_m, omega_b,
    M_g, delta_i, delta_o, K_o, lambda_i,                                   # 0-18
    dQ_i/dv (2), dQ_o/dv (2), dalpha_i/dv (2), dalpha_o/dv (2), domega_m/dv (2), dM_g/dv (2),
    dlambda_i/dv (2)).                                                       # 19-32
    """
    db = prm[I_DB]
    dp = prm[I_DP]
    ai_ = prm[I_LI0] * prm[I_COSA0] + ur - vr
    bi_ = prm[I_LI0] * prm[I_SINA0] + uz - vz
    ao_ = prm[I_LO0] * prm[I_COSA0] + vr
    bo_ = prm[I_LO0] * prm[I_SINA0] + vz
    li = math.sqrt(ai_ * ai_ + bi_ * bi_)                     # eq 20
    lo = math.sqrt(ao_ * ao_ + bo_ * bo_)                     # eq 21
    inv_li = 1.0 / li              # reciprocals once: the divisions below become multiplications
    inv_lo = 1.0 / lo
    inv_db = 1.0 / db
    ci = ai_ * inv_li
    si = bi_ * inv_li                                         # eq 18
    co = ao_ * inv_lo
    so = bo_ * inv_lo                                         # eq 19
    di = li - dist_i                                          # eq 22
    do = lo - dist_o                                          # eq 23
    # Hertz (eqs 24-27, App. A): K(cos alpha) of each race from its polynomial (hertz.py), and
    # dK/d(alpha) = -sin(alpha) dK/d(cos alpha) (C.11-C.18)
    ki, dki_dc = hertz_constant_poly(prm, I_KI, ci)
    ko, dko_dc = hertz_constant_poly(prm, I_KO, co)
    # derivatives of the angles and distances w.r.t. (v_r, v_z) (C.5, C.6)
    dai_r = si * inv_li
    dai_z = -ci * inv_li
    dao_r = -so * inv_lo
    dao_z = co * inv_lo
    qi, dqi_da, dqi_dl = hertz_load(di, ki, -si * dki_dc)
    qo, dqo_da, dqo_dl = hertz_load(do, ko, -so * dko_dc)
    dqi_r = dqi_da * dai_r - dqi_dl * ci                      # C.7
    dqi_z = dqi_da * dai_z - dqi_dl * si                      # C.9
    dqo_r = dqo_da * dao_r + dqo_dl * co                      # C.8
    dqo_z = dqo_da * dao_z + dqo_dl * so                      # C.10
    # race control (App. B), eqs 29-30
    wm, dwm_i, dwm_o, mg, dmg_i, dmg_o, wb = race_control_kinematics(
        ci, si, co, so, omega, prm[I_GAM], prm[I_IB], inner_control)
    s_i, ds_i = contact_factor(di)
    s_o, ds_o = contact_factor(do)
    if inner_control:
        lam_i = s_i
        lam_o = s_o
        dlam_i = ds_i
        dlam_o = ds_o
    else:
        lam_i = 0.0
        lam_o = 2.0 * s_o
        dlam_i = 0.0
        dlam_o = 2.0 * ds_o
    # d(lambda)/dv through the deflections: d delta_i/dv = -(ci, si), d delta_o/dv = (co, so)
    dlam_i_r = -dlam_i * ci
    dlam_i_z = -dlam_i * si
    dlam_o_r = dlam_o * co
    dlam_o_z = dlam_o * so
    mb = prm[I_MB]
    rad = dp + 2.0 * vr
    fe = 0.5 * rad * mb * wm * wm                             # eq 29
    dwm_r = dwm_i * dai_r + dwm_o * dao_r
    dwm_z = dwm_i * dai_z + dwm_o * dao_z
    dfe_r = mb * wm * (rad * dwm_r + wm)                      # C.19
    dfe_z = mb * wm * rad * dwm_z                             # C.20
    dmg_r = dmg_i * dai_r + dmg_o * dao_r                     # C.21
    dmg_z = dmg_i * dai_z + dmg_o * dao_z
    mgd = mg * inv_db
    gr = qi * ci - qo * co + (lam_i * si - lam_o * so) * mgd + fe          # eq 28
    gz = qi * si - qo * so - (lam_i * ci - lam_o * co) * mgd
    jrr, jzr = _dg(dai_r, dao_r, dqi_r, dqo_r, dmg_r, dfe_r, dlam_i_r, dlam_o_r, qi, qo, ci, si,
                   co, so, lam_i, lam_o, mg, inv_db)
    jrz, jzz = _dg(dai_z, dao_z, dqi_z, dqo_z, dmg_z, dfe_z, dlam_i_z, dlam_o_z, qi, qo, ci, si,
                   co, so, lam_i, lam_o, mg, inv_db)
    return (gr, gz, jrr, jrz, jzr, jzz, qi, qo, ci, si, co, so, wm, wb, mg, di, do, ko, lam_i,
            dqi_r, dqi_z, dqo_r, dqo_z, dai_r, dai_z, dao_r, dao_z, dwm_r, dwm_z, dmg_r, dmg_z,
            dlam_i_r, dlam_i_z)


@njit(cache=True, inline="always")
def prefers_outer_control(qi, qo, ci, si, co, so, prm):
    """Jones/Harris race-control criterion: outer-race control when
    Q_o a_o E(k_o) cos(alpha_i - alpha_o) > Q_i a_i E(k_i) (spin-friction torques)."""
    db = prm[I_DB]
    dp = prm[I_DP]
    rxi = db * (dp - db * ci) / (2.0 * dp)
    rxo = db * (dp + db * co) / (2.0 * dp)
    a_i, e_i = contact_semi_major_axis(qi, rxi, prm[I_RYI], prm[I_EEFF])
    a_o, e_o = contact_semi_major_axis(qo, rxo, prm[I_RYO], prm[I_EEFF])
    return qo * a_o * e_o * (ci * co + si * so) > qi * a_i * e_i


@njit(cache=True, inline="always")
def _arc_point(l_o, co, so, d_alpha, prm):
    """Ball displacement v at distance ``l_o`` from the outer-groove centre, at the angle
    alpha_o + d_alpha where (co, so) = (cos, sin) alpha_o (eq 19 inverted). A Newton step's
    d_alpha is tiny: below ``ARC_SERIES_RAD`` its sine and cosine are their Taylor series to
    d^7 and d^8, exact to rounding there (the first term left out is < 1e-18 of the sum)."""
    if abs(d_alpha) < ARC_SERIES_RAD:
        d2 = d_alpha * d_alpha
        s = d_alpha * (1.0 + d2 * (_SIN3 + d2 * (_SIN5 + d2 * _SIN7)))
        c = 1.0 + d2 * (_COS2 + d2 * (_COS4 + d2 * (_COS6 + d2 * _COS8)))
    else:
        s, c = sincos(d_alpha)
    vr = l_o * (co * c - so * s) - prm[I_LO0] * prm[I_COSA0]
    vz = l_o * (so * c + co * s) - prm[I_LO0] * prm[I_SINA0]
    return vr, vz


@njit(cache=True, inline="always")
def solve_ball(vr, vz, ur, uz, dist_i, dist_o, omega, inner_control, prm, out, j):
    """Newton-Raphson (eq 31) for one ball, warm-started at (vr, vz).

    Writes the converged contact state into ``out[j, :]`` (columns ``B_*``) and returns
    (v_r, v_z, status). The step is limited to a tenth of the outer-groove free distance so a
    poor start cannot throw the ball out of the groove.

    Stopping rule: the iteration stops when its next step |dv| is below ``newton_tol_m``, or,
    once the loaded contacts' deflections exceed ``QUADRATIC_REGIME_M`` (and an open contact's
    gap is more than twice the step, so the step cannot close it), when the error left after
    that step, estimated as |dv|^2 / d_min with d_min the smaller loaded deflection, is below
    the rotor's ``newmark_tol_m`` (a ball need not be solved more finely than the rotor's
    equilibrium iteration it feeds). It takes that last step (to first order, without another
    evaluation). Newton's error after a step is (|g''| / 2 |g'|) |dv|^2, and for the Hertz load
    Q = K delta^1.5 (eq 24) Q'' / (2 Q') = 1 / (4 delta), so |dv|^2 / d_min bounds it with a
    margin of 4 (the friction's contact factor and the kinematics vary on longer scales there).
    """
    tol = prm[I_NT_TOL]
    error_tol = prm[I_NM_TOL]
    maxit = int(prm[I_NT_MAXIT])
    max_step = 0.1 * (prm[I_LO0] + 1e-9)
    status = BALL_NOT_CONVERGED
    prev_norm = math.inf
    prev_lo = 0.0
    prev_co = 1.0
    prev_so = 0.0
    dl = 0.0
    da = 0.0
    halvings = 0
    for _ in range(maxit + 1):
        out[j, B_NITER] += 1.0
        (gr, gz, jrr, jrz, jzr, jzz, qi, qo, ci, si, co, so, wm, wb, mg, di, do, ko, lam_i,
         dqi_r, dqi_z, dqo_r, dqo_z, dai_r, dai_z, dao_r, dao_z, dwm_r, dwm_z, dmg_r, dmg_z,
         dlam_r, dlam_z) = ball_model(vr, vz, ur, uz, dist_i, dist_o, omega, inner_control, prm)
        if do <= 0.0:
            fe = 0.5 * (prm[I_DP] + 2.0 * vr) * prm[I_MB] * wm * wm
            if fe + qi > 0.0:
                # no outer contact at speed: nothing can hold the ball against its centrifugal
                # force (and the inner-race push), so put it against the outer race, where the
                # Hertz load balances that force, and let Newton go on from there
                target = dist_o + pow((fe + qi) / ko, 2.0 / 3.0)
                vr = target * co - prm[I_LO0] * prm[I_COSA0]
                vz = target * so - prm[I_LO0] * prm[I_SINA0]
                prev_norm = math.inf
                continue
            if di <= 0.0:
                status = BALL_OK        # unloaded ball at rest: no force, keep its position
                break
        norm = max(abs(gr), abs(gz))
        if norm > prev_norm and halvings < 30:
            # backtracking: the last Newton step made things worse; try half of it (on the arc)
            halvings += 1
            dl *= 0.5
            da *= 0.5
            vr, vz = _arc_point(prev_lo + dl, prev_co, prev_so, da, prm)
            continue
        halvings = 0
        # Newton step in polar coordinates about the outer-groove centre, (l_o, alpha_o): the
        # ball then moves along the groove arc, not along its tangent (a Cartesian step of a
        # lightly loaded ball rolling down the groove would cut into the race)
        lo = do + dist_o
        # J_p = J [d v / d l_o, d v / d alpha_o] with d v / d l = (co, so), d v / d a = l (-so, co)
        p11 = jrr * co + jrz * so
        p21 = jzr * co + jzz * so
        p12 = lo * (-jrr * so + jrz * co)
        p22 = lo * (-jzr * so + jzz * co)
        det = p11 * p22 - p12 * p21
        if not (det != 0.0 and math.isfinite(det)):
            status = BALL_SINGULAR
            break
        inv_det = 1.0 / det
        dl = -(p22 * gr - p12 * gz) * inv_det
        da = -(-p21 * gr + p11 * gz) * inv_det
        step = max(abs(dl), abs(lo * da))
        d_min = do                  # the smaller loaded deflection; 0 if a gap may close
        if di > 0.0:
            d_min = min(d_min, di)
        elif -di <= 2.0 * step:
            d_min = 0.0
        if step < tol or (d_min > QUADRATIC_REGIME_M and step * step < error_tol * d_min):
            # converged: take this last step (to first order) and move the contact state to
            # the new point instead of evaluating the model once more
            dvr = dl * co - lo * da * so
            dvz = dl * so + lo * da * co
            vr += dvr
            vz += dvz
            qi += dqi_r * dvr + dqi_z * dvz
            qo += dqo_r * dvr + dqo_z * dvz
            da_i = dai_r * dvr + dai_z * dvz
            ci, si = ci - si * da_i, si + ci * da_i
            co, so = co - so * da, so + co * da
            wm += dwm_r * dvr + dwm_z * dvz
            mg += dmg_r * dvr + dmg_z * dvz
            lam_i += dlam_r * dvr + dlam_z * dvz
            di -= ci * dvr + si * dvz
            do += dl
            if qi < 0.0:
                qi = 0.0
            if qo < 0.0:
                qo = 0.0
            status = BALL_OK
            break
        if step > max_step:
            dl *= max_step / step
            da *= max_step / step
        prev_norm = norm
        prev_lo = lo
        prev_co = co
        prev_so = so
        vr, vz = _arc_point(lo + dl, co, so, da, prm)     # exact move along the arc
    out[j, B_QI] = qi
    out[j, B_QO] = qo
    out[j, B_CI] = ci
    out[j, B_SI] = si
    out[j, B_CO] = co
    out[j, B_SO] = so
    out[j, B_WM] = wm
    out[j, B_WB] = wb
    out[j, B_MG] = mg
    out[j, B_CTRL] = 1.0 if inner_control else 0.0
    out[j, B_DI] = di
    out[j, B_DO] = do
    out[j, B_LAMI] = lam_i
    return vr, vz, status
