"""``bearing-gym``: the command line of bearing_gym.

Subcommands (``bearing-gym COMMAND --help`` lists every option with its unit and default):

* ``simulate``     run the Simulator at an operating point, print a summary (peak-to-peak,
                   principal frequencies, periodic or quasi-periodic -- or undetermined, with a
                   warning and a longer ``--duration`` to try, when the analysed second half is
                   too short or still ringing) and save time-series, orbit, spectrum and
                   Poincare plots plus the raw record (NPZ) in ``--out``;
* ``equilibrium``  static equilibrium: contact angles, loads per ball, 5x5 stiffness matrix;
* ``floquet``      Floquet multipliers of the settled response (finite differences);
* ``sweep``        stability map over preloads x speeds x radial loads x clearances, written
                   to a CSV file; a rerun with the same ``--out`` reuses the finished points;
                   tasks run on a local process pool or on Ray (``--backend ray --address``);
* ``reproduce``    the reproduction of Bai & Xu (2006) (``python -m bearing_gym.reproduction``;
                   its options are passed through).

Every subcommand takes ``--config FILE`` (TOML or YAML; keys are the long option names with
underscores, e.g. ``clearance_um = 4``; a table named after a subcommand, e.g. ``[sweep]``,
applies to that subcommand only; options given on the command line win) and ``-q/--quiet``
(print nothing but errors). Bad values exit with status 2 and a one-line message on stderr
naming the option and its allowed range.

Playing a policy in the environment is ``python -m agents.evaluation.watch`` (console script
``bearing-gym-watch``): the agents sit above this package, which does not import them.

Modules: :mod:`.main` (entry point), :mod:`.parser`, :mod:`.options` (option <-> parameter),
:mod:`.config`, :mod:`.output`, :mod:`.errors`, and one module per command.
"""

from __future__ import annotations

import contextlib
import os
import sys
from typing import Callable, Sequence

from .config import config_defaults, load_config, reproduce_config_args
from .equilibrium import cmd_equilibrium
from .errors import CLIError, RunError, one_line
from .floquet import cmd_floquet
from .output import Out
from .parser import PROG, build_parser
from .simulate import cmd_simulate
from .preload_map import cmd_preload_map
from .schedule import cmd_schedule
from .sweep import cmd_sweep

__all__ = ["main", "guarded", "CLIError", "RunError"]


def cmd_reproduce(args, extras: list[str], cfg: dict, say: Out) -> int:
    from bearing_gym.reproduction import main as reproduction

    argv = reproduce_config_args(cfg) + list(extras)
    if say.quiet and "--no-progress" not in argv:
        argv.append("--no-progress")
    if say.quiet:
        with open(os.devnull, "w") as devnull, contextlib.redirect_stdout(devnull):
            return int(reproduction.main(argv) or 0)
    return int(reproduction.main(argv) or 0)


def _run(argv: list[str]) -> int:
    top, subs = build_parser()
    args, extras = top.parse_known_args(argv)
    cfg: dict = {}
    if args.config:
        cfg = load_config(args.config)
        if args.command != "reproduce":
            subs[args.command].set_defaults(**config_defaults(cfg, args.command, subs))
            args, extras = top.parse_known_args(argv)
        elif isinstance(cfg.get("quiet"), bool) and cfg["quiet"]:
            args.quiet = True
    if args.command != "reproduce" and extras:
        subs[args.command].error(f"unrecognized arguments: {' '.join(extras)}")
    say = Out(bool(args.quiet))
    if args.command == "reproduce":
        return cmd_reproduce(args, extras, cfg, say)
    return {"simulate": cmd_simulate, "equilibrium": cmd_equilibrium, "floquet": cmd_floquet,
            "sweep": cmd_sweep, "preload-map": cmd_preload_map,
            "schedule": cmd_schedule}[args.command](args, say)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``bearing-gym`` command line; returns the exit status (0 ok, 1 the computation
    failed, 2 bad options)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    return guarded(lambda: _run(argv), PROG)


def guarded(run: Callable[[], int], prog: str) -> int:
    """``run()`` with the command line's error handling: a CLIError is one line on stderr and
    status 2, a RunError one line and status 1; argparse exits, Ctrl-C (130) and a closed
    output pipe (1) end quietly."""
    try:
        return run()
    except CLIError as err:
        print(f"{prog}: error: {one_line(err)}", file=sys.stderr)
        return 2
    except RunError as err:
        print(f"{prog}: error: {one_line(err)}", file=sys.stderr)
        return 1
    except SystemExit as err:          # argparse (--help, usage errors) and reproduce's parser
        code = err.code
        if code is None:
            return 0
        if isinstance(code, int):
            return code
        print(code, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:            # output piped into e.g. head: stop quietly
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return 1
