"""What the commands share to report: the quiet-aware printer, JSON files, the operating
point in words and a simulation run in chunks with a progress bar."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from bearing_gym.serialization import to_jsonable

__all__ = ["Out", "write_json", "op_text", "radial_text", "params_dict", "advance", "RecordWindow"]


class Out:
    """print() unless --quiet."""

    def __init__(self, quiet: bool):
        self.quiet = quiet

    def __call__(self, *a: Any, **k: Any) -> None:
        if not self.quiet:
            print(*a, **k)


def write_json(data: dict, dest: str | None) -> None:
    if dest is None:
        return
    text = json.dumps(to_jsonable(data), indent=1) + "\n"
    if dest == "-":
        sys.stdout.write(text)
        return
    path = Path(dest)
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def op_text(params) -> str:
    g, ld = params.geometry, params.loads
    c = (f"c = {g.clearance_inner_m * 1e6:g} um" if g.clearance_inner_m == g.clearance_outer_m
         else f"c_i = {g.clearance_inner_m * 1e6:g} um, c_o = {g.clearance_outer_m * 1e6:g} um")
    return (f"{params.shaft_speed_rpm:g} rpm, P_z = {ld.axial_preload_n:g} N, "
            f"{radial_text(ld.radial_load_x_n, ld.radial_load_y_n)}, {c}, "
            f"e = {params.rotor.eccentricity_m * 1e6:g} um, zeta = {params.damping.damping_ratio:g}, "
            f"{params.race_control}-race control")


def radial_text(fx: float, fy: float) -> str:
    """The radial load per axis and, when there is one, its resultant: ``--radial-load 200``
    loads both axes, ``P_x = 200 N, P_y = 200 N (resultant 283 N at 45 deg)``."""
    import math

    text = f"P_x = {fx:g} N, P_y = {fy:g} N"
    if fx or fy:
        text += (f" (resultant {math.hypot(fx, fy):.4g} N at "
                 f"{math.degrees(math.atan2(fy, fx)):.4g} deg)")
    return text


def params_dict(params) -> dict:
    import dataclasses

    return to_jsonable(dataclasses.asdict(params))


def advance(sim, duration_s: float, record_every: int, quiet: bool, desc: str):
    """sim.advance in chunks with a tqdm bar (shown only if the run takes more than ~1 s).
    The chunks are whole multiples of record_every steps, so the record equals one call's."""
    import numpy as np

    from bearing_gym.physics import SimulationError, SimulationRecord

    dt = sim.dt_s
    n_total = int(round(duration_s / dt))
    chunk = max(record_every, (max(n_total // 100, 1) // record_every) * record_every)
    bar = None
    if not quiet:
        from tqdm.auto import tqdm

        bar = tqdm(total=round(n_total * dt, 9), desc=desc, unit="s", delay=1.0,
                   bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s simulated [{elapsed}<{remaining}]")
    parts = []
    done = 0
    try:
        while done < n_total:
            k = min(chunk, n_total - done)
            try:
                rec = sim.advance(k * dt, record_every)
            except SimulationError as err:    # hand back everything computed so far
                if err.record is not None:
                    parts.append(err.record.data)
                partial = SimulationRecord(np.concatenate(parts), err.record.status
                                           if err.record is not None else str(err))
                raise SimulationError(str(err), partial) from None
            parts.append(rec.data)
            done += k
            if bar is not None:     # clamped: float steps must not overshoot the total
                bar.update(min(k * dt, bar.total - bar.n))
    finally:
        if bar is not None:
            bar.close()
    return SimulationRecord(np.concatenate(parts) if parts else np.empty((0, 0)))


class RecordWindow:
    """A SimulationRecord restricted to a boolean mask (for the analysis functions)."""

    def __init__(self, rec, mask):
        self._rec, self._mask = rec, mask

    def __getattr__(self, name: str):
        return getattr(self._rec, name)[self._mask]
