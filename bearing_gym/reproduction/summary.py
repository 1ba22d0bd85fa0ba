"""The numbers of a reproduction run (``summary.json``): critical preloads with their brackets,
Floquet multipliers, responses, cage speeds, waviness and linear stability."""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import numpy as np

from bearing_gym.analysis.sweeps import axial_index, critical_preload, stable_windows
from bearing_gym.params import default_params

from .experiments import collect, waviness_summary
from .plan import DAMPING_MODEL, QPI_THRESHOLD, Plan

__all__ = ["crit", "loss_mode", "floquet_axial_pair", "physics_hash", "summarize"]

def crit(rows: list[dict]) -> dict:
    """Critical preload of one sweep with its bracket, the period-1 windows, how the points were
    reached and the damping ratio they were computed with."""
    c = critical_preload(rows)
    modes = sorted({r["mode"] for r in rows})
    zetas = sorted({r["damping_ratio"] for r in rows if math.isfinite(r["damping_ratio"])})
    return dict(critical_n=c["critical_n"], bracket_n=list(c["bracket_n"]), note=c["note"],
                stable_windows_n=[list(w) for w in stable_windows(rows)],
                method=" / ".join(modes), damping_ratio=zetas[0] if len(zetas) == 1 else zetas)


def loss_mode(rows: list[dict]) -> dict | None:
    """The first unstable point of a descending chain that was still on the orbit (index below
    the threshold, leading multiplier outside the unit circle): which mode lost stability."""
    for r in sorted(rows, key=lambda r: -r["axial_preload_n"]):
        if math.isfinite(r["floquet_max_modulus"]) and r["floquet_max_modulus"] >= 1.0:
            return dict(axial_preload_n=r["axial_preload_n"], modulus=r["floquet_max_modulus"],
                        angle_deg=r["floquet_max_angle_deg"], mode=r["floquet_max_mode"])
    return None


def floquet_axial_pair(fl: dict | None) -> dict | None:
    """The least stable multiplier pair with at least 20 % axial (z, z_dot) share, chosen as
    :func:`bearing_gym.analysis.sweeps.axial_pair` chooses it, from the ``pairs`` of a
    response's Floquet summary (None without multipliers)."""
    if not fl or not fl["pairs"]:
        return None
    pairs = fl["pairs"]
    return pairs[axial_index([m["modulus"] for m in pairs], [m["axial_share"] for m in pairs])]


