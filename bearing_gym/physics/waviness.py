"""Race and ball waviness (paper eqs 9-14, with the eqs 9-12 erratum corrected).

Waviness is a function of the angle measured on the ring, so the ball-spacing term is
multiplied by the order n (docs/model.md, errata): at ball j, with phi_j the ball angle of eq 6 and
theta_s the shaft angle (the inner race turns with the shaft, the outer race is fixed),

    p_ij = sum_n A_in cos(n (phi_j - theta_s) + xi_in)      q_ij = sum_n B_in cos(... + eta_in)
    p_oj = sum_n A_on cos(n phi_j + xi_on)                  q_oj = sum_n B_on cos(... + eta_on)
    w_ij = sum_n C_n cos(n psi_bj + zeta_nj)                w_oj = sum_n C_n cos(n (psi_bj + pi) + zeta_nj)

The angles change only between time steps, so :func:`bearing.ball_geometry` evaluates these
sums once per step (not once per bearing-force evaluation); the cosines are the portable ones
of :mod:`.portable_math`.
"""

from __future__ import annotations

from numba import njit

from .portable_math import PI, cos, sincos


@njit(cache=True, inline="always")
def race_waviness(race_wav, phi, shaft_angle):
    """Radial and axial waviness (p_i, q_i, p_o, q_o) at ball angle ``phi`` (eqs 9-12)."""
    p_i = 0.0
    q_i = 0.0
    p_o = 0.0
    q_o = 0.0
    for k in range(race_wav.shape[0]):
        race = race_wav[k, 0]
        kind = race_wav[k, 1]
        order = race_wav[k, 2]
        if race == 0.0:
            val = race_wav[k, 3] * cos(order * (phi - shaft_angle) + race_wav[k, 4])
            if kind == 0.0:
                p_i += val
            else:
                q_i += val
        else:
            val = race_wav[k, 3] * cos(order * phi + race_wav[k, 4])
            if kind == 0.0:
                p_o += val
            else:
                q_o += val
    return p_i, q_i, p_o, q_o


@njit(cache=True, inline="always")
def race_waviness_all_balls(race_wav, cage_phase, shaft_angle, n_balls, out, col):
    """:func:`race_waviness` at every ball j of the angle phi_j = cage_phase + 2 pi j / N (eq 6),
    added into ``out[j, col + (p_i, q_i, p_o, q_o)]``.

    Ball j + 1 sits 2 pi / N further on, so each term's angle n (phi_j - theta_s) + xi advances
    by n 2 pi / N from one ball to the next: its (cos, sin) is rotated by that fixed angle
    instead of evaluated anew (two sincos per term and step instead of one cosine per ball;
    the rotation's rounding grows by about one ulp per ball).
    """
    for k in range(race_wav.shape[0]):
        order = race_wav[k, 2]
        amp = race_wav[k, 3]
        if race_wav[k, 0] == 0.0:
            angle = order * (cage_phase - shaft_angle) + race_wav[k, 4]       # eqs 9, 11
        else:
            angle = order * cage_phase + race_wav[k, 4]                        # eqs 10, 12
        sa, ca = sincos(angle)
        sd, cd = sincos(order * (2.0 * PI / n_balls))
        c = col + 2 * int(race_wav[k, 0]) + int(race_wav[k, 1])              # p_i, q_i, p_o, q_o
        for j in range(n_balls):
            out[j, c] += amp * ca
            ca, sa = ca * cd - sa * sd, sa * cd + ca * sd


@njit(cache=True, inline="always")
def ball_waviness(ball_wav, ball_phase, j, psi_b):
    """Ball waviness at its inner and outer contacts (w_ij, w_oj), eqs 13-14."""
    w_i = 0.0
    w_o = 0.0
    for k in range(ball_wav.shape[0]):
        order = ball_wav[k, 0]
        amp = ball_wav[k, 1]
        ph = ball_phase[j, k]
        w_i += amp * cos(order * psi_b + ph)
        w_o += amp * cos(order * (psi_b + PI) + ph)
    return w_i, w_o
