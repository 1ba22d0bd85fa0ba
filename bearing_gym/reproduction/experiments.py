"""The computations of the reproduction: one worker task per curve or response (module-level
functions, so that process pools can pickle them) and the task list of a plan."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from bearing_gym.params import BallWaviness, BearingParams, RaceWaviness, Waviness, default_params
from bearing_gym.units import rpm_to_rad_s

from .plan import QPI_THRESHOLD, Plan, sweep_settings

__all__ = ["WAVINESS_CASES", "run_task", "tasks", "collect", "waviness_summary",
           "simulator_variant"]

def run_task(kind: str, kwargs: dict) -> Any:
    from bearing_gym.analysis import sweeps

    if kind == "chain":
        return sweeps.continuation_chain(**kwargs)
    if kind == "cold":
        return sweeps.cold_start_point(**kwargs)
    return {"detail": _detail, "cage": _cage_run, "cage_static": _cage_static,
            "models": _models_run, "waviness": _waviness_run, "linear": _linear_run,
            "clearance_static": _clearance_static}[kind](**kwargs)


def _clearance_static(clearances_um: tuple, preload: float = 800.0) -> dict:
    """Static equilibrium at 20,000 rpm for each clearance: contact angles, loads and the
    radial and axial stiffness (claim 5 discussion)."""
    from bearing_gym.physics import static_equilibrium

    out = {}
    for c in clearances_um:
        eq = static_equilibrium(default_params(clearance_inner_m=c * 1e-6, clearance_outer_m=c * 1e-6,
                                               axial_preload_n=preload))
        out[f"{c:g}"] = dict(alpha_i_deg=math.degrees(float(eq.alpha_i[0])),
                             alpha_o_deg=math.degrees(float(eq.alpha_o[0])), q_i_n=float(eq.q_i[0]),
                             k_xx_n_per_m=float(eq.stiffness[0, 0]), k_zz_n_per_m=float(eq.stiffness[2, 2]))
    return out


def _cage_static(rpms: tuple) -> dict:
    """Quasi-static cage/shaft speed ratio (eq 7 at the static equilibrium), no unbalance."""
    from bearing_gym.physics import static_equilibrium

    out = {}
    for rpm in rpms:
        eq = static_equilibrium(default_params(shaft_speed_rpm=rpm, eccentricity_m=2e-5))
        out[rpm] = dict(ratio=eq.cage_speed_ratio, alpha_i_deg=math.degrees(float(eq.alpha_i[0])),
                        alpha_o_deg=math.degrees(float(eq.alpha_o[0])))
    return out


def _cage_run(rpm: float, settle_s: float, measure_s: float, eccentricity_m: float = 2e-5) -> dict:
    """Claim 1: mean cage speed of the dynamic response, default preload (800 N), cold start."""
    from bearing_gym.analysis import quasi_periodicity_index
    from bearing_gym.physics import Simulator

    sim = Simulator(default_params(shaft_speed_rpm=rpm, eccentricity_m=eccentricity_m))
    sim.advance(settle_s)
    rec = sim.advance(measure_s)
    w = rpm_to_rad_s(rpm)
    return dict(rpm=rpm, eccentricity_m=eccentricity_m, ratio=float(np.mean(rec.cage_speed)) / w,
                qpi=quasi_periodicity_index(rec.t, np.column_stack([rec.x, rec.y, rec.z]), w),
                ptp_x_m=float(np.ptp(rec.x)), ptp_z_m=float(np.ptp(rec.z)),
                min_inner_contacts=int(np.min(rec.n_inner_contacts)),
                ratio_min=float(np.min(rec.cage_speed)) / w,
                ratio_max=float(np.max(rec.cage_speed)) / w,
                ratio_static=sim.equilibrium.cage_speed_ratio)


def simulator_variant(params: BearingParams, centrifugal: bool, gyroscopic: bool):
    """Simulator of ``params`` with the ball centrifugal force and/or gyroscopic moment switched
    off (``include_centrifugal``, ``include_gyroscopic``), started at the static equilibrium *of
    that variant*, with the damping coefficients of the full model (so that the three models
    differ only in the high-speed terms)."""
    from bearing_gym.physics import Simulator

    sim = Simulator(params)
    if centrifugal and gyroscopic:
        return sim
    return Simulator(params.replace(include_centrifugal=centrifugal, include_gyroscopic=gyroscopic,
                                    damping_coefficients=tuple(sim.damping_coefficients)))


def _models_run(settle_s: float, measure_s: float) -> dict:
    """Claim 2: x(t) at 2,000 rpm, 800 N for the three models (same damping coefficients)."""
    params = default_params(shaft_speed_rpm=2000.0)
    out = {}
    for name, cf, gy in (("full", True, True), ("no centrifugal, no gyroscopic", False, False),
                         ("centrifugal only", True, False)):
        sim = simulator_variant(params, cf, gy)
        sim.advance(settle_s)
        rec = sim.advance(measure_s)
        out[name] = dict(t=rec.t.copy(), x=rec.x.copy(), ratio=sim.equilibrium.cage_speed_ratio,
                         alpha_i_deg=math.degrees(float(sim.equilibrium.alpha_i[0])),
                         alpha_o_deg=math.degrees(float(sim.equilibrium.alpha_o[0])),
                         z_static=float(sim.equilibrium.U[2]))
    return out


WAVINESS_CASES = ("none", "inner race", "outer race", "balls", "balls, random phases")


def _waviness_case(case: str) -> Waviness:
    if case == "none":
        return Waviness()
    if case == "inner race":
        return Waviness(inner=RaceWaviness(orders=(18,), radial_amplitudes_m=(1e-6,)))
    if case == "outer race":
        return Waviness(outer=RaceWaviness(orders=(18,), radial_amplitudes_m=(1e-6,)))
    if case == "balls":
        return Waviness(balls=BallWaviness(orders=(2,), amplitudes_m=(1e-6,)))
    if case == "balls, random phases":     # zeta_nj of eqs 13-14 drawn per ball (seed 0)
        phases = np.random.default_rng(0).uniform(0.0, 2 * math.pi, (18, 1))
        return Waviness(balls=BallWaviness(orders=(2,), amplitudes_m=(1e-6,),
                                           phases_rad=tuple(tuple(r) for r in phases)))
    raise ValueError(case)


def _waviness_run(case: str, settle_s: float, measure_s: float, eccentricity_m: float) -> dict:
    """Claim 7: cage speed with waviness (20,000 rpm, 800 N), cold start. With e = 0 the rotor
    without waviness is at rest, so every variation of the cage speed is the waviness's own;
    with e = 1e-5 m (the paper's setting) it adds to the unbalance response."""
    from bearing_gym.physics import Simulator
    from bearing_gym.analysis.spectra import principal_frequency

    sim = Simulator(default_params(waviness=_waviness_case(case), eccentricity_m=eccentricity_m))
    sim.advance(settle_s)
    rec = sim.advance(measure_s)
    keep = rec.t >= rec.t[-1] - 0.01
    cage = rec.cage_speed
    return dict(case=case, eccentricity_m=eccentricity_m, t=rec.t[keep].copy(), cage=cage[keep].copy(),
                cage_mean_rad_s=float(np.mean(cage)), cage_ptp_rad_s=float(np.ptp(cage)),
                cage_std_rad_s=float(np.std(cage)),
                cage_principal_hz=principal_frequency(rec.t, cage) if np.ptp(cage) > 1e-9 else None,
                ptp_z_m=float(np.ptp(rec.z)), ptp_x_m=float(np.ptp(rec.x)))


def waviness_summary(results: dict) -> dict:
    keys = ("cage_mean_rad_s", "cage_ptp_rad_s", "cage_std_rad_s", "cage_principal_hz", "ptp_z_m", "ptp_x_m")
    return {f"e={e:g}": {case: {k: results[f"waviness_{case}_e{e:g}"][k] for k in keys}
                         for case in WAVINESS_CASES} for e in (0.0, 1e-5)}


def _linear_run(preloads: tuple) -> list[dict]:
    from bearing_gym.analysis.linear import equilibrium_eigenvalues

    out = []
    for p in preloads:
        lam, _ = equilibrium_eigenvalues(default_params(axial_preload_n=p, eccentricity_m=0.0))
        out.append(dict(axial_preload_n=p, max_real_per_s=float(lam[0].real),
                        eigenvalues=[(float(v.real), float(v.imag / (2 * math.pi))) for v in lam]))
    return out


def _detail(params: BearingParams, path: tuple, first_settle_s: float, path_settle_s: float,
            measure_s: float, lyapunov_s: float) -> dict:
    """Response at the last preload of ``path``: cold start at path[0] (``first_settle_s``), then
    continuation through the other preloads (``path_settle_s`` each), then ``measure_s`` of
    record. Returns the traces, spectra, Poincare points, Floquet multipliers (if period-1)
    and the largest Lyapunov exponent (over ``lyapunov_s`` after the record)."""
    from bearing_gym.analysis import quasi_periodicity_index
    from bearing_gym.analysis.floquet import simulator_floquet
    from bearing_gym.analysis.lyapunov import simulator_lyapunov
    from bearing_gym.analysis.poincare import cage_section, shaft_section
    from bearing_gym.analysis.spectra import (ball_pass_frequency, ball_pass_frequency_inner,
                                              power_spectrum, spectral_peaks)
    from bearing_gym.physics import Simulator

    state = None
    for k, p in enumerate(path):
        sim = Simulator(params.replace(axial_preload_n=float(p)))
        if state is not None:
            sim.state = state
        sim.advance(first_settle_s if k == 0 else path_settle_s)
        state = sim.state
    rec = sim.advance(measure_s)
    w = rpm_to_rad_s(sim.shaft_speed_rpm)
    xyz = np.column_stack([rec.x, rec.y, rec.z])
    qpi = quasi_periodicity_index(rec.t, xyz, w)
    wc = float(np.mean(rec.cage_speed))
    n_balls = params.geometry.n_balls
    spectra = {}
    for name, sig in (("cage", rec.cage_speed), ("z", rec.z), ("x", rec.x)):
        f, p = power_spectrum(rec.t, sig, segment_s=min(measure_s, 0.1))
        keep = f <= 4000.0
        spectra[name] = dict(f=f[keep], p=p[keep],
                             peaks=spectral_peaks(rec.t, sig, 8, fmin_hz=1.0, segment_s=min(measure_s, 0.1)))
    win = rec.t >= rec.t[-1] - 0.03
    orb = rec.t >= rec.t[-1] - 0.1
    out = dict(
        preload=float(path[-1]), path=tuple(path), qpi=qpi, shaft_hz=w / (2 * math.pi),
        cage_mean=wc, bpfo_hz=ball_pass_frequency(wc, n_balls),
        bpfi_hz=ball_pass_frequency_inner(w, wc, n_balls),
        ptp=dict(x=float(np.ptp(rec.x)), y=float(np.ptp(rec.y)), z=float(np.ptp(rec.z)),
                 cage=float(np.ptp(rec.cage_speed))),
        trace=dict(t=rec.t[win].copy(), x=rec.x[win].copy(), z=rec.z[win].copy(),
                   cage=rec.cage_speed[win].copy()),
        orbit=dict(x=rec.x[orb][::2].copy(), y=rec.y[orb][::2].copy(), z=rec.z[orb][::2].copy()),
        shaft_section=shaft_section(rec), cage_section=cage_section(rec),
        spectra=spectra, floquet=None, lyapunov=None)
    if qpi < QPI_THRESHOLD:
        res = simulator_floquet(sim)
        axial = res.share(("z", "z_dot"))
        out["floquet"] = dict(multipliers=[complex(m) for m in res.multipliers],
                              pairs=[dict(mu=m["mu"], modulus=m["modulus"], angle_deg=m["angle_deg"],
                                          rate_per_s=m["rate_per_s"], freq_folded_hz=m["freq_hz"],
                                          dominant=[lab for lab, _ in m["dominant"]],
                                          axial_share=float(axial[m["index"]]))
                                     for m in res.pairs()],
                              det=float(np.prod(res.multipliers).real),
                              liouville_det=res.info["liouville_det"], section=res.section)
    if lyapunov_s > 0:
        # the first 0.1 s is not counted: the separation aligns with the least stable direction
        ly = simulator_lyapunov(sim, lyapunov_s, transient_s=min(0.1, lyapunov_s))
        out["lyapunov"] = dict(exponent_per_s=ly.exponent, spread_per_s=ly.spread(),
                               duration_s=lyapunov_s)
    return out


def tasks(plan: Plan) -> list[tuple[str, str, dict]]:
    base = default_params()
    T: list[tuple[str, str, dict]] = []
    s = sweep_settings(plan)
    # longest first (chains), for load balance
    T.append(("default_down", "chain", dict(base=base, preloads=plan.default_down,
                                             settings=sweep_settings(plan, plan.default_refine_n),
                                             label="down")))
    if plan.default_up:
        T.append(("default_up", "chain", dict(base=base, preloads=plan.default_up, settings=s,
                                               label="up")))
    for c in plan.clearances_um:
        T.append((f"clearance_down_{c:g}", "chain", dict(
            base=base.replace(clearance_inner_m=c * 1e-6, clearance_outer_m=c * 1e-6),
            preloads=plan.clearance_down, settings=sweep_settings(plan, plan.clearance_refine_n),
            label=f"c{c:g}um")))
    for pr in plan.radial_loads_n:
        T.append((f"radial_down_{pr:g}", "chain", dict(
            base=base.replace(radial_load_x_n=pr, radial_load_y_n=pr), preloads=plan.radial_down,
            settings=sweep_settings(plan, plan.radial_refine_n), label=f"Pr{pr:g}N")))
    for rpm in plan.speed_map_rpms:
        T.append((f"speed_{rpm:g}", "chain", dict(base=base.replace(shaft_speed_rpm=rpm),
                                                   preloads=plan.speed_map_preloads, settings=s,
                                                   label=f"{rpm:g}rpm")))
    for z in plan.damping_ratios:
        T.append((f"damping_down_{z:g}", "chain", dict(
            base=base.replace(damping_ratio=z), preloads=plan.damping_down,
            settings=sweep_settings(plan, plan.default_refine_n), label=f"zeta{z:g}")))
    # details
    T.append(("detail_800", "detail", dict(params=base, path=(1000.0, 900.0, 800.0),
                                           first_settle_s=plan.detail_first_settle_s,
                                           path_settle_s=plan.detail_path_settle_s,
                                           measure_s=plan.detail_measure_s, lyapunov_s=plan.lyapunov_s)))
    T.append(("detail_600_cold", "detail", dict(params=base, path=(600.0,),
                                                first_settle_s=plan.detail_first_settle_s,
                                                path_settle_s=plan.detail_path_settle_s,
                                                measure_s=plan.detail_measure_s, lyapunov_s=plan.lyapunov_s)))
    T.append(("detail_600_cont", "detail", dict(params=base, path=(800.0, 700.0, 650.0, 620.0, 600.0),
                                                first_settle_s=plan.detail_first_settle_s,
                                                path_settle_s=plan.detail_path_settle_s,
                                                measure_s=plan.detail_measure_s, lyapunov_s=plan.lyapunov_s)))
    T.append(("detail_570_cont", "detail", dict(
        params=base, path=(800.0, 700.0, 650.0, 620.0, 600.0, 590.0, 585.0, 580.0, 575.0, 570.0),
        first_settle_s=plan.detail_first_settle_s, path_settle_s=plan.detail_path_settle_s,
        measure_s=plan.detail_measure_s, lyapunov_s=plan.lyapunov_s)))
    if plan.radial_spectra:
        pr200 = base.replace(radial_load_x_n=200.0, radial_load_y_n=200.0)
        for p_end in (1200.0, 1100.0):
            path = tuple(float(p) for p in range(2000, int(p_end) - 1, -100))
            T.append((f"detail_pr200_{p_end:g}", "detail", dict(
                params=pr200, path=path, first_settle_s=plan.detail_first_settle_s,
                path_settle_s=plan.sweep_settle_s, measure_s=plan.detail_measure_s, lyapunov_s=0.0)))
    T.append(("models", "models", dict(settle_s=plan.models_settle_s, measure_s=plan.models_measure_s)))
    for rpm in plan.cage_rpms:
        T.append((f"cage_{rpm:g}", "cage", dict(rpm=rpm, settle_s=plan.cage_settle_s,
                                                 measure_s=plan.cage_measure_s)))
    T.append(("cage_20000_e1e-05", "cage", dict(rpm=20000.0, settle_s=plan.cage_settle_s,
                                                 measure_s=plan.cage_measure_s, eccentricity_m=1e-5)))
    T.append(("cage_static", "cage_static", dict(rpms=plan.cage_static_rpms)))
    T.append(("clearance_static", "clearance_static", dict(clearances_um=plan.clearances_um)))
    for e in (0.0, 1e-5):
        for case in WAVINESS_CASES:
            T.append((f"waviness_{case}_e{e:g}", "waviness", dict(
                case=case, settle_s=plan.waviness_settle_s, measure_s=plan.waviness_measure_s,
                eccentricity_m=e)))
    T.append(("linear", "linear", dict(preloads=plan.linear_preloads)))
    # cold starts (many short tasks last)
    for p in plan.default_cold:
        T.append((f"default_cold_{p:g}", "cold", dict(params=base.replace(axial_preload_n=p),
                                                       settings=s, label="cold")))
    if plan.clearance_cold:
        for c in plan.clearances_um:
            for p in plan.clearance_down:
                T.append((f"clearance_cold_{c:g}_{p:g}", "cold", dict(
                    params=base.replace(clearance_inner_m=c * 1e-6, clearance_outer_m=c * 1e-6,
                                        axial_preload_n=p), settings=s, label=f"c{c:g}um")))
    if plan.radial_cold:
        for pr in plan.radial_loads_n:
            for p in plan.radial_down:
                T.append((f"radial_cold_{pr:g}_{p:g}", "cold", dict(
                    params=base.replace(radial_load_x_n=pr, radial_load_y_n=pr, axial_preload_n=p),
                    settings=s, label=f"Pr{pr:g}N")))
    for z in plan.damping_ratios:
        for p in plan.damping_cold:
            T.append((f"damping_cold_{z:g}_{p:g}", "cold", dict(
                params=base.replace(damping_ratio=z, axial_preload_n=p), settings=s,
                label=f"zeta{z:g}")))
    return T


def collect(results: dict, prefix: str) -> list[dict]:
    rows = []
    for k, v in results.items():
        if k.startswith(prefix):
            rows.extend(v if isinstance(v, list) else [v])
    return rows
