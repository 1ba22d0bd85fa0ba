"""The evaluation report of :func:`agents.leaderboard.compare.evaluate`: the markdown table with paired
differences to a reference, the per-policy and per-episode CSV files, and the trace figure of
the first scenario."""

from __future__ import annotations

import csv
import math
import textwrap
from pathlib import Path

import numpy as np

from bearing_gym.analysis.signals import QPI_THRESHOLD

from agents.evaluation.result import EvalResult


__all__ = ["paired_difference", "write_report", "describe_scenario", "plot_traces"]


def paired_difference(a: EvalResult, b: EvalResult) -> tuple[float, float, float]:
    """Mean of the per-episode return differences a - b on the same scenarios, with its 95 %
    Student-t interval (the paired comparison removes the scenario-to-scenario spread)."""
    from scipy import stats
    d = np.asarray(a.returns) - np.asarray(b.returns)
    m = float(np.mean(d))
    if len(d) < 2:
        return m, m, m
    h = float(stats.t.ppf(0.975, len(d) - 1) * np.std(d, ddof=1) / math.sqrt(len(d)))
    return m, m - h, m + h


def write_report(results: list[EvalResult], out_dir: Path, header: str = "",
                 reference: str | None = None, first_seed: int | None = None) -> list[Path]:
    """evaluation.md (table, paired differences to ``reference``), evaluation.csv (one row per
    policy), evaluation_episodes.csv (the return of every policy in every episode, for statistics
    of your own; with ``first_seed`` the episode's scenario seed) and evaluation_traces.png; returns
    the paths written."""
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = [r.row() for r in results]
    with (out_dir / "evaluation.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with (out_dir / "evaluation_episodes.csv").open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["episode", "seed"] + [r.name for r in results])
        for i in range(min(len(r.returns) for r in results)):
            w.writerow([i, "" if first_seed is None else first_seed + i] + [repr(float(r.returns[i])) for r in results])
    lines = ["# Evaluation\n", header, "",
             "| policy | episodes | mean return | 95 % CI | vibration | heat | fatigue | actuation "
             "| time quasi-periodic | mean preload (N) | terminated early |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['policy']} | {r['episodes']} | {r['mean_return']:.2f} | [{r['ci95_low']:.2f}, {r['ci95_high']:.2f}] "
                     f"| {r['mean_vibration']:.2f} | {r['mean_heat']:.2f} | {r['mean_fatigue']:.2f} | {r['mean_actuation']:.2f} "
                     f"| {100 * r['quasi_periodic_fraction']:.1f} % | {r['mean_preload_n']:.0f} | {r['terminated_episodes']} |")
    if any(r["terminated_episodes"] for r in rows):
        lines += ["", "Terminated early: episodes in which the integrator diverged; such an episode ends "
                      "there and its return holds the termination penalty."]
    ref = next((r for r in results if r.name == reference), None)
    if ref is not None:
        lines += ["", f"Paired difference of return to **{ref.name}** on the same scenarios "
                      "(mean and 95 % CI of the per-episode differences; positive = better):", ""]
        for r in results:
            if r is not ref:
                m, lo, hi = paired_difference(r, ref)
                lines.append(f"- {r.name}: {m:+.2f} [{lo:+.2f}, {hi:+.2f}]")
    (out_dir / "evaluation.md").write_text("\n".join(lines) + "\n")
    written = [out_dir / n for n in ("evaluation.md", "evaluation.csv", "evaluation_episodes.csv")]
    try:
        plot_traces(results, out_dir / "evaluation_traces.png", first_seed)
        written.append(out_dir / "evaluation_traces.png")
    except Exception as err:  # a figure must never lose the numbers
        print(f"warning: no trace figure ({err})")
    return written


def describe_scenario(sc) -> str:
    """One line for a Scenario: speed (ramp), radial load (step), clearance."""
    if sc is None:
        return ""
    sp = sc.speed_profile
    levels = [f"{v:,.0f}" for k, (_, v) in enumerate(sp) if k == 0 or v != sp[k - 1][1]]
    speed = " -> ".join(levels) + " rpm"
    load = "radial load " + " -> ".join(f"{f:.0f}" for _, f in sc.radial_load_profile) + " N"
    if len(sp) > 1 or len(sc.radial_load_profile) > 1:
        times = sorted({t for t, _ in sp[1::2]} | {t for t, _ in sc.radial_load_profile[1:]})
        load += " (events at " + ", ".join(f"{t:.2f}" for t in times) + " s)"
    return f"{speed}, {load}, clearance {sc.clearance_m * 1e6:.1f} um"


def plot_traces(results: list[EvalResult], path: Path | None, first_seed: int | None = None):
    """evaluation_traces.png: preload, quasi-periodicity index and operating point over the
    first evaluation scenario, for every policy with a trace (the hindsight reference included).
    With ``path`` None the figure is returned instead of saved (the caller closes it)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    traced = [r for r in results if r.trace and len(r.trace.get("t", ()))]
    fig, (a1, a2, a3) = plt.subplots(3, 1, figsize=(11, 8.5), sharex=True, layout="constrained",
                                     gridspec_kw={"height_ratios": [3, 2, 1.4]})
    for r in traced:
        hindsight = bool(r.trace_label)
        style = dict(color="k", ls="--", lw=1.2) if hindsight else {}
        label = r.trace_label or r.name
        a1.plot(r.trace["t"], r.trace["preload_n"], label=label, **style)
        a2.plot(r.trace["t"], r.trace["qpi"], label=label, **style)
        if r.terminated is not None and r.terminated[0]:
            a1.plot(r.trace["t"][-1], r.trace["preload_n"][-1], "x", color="r", ms=8)
    a2.axhline(QPI_THRESHOLD, color="0.5", lw=0.8, ls=":")
    # the threshold's label right of the panel, where no trace runs
    a2.annotate(f"quasi-periodic\nabove {QPI_THRESHOLD}", xy=(1.0, QPI_THRESHOLD),
                xycoords=("axes fraction", "data"), xytext=(4, 0), textcoords="offset points",
                fontsize=7, color="0.4", va="center", ha="left", annotation_clip=False)
    a1.set_ylabel("axial preload (N)")
    a2.set_ylabel("quasi-periodicity index (-)")
    if traced:                   # outside the panels, beside the top one: it covers no trace
        a1.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ref = max(traced, key=lambda r: len(r.trace["t"])) if traced else None
    if ref is not None and "shaft_speed_rpm" in ref.trace:
        a3.plot(ref.trace["t"], ref.trace["shaft_speed_rpm"], color="C0")
        a3.set_ylabel("shaft speed (rpm)", color="C0")
        b3 = a3.twinx()
        b3.plot(ref.trace["t"], ref.trace["radial_load_n"], color="C3")
        b3.set_ylabel("radial load (N)", color="C3")
    a3.set_xlabel("time in episode (s)")
    seed = "" if first_seed is None else f"seed {first_seed}: "
    sc = describe_scenario(ref.scenario) if ref is not None else ""
    ended = any(r.terminated is not None and r.terminated[0] for r in traced)
    fig.suptitle("\n".join(textwrap.wrap(f"First evaluation scenario ({seed}{sc})", 110))
                 + "\npreload and quasi-periodicity index per policy"
                 + (" (x: the episode terminated early)" if ended else ""), fontsize=9)
    if path is None:
        return fig
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return None
