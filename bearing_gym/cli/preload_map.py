"""``bearing-gym preload-map``: the preload to run at each operating point, with its margins
(:mod:`bearing_gym.engineering.preload_map`)."""

from __future__ import annotations

import math
from pathlib import Path

from .errors import CLIError, one_line
from .output import Out
from .sweep import check_backend, sweep_pool

__all__ = ["cmd_preload_map", "preload_grid", "check_um"]


#: preloads a grid may hold (each costs one env of a cell's batch)
MAX_GRID_PRELOADS = 400


def preload_grid(lo: float, hi: float, step: float) -> tuple[float, ...]:
    """The preload grid lo, lo + step, ... <= hi, inside the actuator's range; CLIError naming the
    option otherwise."""
    from bearing_gym.envs.actuator import PreloadActuator
    a = PreloadActuator()
    amin, amax = float(a.min_preload_n), float(a.max_preload_n)
    for name, v in (("--preload-min", lo), ("--preload-max", hi), ("--preload-step", step)):
        if not math.isfinite(v):
            raise CLIError(f"{name}: must be a finite number of N, got {v}")
    if not step > 0:
        raise CLIError(f"--preload-step: must be > 0 N, got {step:g}")
    if not amin <= lo < hi <= amax:
        raise CLIError(f"--preload-min/--preload-max: need {amin:g} <= min < max <= {amax:g} N (the actuator's range), "
                       f"got {lo:g} and {hi:g}")
    n = int(math.floor((hi - lo) / step + 1e-9)) + 1
    if n > MAX_GRID_PRELOADS:
        raise CLIError(f"--preload-step: {step:g} N makes {n} preloads; at most {MAX_GRID_PRELOADS} (a larger step)")
    return tuple(lo + k * step for k in range(n))


def check_um(name: str, values, low: float, high: float) -> None:
    """CLIError naming the option unless every value (um) is finite and in [low, high]."""
    for v in values:
        if not (math.isfinite(v) and low <= v <= high):
            raise CLIError(f"{name}: must be in [{low:g}, {high:g}] um, got {v:g}")


def _grid(args) -> tuple[float, ...]:
    return preload_grid(args.preload_min, args.preload_max, args.preload_step)


def cmd_preload_map(args, say: Out) -> int:
    from bearing_gym.envs.core import env_params
    from bearing_gym.engineering.preload_map import plot, preload_map, write_csv
    from bearing_gym.envs.reward_map import write_csv as write_points

    check_backend(args)
    if not (math.isfinite(args.min_margin) and args.min_margin >= 0):
        raise CLIError(f"--min-margin: must be a finite number >= 0 N, got {args.min_margin:g}")
    for name, vals, lo, hi in (("--rpms", args.rpms, 1000.0, 60000.0), ("--radial-loads", args.radial_loads, 0.0, 5000.0)):
        for v in vals:
            if not (math.isfinite(v) and lo <= v <= hi):
                raise CLIError(f"{name}: must be in [{lo:g}, {hi:g}], got {v:g}")
    check_um("--clearances-um", args.clearances_um, 0.0, 100.0)
    check_um("--eccentricities-um", args.eccentricities_um, 0.0, 1000.0)
    try:
        params = env_params(damping_ratio=args.damping_ratio)
    except ValueError as err:
        raise CLIError(f"--damping-ratio: {one_line(err)}") from None
    grid = _grid(args)
    cells = len(args.rpms) * len(args.radial_loads) * len(args.clearances_um) * len(args.eccentricities_um)
    say(f"preload map: {cells} operating points x {len(grid)} preloads ({grid[0]:g}-{grid[-1]:g} N, step "
        f"{args.preload_step:g} N), 0.5 s settled and measured each, on {args.workers} "
        f"{'Ray CPUs' if args.backend == 'ray' else 'processes'}")
    executor = sweep_pool(args, args.workers, args.quiet)()
    try:
        rows, points = preload_map(args.rpms, args.radial_loads, [c * 1e-6 for c in args.clearances_um],
                                   [e * 1e-6 for e in args.eccentricities_um], grid, params=params,
                                   executor=executor, progress=not args.quiet, min_margin_n=args.min_margin)
    except ValueError as err:
        raise CLIError(one_line(err)) from None
    finally:
        executor.shutdown()
    out = write_csv(rows, args.out)
    if args.points:
        write_points(points, args.points)
    png = plot(rows, points, args.plot or Path(args.out).with_suffix(".png"))
    say(f"{'rpm':>7} {'radial N':>8} {'lowest P1 N':>11} {'preferred N':>11} {'margin -/+ N':>13} "
        f"{'K_r N/um':>8} {'L10 h':>8}")
    for r in rows:
        def f(x, spec):
            return "-" if math.isnan(x) else format(x, spec)
        margins = f"{f(r.margin_below_n, '.0f')}/{f(r.margin_above_n, '.0f')}"
        say(f"{r.speed_rpm:7.0f} {r.radial_load_n:8.0f} {f(r.lowest_period1_n, '11.0f')} {f(r.preferred_n, '11.0f')} "
            f"{margins:>13} {f(r.radial_stiffness_n_per_um, '8.1f')} {f(r.l10_life_h, '8.0f')}")
    say(f"wrote {out} and {png} ('-': none on the grid; a margin is known to the grid step)")
    return 0
