"""Play a policy in BearingPreload-v0, live: ``python -m agents.evaluation.watch`` (console script
``bearing-gym-watch``).

A trained policy (``--model DIR`` written by train.py) or a scripted baseline
(``--policy constant:1000``, ``feedback``, ``schedule[:MARGIN]``, ``oracle[:MARGIN]``) runs with
``render_mode="human"`` (a live window, or PNG frames on a headless machine), one line per
control step. Bad options exit with status 2 and one line on stderr naming the option.

This lives with the agents (it loads them); ``bearing_gym`` below does not import ``agents``.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Sequence

from bearing_gym.cli.errors import CLIError, one_line
from bearing_gym.cli.main import guarded
from bearing_gym.cli.output import Out
from bearing_gym.cli.parser import OneLineParser, integer
from bearing_gym.analysis.signals import QPI_THRESHOLD
from bearing_gym.envs.tiers import DEFAULT_TIER, EPISODE_STEPS, TIERS


__all__ = ["build_parser", "make_policy", "watch", "main"]

PROG = "bearing-gym-watch"


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``bearing-gym-watch``."""
    p = OneLineParser(
        prog=PROG, formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Play a policy in BearingPreload-v0 with render_mode='human': "
                    "a matplotlib window showing the orbit, the Poincare section "
                    "and the preload, updated every control interval (20 ms); on "
                    "a machine without a display the frames are written as PNG "
                    "files instead (--frames). Prints one line per step: t, "
                    "preload, set-point, quasi-periodicity index, reward.")
    g = p.add_argument_group("policy (one of)")
    g.add_argument("--model", metavar="DIR", default=None,
                   help="directory written by train.py (model.zip, config.json and "
                        "vec_normalize.pkl, whose statistics normalise the observations), or a "
                        "shipped one holding portable_policy.npz and config.json")
    g.add_argument("--policy", metavar="NAME", default=None,
                   help="scripted baseline: constant:N (fixed set-point, N in 300-2000), "
                        "feedback (raise on quasi-periodic vibration, lower slowly), "
                        "schedule[:MARGIN] (speed-scheduled table, + MARGIN N, default 100), "
                        "oracle[:MARGIN] (true operating point + stability map)")
    g = p.add_argument_group("episodes")
    g.add_argument("--episodes", type=integer, default=1, metavar="N",
                   help="episodes to play (1-1000; default %(default)d)")
    g.add_argument("--steps", type=integer, default=EPISODE_STEPS, metavar="N",
                   help="control intervals (20 ms) per episode (1-100000; default %(default)d, "
                        "the benchmark's horizon)")
    g.add_argument("--seed", type=integer, default=0, metavar="S",
                   help="seed of the first episode; episode k uses S + k (>= 0; default "
                        "%(default)d)")
    g.add_argument("--tier", choices=tuple(TIERS), default=DEFAULT_TIER,
                   help="difficulty tier (bearing_gym.envs.tiers): paper (20000 rpm, c = 4 um), "
                        "stationary (a random operating point), transient (plus speed ramps and "
                        "load steps) or field (plus sensor errors); default %(default)s")
    g.add_argument("--frames", metavar="DIR", default=None,
                   help="also save every frame as DIR/frame_NNNNN.png (default without a "
                        "display: only the latest frame, in <temp dir>/bearing_gym_frames/latest.png)")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="print nothing but errors (no step lines)")
    return p


_POLICY_HELP = "constant:N, feedback, schedule[:MARGIN] or oracle[:MARGIN]"


def make_policy(args):
    """The policy of --model or --policy; CLIError naming the option if it is not usable."""
    if (args.model is None) == (args.policy is None):
        raise CLIError("--model/--policy: give exactly one (a train.py output directory, or a "
                       f"scripted policy: {_POLICY_HELP})")
    if args.model is not None:
        d = Path(args.model)
        if not d.is_dir():
            raise CLIError(f"--model: no such directory: {d}")
        # train.py's directory (model.zip), or a shipped or collected run's portable export alone
        from agents.evaluation.trained import is_model_dir, load_trained
        missing = [n for n, ok in (("model.zip or portable_policy.npz", is_model_dir(d)),
                                   ("config.json", (d / "config.json").is_file())) if not ok]
        if missing:
            raise CLIError(f"--model: {d} has no {' and no '.join(missing)} (expected a directory written by "
                           "train.py, or one holding portable_policy.npz and config.json)")
        try:
            return load_trained(d, portable="auto")   # as the board loads it
        except Exception as err:  # noqa: BLE001 - a broken zip, an unknown algo, ...
            raise CLIError(f"--model: cannot load {d}: {type(err).__name__}: "
                           f"{one_line(err)}") from None
    from agents.policies.scripted import ConstantPreload, FeedbackRule, OraclePreload, SpeedScheduledPreload

    name, _, value = str(args.policy).strip().partition(":")
    name = name.lower()
    if name == "feedback" and not value:
        return FeedbackRule()
    if name == "constant" or name in ("schedule", "oracle"):
        if name == "constant" and not value:
            raise CLIError("--policy: constant needs a preload, e.g. constant:1000 (N)")
        try:
            number = float(value) if value else 100.0
        except ValueError:
            raise CLIError(f"--policy: not a number after '{name}:': {value!r}") from None
        if name == "constant":
            from bearing_gym.envs import PreloadActuator
            a = PreloadActuator()
            if not (math.isfinite(number) and a.min_preload_n <= number <= a.max_preload_n):
                raise CLIError(f"--policy: the constant preload must be in [{a.min_preload_n:g}, "
                               f"{a.max_preload_n:g}] N, got {number:g}")
            return ConstantPreload(number)
        if not (math.isfinite(number) and -2000 <= number <= 2000):
            raise CLIError(f"--policy: the margin of {name} must be in [-2000, 2000] N, got "
                           f"{number:g}")
        from agents.policies.stability_table import StabilityTable
        try:
            table = StabilityTable.load()
        except FileNotFoundError as err:
            raise CLIError(f"--policy: {name} needs the stability table: {one_line(err)}") from None
        cls = SpeedScheduledPreload if name == "schedule" else OraclePreload
        return cls(table, margin_n=number)
    raise CLIError(f"--policy: unknown policy {args.policy!r} (use {_POLICY_HELP})")


