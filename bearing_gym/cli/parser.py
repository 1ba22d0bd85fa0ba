"""The argument parser of ``bearing-gym``: one subparser per command, every option with its
unit, range and default in its help."""

from __future__ import annotations

import argparse
import os

from bearing_gym import __version__
from bearing_gym.analysis.signals import QPI_THRESHOLD
from bearing_gym.analysis.sweeps import SweepSettings

from .errors import CLIError
from .options import option_defaults

__all__ = ["PROG", "COMMANDS", "OneLineParser", "number", "integer", "build_parser"]

PROG = "bearing-gym"
COMMANDS = ("simulate", "equilibrium", "floquet", "sweep", "preload-map", "schedule", "reproduce")


class OneLineParser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors are one line: ``bearing-gym: error: argument --rpm:
    ...`` (raised as CLIError, exit status 2)."""

    def error(self, message: str):  # type: ignore[override]
        raise CLIError(f"{message} (see '{self.prog} --help')")


def number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None


def integer(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None


def _execution_options(g: argparse._ArgumentGroup, unit: str) -> None:
    """--workers, --backend and --address: where a command's tasks run (``unit``: what one Ray task is)."""
    g.add_argument("--workers", type=integer, default=min(2, os.cpu_count() or 1), metavar="N",
                   help="parallel worker processes of the local backend, or CPUs of the local "
                        "Ray instance of --backend ray without --address (>= 1; default "
                        "%(default)d)")
    g.add_argument("--backend", choices=("local", "ray"), default="local",
                   help="where the tasks run: local = a pool of --workers processes on this "
                        "machine; ray = Ray tasks, on a new local Ray instance or on the cluster "
                        f"at --address, {unit} (needs pip install "
                        "'bearing-gym[ray]'); the rows are the same (default %(default)s)")
    g.add_argument("--address", default=None, metavar="ADDR",
                   help="with --backend ray: the Ray cluster: 'auto' (the cluster this node "
                        "joined with 'ray start', or $RAY_ADDRESS), HOST:6379, or "
                        "ray://HOST:10001 (Ray Client, from outside the cluster); every node "
                        "needs the same bearing-gym install (default: start a local Ray "
                        "instance with --workers CPUs, stopped at the end)")


