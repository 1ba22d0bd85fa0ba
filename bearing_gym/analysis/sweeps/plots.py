"""Figures of sweep rows (matplotlib imported lazily; the functions return a Figure and draw
nothing on screen)."""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from .io import truthy

__all__ = ["plot_sweep", "plot_stability_map"]


def plot_sweep(rows: Sequence[dict], quantities: Sequence[str] = ("ptp_x_m", "ptp_z_m", "cage_ptp_rad_s"),
               group: str = "label", title: str = ""):
    """Quantities vs axial preload, one line per ``group`` value; non-periodic points hollow."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 2.2 * len(quantities) + 0.6), layout="constrained")
    axes = fig.subplots(len(quantities), 1, sharex=True, squeeze=False)[:, 0]
    groups: dict = {}
    for r in rows:
        groups.setdefault(r[group], []).append(r)
    for ax, qname in zip(axes, quantities):
        f, unit = (1e6, "um") if qname.endswith("_m") else (1.0, "")
        for k, (g, rs) in enumerate(groups.items()):
            rs = sorted(rs, key=lambda r: float(r["axial_preload_n"]))
            p = np.array([float(r["axial_preload_n"]) for r in rs])
            v = np.array([float(r.get(qname, math.nan)) for r in rs]) * f
            per = np.array([truthy(r["periodic"]) for r in rs])
            line, = ax.plot(p, v, "-", lw=1, label=str(g))
            ax.plot(p[per], v[per], "o", ms=3.5, color=line.get_color())
            ax.plot(p[~per], v[~per], "o", ms=4, mfc="none", color=line.get_color())
        ax.set_ylabel(qname.replace("_m", f" ({unit})") if unit else qname)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("axial preload P_z (N)")
    axes[0].legend(fontsize=7, ncol=2)
    if title:
        import textwrap
        axes[0].set_title("\n".join(textwrap.wrap(title, 80)), fontsize=9)
    return fig


def plot_stability_map(rows: Sequence[dict], y: str = "shaft_speed_rpm", title: str = ""):
    """Preload (x) against ``y`` (a column, e.g. shaft speed, radial load or clearance): filled
    circles periodic, crosses non-periodic, coloured by the quasi-periodicity index."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    ax = fig.subplots()
    p = np.array([float(r["axial_preload_n"]) for r in rows])
    yv = np.array([float(r[y]) for r in rows])
    if y.endswith("_m"):
        yv = yv * 1e6
    q = np.array([float(r["qpi"]) for r in rows])
    per = np.array([truthy(r["periodic"]) for r in rows])
    sc = ax.scatter(p[per], yv[per], c=q[per], vmin=0, vmax=1, cmap="viridis", marker="o", s=30,
                    label="period-1 (stable)")
    ax.scatter(p[~per], yv[~per], c=q[~per], vmin=0, vmax=1, cmap="viridis", marker="x", s=30,
               label="not period-1")
    fig.colorbar(sc, ax=ax, label="quasi-periodicity index")
    ax.set_xlabel("axial preload P_z (N)")
    ax.set_ylabel(y.replace("_m", " (um)") if y.endswith("_m") else y)
    ax.legend(fontsize=7, loc="lower left", framealpha=0.9)
    ax.grid(alpha=0.3)
    if title:
        import textwrap
        ax.set_title("\n".join(textwrap.wrap(title, 80)), fontsize=9)
    return fig
