"""``python -m bearing_gym``: simulate the paper's spindle and print a summary.

Options: ``--rpm``, ``--preload`` (N), ``--duration`` (s). Prints the static equilibrium at the
operating point and the peak-to-peak x, z and cage speed over the second half of the run.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from bearing_gym import default_params
from bearing_gym.physics import Simulator


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m bearing_gym", description=__doc__.splitlines()[0])
    ap.add_argument("--rpm", type=float, default=20000.0, help="shaft speed (rpm)")
    ap.add_argument("--preload", type=float, default=800.0, help="axial preload (N)")
    ap.add_argument("--duration", type=float, default=0.2, help="simulated time (s)")
    args = ap.parse_args(argv)
    try:
        params = default_params(shaft_speed_rpm=args.rpm, axial_preload_n=args.preload)
    except ValueError as err:
        ap.error(str(err))
    t0 = time.perf_counter()
    sim = Simulator(params)
    eq = sim.equilibrium
    print(f"Bai & Xu (2006) spindle, {args.rpm:g} rpm, axial preload {args.preload:g} N")
    print(f"static equilibrium: alpha_i = {math.degrees(eq.alpha_i[0]):.2f} deg, "
          f"alpha_o = {math.degrees(eq.alpha_o[0]):.2f} deg, Q_i = {eq.q_i[0]:.1f} N, "
          f"Q_o = {eq.q_o[0]:.1f} N, cage/shaft = {eq.cage_speed_ratio:.4f}")
    rec = sim.advance(args.duration, record_every=1)
    wall = time.perf_counter() - t0
    half = rec.t > rec.t[-1] / 2
    print(f"simulated {args.duration:g} s in {wall:.2f} s wall (dt = {sim.dt_s * 1e6:g} us)")
    print(f"peak-to-peak over the second half: x = {np.ptp(rec.x[half]) * 1e6:.3f} um, "
          f"z = {np.ptp(rec.z[half]) * 1e6:.3f} um, cage speed = {np.ptp(rec.cage_speed[half]):.3f} rad/s")
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
