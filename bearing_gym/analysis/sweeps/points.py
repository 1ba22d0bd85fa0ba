"""Parameter sweeps: preload continuation, cold starts and stability maps (paper sections
3.2-3.4, Figs 7, 15-17).

Two ways to reach the steady response at a preload P, which give *different* answers near the
stability boundary because a stable period-1 orbit coexists there with large quasi-periodic or
chaotic motion (docs/model.md, "Multistability"):

* **continuation** (:func:`continuation_chain`): each point starts from the end state of the
  previous one (``Simulator.state``), so a descending chain follows the period-1 orbit until it
  loses stability. Its critical preload is the bifurcation of the periodic orbit. With
  ``refine_step_n`` the chain, on the first loss of stability, goes back to the last periodic
  state and steps down by the finer step to bracket the boundary more tightly.
* **cold start** (:func:`cold_start_point`): every point starts from the static equilibrium
  (no unbalance response yet), as a machine does when it is run up at that preload. Cold
  starts can wander for a long time before settling; the outcome is the state after
  ``SweepSettings.cold_settle_s``.

Each point is measured over ``measure_s`` after the settling time: quasi-periodicity index of
(x, y, z) (:func:`..signals.quasi_periodicity_index`), peak-to-peak and RMS of x, y, z, mean,
peak-to-peak and maximum of the cage speed, the fewest balls touching the inner race, and (if
``floquet``) the Floquet multipliers of the end state (:func:`..floquet.simulator_floquet`): the
largest modulus, its angle per shaft period and the two coordinates that dominate its
eigenvector (``floquet_max_mode``), and the least stable axial pair (:func:`axial_pair`). A
point is **periodic** when its index is below ``qpi_threshold`` *and*, when the multipliers were
computed, all of them lie inside the unit circle.

**Damping**: each point builds its Simulator from ``base.replace(axial_preload_n=P, ...)``, so
with the default damping model (``params.Damping``: ratio ζ on each rotor DOF's uncoupled,
non-rotating mode) the coefficients are referred to the static stiffness *at that point*; pass
``damping_coefficients`` in ``base`` to keep them fixed over the sweep. The ``damping_ratio``
column records ζ (NaN when fixed coefficients are used).

This module computes one point or one chain; :mod:`.runner` runs many of them in parallel,
:mod:`.store` resumes them from a CSV file, :mod:`.io` reads and writes the rows,
:mod:`.results` reads critical preloads off them and :mod:`.plots` draws them.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from bearing_gym.params import BearingParams
from bearing_gym.units import rpm_to_rad_s

from ..signals import QPI_THRESHOLD, quasi_periodicity_index

__all__ = ["COLUMNS", "SweepSettings", "AXIAL_SHARE", "axial_index", "axial_pair",
           "operating_point", "measure_point", "cold_start_point", "continuation_chain"]

COLUMNS = ("label", "mode", "order", "shaft_speed_rpm", "axial_preload_n", "radial_load_x_n",
           "radial_load_y_n", "clearance_m", "damping_ratio", "eccentricity_m", "qpi",
           "periodic", "ptp_x_m", "ptp_y_m", "ptp_z_m", "rms_x_m", "rms_y_m", "rms_z_m",
           "mean_z_m", "cage_mean_rad_s", "cage_ptp_rad_s", "cage_max_rad_s",
           "min_inner_contacts", "floquet_max_modulus", "floquet_max_angle_deg",
           "floquet_max_mode", "floquet_axial_modulus", "floquet_axial_angle_deg", "refined",
           "status", "wall_s")


@dataclass(frozen=True)
class SweepSettings:
    """Durations (s) and criteria of a sweep point.

    ``settle_s``: time run before measuring in a continuation point; ``cold_settle_s``: the same
    for a cold start (longer: it starts from the static equilibrium); ``measure_s``: the
    measured window (>= 3 shaft periods); ``qpi_threshold``: index above which the motion is
    not period-1 (periodic motion settles at 0.00-0.04, quasi-periodic at 0.2-1);
    ``floquet``: compute the multipliers at points whose index is below the threshold;
    ``refine_step_n``: finer preload step used to bracket the first loss of stability in a
    descending continuation chain (None: no refinement).
    """

    settle_s: float = 0.3
    measure_s: float = 0.1
    cold_settle_s: float = 0.5
    qpi_threshold: float = QPI_THRESHOLD
    floquet: bool = True
    refine_step_n: float | None = None

    def __post_init__(self) -> None:
        for name in ("settle_s", "measure_s", "cold_settle_s"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v >= 0 and math.isfinite(v)):
                raise ValueError(f"SweepSettings.{name} must be a finite number >= 0, got {v!r}")
        if not self.measure_s > 0:
            raise ValueError("SweepSettings.measure_s must be > 0 (at least 3 shaft periods)")
        if self.refine_step_n is not None and not self.refine_step_n > 0:
            raise ValueError("SweepSettings.refine_step_n must be > 0 or None")


# ---------------------------------------------------------------------------------------------
# one point
# ---------------------------------------------------------------------------------------------
def operating_point(params: BearingParams) -> dict:
    """The operating-point columns of a row (:data:`COLUMNS`): speed, loads, clearance (NaN
    when c_i != c_o), damping ratio (NaN with fixed coefficients) and eccentricity."""
    g = params.geometry
    coeffs = params.damping.coefficients
    return dict(shaft_speed_rpm=params.shaft_speed_rpm,
                axial_preload_n=params.loads.axial_preload_n,
                radial_load_x_n=params.loads.radial_load_x_n,
                radial_load_y_n=params.loads.radial_load_y_n,
                clearance_m=g.clearance_inner_m if g.clearance_inner_m == g.clearance_outer_m
                else math.nan,
                damping_ratio=params.damping.damping_ratio if coeffs is None else math.nan,
                eccentricity_m=params.rotor.eccentricity_m)


AXIAL_SHARE = 0.2


def axial_index(moduli: Sequence[float], axial_shares: Sequence[float]) -> int:
    """Index of the least stable *axial* multiplier: the largest modulus among those whose
    axial share is at least ``AXIAL_SHARE`` (20 %), or, if none is, the one with the largest
    axial share (the first one on ties)."""
    mods = np.asarray(moduli, dtype=float)
    share = np.asarray(axial_shares, dtype=float)
    if mods.shape != share.shape or mods.size == 0:
        raise ValueError(f"moduli and axial_shares must be non-empty and of one length, got "
                         f"{mods.shape} and {share.shape}")
    cand = np.flatnonzero(share >= AXIAL_SHARE)
    return int(cand[np.argmax(mods[cand])]) if cand.size else int(np.argmax(share))


def axial_pair(res) -> tuple[float, float]:
    """Modulus and angle (deg, 0-180) of the least stable *axial* multiplier pair: the largest
    |μ| among the pairs whose scaled eigenvector has at least ``AXIAL_SHARE`` (20 %) of its
    weight in (z, z_dot) (or, if none has, the pair with the largest such share). In the
    default configuration this mode family loses stability at the critical preload; near it
    two axial pairs exchange character (veering), which is why a share threshold is used
    rather than the single most axial pair."""
    k = axial_index(np.abs(res.multipliers), res.share(("z", "z_dot")))
    mu = res.multipliers[k]
    return float(abs(mu)), float(abs(math.degrees(np.angle(mu))))


def measure_point(sim, settings: SweepSettings, settle_s: float) -> tuple[dict, Any]:
    """Advance ``sim`` by ``settle_s``, record ``settings.measure_s`` and return the metrics
    (the measured columns of :data:`COLUMNS`) and the record."""
    from bearing_gym.physics import SimulationError

    t0 = time.perf_counter()
    row: dict = dict(status="ok")
    try:
        if settle_s > 0:
            sim.advance(settle_s)
        rec = sim.advance(settings.measure_s)
    except SimulationError as err:
        row.update(status=str(err), qpi=math.nan, periodic=False, wall_s=time.perf_counter() - t0)
        return row, None
    w = rpm_to_rad_s(sim.shaft_speed_rpm)
    xyz = np.column_stack([rec.x, rec.y, rec.z])
    q = quasi_periodicity_index(rec.t, xyz, w)
    ptp = np.ptp(xyz, axis=0)
    rmsv = np.std(xyz, axis=0)
    row.update(qpi=q, ptp_x_m=ptp[0], ptp_y_m=ptp[1], ptp_z_m=ptp[2], rms_x_m=rmsv[0],
               rms_y_m=rmsv[1], rms_z_m=rmsv[2], mean_z_m=float(np.mean(rec.z)),
               cage_mean_rad_s=float(np.mean(rec.cage_speed)),
               cage_ptp_rad_s=float(np.ptp(rec.cage_speed)),
               cage_max_rad_s=float(np.max(rec.cage_speed)),
               min_inner_contacts=int(np.min(rec.n_inner_contacts)))
    periodic = bool(q < settings.qpi_threshold)
    row.update(floquet_max_modulus=math.nan, floquet_max_angle_deg=math.nan, floquet_max_mode="",
               floquet_axial_modulus=math.nan, floquet_axial_angle_deg=math.nan)
    if settings.floquet and periodic and w > 0:
        from ..floquet import simulator_floquet
        try:
            res = simulator_floquet(sim)
        except Exception as err:  # noqa: BLE001 - a failed FD run is reported, not fatal
            row["status"] = f"floquet failed: {err}"
        else:
            lead = res.multipliers[0]
            row.update(floquet_max_modulus=abs(lead),
                       floquet_max_angle_deg=abs(math.degrees(np.angle(lead))),
                       floquet_max_mode="+".join(lab for lab, _ in res.modes()[0]["dominant"]))
            am, aa = axial_pair(res)
            row.update(floquet_axial_modulus=am, floquet_axial_angle_deg=aa)
            periodic = periodic and res.stable
    row["periodic"] = periodic
    row["wall_s"] = time.perf_counter() - t0
    return row, rec


def _simulator(params: BearingParams, state=None):
    from bearing_gym.physics import Simulator

    sim = Simulator(params)
    if state is not None:
        sim.state = state
    return sim


def cold_start_point(params: BearingParams, settings: SweepSettings = SweepSettings(),
                     label: str = "") -> dict:
    """One point started from the static equilibrium (see the module docstring)."""
    sim = _simulator(params)
    row, _ = measure_point(sim, settings, settings.cold_settle_s)
    return {**dict(label=label, mode="cold", order=0, refined=False),
            **operating_point(params), **row}


def continuation_chain(base: BearingParams, preloads: Sequence[float],
                       settings: SweepSettings = SweepSettings(), label: str = "",
                       start_state=None, first_settle_s: float | None = None) -> list[dict]:
    """Preload continuation: point k starts from the end state of point k-1.

    The first point starts from ``start_state`` or, by default, from the static equilibrium and
    is settled for ``first_settle_s`` (default ``settings.cold_settle_s``). A point whose
    integration fails is reported with its ``status`` and the next one starts from its own
    static equilibrium. Rows come in chain order (``order`` column); rows added by the
    refinement of the first loss of stability have ``refined=True``.
    """
    rows: list[dict] = []
    state = start_state
    prev_periodic_state = None
    prev_periodic_p = None
    refined_done = False
    order = 0

    def run(p: float, st, settle: float, refined: bool) -> tuple[dict, Any]:
        nonlocal order
        params = base.replace(axial_preload_n=float(p))
        sim = _simulator(params, st)
        row, _ = measure_point(sim, settings, settle)
        out = {**dict(label=label, mode="continuation", order=order, refined=refined),
               **operating_point(params), **row}
        order += 1
        return out, (sim.state if row["status"] == "ok" or row["status"].startswith("floquet") else None)

    for k, p in enumerate(preloads):
        settle = settings.settle_s if (k > 0 or start_state is not None) else \
            (settings.cold_settle_s if first_settle_s is None else first_settle_s)
        if state is None and k > 0:
            settle = settings.cold_settle_s
        row, state = run(p, state, settle, False)
        lost = not row["periodic"]
        if (lost and not refined_done and settings.refine_step_n and prev_periodic_state is not None
                and prev_periodic_p > p):
            # bracket the first loss of stability: back to the last periodic state, finer steps
            refined_done = True
            q = prev_periodic_p - settings.refine_step_n
            st = prev_periodic_state
            while q > p + 1e-9:
                r2, st2 = run(q, st, settings.settle_s, True)
                rows.append(r2)
                if not r2["periodic"] or st2 is None:
                    break
                st = st2
                q -= settings.refine_step_n
        rows.append(row)
        if row["periodic"] and state is not None:
            prev_periodic_state, prev_periodic_p = state, p
    return rows