def watch(args, say: Out) -> int:
    """Play the policy of ``args`` for ``args.episodes`` episodes, one line per step."""
    import warnings

    import gymnasium as gym
    import numpy as np

    import bearing_gym  # noqa: F401 - registers BearingPreload-v0

    for opt, value, low, high in (("--episodes", args.episodes, 1, 1000),
                                  ("--steps", args.steps, 1, 100000),
                                  ("--seed", args.seed, 0, 2**32 - 1)):
        if not low <= value <= high:
            raise CLIError(f"{opt}: must be an integer in [{low}, {high}], got {value}")
    if args.frames is not None and Path(args.frames).exists() and not Path(args.frames).is_dir():
        raise CLIError(f"--frames: {args.frames} is a file; give a directory")
    policy = make_policy(args)
    oracle = type(policy).__name__ == "OraclePreload"
    env = gym.make("BearingPreload-v0", tier=args.tier, render_mode="human",
                   render_dir=args.frames, max_episode_steps=args.steps, episode_steps=args.steps)
    base = env.unwrapped
    say(f"bearing-gym watch: {policy.name} on BearingPreload-v0 (tier {args.tier}, "
        f"{args.episodes} episode(s) of {args.steps} steps of {base.control_dt_s * 1e3:g} ms)")
    try:
        for ep in range(args.episodes):
            with warnings.catch_warnings():      # the headless note is printed below instead
                warnings.filterwarnings("ignore", message=".*render_mode='human'")
                obs, info = env.reset(seed=args.seed + ep)
            target = base.human_render_target
            if ep == 0 and target not in (None, "window"):
                say("no display (or no interactive matplotlib backend): "
                    + (f"frames go to {args.frames}" if args.frames else
                       f"the latest frame goes to {target} (--frames DIR keeps all)"))
            sc = base.scenario
            sp = sc.speed_profile
            speed = " -> ".join(f"{v:.0f}" for k, (_, v) in enumerate(sp) if k == 0 or v != sp[k - 1][1])
            load = " -> ".join(f"{f:.0f}" for _, f in sc.radial_load_profile)
            say(f"episode {ep} (seed {args.seed + ep}): {speed} rpm, radial load {load} N, "
                f"clearance {sc.clearance_m * 1e6:.1f} um, initial preload "
                f"{info['preload_n']:.0f} N")
            say(f"{'ep':>3} {'step':>5} {'t (s)':>7} {'preload (N)':>12} {'set-point (N)':>14} "
                f"{'qpi':>7} {'reward':>9}")
            state, start, ret, n, qp, preload_sum = None, True, 0.0, 0, 0, 0.0
            reason = ""
            while True:
                if oracle:
                    policy.set_conditions(np.array([info["shaft_speed_rpm"]]), np.array([info["radial_load_n"]]),
                                          np.array([sc.clearance_m]), np.array([sc.eccentricity_m]))
                act, state = policy.predict(obs[None], state=state,
                                            episode_start=np.array([start]), deterministic=True)
                start = False
                action = np.clip(np.asarray(act, dtype=np.float32).reshape(1), -1.0, 1.0)
                obs, reward, term, trunc, info = env.step(action)
                n += 1
                ret += reward
                qp += info["quasi_periodic"]
                preload_sum += info["preload_n"]
                say(f"{ep:>3d} {n:>5d} {info['t']:>7.3f} {info['preload_n']:>12.1f} "
                    f"{info['setpoint_n']:>14.1f} {info['qpi']:>7.3f} {reward:>9.3f}")
                if term or trunc:
                    reason = f"; terminated: {info['termination_reason']}" if term else ""
                    break
            say(f"episode {ep}: return {ret:.3f} over {n} steps, mean preload "
                f"{preload_sum / n:.0f} N, quasi-periodic (index > {QPI_THRESHOLD}) {100 * qp / n:.0f} % of "
                f"the time{reason}")
    finally:
        env.close()
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``bearing-gym-watch``; returns the exit status (0 ok, 2 bad options)."""
    argv = list(sys.argv[1:] if argv is None else argv)

    def run() -> int:
        args = build_parser().parse_args(argv)
        return watch(args, Out(bool(args.quiet)))

    return guarded(run, PROG)


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
