"""``bearing-gym equilibrium``: the static equilibrium at an operating point."""

from __future__ import annotations

import math

from .errors import RunError, one_line
from .options import params_from_args
from .output import Out, op_text, params_dict, write_json

__all__ = ["cmd_equilibrium"]

_K_ROWS = ("F_x", "F_y", "F_z", "M_x", "M_y")


_K_COLS = ("x", "y", "z", "theta_x", "theta_y")


def cmd_equilibrium(args, say: Out) -> int:
    import numpy as np

    from bearing_gym.physics import static_equilibrium
    from bearing_gym.physics.equilibrium import EquilibriumError

    params = params_from_args(args)
    if args.json == "-":               # JSON on stdout: no table mixed into it
        say = Out(True)
    try:
        eq = static_equilibrium(params)
    except EquilibriumError as err:
        raise RunError(one_line(err)) from None
    n = params.geometry.n_balls
    phi = np.degrees(2 * np.pi * np.arange(n) / n + params.initial_cage_angle_rad)
    U = eq.U
    say(f"static equilibrium: {op_text(params)}")
    say(f"rotor displacement: x {U[0] * 1e6:.4f} um, y {U[1] * 1e6:.4f} um, z {U[2] * 1e6:.4f} um, "
        f"theta_x {U[3] * 1e6:.4f} urad, theta_y {U[4] * 1e6:.4f} urad")
    say(f"cage/shaft speed ratio {eq.cage_speed_ratio:.5f} (cage speed {eq.cage_speed_rad_s:.2f} "
        f"rad/s); residual {eq.residual:.2g} N after {eq.iterations} iterations")
    say("")
    say(f"{'ball':>4} {'angle':>7} {'alpha_i':>8} {'alpha_o':>8} {'Q_i':>9} {'Q_o':>9} "
        f"{'delta_i':>8} {'delta_o':>8} {'omega_m':>9} {'control':>7}")
    say(f"{'':>4} {'(deg)':>7} {'(deg)':>8} {'(deg)':>8} {'(N)':>9} {'(N)':>9} "
        f"{'(um)':>8} {'(um)':>8} {'(rad/s)':>9} {'race':>7}")
    for j in range(n):
        say(f"{j:>4d} {phi[j]:7.1f} {math.degrees(eq.alpha_i[j]):8.3f} "
            f"{math.degrees(eq.alpha_o[j]):8.3f} {eq.q_i[j]:9.2f} {eq.q_o[j]:9.2f} "
            f"{eq.delta_i[j] * 1e6:8.4f} {eq.delta_o[j] * 1e6:8.4f} {eq.orbital_speed[j]:9.2f} "
            f"{'inner' if eq.inner_race_control[j] else 'outer':>7}")
    say("")
    say("stiffness matrix K = -dF/dU (rows F_x, F_y, F_z in N and M_x, M_y in N m; columns "
        "x, y, z in m and theta_x, theta_y in rad):")
    say(f"{'':>5}" + "".join(f"{c:>12}" for c in _K_COLS))
    for i, r in enumerate(_K_ROWS):
        say(f"{r:>5}" + "".join(f"{v:12.4e}" for v in eq.stiffness[i]))
    data = dict(operating_point=op_text(params), params=params_dict(params),
                rotor_displacement=dict(zip(("x_m", "y_m", "z_m", "theta_x_rad", "theta_y_rad"), U)),
                cage_speed_ratio=eq.cage_speed_ratio, cage_speed_rad_s=eq.cage_speed_rad_s,
                residual_n=eq.residual, iterations=eq.iterations,
                balls=dict(angle_deg=phi, alpha_i_deg=np.degrees(eq.alpha_i),
                           alpha_o_deg=np.degrees(eq.alpha_o), q_i_n=eq.q_i, q_o_n=eq.q_o,
                           delta_i_m=eq.delta_i, delta_o_m=eq.delta_o,
                           orbital_speed_rad_s=eq.orbital_speed, spin_speed_rad_s=eq.spin_speed,
                           gyroscopic_moment_n_m=eq.gyroscopic_moment,
                           inner_race_control=eq.inner_race_control),
                stiffness=dict(rows=_K_ROWS, columns=_K_COLS, matrix=eq.stiffness,
                               units="rows F_x, F_y, F_z (N), M_x, M_y (N m); columns x, y, z (m), "
                                     "theta_x, theta_y (rad)"))
    write_json(data, args.json)
    if args.json not in (None, "-"):
        say(f"wrote the results as JSON to {args.json}")
    return 0