def physics_hash() -> str:
    """sha256 of the physics sources, params.py and the modules it builds on, with which the
    numbers were computed."""
    root = Path(__file__).resolve().parent.parent
    h = hashlib.sha256()
    for path in ([root / "validation.py", root / "units.py", root / "params.py"]
                 + sorted((root / "physics").glob("*.py"))):
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def summarize(results: dict, plan: Plan, wall_s: float, physics_sha: str) -> dict:
    down = results["default_down"]
    cold = collect(results, "default_cold_")
    d800, d600c, d600 = results["detail_800"], results["detail_600_cont"], results["detail_600_cold"]
    ax800, ax600 = floquet_axial_pair(d800["floquet"]), floquet_axial_pair(d600c["floquet"])
    S: dict = dict(
        plan=plan.name, wall_time_s=wall_s, physics_source_sha256=physics_sha,
        grids=dict(default_down=[plan.default_down[0], plan.default_down[-1]],
                   default_up_start=plan.default_up[0] if plan.default_up else None,
                   clearance_down=[plan.clearance_down[0], plan.clearance_down[-1]],
                   radial_down=[plan.radial_down[0], plan.radial_down[-1]]),
        damping_model=DAMPING_MODEL + "; zeta = 0.02 unless stated",
        qpi_threshold=QPI_THRESHOLD,
        sweep_settings=dict(settle_s=plan.sweep_settle_s, measure_s=plan.sweep_measure_s,
                            cold_settle_s=plan.sweep_cold_settle_s),
        critical_preload_n=crit(down)["critical_n"],
        critical_preload_note=("continuation: preload stepped down from the previous end state "
                               "(bifurcation of the period-1 orbit), damping zeta = 2 %"),
        critical_preload_detail=dict(continuation=crit(down), cold_start=crit(cold) if cold else None,
                                     loss_of_stability=loss_mode(down),
                                     upward_continuation=crit(results["default_up"]) if "default_up" in results else None),
        critical_preload_n_cold=crit(cold)["critical_n"] if cold else None,
    )
    if "default_up" in results:
        up = sorted(results["default_up"], key=lambda r: r["axial_preload_n"])
        back = next((r["axial_preload_n"] for r in up if r["periodic"]), math.nan)
        S["upward_continuation_returns_to_period1_at_n"] = back
    for pr in plan.radial_loads_n:
        rows = results[f"radial_down_{pr:g}"]
        S[f"critical_preload_n_radial_{pr:g}"] = crit(rows)["critical_n"]
        S[f"critical_preload_detail_radial_{pr:g}"] = dict(
            continuation=crit(rows), loss_of_stability=loss_mode(rows),
            cold_start=crit([r for r in collect(results, f"radial_cold_{pr:g}_")]) if plan.radial_cold else None)
    S["floquet_modulus_800n"] = ax800["modulus"] if ax800 else None
    S["floquet_modulus_600n"] = ax600["modulus"] if ax600 else None
    S["floquet_note"] = ("modulus of the least stable axial multiplier pair (>= 20 % of the scaled "
                         "eigenvector in z, z_dot: the mode family that leaves the unit circle at the "
                         "critical preload) on the period-1 orbit reached by continuation (800 N: "
                         "1000-900-800 N; 600 N: 800-700-650-620-600 N); stroboscopic section at the "
                         "shaft period, state (X, V), central finite differences; zeta = 2 %. The largest "
                         "modulus overall is the slow backward rocking mode (floquet_leading_modulus_800n)")
    S["floquet_800n"] = d800["floquet"]
    S["floquet_600n_continuation"] = d600c["floquet"]
    S["floquet_leading_modulus_800n"] = max((p["modulus"] for p in d800["floquet"]["pairs"]), default=None) \
        if d800["floquet"] else None
    S["critical_preload_n_by_clearance"] = {f"{c:g}": crit(results[f"clearance_down_{c:g}"])["critical_n"]
                                            for c in plan.clearances_um}
    S["clearance_detail"] = {f"{c:g}": dict(
        continuation=crit(results[f"clearance_down_{c:g}"]),
        cold_start=crit(collect(results, f"clearance_cold_{c:g}_")) if plan.clearance_cold else None)
        for c in plan.clearances_um}
    S["cage_speed_ratio_by_rpm"] = {f"{r:g}": results[f"cage_{r:g}"]["ratio"] for r in plan.cage_rpms}
    S["cage_runs"] = {f"{r:g}": {k: v for k, v in results[f"cage_{r:g}"].items()} for r in plan.cage_rpms}
    S["cage_run_20000rpm_e1e-5"] = results["cage_20000_e1e-05"]
    S["clearance_static_800n"] = results["clearance_static"]
    S["cage_speed_ratio_static_by_rpm"] = {f"{r:g}": v["ratio"] for r, v in results["cage_static"].items()}
    g = default_params().geometry
    S["cage_speed_ratio_epicyclic"] = 0.5 * (1 - g.diameter_ratio * math.cos(g.contact_angle_rad))
    m = results["models"]
    full = m["full"]["x"]
    S["three_models_2000rpm"] = {k: dict(ptp_x_m=float(np.ptp(v["x"])),
                                         max_abs_diff_to_full_m=float(np.max(np.abs(v["x"] - full))),
                                         cage_speed_ratio=v["ratio"], alpha_i_deg=v["alpha_i_deg"],
                                         alpha_o_deg=v["alpha_o_deg"], z_static_m=v["z_static"])
                                 for k, v in m.items()}
    for key, d in (("800n", d800), ("600n_cold", d600), ("600n_continuation", d600c),
                   ("570n_continuation", results["detail_570_cont"])):
        S[f"response_{key}"] = dict(
            qpi=d["qpi"], ptp_m={k: v for k, v in d["ptp"].items() if k != "cage"},
            cage_ptp_rad_s=d["ptp"]["cage"], cage_mean_rad_s=d["cage_mean"],
            cage_principal_hz=d["spectra"]["cage"]["peaks"][0][0] if d["spectra"]["cage"]["peaks"] else None,
            z_principal_hz=d["spectra"]["z"]["peaks"][0][0] if d["spectra"]["z"]["peaks"] else None,
            x_principal_hz=d["spectra"]["x"]["peaks"][0][0] if d["spectra"]["x"]["peaks"] else None,
            x_peaks_hz=[p[0] for p in d["spectra"]["x"]["peaks"]],
            z_peaks_hz=[p[0] for p in d["spectra"]["z"]["peaks"]],
            cage_peaks_hz=[p[0] for p in d["spectra"]["cage"]["peaks"]],
            shaft_hz=d["shaft_hz"], ball_pass_hz=d["bpfo_hz"], ball_pass_inner_hz=d["bpfi_hz"],
            lyapunov_per_s=d["lyapunov"]["exponent_per_s"] if d["lyapunov"] else None,
            path_n=list(d["path"]))
    for p_end in (1200.0, 1100.0):
        k = f"detail_pr200_{p_end:g}"
        if k in results:
            d = results[k]
            S[f"response_radial200_{p_end:g}n"] = dict(
                qpi=d["qpi"], cage_principal_hz=d["spectra"]["cage"]["peaks"][0][0],
                x_peaks_hz=[p[0] for p in d["spectra"]["x"]["peaks"]],
                cage_peaks_hz=[p[0] for p in d["spectra"]["cage"]["peaks"]],
                ball_pass_hz=d["bpfo_hz"], ball_pass_inner_hz=d["bpfi_hz"], shaft_hz=d["shaft_hz"],
                path_n=list(d["path"]))
    S["waviness"] = waviness_summary(results)
    S["linear_stability_e0"] = results["linear"]
    if plan.speed_map_rpms:
        S["critical_preload_n_by_rpm"] = {f"{r:g}": crit(results[f"speed_{r:g}"])["critical_n"]
                                          for r in plan.speed_map_rpms}
    if plan.damping_ratios:
        S["critical_preload_n_by_damping_ratio"] = {"0.02": S["critical_preload_n"]}
        S["critical_preload_n_cold_by_damping_ratio"] = {"0.02": S["critical_preload_n_cold"]}
        for z in plan.damping_ratios:
            S["critical_preload_n_by_damping_ratio"][f"{z:g}"] = crit(results[f"damping_down_{z:g}"])["critical_n"]
            S["critical_preload_n_cold_by_damping_ratio"][f"{z:g}"] = crit(
                collect(results, f"damping_cold_{z:g}_"))["critical_n"]
    return S
