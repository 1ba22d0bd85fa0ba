"""The checks of the paper's seven claims: one per sentence of the paper, with fixed criteria
written before the numbers were known; a claim is *matched* when every check passes."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from bearing_gym.units import rpm_to_rad_s

from .plan import PAPER, QPI_THRESHOLD, Plan
from .summary import floquet_axial_pair

__all__ = ["verdict", "combination_share", "check_claims", "fmt"]


def fmt(x: Any, spec: str = ".0f", unit: str = "") -> str:
    """``x`` formatted with ``spec`` and ``unit``, or "n/a" for None and non-finite numbers."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "n/a"
    return f"{x:{spec}}{unit}"


def _check(text: str, passed: bool | None, ours: str) -> dict:
    return dict(text=text, passed=passed, ours=ours)


def verdict(checks: list[dict]) -> str:
    """matched: every check passes; partly: some do; not matched: none does."""
    known = [c["passed"] for c in checks if c["passed"] is not None]
    if known and all(known):
        return "matched"
    if any(known):
        return "partly"
    return "not matched"


def _crit_value(c: float | None, lo: float) -> float:
    """Critical preload for ordering: NaN/None (period-1 over the whole range) counts as just
    below the lowest preload swept."""
    return lo - 1.0 if c is None or not math.isfinite(c) else c


def _fraction_monotone(rows: list[dict], key: str, sign: int) -> float:
    """Share of consecutive period-1 points (by preload) along which ``key`` moves with sign."""
    rs = sorted([r for r in rows if r["periodic"] and not r["refined"]], key=lambda r: r["axial_preload_n"])
    steps = [sign * (b[key] - a[key]) > 0 for a, b in zip(rs, rs[1:])]
    return float(np.mean(steps)) if steps else math.nan


def combination_share(peaks: list[float], f1: float, f2: float, tol: float, order: int = 3) -> float:
    """Share of the peak frequencies equal to |m f1 + n f2| (|m|, |n| <= order, not both 0)
    within ``tol`` Hz."""
    combos = [abs(m * f1 + n * f2) for m in range(-order, order + 1) for n in range(-order, order + 1)
              if (m, n) != (0, 0)]
    hits = [any(abs(p - c) <= tol for c in combos) for p in peaks]
    return float(np.mean(hits)) if hits else math.nan


