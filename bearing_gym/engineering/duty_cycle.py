"""A preload schedule for a machining duty cycle, checked on the true model, against the best
constant preload for the cycle.

A cycle is a CSV of ``time_s, speed_rpm, radial_load_n`` rows (:func:`read_cycle`): the speed runs
linearly from row to row (a row repeating the speed holds it), the radial load steps to each row's
value at its time (at 45 deg, as the env applies it); the cycle ends at the last row's time.

:func:`plan_schedule`:

1. **From the map.** At every distinct operating point of the cycle (a row's speed and load) the
   preload map (:mod:`bearing_gym.engineering.preload_map`) gives its preferred preload, with
   ``min_margin_n`` to a quasi-periodic preload on each side; while the speed ramps between two
   rows the schedule holds the larger of the two ends' preloads (the stiffer side), and switches at
   the rows' times.
2. **Checked on the whole cycle.** The schedule runs on the env's physics from the settled start
   (:class:`CycleRun`: one batch, the cycle's speed and load fed to the kernel window by window).
   Where the motion is quasi-periodic in the ``ring_intervals`` control intervals after a switch
   (the transition rings), the planner's moves are tried from a copy of the run at that switch,
   each to the next switch: a linear ramp to the new level over 6 or 15 intervals, and a kick at
   the actuator's top preload for 3, 6 or 10 intervals before the new level. The move with the
   best reward over that stretch is kept (the plain switch if none beats it); then the run goes on.
3. **Against the best constant.** Every preload of the comparison grid runs the whole cycle in the
   same batch; the best constant is the one with the highest return.

The result (:class:`Schedule`) holds the set-point of every control interval and, for the
schedule and the best constant, the cost breakdown: time quasi-periodic, the reward's heat and
fatigue costs, the share of the bearing's L10 life the cycle uses (Lundberg-Palmgren from the
contact loads), and the return. ``bearing-gym schedule --duty cycle.csv`` is the command.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

__all__ = ["Cycle", "read_cycle", "CycleRun", "Costs", "Schedule", "plan_schedule", "write_schedule", "plot",
           "EXAMPLE_CYCLE"]

#: the shipped example: a 60 s cycle of roughing at low speed under load, a ramp, finishing at
#: high speed and light load, a tool change at low speed
EXAMPLE_CYCLE = Path(__file__).resolve().parent / "example_cycle.csv"
#: rows a cycle may have (each operating point costs a row of the preload map)
MAX_CYCLE_ROWS = 200


@dataclass(frozen=True)
class Cycle:
    """A duty cycle: increasing ``times_s`` from 0, the speed (rpm) and radial load (N) at each."""

    times_s: tuple[float, ...]
    speeds_rpm: tuple[float, ...]
    radial_loads_n: tuple[float, ...]

    def __post_init__(self) -> None:
        from bearing_gym.validation import check_real_tuple
        t = check_real_tuple("duty cycle time_s", self.times_s, 0.0, 1e5)
        check_real_tuple("duty cycle speed_rpm", self.speeds_rpm, 1000.0, 60000.0)
        check_real_tuple("duty cycle radial_load_n", self.radial_loads_n, 0.0, 5000.0)
        if len(t) < 2 or t[0] != 0.0 or any(b <= a for a, b in zip(t, t[1:])):
            raise ValueError("duty cycle time_s must start at 0 and increase, with at least two rows; got "
                             f"{list(t)[:5]}...")
        if not len(t) == len(self.speeds_rpm) == len(self.radial_loads_n):
            raise ValueError("duty cycle: every row needs time_s, speed_rpm and radial_load_n")
        from bearing_gym.envs.tiers import CONTROL_DT_S
        close = [(a, b) for a, b in zip(t, t[1:]) if b - a < CONTROL_DT_S - 1e-12]
        if close:
            raise ValueError(f"duty cycle rows must be at least one control interval ({CONTROL_DT_S * 1e3:g} ms) apart; "
                             f"rows at {close[0][0]:g} s and {close[0][1]:g} s are not: resample a dense log into "
                             "segments (a row where the speed or the load changes)")
        if len(t) > MAX_CYCLE_ROWS:
            raise ValueError(f"duty cycle: {len(t)} rows; at most {MAX_CYCLE_ROWS} (each row's operating point gets a "
                             "preload-map row): resample a dense log into segments")

    @property
    def duration_s(self) -> float:
        return self.times_s[-1]

    def at(self, t: float) -> tuple[float, float]:
        """(speed rpm, radial load N) at time ``t``."""
        return float(np.interp(t, self.times_s, self.speeds_rpm)), \
            float(self.radial_loads_n[int(np.searchsorted(self.times_s, t, side="right")) - 1])

    def schedule_row(self, t: float, angle_rad: float = math.pi / 4) -> np.ndarray:
        """The kernel's schedule row (``Scenario.schedule_array``'s layout, absolute times) for the
        window from the last row at or before ``t`` on (at most ``MAX_EVENTS`` rows)."""
        from bearing_gym.envs.scenario import MAX_EVENTS, SCHEDULE_SIZE
        from bearing_gym.physics.portable_math import sincos
        from bearing_gym.units import rpm_to_rad_s
        i = max(int(np.searchsorted(self.times_s, t, side="right")) - 1, 0)
        rows = range(i, min(i + MAX_EVENTS, len(self.times_s)))
        row = np.zeros(SCHEDULE_SIZE)
        row[0] = len(rows)
        for k, j in enumerate(rows):
            row[1 + 2 * k], row[2 + 2 * k] = self.times_s[j], rpm_to_rad_s(self.speeds_rpm[j])
        base = 1 + 2 * MAX_EVENTS
        row[base] = len(rows)
        s, c = sincos(angle_rad)
        for k, j in enumerate(rows):
            f = self.radial_loads_n[j]
            row[base + 1 + 3 * k: base + 4 + 3 * k] = (self.times_s[j], f * c, f * s)
        return row


def read_cycle(path: str | Path) -> Cycle:
    """A cycle from a CSV with the columns ``time_s, speed_rpm, radial_load_n``; ValueError
    naming the file and what is wrong."""
    try:
        with Path(path).open(newline="") as fh:
            rows = list(csv.DictReader(fh))
        return Cycle(tuple(float(r["time_s"]) for r in rows), tuple(float(r["speed_rpm"]) for r in rows),
                     tuple(float(r["radial_load_n"]) for r in rows))
    except (KeyError, ValueError, TypeError) as err:
        raise ValueError(f"{path}: a duty cycle needs the columns time_s, speed_rpm, radial_load_n with numbers "
                         f"({err})") from None


@dataclass
class Costs:
    """What a preload course costs over the cycle."""

    quasi_periodic_s: float
    heat_cost: float
    fatigue_cost: float
    life_used: float                # the share of the bearing's L10 life the cycle uses
    return_: float
    quasi_periodic_intervals: list[int] = field(default_factory=list)
    #: the motion diverged (the env would end the episode there): the costs stop at that interval
    terminated: bool = False

    def as_dict(self) -> dict[str, Any]:
        return {"quasi_periodic_s": self.quasi_periodic_s, "heat_cost": self.heat_cost,
                "fatigue_cost": self.fatigue_cost, "life_used": self.life_used, "return": self.return_,
                "terminated": self.terminated}


class CycleRun:
    """``n`` copies of the cycle on the env's physics, stepped one control interval at a time,
    each with its own set-point; starts settled at ``initial_preloads_n`` (as an episode's reset)."""

    def __init__(self, cycle: Cycle, initial_preloads_n: Sequence[float], params=None, eccentricity_m: float = 10e-6,
                 clearance_m: float = 4e-6):
        from bearing_gym.envs.core import PreloadBatch
        from bearing_gym.envs.scenario import Scenario
        from bearing_gym.envs.tiers import CONTROL_DT_S, tier_parts
        parts = tier_parts("stationary")
        self.cycle, self.dt = cycle, CONTROL_DT_S
        self.reward = parts["reward"]
        self.n = len(initial_preloads_n)
        self.steps = int(round(cycle.duration_s / CONTROL_DT_S))
        self.batch = PreloadBatch(self.n, params, CONTROL_DT_S, parts["actuator"])
        v0, f0 = cycle.at(0.0)
        for b, p in enumerate(initial_preloads_n):
            self.batch.load(b, Scenario(speed_profile=((0.0, v0),), radial_load_profile=((0.0, f0),),
                                        clearance_m=clearance_m, eccentricity_m=eccentricity_m,
                                        initial_preload_n=float(p)))
        self.batch.settle(np.arange(self.n))
        self.k = 0                                   # control intervals done
        self.failed = self.batch.start_failed.copy()
        self.rewards = np.zeros((self.n, self.steps))
        self.heat = np.zeros((self.n, self.steps))
        self.fatigue = np.zeros((self.n, self.steps))
        self.life = np.zeros((self.n, self.steps))
        self.qp = np.zeros((self.n, self.steps), dtype=bool)

    def step(self, setpoints_n: np.ndarray, active: np.ndarray | None = None) -> None:
        """One control interval of the envs ``active`` (default all) towards ``setpoints_n``."""
        from bearing_gym.envs.composition import measurement
        active = np.ones(self.n, dtype=bool) if active is None else np.asarray(active, dtype=bool)
        live = active & ~self.failed                 # a diverged env is scored once, as the env ends there
        row = self.cycle.schedule_row(self.k * self.dt)
        self.batch.sched[active] = row
        before = self.batch.preload.copy()
        self.batch.step(np.asarray(setpoints_n, dtype=float), live)
        self.failed |= self.batch.status != 0
        idx = np.flatnonzero(live)
        if not len(idx):
            return
        m = measurement(self.batch, idx, before[idx], np.full(len(idx), self.steps - self.k - 1), self.failed[idx])
        r, terms = self.reward(m)
        k = self.k
        self.rewards[idx, k], self.heat[idx, k], self.fatigue[idx, k] = r, terms["heat"], terms["fatigue"]
        self.life[idx, k] = m.life_used_per_s * self.dt
        self.qp[idx, k] = m.quasi_periodic

    def advance(self) -> None:
        self.k += 1

    def branch(self, src: int, dst: Sequence[int]) -> None:
        """Envs ``dst`` become exact copies of env ``src`` (and of its record so far)."""
        self.batch.copy_env(src, np.asarray(dst))
        for a in (self.rewards, self.heat, self.fatigue, self.life, self.qp):
            a[list(dst)] = a[src]
        self.failed[list(dst)] = self.failed[src]

    def costs(self, b: int) -> Costs:
        total = 0.0
        for r in self.rewards[b]:                   # summed in step order, as every return
            total += float(r)
        return Costs(float(self.qp[b].sum() * self.dt), float(-self.heat[b].sum()), float(-self.fatigue[b].sum()),
                     float(self.life[b].sum()), total, [int(k) for k in np.flatnonzero(self.qp[b])], bool(self.failed[b]))


@dataclass
class Schedule:
    """The planned course (one set-point per control interval) and what it and the best constant
    cost; ``transitions``: each switch, whether it rang and the move kept."""

    setpoints_n: np.ndarray
    dt_s: float
    costs: Costs
    best_constant_n: float
    constant_costs: Costs
    transitions: list[dict[str, Any]]
    map_preloads: dict[str, float]


def _levels(cycle: Cycle, preferred: dict[tuple[float, float], float]) -> np.ndarray:
    """The map's schedule, one set-point per control interval (module docstring, step 1)."""
    from bearing_gym.envs.tiers import CONTROL_DT_S
    steps = int(round(cycle.duration_s / CONTROL_DT_S))
    out = np.empty(steps)
    for k in range(steps):
        t = k * CONTROL_DT_S
        i = int(np.searchsorted(cycle.times_s, t, side="right")) - 1
        here = preferred[(cycle.speeds_rpm[i], cycle.radial_loads_n[i])]
        ramp = i + 1 < len(cycle.times_s) and cycle.speeds_rpm[i + 1] != cycle.speeds_rpm[i]
        out[k] = max(here, preferred[(cycle.speeds_rpm[i + 1], cycle.radial_loads_n[i])]) if ramp else here
    return out


def _moves(old: float, new: float, top: float) -> list[tuple[str, list[float]]]:
    """The planner's transition moves from ``old`` to ``new`` (set-points of the first intervals)."""
    out = [(f"ramp over {n}", [old + (new - old) * (j + 1) / n for j in range(n)]) for n in (6, 15)]
    out += [(f"kick {n} at {top:.0f} N", [top] * n) for n in (3, 6, 10)]
    return out


def plan_schedule(cycle: Cycle, min_margin_n: float = 100.0, preloads_n: Sequence[float] | None = None,
                  constants_n: Sequence[float] | None = None, ring_intervals: int = 10, params=None,
                  eccentricity_m: float = 10e-6, clearance_m: float = 4e-6, workers: int | None = None,
                  progress=print) -> Schedule:
    """The schedule for ``cycle`` (module docstring). ``preloads_n``: the map's grid (default
    300-2000 N every 50 N); ``constants_n``: the constants compared (default every 100 N)."""
    from bearing_gym.envs.tiers import tier_parts
    from .preload_map import DEFAULT_PRELOADS_N, map_points
    say = progress or (lambda *_: None)
    act = tier_parts("stationary")["actuator"]
    lo, top = float(act.min_preload_n), float(act.max_preload_n)
    grid = tuple(preloads_n or DEFAULT_PRELOADS_N)
    constants = tuple(constants_n or tuple(float(p) for p in range(int(lo), int(top) + 1, 100)))
    points = sorted({(v, f) for v, f in zip(cycle.speeds_rpm, cycle.radial_loads_n)}
                    | {(cycle.speeds_rpm[i + 1], cycle.radial_loads_n[i]) for i in range(len(cycle.times_s) - 1)})
    say(f"duty cycle: {cycle.duration_s:g} s, {len(points)} operating points; the preload map at each")
    preferred: dict[tuple[float, float], float] = {}
    rows, _ = map_points([(v, f, clearance_m, eccentricity_m) for v, f in points], grid, params=params,
                         workers=workers, progress=progress is not None, min_margin_n=min_margin_n)
    for (v, f), row in zip(points, rows):
        p = row.preferred_n if not math.isnan(row.preferred_n) else (
            row.lowest_period1_n if not math.isnan(row.lowest_period1_n) else top)
        preferred[(v, f)] = float(p)
        say(f"  {v:,.0f} rpm, {f:.0f} N: {p:.0f} N"
            + ("" if not math.isnan(row.preferred_n) else " (no preload with the margin: the lowest period-1, or the top)"))
    plan = _levels(cycle, preferred)
    switches = [k for k in range(1, len(plan)) if plan[k] != plan[k - 1]]
    moves = max(len(_moves(0.0, 1.0, top)), 1)
    run = CycleRun(cycle, [plan[0]] + list(constants) + [plan[0]] * moves, params, eccentricity_m, clearance_m)
    n_c = len(constants)
    spare = np.arange(1 + n_c, 1 + n_c + moves)
    setp = np.zeros(run.n)
    setp[1:1 + n_c] = constants
    say(f"simulating the cycle: the schedule ({len(switches)} switches) and {n_c} constants, "
        f"{run.steps} control intervals")
    transitions: list[dict[str, Any]] = []
    constants_only = np.zeros(run.n, dtype=bool)
    constants_only[1:1 + n_c] = True
    everyone = constants_only.copy()
    everyone[0] = True

    def stretch(k0: int, k1: int, mask: np.ndarray, heads: dict[int, list[float]]) -> None:
        """Intervals k0..k1-1 of the envs ``mask``: the schedule's env on ``plan``, the constants on
        theirs, a move's env on its head then on ``plan``."""
        for j in range(k0, k1):
            sp = setp.copy()
            sp[0] = plan[j]
            for b, head in heads.items():
                sp[b] = head[j - k0] if j - k0 < len(head) else plan[j]
            run.step(sp, mask)
            run.advance()

    k = 0
    while k < run.steps:
        if k not in switches:
            stretch(k, k + 1, everyone, {})
            k += 1
            continue
        nxt = next((x for x in switches if x > k), run.steps)
        old_n, new_n = float(plan[k - 1]), float(plan[k])
        cands = _moves(old_n, new_n, top)
        run.branch(0, spare[:len(cands)])
        trial = np.zeros(run.n, dtype=bool)
        trial[0] = True
        trial[spare[:len(cands)]] = True
        stretch(k, nxt, trial, {int(spare[c]): head for c, (_, head) in enumerate(cands)})
        rang = bool(run.qp[0, k:min(k + ring_intervals, nxt)].any())
        totals = [float(np.sum(run.rewards[b, k:nxt])) for b in [0, *spare[:len(cands)]]]
        best = int(np.argmax(totals))
        kept = "switch"
        if rang and best > 0:                     # the schedule takes the better move's course and state
            kept, head = cands[best - 1]
            plan[k:k + min(len(head), nxt - k)] = head[:nxt - k]
            run.branch(int(spare[best - 1]), [0])
        transitions.append({"interval": k, "time_s": k * run.dt, "from_n": old_n, "to_n": new_n, "rang": rang,
                            "kept": kept,
                            "stretch_returns": dict(zip(["switch"] + [c[0] for c in cands], totals))})
        run.k = k                                  # the constants over the same stretch
        stretch(k, nxt, constants_only, {})
        say(f"  switch at {k * run.dt:.2f} s ({old_n:.0f} -> {new_n:.0f} N): "
            + (f"rang; kept: {kept}" if rang else "no ringing"))
        k = nxt
    returns = [run.costs(b).return_ for b in range(1, 1 + n_c)]
    b_best = 1 + int(np.argmax(returns))
    return Schedule(plan, run.dt, run.costs(0), float(constants[b_best - 1]), run.costs(b_best), transitions,
                    {f"{v:.0f} rpm, {f:.0f} N": p for (v, f), p in preferred.items()})


def write_schedule(s: Schedule, cycle: Cycle, path: str | Path) -> Path:
    """The schedule as CSV: time, speed, radial load, the set-point and the best constant."""
    path = Path(path)
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time_s", "speed_rpm", "radial_load_n", "preload_setpoint_n", "best_constant_n"])
        for k, p in enumerate(s.setpoints_n):
            v, f = cycle.at(k * s.dt_s)
            w.writerow([f"{k * s.dt_s:.2f}", f"{v:.1f}", f"{f:.1f}", f"{p:.1f}", f"{s.best_constant_n:.0f}"])
    return path


def plot(s: Schedule, cycle: Cycle, path: str | Path) -> Path:
    """Speed and load (top), the schedule against the best constant with the quasi-periodic
    intervals of each (bottom)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    t = np.arange(len(s.setpoints_n)) * s.dt_s
    fig = Figure(figsize=(9, 5.5), layout="constrained")
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.plot(t, [cycle.at(x)[0] for x in t], color="tab:blue")
    ax1.set_ylabel("speed (rpm)", color="tab:blue")
    ax1b = ax1.twinx()
    ax1b.plot(t, [cycle.at(x)[1] for x in t], color="tab:orange")
    ax1b.set_ylabel("radial load (N)", color="tab:orange")
    ax2.plot(t, s.setpoints_n, color="black", label=f"schedule ({s.costs.quasi_periodic_s:.2f} s quasi-periodic)")
    ax2.axhline(s.best_constant_n, color="tab:green", ls="--",
                label=f"best constant {s.best_constant_n:.0f} N ({s.constant_costs.quasi_periodic_s:.2f} s quasi-periodic)")
    for ks, c, y in ((s.costs.quasi_periodic_intervals, "red", 1.0), (s.constant_costs.quasi_periodic_intervals,
                                                                       "tab:green", 0.97)):
        if ks:
            ax2.scatter(np.array(ks) * s.dt_s, [ax2.get_ylim()[1] * y] * len(ks), marker="|", color=c, s=30)
    ax2.set_ylabel("preload set-point (N)")
    ax2.set_xlabel("time (s); ticks at the top: quasi-periodic intervals")
    ax2.legend(fontsize=8, loc="lower right")
    fig.savefig(path, dpi=100)
    return Path(path)
