"""The reproduction's figures (PNG files in the output directory).

Every file name a run can write is in :data:`FIGURE_NAMES`; :func:`remove_stale_figures` removes
only those of them that the current run did not write (figures of an earlier run with another
plan), never another file in the directory.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from bearing_gym.params import default_params

from .experiments import WAVINESS_CASES, collect
from .plan import PAPER, Plan

__all__ = ["FIGURE_NAMES", "write_figures", "remove_stale_figures"]

FIGURE_NAMES = frozenset({
    "claim1_cage_speed_vs_shaft_speed.png", "claim2_three_models_2000rpm.png",
    "claim3_800N_response.png", "claim4_600N_cold_start.png", "claim4_600N_continuation.png",
    "claim4_570N_continuation.png", "claim6_radial200_1200N.png", "claim6_radial200_1100N.png",
    "claim3_4_floquet_multipliers.png", "claim3_4_preload_sweep.png",
    "claim5_clearance_continuation.png", "claim5_clearance_cold.png",
    "claim6_radial_load_continuation.png", "claim6_radial_load_cold.png",
    "claim7_waviness_cage_speed.png", "stability_map_preload_speed.png",
    "damping_sensitivity.png", "linear_stability_equilibrium.png",
})


def _fig():
    from matplotlib.figure import Figure
    return Figure


def _save(fig, out: Path, name: str, written: list) -> None:
    if name not in FIGURE_NAMES:       # keeps remove_stale_figures complete
        raise ValueError(f"figure name {name!r} is not in FIGURE_NAMES")
    fig.savefig(out / name, dpi=110)
    written.append(name)


def _fig_cage(results: dict, plan: Plan, out: Path, written: list) -> None:
    Figure = _fig()
    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    ax = fig.subplots()
    st = results["cage_static"]
    rpms = sorted(st)
    ax.plot(rpms, [st[r]["ratio"] for r in rpms], "-", label="quasi-static (eq 7 at equilibrium)")
    dyn = [results[f"cage_{r:g}"] for r in plan.cage_rpms]
    ax.errorbar([d["rpm"] for d in dyn], [d["ratio"] for d in dyn],
                yerr=[[d["ratio"] - d["ratio_min"] for d in dyn], [d["ratio_max"] - d["ratio"] for d in dyn]],
                fmt="o", capsize=3, label="dynamic, e = 2e-5 m (mean, min-max)")
    g = default_params().geometry
    epi = 0.5 * (1 - g.diameter_ratio * math.cos(g.contact_angle_rad))
    ax.axhline(epi, color="k", ls="--", lw=1, label=f"epicyclic 0.5(1 - gamma cos a0) = {epi:.4f}")
    ax.set_xlabel("shaft speed (rpm)")
    ax.set_ylabel("cage speed / shaft speed")
    ax.set_title("Claim 1 (Fig. 5): cage speed vs shaft speed, P_z = 800 N", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    _save(fig, out, "claim1_cage_speed_vs_shaft_speed.png", written)


def _fig_models(results: dict, out: Path, written: list) -> None:
    Figure = _fig()
    fig = Figure(figsize=(6.4, 3.8), layout="constrained")
    ax = fig.subplots()
    for name, d in results["models"].items():
        ax.plot((d["t"] - d["t"][0]) * 1e3, d["x"] * 1e6, lw=1.2 if name == "full" else 1,
                ls="-" if name == "full" else "--", label=name)
    ax.set_xlabel("t (ms)")
    ax.set_ylabel("x (um)")
    ax.set_title("Claim 2 (Fig. 6): x at 2,000 rpm, P_z = 800 N, three models", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    _save(fig, out, "claim2_three_models_2000rpm.png", written)


def _fig_detail(d: dict, title: str, out: Path, name: str, written: list) -> None:
    Figure = _fig()
    fig = Figure(figsize=(11, 9), layout="constrained")
    ax = fig.subplots(3, 3)
    tr = d["trace"]
    t = (tr["t"] - tr["t"][0]) * 1e3
    for k, (key, lab, f) in enumerate((("cage", "cage speed (rad/s)", 1.0), ("z", "z (um)", 1e6),
                                       ("x", "x (um)", 1e6))):
        ax[0, k].plot(t, tr[key] * f, lw=0.8)
        ax[0, k].set_xlabel("t (ms)")
        ax[0, k].set_ylabel(lab)
        sp = d["spectra"][key]
        ax[1, k].semilogy(sp["f"], sp["p"], lw=0.8)
        for fr, c, lb in ((d["shaft_hz"], "r", "shaft"), (d["bpfo_hz"], "g", "N w_c"),
                          (d["bpfi_hz"], "m", "N (w - w_c)")):
            ax[1, k].axvline(fr, color=c, lw=0.6, ls="--", label=lb)
        if sp["peaks"]:
            fp = sp["peaks"][0][0]
            ax[1, k].set_title(f"{key}: principal {fp:.1f} Hz", fontsize=8)
        ax[1, k].set_xlabel("f (Hz)")
        ax[1, k].set_ylabel(f"PSD of {key}")
    ax[1, 0].legend(fontsize=6)
    o = d["orbit"]
    ax[2, 0].plot(o["x"] * 1e6, o["y"] * 1e6, lw=0.4)
    ax[2, 0].set_xlabel("x (um)")
    ax[2, 0].set_ylabel("y (um)")
    ax[2, 0].set_title("orbit (last 0.1 s)", fontsize=8)
    ax[2, 1].plot(o["x"] * 1e6, o["z"] * 1e6, lw=0.4)
    ax[2, 1].set_xlabel("x (um)")
    ax[2, 1].set_ylabel("z (um)")
    ps = np.asarray(d["shaft_section"])
    ax[2, 2].plot(ps[:, 0] * 1e6, ps[:, 2] * 1e6, ".", ms=3)
    ax[2, 2].set_xlabel("x (um)")
    ax[2, 2].set_ylabel("z (um)")
    ax[2, 2].set_title(f"Poincare, shaft period ({len(ps)} pts); index {d['qpi']:.3f}", fontsize=8)
    for a in ax.flat:
        a.grid(alpha=0.3)
    fig.suptitle(title, fontsize=10)
    _save(fig, out, name, written)


def _fig_floquet(results: dict, out: Path, written: list) -> None:
    Figure = _fig()
    fig = Figure(figsize=(11, 4.2), layout="constrained")
    ax = fig.subplots(1, 2)
    th = np.linspace(0, 2 * math.pi, 361)
    ax[0].plot(np.cos(th), np.sin(th), "k-", lw=0.6)
    for key, lab, mk in (("detail_800", "800 N (ours)", "o"), ("detail_600_cont", "600 N continuation (ours)", "s")):
        fl = results[key]["floquet"]
        if fl is None:
            continue
        mu = np.array(fl["multipliers"])
        ax[0].plot(mu.real, mu.imag, mk, mfc="none", label=lab)
    for key, lab in (("floquet_800n", "paper 800 N (corrected)"), ("floquet_600n", "paper 600 N")):
        m = PAPER[key]
        ax[0].plot([m.real, m.real], [m.imag, -m.imag], "x", ms=8, label=lab)
    ax[0].set_aspect("equal")
    ax[0].set_xlim(-2, 1.3)
    ax[0].set_ylim(-1.6, 1.6)
    ax[0].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    ax[0].set_title("Floquet multipliers (stroboscopic section, zeta = 2 %)", fontsize=9)
    ax[0].grid(alpha=0.3)
    rows = sorted([r for r in results["default_down"] if math.isfinite(r["floquet_max_modulus"])],
                  key=lambda r: r["axial_preload_n"])
    p = [r["axial_preload_n"] for r in rows]
    ax[1].plot(p, [r["floquet_max_modulus"] for r in rows], "o-", ms=3, label="largest |mu| (slow rocking mode where < 1)")
    ax[1].plot(p, [r["floquet_axial_modulus"] for r in rows], "s-", ms=3,
               label="least stable axial pair |mu| (>= 20 % in z, z_dot)")
    unstable = [r for r in results["default_down"] if math.isfinite(r["floquet_max_modulus"])
                and r["floquet_max_modulus"] >= 1]
    if unstable:
        ax[1].plot([r["axial_preload_n"] for r in unstable], [r["floquet_max_modulus"] for r in unstable],
                   "r^", label="unstable orbit (before leaving it)")
    ax[1].axhline(1.0, color="k", lw=0.6)
    ax[1].axhline(abs(PAPER["floquet_800n"]), color="g", lw=0.6, ls="--", label="paper 0.8194 (800 N)")
    ax[1].set_xlabel("axial preload (N), descending continuation")
    ax[1].set_ylabel("|Floquet multiplier|")
    ax[1].legend(fontsize=7)
    ax[1].grid(alpha=0.3)
    _save(fig, out, "claim3_4_floquet_multipliers.png", written)


def _fig_preload_sweep(results: dict, out: Path, written: list) -> None:
    from bearing_gym.analysis.sweeps import plot_sweep
    rows = [r for r in results["default_down"] if not r["refined"]] + list(results.get("default_up", [])) \
        + collect(results, "default_cold_")
    fig = plot_sweep(rows, ("cage_ptp_rad_s", "ptp_z_m", "ptp_x_m", "qpi"),
                     title="Fig. 7: peak-to-peak vs preload, 20,000 rpm, c = 4 um, e = 1e-5 m, zeta = 2 %; "
                           "down/up = continuation, cold = from the static equilibrium; hollow = not period-1")
    _save(fig, out, "claim3_4_preload_sweep.png", written)


def _fig_continuation_and_cold(cont: list, cold: list, quantities: tuple, title: str, name: str,
                               out: Path, written: list) -> None:
    """A sweep figure of the continuation rows and, if there are any, one of the cold starts
    (``name`` with "continuation" replaced by "cold")."""
    from bearing_gym.analysis.sweeps import plot_sweep
    for rows, how, file in ((cont, "descending continuation", name),
                            (cold, "cold starts", name.replace("continuation", "cold"))):
        if rows or file == name:
            _save(plot_sweep(rows, quantities, title=f"{title}, {how}, zeta = 2 %"), out, file, written)


def _fig_clearance(results: dict, plan: Plan, out: Path, written: list) -> None:
    cont = [r for c in plan.clearances_um for r in results[f"clearance_down_{c:g}"] if not r["refined"]]
    _fig_continuation_and_cold(cont, collect(results, "clearance_cold_"),
                               ("ptp_z_m", "ptp_x_m", "cage_max_rad_s"),
                               "Figs 15-16: clearance sweep", "claim5_clearance_continuation.png",
                               out, written)


def _fig_radial(results: dict, plan: Plan, out: Path, written: list) -> None:
    rows = [r for r in results["default_down"] if not r["refined"]
            and r["axial_preload_n"] >= min(plan.radial_down)]
    rows = [{**r, "label": "Pr0N"} for r in rows]
    for pr in plan.radial_loads_n:
        rows += [r for r in results[f"radial_down_{pr:g}"] if not r["refined"]]
    _fig_continuation_and_cold(rows, collect(results, "radial_cold_"), ("ptp_z_m", "ptp_x_m", "qpi"),
                               "Fig. 17: radial load P_x = P_y", "claim6_radial_load_continuation.png",
                               out, written)


def _fig_waviness(results: dict, out: Path, written: list) -> None:
    Figure = _fig()
    fig = Figure(figsize=(6.4, 6.0), layout="constrained")
    ax = fig.subplots(2, 1, sharex=True)
    for a, e, title in ((ax[0], 1e-5, "e = 1e-5 m (unbalance response plus waviness)"),
                        (ax[1], 0.0, "e = 0 (waviness only)")):
        for case in WAVINESS_CASES:
            d = results[f"waviness_{case}_e{e:g}"]
            a.plot((d["t"] - d["t"][0]) * 1e3, d["cage"], lw=0.8,
                   label=f"{case}: std {d['cage_std_rad_s']:.3f} rad/s")
        a.set_ylabel("cage speed (rad/s)")
        a.set_title(title, fontsize=8)
        a.legend(fontsize=7)
        a.grid(alpha=0.3)
    ax[1].set_xlabel("t (ms), last 10 ms of the measured window")
    fig.suptitle("Claim 7 (Fig. 20): races order 18, balls order 2, 1 um; 20,000 rpm, 800 N", fontsize=9)
    _save(fig, out, "claim7_waviness_cage_speed.png", written)


def _fig_extra(results: dict, plan: Plan, out: Path, written: list) -> None:
    from bearing_gym.analysis.sweeps import plot_stability_map, plot_sweep
    if plan.speed_map_rpms:
        rows = [r for rpm in plan.speed_map_rpms for r in results[f"speed_{rpm:g}"]]
        fig = plot_stability_map(rows, "shaft_speed_rpm",
                                 title="Stability map: descending continuation, c = 4 um, e = 1e-5 m, zeta = 2 %")
        _save(fig, out, "stability_map_preload_speed.png", written)
    if plan.damping_ratios:
        rows = [{**r, "label": "zeta0.02"} for r in results["default_down"]
                if not r["refined"] and r["axial_preload_n"] <= max(plan.damping_down)]
        for z in plan.damping_ratios:
            rows += [r for r in results[f"damping_down_{z:g}"] if not r["refined"]]
        fig = plot_sweep(rows, ("ptp_z_m", "qpi"),
                         title="Damping ratio: descending continuation, 20,000 rpm, c = 4 um")
        _save(fig, out, "damping_sensitivity.png", written)
    lin = results["linear"]
    Figure = _fig()
    fig = Figure(figsize=(6.4, 3.6), layout="constrained")
    ax = fig.subplots()
    ps = [d["axial_preload_n"] for d in lin]
    n_modes = len(lin[0]["eigenvalues"])
    for k in range(n_modes):
        ax.plot(ps, [d["eigenvalues"][k][0] for d in lin], "o-", ms=3,
                label=f"{lin[-1]['eigenvalues'][k][1]:.0f} Hz at {ps[-1]:g} N")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xlabel("axial preload (N)")
    ax.set_ylabel("Re(lambda) (1/s)")
    ax.set_title("Static equilibrium, e = 0, linearised eq 35 (zeta = 2 %): all stable", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    _save(fig, out, "linear_stability_equilibrium.png", written)


def write_figures(results: dict, plan: Plan, out: Path) -> list[str]:
    """Draw every figure of ``results`` into ``out``; return the file names written."""
    written: list[str] = []
    _fig_cage(results, plan, out, written)
    _fig_models(results, out, written)
    _fig_detail(results["detail_800"], "Claim 3 (Figs 8-10): P_z = 800 N (continuation 1000-900-800 N), "
                "zeta = 2 %", out,
                "claim3_800N_response.png", written)
    _fig_detail(results["detail_600_cold"], "Claim 4 (Figs 11-14): P_z = 600 N, cold start, zeta = 2 %",
                out, "claim4_600N_cold_start.png", written)
    _fig_detail(results["detail_600_cont"], "P_z = 600 N by continuation 800-700-650-620-600 N, zeta = 2 %",
                out, "claim4_600N_continuation.png", written)
    _fig_detail(results["detail_570_cont"], "P_z = 570 N by continuation from 800 N (just below the "
                "loss of stability), zeta = 2 %", out, "claim4_570N_continuation.png", written)
    for p_end in (1200.0, 1100.0):
        k = f"detail_pr200_{p_end:g}"
        if k in results:
            _fig_detail(results[k], f"Claim 6 (Figs 18-19): P_x = P_y = 200 N, P_z = {p_end:g} N, "
                        "continuation from 2,000 N, zeta = 2 %", out, f"claim6_radial200_{p_end:g}N.png", written)
    _fig_floquet(results, out, written)
    _fig_preload_sweep(results, out, written)
    _fig_clearance(results, plan, out, written)
    _fig_radial(results, plan, out, written)
    _fig_waviness(results, out, written)
    _fig_extra(results, plan, out, written)
    return written


def remove_stale_figures(out: Path, written: list[str]) -> list[str]:
    """Remove the reproduction's own figures in ``out`` that this run did not write (left by a
    run with another plan, so that the folder matches the report); other files stay. Returns
    the names removed."""
    removed = []
    for name in sorted(FIGURE_NAMES - set(written)):
        path = out / name
        if path.is_file():
            path.unlink()
            removed.append(name)
    return removed
