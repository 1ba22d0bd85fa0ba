"""``bearing-gym floquet``: Floquet multipliers of the settled periodic response."""

from __future__ import annotations

import math

from .errors import CLIError, RunError, check_option, one_line
from .options import params_from_args
from .output import Out, advance, op_text, params_dict, write_json

__all__ = ["cmd_floquet"]


def cmd_floquet(args, say: Out) -> int:
    import numpy as np

    from bearing_gym.analysis.floquet import simulator_floquet
    from bearing_gym.analysis.signals import quasi_periodicity_index
    from bearing_gym.physics import SimulationError, Simulator
    from bearing_gym.physics.equilibrium import EquilibriumError

    params = params_from_args(args)
    if args.json == "-":               # JSON on stdout: no table mixed into it
        say = Out(True)
    settle = check_option("--settle-s", args.settle_s, 0.0, 1e4, "s")
    measure = check_option("--measure-s", args.measure_s, 0.0, 1e4, "s", low_open=True)
    h_um = check_option("--fd-step-um", args.fd_step_um, 0.0, 10.0, "um", low_open=True)
    if params.shaft_speed_rpm <= 0:
        raise CLIError("--rpm: must be > 0 for Floquet multipliers (the stroboscopic section is "
                       "one shaft period), got 0")
    period = 60.0 / params.shaft_speed_rpm
    if measure < 3 * period:
        raise CLIError(f"--measure-s: must be at least 3 shaft periods ({3 * period:.3g} s at "
                       f"{params.shaft_speed_rpm:g} rpm), got {measure:g}")
    say(f"bearing-gym floquet: {op_text(params)}")
    try:
        sim = Simulator(params)
    except (EquilibriumError, SimulationError) as err:
        raise RunError(f"no static equilibrium at this operating point: {one_line(err)}") from None
    try:
        if settle > 0:
            advance(sim, settle, 100, say.quiet, "settle")
        rec = sim.advance(measure)
    except SimulationError as err:
        raise RunError(f"simulation stopped: {one_line(err)}") from None
    w = params.shaft_speed_rad_s
    qpi = quasi_periodicity_index(rec.t, np.column_stack([rec.x, rec.y, rec.z]), w)
    periodic = qpi < args.qpi_threshold
    say(f"settled {settle:g} s; quasi-periodicity index over the next {measure:g} s: {qpi:.3f}"
        + ("" if periodic else f" (above {args.qpi_threshold:g}: the motion is not period-1, so "
                                "these are not Floquet multipliers of a periodic orbit)"))
    try:
        res = simulator_floquet(sim, h_m=h_um * 1e-6, include_cage_angle=args.include_cage_angle)
    except (RuntimeError, ValueError, SimulationError) as err:
        raise RunError(f"Floquet computation failed: {one_line(err)}") from None
    prod = float(np.real(np.prod(res.multipliers)))
    say(f"section: {res.section}")
    say(f"leading |mu| = {res.leading_modulus:.5f}: "
        f"{'stable' if res.stable else 'UNSTABLE'} periodic orbit")
    say(f"product of the multipliers {prod:.5g}, Liouville's formula "
        f"{res.info.get('liouville_det', math.nan):.5g}")
    say("")
    say(f"{'#':>3} {'|mu|':>9} {'arg (deg)':>10} {'rate (1/s)':>11} {'freq (Hz)':>10}  dominant")
    modes = res.modes()
    for m in modes:
        dom = ", ".join(f"{lab} {share:.0%}" for lab, share in m["dominant"])
        say(f"{m['index']:>3d} {m['modulus']:9.5f} {m['angle_deg']:10.2f} {m['rate_per_s']:11.3f} "
            f"{m['freq_hz']:10.2f}  {dom}")
    data = dict(operating_point=op_text(params), params=params_dict(params), settle_s=settle,
                measure_s=measure, quasi_periodicity_index=qpi, periodic_before=periodic,
                section=res.section, period_s=res.period_s, leading_modulus=res.leading_modulus,
                stable=res.stable, product=prod, liouville_det=res.info.get("liouville_det"),
                dropped=res.dropped, labels=res.labels,
                multipliers=[dict(re=m["mu"].real, im=m["mu"].imag, modulus=m["modulus"],
                                  angle_deg=m["angle_deg"], rate_per_s=m["rate_per_s"],
                                  freq_hz=m["freq_hz"],
                                  dominant=[dict(label=lab, share=s) for lab, s in m["dominant"]])
                             for m in modes],
                monodromy=res.monodromy)
    write_json(data, args.json)
    if args.json not in (None, "-"):
        say(f"wrote the results as JSON to {args.json}")
    return 0
