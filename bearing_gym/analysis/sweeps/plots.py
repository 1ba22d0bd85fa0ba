"""Figures of sweep rows (matplotlib imported lazily; the functions return a Figure and draw
nothing on screen).

Every point is marked by its class: **period-1** (the row's ``periodic``: index below the
threshold and, when computed, every Floquet multiplier inside the unit circle), **quasi-periodic
or chaotic** (index at or above ``qpi_threshold``, by default the package's ``QPI_THRESHOLD``)
or **not period-1 otherwise** (index below the threshold but a multiplier outside the unit
circle, or a failed point); a legend says which marker is which. Axes are labelled in words
with units (:func:`column_label`).
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..signals import QPI_THRESHOLD
from .io import truthy

__all__ = ["plot_sweep", "plot_stability_map", "column_label", "point_classes"]

# columns of sweeps.COLUMNS in words, with the unit they are plotted in and the factor from SI
_LABELS: dict[str, tuple[str, float]] = {
    "shaft_speed_rpm": ("shaft speed (rpm)", 1.0),
    "axial_preload_n": ("axial preload P_z (N)", 1.0),
    "radial_load_x_n": ("radial load P_x = P_y (N per axis)", 1.0),
    "radial_load_y_n": ("radial load P_y (N)", 1.0),
    "clearance_m": ("radial clearance (um)", 1e6),
    "damping_ratio": ("damping ratio (dimensionless)", 1.0),
    "eccentricity_m": ("mass eccentricity (um)", 1e6),
    "qpi": ("quasi-periodicity index (dimensionless)", 1.0),
    "ptp_x_m": ("x peak-to-peak (um)", 1e6),
    "ptp_y_m": ("y peak-to-peak (um)", 1e6),
    "ptp_z_m": ("z (axial) peak-to-peak (um)", 1e6),
    "rms_x_m": ("x RMS (um)", 1e6),
    "rms_y_m": ("y RMS (um)", 1e6),
    "rms_z_m": ("z (axial) RMS (um)", 1e6),
    "mean_z_m": ("mean z (axial) displacement (um)", 1e6),
    "cage_mean_rad_s": ("mean cage speed (rad/s)", 1.0),
    "cage_ptp_rad_s": ("cage speed peak-to-peak (rad/s)", 1.0),
    "cage_max_rad_s": ("maximum cage speed (rad/s)", 1.0),
    "min_inner_contacts": ("fewest balls touching the inner race", 1.0),
    "floquet_max_modulus": ("largest Floquet multiplier modulus", 1.0),
    "floquet_axial_modulus": ("axial Floquet multiplier modulus", 1.0),
}
_SUFFIXES = (("_rad_s", "rad/s", 1.0), ("_deg", "deg", 1.0), ("_rpm", "rpm", 1.0),
             ("_m", "um", 1e6), ("_n", "N", 1.0), ("_s", "s", 1.0))


def column_label(column: str) -> tuple[str, float]:
    """``(axis label in words with unit, factor from the column's SI value to that unit)``."""
    if column in _LABELS:
        return _LABELS[column]
    for suffix, unit, factor in _SUFFIXES:
        if column.endswith(suffix):
            return f"{column[:-len(suffix)].replace('_', ' ')} ({unit})", factor
    return column.replace("_", " "), 1.0


def point_classes(rows: Sequence[dict], qpi_threshold: float = QPI_THRESHOLD
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Boolean masks (period-1, quasi-periodic, other not period-1) of ``rows``."""
    q = np.array([float(r.get("qpi", math.nan)) for r in rows], dtype=float)
    per = np.array([truthy(r["periodic"]) for r in rows], dtype=bool)
    qp = ~per & (q >= qpi_threshold)
    return per, qp, ~per & ~qp


def _class_labels(qpi_threshold: float) -> tuple[str, str, str]:
    return (f"period-1 (index < {qpi_threshold:g})",
            f"quasi-periodic or chaotic (index >= {qpi_threshold:g})",
            "not period-1: Floquet-unstable or failed")


def _title(ax, title: str) -> None:
    if title:
        import textwrap
        ax.set_title("\n".join(textwrap.wrap(title, 80)), fontsize=9)


def plot_sweep(rows: Sequence[dict], quantities: Sequence[str] = ("ptp_x_m", "ptp_z_m", "cage_ptp_rad_s"),
               group: str = "label", title: str = "", qpi_threshold: float = QPI_THRESHOLD):
    """Quantities vs axial preload, one line per ``group`` value; period-1 points filled,
    quasi-periodic points hollow, other non-periodic points as crosses; the index panel (if
    ``qpi`` is a quantity) shows the threshold."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    fig = Figure(figsize=(6.4, 2.2 * len(quantities) + 0.6), layout="constrained")
    axes = fig.subplots(len(quantities), 1, sharex=True, squeeze=False)[:, 0]
    groups: dict = {}
    for r in rows:
        groups.setdefault(r[group], []).append(r)
    for ax, qname in zip(axes, quantities):
        label, f = column_label(qname)
        for k, (g, rs) in enumerate(groups.items()):
            rs = sorted(rs, key=lambda r: float(r["axial_preload_n"]))
            p = np.array([float(r["axial_preload_n"]) for r in rs])
            v = np.array([float(r.get(qname, math.nan)) for r in rs]) * f
            per, qp, other = point_classes(rs, qpi_threshold)
            line, = ax.plot(p, v, "-", lw=1, label=str(g))
            ax.plot(p[per], v[per], "o", ms=3.5, color=line.get_color())
            ax.plot(p[qp], v[qp], "o", ms=4, mfc="none", color=line.get_color())
            ax.plot(p[other], v[other], "x", ms=4, color=line.get_color())
        if qname == "qpi":
            ax.axhline(qpi_threshold, color="0.3", ls="--", lw=0.8,
                       label=f"threshold {qpi_threshold:g}")
        ax.set_ylabel(label, fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel(column_label("axial_preload_n")[0])
    names = _class_labels(qpi_threshold)
    markers = [Line2D([], [], ls="none", marker="o", ms=4, color="0.2", label=names[0]),
               Line2D([], [], ls="none", marker="o", ms=4, mfc="none", color="0.2", label=names[1]),
               Line2D([], [], ls="none", marker="x", ms=4, color="0.2", label=names[2])]
    handles, _ = axes[0].get_legend_handles_labels()
    axes[0].legend(handles=handles + markers, fontsize=6, ncol=2)
    if "qpi" in quantities and quantities.index("qpi") != 0:
        axes[list(quantities).index("qpi")].legend(fontsize=6)
    _title(axes[0], title or f"sweep over axial preload ({len(rows)} points)")
    return fig


def plot_stability_map(rows: Sequence[dict], y: str = "shaft_speed_rpm", title: str = "",
                       qpi_threshold: float = QPI_THRESHOLD):
    """Preload (x) against ``y`` (a column, e.g. shaft speed, radial load or clearance):
    filled circles period-1, crosses quasi-periodic, triangles other non-periodic points,
    coloured by the quasi-periodicity index (the colour bar marks the threshold)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    ax = fig.subplots()
    ylabel, f = column_label(y)
    p = np.array([float(r["axial_preload_n"]) for r in rows])
    yv = np.array([float(r[y]) for r in rows]) * f
    q = np.array([float(r["qpi"]) for r in rows])
    names = _class_labels(qpi_threshold)
    sc = None
    for mask, marker, name in zip(point_classes(rows, qpi_threshold), ("o", "x", "^"), names):
        if mask.any():
            s = ax.scatter(p[mask], yv[mask], c=q[mask], vmin=0, vmax=1, cmap="viridis",
                           marker=marker, s=30, label=f"{name}: {int(mask.sum())}")
            sc = s if sc is None else sc
    if sc is not None:
        bar = fig.colorbar(sc, ax=ax, label=f"quasi-periodicity index (threshold {qpi_threshold:g})")
        bar.ax.axhline(qpi_threshold, color="w", lw=1.5)
        bar.ax.axhline(qpi_threshold, color="k", lw=0.8, ls="--")
        ax.legend(fontsize=7, loc="best", framealpha=0.9)
    else:
        ax.text(0.5, 0.5, "no points", ha="center", va="center", transform=ax.transAxes)
    ax.set_xlabel(column_label("axial_preload_n")[0])
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    _title(ax, title or f"stability map: axial preload x {ylabel}")
    return fig