def check_claims(results: dict, S: dict, plan: Plan) -> dict:
    C: dict = {}
    # claim 1
    st = S["cage_speed_ratio_static_by_rpm"]
    st_vals = [st[k] for k in sorted(st, key=float)]
    dyn = S["cage_speed_ratio_by_rpm"]
    dyn_vals = [dyn[k] for k in sorted(dyn, key=float)]
    epi = S["cage_speed_ratio_epicyclic"]
    low = [k for k in dyn if float(k) <= 10000 and k in st]
    dev = max(abs(dyn[k] / st[k] - 1) for k in low) if low else math.nan
    C["1"] = [
        _check("quasi-static cage/shaft ratio rises monotonically with speed, above the epicyclic "
               f"value {epi:.4f}", all(b > a for a, b in zip(st_vals, st_vals[1:])) and min(st_vals) > epi,
               f"{st_vals[0]:.4f} -> {st_vals[-1]:.4f}"),
        _check("dynamic mean ratio (e = 2e-5 m) rises monotonically with speed",
               all(b > a for a, b in zip(dyn_vals, dyn_vals[1:])),
               ", ".join(f"{k} rpm: {dyn[k]:.4f}" for k in sorted(dyn, key=float))),
        _check("dynamic ratio within 1 % of the quasi-static one up to 10,000 rpm", bool(dev <= 0.01),
               f"largest deviation {100 * dev:.2f} %"),
    ]
    # claim 2
    m = S["three_models_2000rpm"]
    full_ptp = m["full"]["ptp_x_m"]
    d_none = m["no centrifugal, no gyroscopic"]["max_abs_diff_to_full_m"]
    d_cf = m["centrifugal only"]["max_abs_diff_to_full_m"]
    C["2"] = [
        _check("x without centrifugal force and gyroscopic moment within 5 % (of the full model's "
               "peak-to-peak) of the full model", d_none <= 0.05 * full_ptp,
               f"max difference {d_none * 1e9:.1f} nm = {100 * d_none / full_ptp:.2f} % of {full_ptp * 1e6:.3f} um"),
        _check("adding the centrifugal force brings it closer to the full model", d_cf < d_none,
               f"centrifugal only: {d_cf * 1e9:.1f} nm"),
    ]
    # claim 3
    r8 = S["response_800n"]
    fl8 = results["detail_800"]["floquet"]
    ax8 = floquet_axial_pair(fl8)
    lead8 = max(abs(complex(mu)) for mu in fl8["multipliers"]) if fl8 else math.nan
    p8 = abs(PAPER["floquet_800n"])
    a8 = math.degrees(np.angle(PAPER["floquet_800n"]))
    C["3"] = [
        _check("800 N: stable period-1 motion (index < 0.1, all |mu| < 1)",
               bool(r8["qpi"] < QPI_THRESHOLD and lead8 < 1), f"index {r8['qpi']:.3f}, largest |mu| {lead8:.4f}"),
        _check(f"|mu| of the leading pair (the critical, axial one) within 5 % of {p8:.4f}",
               bool(ax8 and abs(ax8["modulus"] / p8 - 1) <= 0.05),
               f"{ax8['modulus']:.4f}" if ax8 else "n/a"),
        _check(f"its angle per shaft period within 15 deg of {a8:.1f} deg",
               bool(ax8 and abs(abs(ax8["angle_deg"]) - a8) <= 15),
               f"{abs(ax8['angle_deg']):.1f} deg" if ax8 else "n/a"),
        _check("principal frequency of the cage speed within 5 % of the ball passage N w_c",
               bool(r8["cage_principal_hz"] and abs(r8["cage_principal_hz"] / r8["ball_pass_hz"] - 1) <= 0.05),
               f"{fmt(r8['cage_principal_hz'], '.1f')} Hz vs N w_c = {r8['ball_pass_hz']:.1f} Hz "
               f"(N (w - w_c) = {r8['ball_pass_inner_hz']:.1f} Hz)"),
        _check("x spectrum peaks at the shaft frequency (within 1 %)",
               bool(abs(r8["x_principal_hz"] / r8["shaft_hz"] - 1) <= 0.01),
               f"{r8['x_principal_hz']:.1f} Hz vs {r8['shaft_hz']:.1f} Hz"),
    ]
    # claim 4
    r6, r6c = S["response_600n_cold"], S["response_600n_continuation"]
    r57 = S["response_570n_continuation"]
    fl6 = results["detail_600_cont"]["floquet"]
    lead6 = max(abs(complex(mu)) for mu in fl6["multipliers"]) if fl6 else math.nan
    df = 1.0 / min(plan.detail_measure_s, 0.1)
    ly6, ly57 = r6["lyapunov_per_s"], r57["lyapunov_per_s"]
    period = 2 * math.pi / rpm_to_rad_s(20000)
    C["4"] = [
        _check("600 N: the period-1 orbit is unstable (|mu| > 1; paper 1.8639)",
               bool(r6c["qpi"] >= QPI_THRESHOLD or lead6 > 1),
               f"orbit reached by continuation: index {r6c['qpi']:.3f}, largest |mu| {lead6:.4f}"),
        _check("600 N: the motion is not period-1 and much larger (index > 0.1)",
               bool(r6["qpi"] > QPI_THRESHOLD),
               f"from the static equilibrium: index {r6['qpi']:.2f}, p-p z {r6['ptp_m']['z'] * 1e6:.0f} um, "
               f"x {r6['ptp_m']['x'] * 1e6:.0f} um"),
        _check("below the critical preload the bifurcated motion is quasi-periodic: Poincare section "
               "a closed curve (index > 0.1, |largest Lyapunov exponent| < 1 % per shaft period); "
               "tested at 570 N by continuation",
               None if ly57 is None else bool(r57["qpi"] > QPI_THRESHOLD and abs(ly57) * period < 0.01),
               f"570 N: index {r57['qpi']:.2f}, lambda_1 = {fmt(ly57, '.1f')} 1/s; "
               f"600 N from the static equilibrium: lambda_1 = {fmt(ly6, '.1f')} 1/s"),
    ]
    for lab, r in (("600 N from the static equilibrium", r6), ("570 N by continuation", r57)):
        wcp = r["cage_principal_hz"]
        share = combination_share(r["x_peaks_hz"] + r["z_peaks_hz"], r["shaft_hz"], wcp, 0.3 * df) \
            if wcp else math.nan
        C["4"] += [
            _check(f"{lab}: cage principal frequency equals the z principal frequency (2 %) and is "
                   "far below the ball passage (< N w_c / 2)",
                   bool(wcp and r["z_principal_hz"] and abs(wcp / r["z_principal_hz"] - 1) <= 0.02
                        and wcp < 0.5 * r["ball_pass_hz"]),
                   f"{fmt(wcp, '.1f')} Hz and {fmt(r['z_principal_hz'], '.1f')} Hz; N w_c = {r['ball_pass_hz']:.0f} Hz"),
            _check(f"{lab}: the spectral peaks are combinations of w and w_cp: at least 75 % of the 8 "
                   f"strongest x and z peaks equal |m w + n w_cp| (|m|, |n| <= 3, within {0.3 * df:.0f} Hz)",
                   bool(share >= 0.75), f"{100 * share:.0f} %"),
        ]
    # claim 5
    crit = S["critical_preload_n_by_clearance"]
    lo = min(plan.clearance_down)
    cs = [_crit_value(crit[f"{c:g}"], lo) for c in plan.clearances_um]
    det = S["clearance_detail"]

    def _names(vals: list[float]) -> str:
        return ", ".join(f"{c:g} um: " + ("below range" if v < lo else f"{v:.0f} N")
                         for c, v in zip(plan.clearances_um, vals))

    chk = [_check("critical preload (continuation) rises with clearance",
                  all(b > a for a, b in zip(cs, cs[1:])), _names(cs))]
    if plan.clearance_cold:
        cc = [_crit_value(det[f"{c:g}"]["cold_start"]["critical_n"], lo) for c in plan.clearances_um]
        chk.append(_check("critical preload (cold start) rises with clearance",
                          all(b > a for a, b in zip(cc, cc[1:])), _names(cc)))
    windows: dict = {}
    for c in (20.0, 30.0):
        if c in plan.clearances_um:
            srcs = [("continuation", det[f"{c:g}"]["continuation"]["stable_windows_n"])]
            if plan.clearance_cold:
                srcs.append(("cold start", det[f"{c:g}"]["cold_start"]["stable_windows_n"]))
            windows[c] = srcs

    def _lower_window_near_750(ws: list) -> bool:   # a stable interval below an unstable one
        return any(w[0] <= 775 and w[1] >= 725 for w in ws[1:])

    second = bool(windows) and all(any(_lower_window_near_750(ws) for _, ws in srcs)
                                   for srcs in windows.values())
    chk.append(_check("a second stable window near 750 N at 20 and 30 um (a period-1 interval below "
                      "a non-periodic one)", second,
                      "; ".join(f"{c:g} um {src}: period-1 over " +
                                (", ".join(f"{w[0]:.0f}-{w[1]:.0f} N" for w in ws) or "nothing")
                                for c, srcs in windows.items() for src, ws in srcs)))
    rows_c = {c: results[f"clearance_down_{c:g}"] for c in plan.clearances_um}
    inc = [_fraction_monotone(rows_c[c], "ptp_x_m", +1) for c in plan.clearances_um]
    chk.append(_check("radial peak-to-peak grows with preload in the stable range (>= 80 % of the "
                      "steps, every clearance)", all(v >= 0.8 for v in inc),
                      ", ".join(f"{c:g} um: {100 * v:.0f} %" for c, v in zip(plan.clearances_um, inc))))
    common = None
    for c in plan.clearances_um:
        ps = {r["axial_preload_n"] for r in rows_c[c] if r["periodic"] and not r["refined"]}
        common = ps if common is None else common & ps
    common = sorted(common or [])
    if common:
        by_c = [np.mean([r["ptp_x_m"] for r in rows_c[c] if r["axial_preload_n"] in common and not r["refined"]])
                for c in plan.clearances_um]
        cage_c = [np.mean([r["cage_max_rad_s"] for r in rows_c[c] if r["axial_preload_n"] in common
                           and not r["refined"]]) for c in plan.clearances_um]
        chk.append(_check("radial peak-to-peak falls with clearance (mean over the preloads where "
                          "every clearance is period-1)", all(b < a for a, b in zip(by_c, by_c[1:])),
                          ", ".join(f"{v * 1e6:.1f} um" for v in by_c)))
    stable_z = [r["ptp_z_m"] for c in plan.clearances_um for r in rows_c[c] if r["periodic"]]
    unstable_z = [r["ptp_z_m"] for c in plan.clearances_um for r in rows_c[c]
                  if not r["periodic"] and r["status"] == "ok"]
    chk.append(_check("axial peak-to-peak stays flat in the stable range (varies by < 1 um, while it "
                      "jumps by tens of um where not period-1)", bool(stable_z) and float(np.ptp(stable_z)) < 1e-6,
                      (f"period-1: {min(stable_z) * 1e6:.3f}-{max(stable_z) * 1e6:.3f} um" +
                       (f"; otherwise up to {max(unstable_z) * 1e6:.0f} um" if unstable_z else ""))
                      if stable_z else "n/a"))
    dec = [_fraction_monotone(rows_c[c], "cage_max_rad_s", -1) for c in plan.clearances_um]
    chk.append(_check("maximum cage speed falls with preload in the stable range (>= 80 % of the "
                      "steps, every clearance)", all(v >= 0.8 for v in dec),
                      ", ".join(f"{c:g} um: {100 * v:.0f} %" for c, v in zip(plan.clearances_um, dec))))
    if common:
        chk.append(_check("maximum cage speed falls with clearance", all(b < a for a, b in zip(cage_c, cage_c[1:])),
                          ", ".join(f"{v:.1f} rad/s" for v in cage_c)))
    C["5"] = chk
    # claim 6
    lo6 = min(plan.radial_down)
    c0 = _crit_value(S["critical_preload_n"], min(plan.default_down))
    c2 = _crit_value(S.get("critical_preload_n_radial_200"), lo6)
    c5 = _crit_value(S.get("critical_preload_n_radial_500"), lo6)
    chk = [_check("critical preload (continuation) rises with the radial load 0 -> 200 -> 500 N",
                  c0 < c2 < c5, f"{c0:.0f}, {c2:.0f}, {c5:.0f} N")]
    if plan.radial_cold:
        cc2 = _crit_value(S["critical_preload_detail_radial_200"]["cold_start"]["critical_n"], lo6)
        cc5 = _crit_value(S["critical_preload_detail_radial_500"]["cold_start"]["critical_n"], lo6)
        cc0 = _crit_value(S["critical_preload_n_cold"], min(plan.default_cold))
        chk.append(_check("critical preload (cold start) rises with the radial load", cc0 < cc2 < cc5,
                          f"{cc0:.0f}, {cc2:.0f}, {cc5:.0f} N"))
    chk.append(_check("about 1150 N at P_x = P_y = 200 N (within 10 %)", abs(c2 / 1150 - 1) <= 0.1, f"{c2:.0f} N"))
    chk.append(_check("about 1350 N at P_x = P_y = 500 N (within 10 %)", abs(c5 / 1350 - 1) <= 0.1, f"{c5:.0f} N"))
    if "response_radial200_1200n" in S:
        q12, q11 = S["response_radial200_1200n"]["qpi"], S["response_radial200_1100n"]["qpi"]
        chk.append(_check("P_x = P_y = 200 N: period-1 at 1200 N, not at 1100 N (continuation from 2000 N)",
                          q12 < QPI_THRESHOLD <= q11, f"index {q12:.3f} at 1200 N, {q11:.3f} at 1100 N"))
        r = S["response_radial200_1200n"]
        chk.append(_check("there, at 1200 N and period-1, the cage principal frequency is near the shaft "
                          "frequency (5 %)",
                          abs(r["cage_principal_hz"] / r["shaft_hz"] - 1) <= 0.05 if q12 < QPI_THRESHOLD else None,
                          f"{r['cage_principal_hz']:.1f} Hz vs {r['shaft_hz']:.1f} Hz" +
                          ("" if q12 < QPI_THRESHOLD else " (not comparable: not period-1 there)")))
    C["6"] = chk
    # claim 7 ("more than" = by at least 10 %)
    w = S["waviness"]["e=0"]
    o, i, b, br = (w[k]["cage_std_rad_s"] for k in ("outer race", "inner race", "balls", "balls, random phases"))
    C["7"] = [
        _check("outer-race waviness makes the cage speed vary more (by 10 %) than inner-race waviness",
               o > 1.1 * i, f"std of the cage speed with e = 0: outer {o:.4f}, inner {i:.4f} rad/s"),
        _check("outer-race waviness makes it vary more (by 10 %) than ball waviness, same phase on "
               "every ball", o > 1.1 * b, f"balls {b:.4f} rad/s"),
        _check("the same with a random phase per ball (zeta_nj of eqs 13-14)", o > 1.1 * br,
               f"balls, random phases {br:.4f} rad/s"),
        _check("the ball-waviness effect is hardly visible (< 10 % of the outer-race one), same phase",
               b < 0.1 * o, f"{100 * b / o:.1f} %" if o > 0 else "n/a"),
        _check("the same with a random phase per ball", br < 0.1 * o, f"{100 * br / o:.1f} %" if o > 0 else "n/a"),
    ]
    return {k: dict(checks=v, verdict=verdict(v)) for k, v in C.items()}
