"""``bearing-gym schedule --duty cycle.csv``: a preload schedule for a duty cycle
(:mod:`bearing_gym.engineering.duty_cycle`)."""

from __future__ import annotations

import math
from pathlib import Path

from .errors import CLIError, one_line
from .output import Out, write_json
from .preload_map import check_um, preload_grid

__all__ = ["cmd_schedule"]


def cmd_schedule(args, say: Out) -> int:
    from bearing_gym.engineering.duty_cycle import plan_schedule, plot, read_cycle, write_schedule
    from bearing_gym.engineering.preload_map import DEFAULT_PRELOADS_N
    if not (math.isfinite(args.min_margin) and args.min_margin >= 0):
        raise CLIError(f"--min-margin: must be a finite number >= 0 N, got {args.min_margin:g}")
    check_um("--clearance-um", [args.clearance_um], 0.0, 100.0)
    check_um("--eccentricity-um", [args.eccentricity_um], 0.0, 1000.0)
    grid = preload_grid(DEFAULT_PRELOADS_N[0], DEFAULT_PRELOADS_N[-1], args.preload_step)
    if isinstance(args.workers, bool) or args.workers < 1:
        raise CLIError(f"--workers: must be an integer >= 1, got {args.workers}")
    if not Path(args.duty).is_file():
        raise CLIError(f"--duty: no such file: {args.duty}")
    try:
        cycle = read_cycle(args.duty)
    except ValueError as err:
        raise CLIError(f"--duty: {one_line(err)}") from None
    try:
        s = plan_schedule(cycle, args.min_margin, grid, clearance_m=args.clearance_um * 1e-6,
                          eccentricity_m=args.eccentricity_um * 1e-6, workers=args.workers,
                          progress=None if args.quiet else print)
    except ValueError as err:
        raise CLIError(one_line(err)) from None
    out = write_schedule(s, cycle, args.out)
    png = plot(s, cycle, args.plot or Path(args.out).with_suffix(".png"))
    say(f"{'':28s} {'schedule':>12s} {f'constant {s.best_constant_n:.0f} N':>16s}")
    for name, key, spec in (("time quasi-periodic (s)", "quasi_periodic_s", ".2f"), ("heat cost", "heat_cost", ".1f"),
                            ("fatigue cost", "fatigue_cost", ".1f"), ("L10 life used (ppm)", "life_used", ".3f"),
                            ("return", "return", ".1f")):
        a, b = s.costs.as_dict()[key], s.constant_costs.as_dict()[key]
        if key == "life_used":
            a, b = a * 1e6, b * 1e6
        say(f"{name:28s} {format(a, spec):>12s} {format(b, spec):>16s}")
    say(f"wrote {out} and {png}")
    write_json({"cycle": str(args.duty), "schedule": s.costs.as_dict(), "best_constant_n": s.best_constant_n,
                "best_constant": s.constant_costs.as_dict(), "map_preloads_n": s.map_preloads,
                "transitions": s.transitions}, args.json)
    return 0