def _common(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("general")
    g.add_argument("--config", metavar="FILE", default=None,
                   help="TOML (.toml) or YAML (.yaml/.yml) file of options: keys are the long "
                        "option names with underscores (clearance_um = 4); a table named after "
                        "the subcommand ([sweep]) applies to it only; command-line options win")
    g.add_argument("-q", "--quiet", action="store_true",
                   help="print nothing but errors (no summary, no progress bar)")


def _json_option(g: argparse._ArgumentGroup) -> None:
    g.add_argument("--json", metavar="FILE", default=None,
                   help="also write the results as JSON to FILE ('-': stdout, instead of the table)")


def _operating_point(p: argparse.ArgumentParser, d: dict, *, preload: bool = True,
                     dt: bool = True) -> None:
    g = p.add_argument_group("operating point")
    g.add_argument("--rpm", type=number, default=d["rpm"], metavar="RPM",
                   help="shaft speed (rpm, 0-200000; default %(default)g)")
    if preload:
        g.add_argument("--preload", type=number, default=d["preload"], metavar="N",
                       help="axial preload P_z (N, 0-1e6; default %(default)g)")
    g.add_argument("--clearance-um", type=number, default=d["clearance_um"], metavar="UM",
                   help=f"radial clearance c_i = c_o (um, 0 to below {d['clearance_max_um']:g}; "
                        "default %(default)g)")
    g.add_argument("--radial-load", type=number, default=d["radial_load"], metavar="N",
                   help="radial load on EACH of the x and y axes, P_x = P_y = N as in the paper "
                        "(N, -1e6 to 1e6; default %(default)g): the resultant is 1.414 x N at 45 "
                        "deg, e.g. 283 N for 200; for a resultant F give F/1.414")
    g.add_argument("--eccentricity-um", type=number, default=d["eccentricity_um"], metavar="UM",
                   help="rotor mass eccentricity e (um, 0-10000; default %(default)g)")
    g.add_argument("--damping-ratio", type=number, default=d["damping_ratio"], metavar="ZETA",
                   help="viscous damping ratio on each rotor DOF (dimensionless, 0-1; "
                        "default %(default)g)")
    g.add_argument("--race-control", choices=("outer", "inner", "auto"),
                   default=d["race_control"],
                   help="race-control hypothesis of the ball kinematics (default %(default)s)")
    if dt:
        g.add_argument("--dt-us", type=number, default=d["dt_us"], metavar="US",
                       help="integration time step (us, 0-1000; default %(default)g)")


def build_parser() -> tuple[argparse.ArgumentParser, dict[str, argparse.ArgumentParser]]:
    """The top-level parser and the subparsers by name."""
    d = option_defaults()
    s = SweepSettings()
    fmt = argparse.RawDescriptionHelpFormatter
    top = OneLineParser(
        prog=PROG, formatter_class=fmt,
        description="High-speed ball-bearing spindle (Bai & Xu 2006 model): simulation, "
                    "equilibrium, Floquet stability, stability maps and the paper's reproduction.",
        epilog="Options go after the subcommand; 'bearing-gym COMMAND --help' lists them.")
    top.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = top.add_subparsers(dest="command", metavar="COMMAND", required=True)
    subs: dict[str, argparse.ArgumentParser] = {}

    p = sub.add_parser("simulate", help="time simulation with summary, plots and NPZ record",
                       description="Simulate the rotor from its static equilibrium; summarise the "
                                   "second half of the run (peak-to-peak, principal frequencies, "
                                   "periodic or quasi-periodic, or undetermined with a warning "
                                   "when that half is too short or still ringing) and save plots "
                                   "and the record.")
    _operating_point(p, d)
    g = p.add_argument_group("simulation")
    g.add_argument("--duration", type=number, default=0.5, metavar="S",
                   help="simulated time (s, > 0; default %(default)g); the first half is the "
                        "start transient, the summary uses the second half. The periodic / "
                        "quasi-periodic verdict needs at least 20 shaft turns in that half "
                        "(--duration >= 40 turns, 0.12 s at 20000 rpm) and the same verdict from "
                        "its two halves, else it says 'undetermined' and how long to run")
    g.add_argument("--record-every", type=integer, default=1, metavar="STEPS",
                   help="keep every STEPS-th time step in the record (default %(default)d)")
    g.add_argument("--qpi-threshold", type=number, default=QPI_THRESHOLD, metavar="Q",
                   help="quasi-periodicity index above which the motion is called "
                        "quasi-periodic (dimensionless, 0-2; default %(default)g, the package's "
                        "QPI_THRESHOLD)")
    g.add_argument("--out", default="simulation", metavar="DIR",
                   help="output directory for record.npz, summary.json and the PNG plots "
                        "(default %(default)s)")
    g.add_argument("--no-plots", action="store_true", help="save the record and summary only")
    _common(p)
    subs["simulate"] = p

    p = sub.add_parser("equilibrium", help="static equilibrium: contact angles, loads, stiffness",
                       description="Quasi-static equilibrium of the rotor on the bearing at the "
                                   "operating point (no unbalance): rotor displacement, per-ball "
                                   "contact angles and loads, and the 5x5 stiffness matrix.")
    _operating_point(p, d, dt=False)
    g = p.add_argument_group("output")
    _json_option(g)
    _common(p)
    subs["equilibrium"] = p

    p = sub.add_parser("floquet", help="Floquet multipliers of the settled periodic response",
                       description="Settle the response from the static equilibrium, then "
                                   "compute the Floquet multipliers of the stroboscopic map "
                                   "(one shaft period) by central finite differences.")
    _operating_point(p, d)
    g = p.add_argument_group("floquet")
    g.add_argument("--settle-s", type=number, default=s.cold_settle_s, metavar="S",
                   help="simulated time before the multipliers are computed (s, >= 0; "
                        "default %(default)g)")
    g.add_argument("--measure-s", type=number, default=s.measure_s, metavar="S",
                   help="window after settling used to check that the motion is periodic "
                        "(s, > 0, at least 3 shaft periods; default %(default)g)")
    g.add_argument("--fd-step-um", type=number, default=0.1, metavar="UM",
                   help="finite-difference step of the translations (um, 0-10; tilts and "
                        "velocities are scaled from it; default %(default)g)")
    g.add_argument("--include-cage-angle", action="store_true",
                   help="add the cage angle as an 11th coordinate and drop its trivial multiplier")
    g.add_argument("--qpi-threshold", type=number, default=s.qpi_threshold, metavar="Q",
                   help="quasi-periodicity index above which a warning says the motion is not "
                        "period-1 (dimensionless; default %(default)g)")
    _json_option(g)
    _common(p)
    subs["floquet"] = p

    p = sub.add_parser("sweep", help="stability map over preload and other parameters (CSV)",
                       description="Stability map (bearing_gym.analysis.sweeps.stability_map): "
                                   "every preload for every combination of speed, radial load, "
                                   "clearance and damping ratio. Rows are appended to --out as "
                                   "points finish; a rerun with the same --out reuses the points "
                                   "already in it (same label, mode, preloads and operating "
                                   "point) and computes only the others; a rerun with other "
                                   "durations, criteria, --dt-us or --race-control is refused.")
    _operating_point(p, d, preload=False)
    g = p.add_argument_group("grid")
    g.add_argument("--preloads", type=number, nargs="+", metavar="N", default=None,
                   help="axial preloads (N, 0-1e6; required); with --mode continuation give them "
                        "in the order to follow, descending to track the period-1 orbit down")
    g.add_argument("--rpms", type=number, nargs="+", metavar="RPM", default=None,
                   help="shaft speeds (rpm; default: --rpm only)")
    g.add_argument("--radial-loads", type=number, nargs="+", metavar="N", default=None,
                   help="radial loads, each on both axes: P_x = P_y (N per axis, resultant "
                        "1.414 times larger at 45 deg; default: --radial-load only)")
    g.add_argument("--clearances-um", type=number, nargs="+", metavar="UM", default=None,
                   help="clearances c_i = c_o (um; default: --clearance-um only)")
    g.add_argument("--damping-ratios", type=number, nargs="+", metavar="ZETA", default=None,
                   help="damping ratios (dimensionless; default: --damping-ratio only)")
    g.add_argument("--mode", choices=("continuation", "cold"), default="continuation",
                   help="continuation: each preload starts from the previous end state; cold: "
                        "every point from its static equilibrium (default %(default)s)")
    g = p.add_argument_group("sweep settings")
    g.add_argument("--settle-s", type=number, default=s.settle_s, metavar="S",
                   help="settling time of a continuation point (s, >= 0; default %(default)g)")
    g.add_argument("--cold-settle-s", type=number, default=s.cold_settle_s, metavar="S",
                   help="settling time of a cold start and of the first point of a chain "
                        "(s, >= 0; default %(default)g)")
    g.add_argument("--measure-s", type=number, default=s.measure_s, metavar="S",
                   help="measured window per point (s, > 0, at least 3 shaft periods; "
                        "default %(default)g)")
    g.add_argument("--qpi-threshold", type=number, default=s.qpi_threshold, metavar="Q",
                   help="quasi-periodicity index above which a point is not period-1 "
                        "(dimensionless; default %(default)g)")
    g.add_argument("--refine-step", type=number, default=s.refine_step_n, metavar="N",
                   help="finer preload step to bracket the first loss of stability in a "
                        "continuation chain (N, > 0; default: no refinement)")
    g.add_argument("--no-floquet", action="store_true",
                   help="skip the Floquet multipliers (faster; stability from the index only)")
    _execution_options(g, "one CPU per chain or cold start")
    g = p.add_argument_group("output")
    g.add_argument("--out", default="stability_map.csv", metavar="CSV",
                   help="CSV file of the points (columns of sweeps.COLUMNS; lengths in m); "
                        "reused on a rerun (default %(default)s)")
    g.add_argument("--plot", default=None, metavar="PNG",
                   help="also save a stability-map (or preload-sweep) figure to PNG")
    _common(p)
    subs["sweep"] = p

    p = sub.add_parser("preload-map", help="the preload to run per speed x radial load, with its margins (CSV, PNG)",
                       description="Preload map (bearing_gym.engineering.preload_map): per operating point the "
                                   "lowest period-1 preload, the period-1 preload of the lowest heat and "
                                   "fatigue cost (with at least --min-margin to a quasi-periodic preload on "
                                   "each side), its margins, static stiffness, L10 life and friction torque. "
                                   "Every preload of the grid is settled and held 0.5 s in the env's physics.")
    g = p.add_argument_group("grid")
    g.add_argument("--rpms", type=number, nargs="+", metavar="RPM", default=[10000.0, 15000.0, 20000.0, 25000.0],
                   help="shaft speeds (rpm, 1000-60000; default %(default)s)")
    g.add_argument("--radial-loads", type=number, nargs="+", metavar="N", default=[0.0, 250.0, 500.0],
                   help="radial load resultants (N, 0-5000, at 45 deg as the env applies them; default %(default)s)")
    g.add_argument("--clearances-um", type=number, nargs="+", metavar="UM", default=[4.0],
                   help="radial clearances c_i = c_o (um; default %(default)s)")
    g.add_argument("--eccentricities-um", type=number, nargs="+", metavar="UM", default=[10.0],
                   help="rotor unbalance: mass-centre eccentricity (um; default %(default)s; ISO 1940 grade G = "
                        "e x omega: 1 um at 25,000 rpm is G2.6)")
    g.add_argument("--preload-min", type=number, default=300.0, metavar="N",
                   help="lowest preload of the grid (N; default %(default)g: the actuator's)")
    g.add_argument("--preload-max", type=number, default=2000.0, metavar="N",
                   help="highest preload of the grid (N; default %(default)g: the actuator's)")
    g.add_argument("--preload-step", type=number, default=50.0, metavar="N",
                   help="preload grid step (N, > 0; default %(default)g): margins are known to this step")
    g.add_argument("--min-margin", type=number, default=0.0, metavar="N",
                   help="the preferred preload keeps at least this distance to a quasi-periodic preload on "
                        "each side (N, >= 0; default %(default)g: the cheapest period-1 preload)")
    g.add_argument("--damping-ratio", type=number, default=d["damping_ratio"], metavar="ZETA",
                   help="viscous damping ratio on each rotor DOF (dimensionless, 0-1; default %(default)g)")
    g = p.add_argument_group("execution")
    _execution_options(g, "one task per operating point")
    g = p.add_argument_group("output")
    g.add_argument("--out", default="preload_map.csv", metavar="CSV", help="the map's rows (default %(default)s)")
    g.add_argument("--points", default=None, metavar="CSV",
                   help="also every measured (operating point, preload) as a reward-map CSV")
    g.add_argument("--plot", default=None, metavar="PNG", help="also the figure (default: beside --out, .png)")
    _common(p)
    subs["preload-map"] = p

    p = sub.add_parser("schedule", help="a preload schedule for a duty cycle, checked on the model, against the best constant",
                       description="Duty-cycle schedule (bearing_gym.engineering.duty_cycle): the preload map's "
                                   "preferred preload at each operating point of the cycle, every switch checked by "
                                   "simulating the whole cycle (a switch that rings gets the planner's ramp or kick "
                                   "if one does better), with its cost against the best constant preload.")
    g = p.add_argument_group("cycle")
    g.add_argument("--duty", required=True, metavar="CSV",
                   help="the cycle: columns time_s, speed_rpm, radial_load_n (speed linear between rows, load "
                        "stepping at each row; the example: bearing_gym/engineering/example_cycle.csv)")
    g.add_argument("--min-margin", type=number, default=100.0, metavar="N",
                   help="the map's minimum margin to a quasi-periodic preload on each side (N, >= 0; default %(default)g)")
    g.add_argument("--preload-step", type=number, default=50.0, metavar="N",
                   help="the map's preload grid step over the actuator's range (N, > 0; default %(default)g)")
    g.add_argument("--clearance-um", type=number, default=4.0, metavar="UM", help="radial clearance (um; default %(default)g)")
    g.add_argument("--eccentricity-um", type=number, default=10.0, metavar="UM",
                   help="rotor unbalance, mass-centre eccentricity (um; default %(default)g)")
    g.add_argument("--workers", type=integer, default=min(2, os.cpu_count() or 1), metavar="N",
                   help="processes for the preload map (>= 1; default %(default)d)")
    g = p.add_argument_group("output")
    g.add_argument("--out", default="schedule.csv", metavar="CSV", help="the set-point per 20 ms interval (default %(default)s)")
    g.add_argument("--plot", default=None, metavar="PNG", help="the figure (default: beside --out, .png)")
    _json_option(g)
    _common(p)
    subs["schedule"] = p

    p = sub.add_parser("reproduce", add_help=False, allow_abbrev=False,
                       help="reproduce Bai & Xu (2006) (options of python -m bearing_gym.reproduction)",
                       description="Run python -m bearing_gym.reproduction; every option other than "
                                   "--config and --quiet is passed through (see "
                                   "'bearing-gym reproduce --help'). The config file's "
                                   "[reproduce] table is turned into options.")
    _common(p)
    subs["reproduce"] = p
    return top, subs
