"""``bearing-gym simulate``: run the Simulator at an operating point, print a summary and save
the record, the summary and the plots."""

from __future__ import annotations

import json
import math
from pathlib import Path

from bearing_gym.serialization import to_jsonable

from .errors import CLIError, RunError, check_option, one_line
from .options import params_from_args
from .output import Out, RecordWindow, advance, op_text, params_dict

__all__ = ["cmd_simulate"]

_RECORD_FIELDS = ("t", "x", "y", "z", "theta_x", "theta_y", "x_dot", "y_dot", "z_dot",
                  "theta_x_dot", "theta_y_dot", "cage_speed", "cage_angle", "shaft_angle",
                  "bearing_force", "n_inner_contacts")


def cmd_simulate(args, say: Out) -> int:
    import time

    import numpy as np

    from bearing_gym.analysis.poincare import shaft_section
    from bearing_gym.analysis.signals import quasi_periodicity_index
    from bearing_gym.analysis.spectra import (ball_pass_frequency, ball_pass_frequency_inner,
                                              principal_frequency, spectral_peaks)
    from bearing_gym.physics import SimulationError, Simulator
    from bearing_gym.physics.equilibrium import EquilibriumError

    params = params_from_args(args)
    duration = check_option("--duration", args.duration, 0.0, 1e4, "s", low_open=True)
    if isinstance(args.record_every, bool) or not 1 <= args.record_every <= 10**6:
        raise CLIError(f"--record-every: must be an integer in [1, 1000000], got {args.record_every}")
    check_option("--qpi-threshold", args.qpi_threshold, 0.0, 2.0, low_open=True)
    dt = params.integrator.dt_s
    if int(round(duration / dt)) < 4 * args.record_every:
        raise CLIError(f"--duration: must span at least 4 recorded steps "
                       f"({4 * args.record_every * dt:g} s at --dt-us {dt * 1e6:g} and "
                       f"--record-every {args.record_every}), got {duration:g}")
    out = Path(args.out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise CLIError(f"--out: cannot create {out}: {err.strerror or err}") from None

    say(f"bearing-gym simulate: {op_text(params)}; {duration:g} s at dt = {dt * 1e6:g} us")
    t0 = time.perf_counter()
    try:
        sim = Simulator(params)
    except (EquilibriumError, SimulationError) as err:
        raise RunError(f"no static equilibrium at this operating point: {one_line(err)}") from None
    status = "ok"
    try:
        rec = advance(sim, duration, args.record_every, say.quiet, "simulate")
    except SimulationError as err:
        rec, status = err.record, one_line(err)
    wall = time.perf_counter() - t0

    fields = {}
    if len(rec.data):
        fields = {f: getattr(rec, f) for f in _RECORD_FIELDS}
    np.savez_compressed(out / "record.npz", **fields, status=np.array(status),
                        record_every=np.array(args.record_every), dt_s=np.array(dt),
                        params_json=np.array(json.dumps(params_dict(params))))
    if status != "ok":
        raise RunError(f"simulation stopped: {status} (partial record in {out / 'record.npz'})")

    t = rec.t
    late = t >= t[0] + 0.5 * (t[-1] - t[0])
    w = params.shaft_speed_rad_s
    win = RecordWindow(rec, late)
    ptp = {k: float(np.ptp(getattr(win, k))) for k in ("x", "y", "z", "cage_speed")}
    cage_mean = float(np.mean(win.cage_speed))
    xyz = np.column_stack([win.x, win.y, win.z])
    try:
        qpi = quasi_periodicity_index(win.t, xyz, w)
    except ValueError:
        qpi = None
    if qpi is None:
        verdict = "undetermined (the second half spans fewer than 3 shaft periods)"
    elif w == 0:
        verdict = "static (shaft not turning)"
    elif qpi < args.qpi_threshold:
        verdict = "periodic (period-1)"
    else:
        verdict = "quasi-periodic (or chaotic)"
    freqs = {}
    for k in ("x", "y", "z", "cage_speed"):
        try:
            f = principal_frequency(win.t, getattr(win, k))
        except (ValueError, IndexError):
            f = math.nan
        freqs[k] = f
    try:
        peaks_x = spectral_peaks(win.t, win.x, 3, fmin_hz=1.0)
    except (ValueError, IndexError):
        peaks_x = []
    nb = params.geometry.n_balls
    ref = dict(shaft_hz=w / (2 * math.pi), ball_pass_outer_hz=ball_pass_frequency(cage_mean, nb),
               ball_pass_inner_hz=ball_pass_frequency_inner(w, cage_mean, nb))
    summary = dict(operating_point=op_text(params), duration_s=duration, dt_s=dt,
                   window_s=[float(win.t[0]), float(win.t[-1])], wall_s=wall,
                   ptp_x_um=ptp["x"] * 1e6, ptp_y_um=ptp["y"] * 1e6, ptp_z_um=ptp["z"] * 1e6,
                   cage_speed_ptp_rad_s=ptp["cage_speed"], cage_speed_mean_rad_s=cage_mean,
                   principal_frequency_hz={k: v for k, v in freqs.items()},
                   spectral_peaks_x_hz=[f for f, _ in peaks_x], reference_frequencies_hz=ref,
                   quasi_periodicity_index=qpi, qpi_threshold=args.qpi_threshold,
                   motion=verdict, params=params_dict(params))

    def hz(v: float) -> str:
        return "n/a" if not math.isfinite(v) else f"{v:.1f}"

    say(f"simulated {duration:g} s in {wall:.2f} s wall; summary over "
        f"t = {win.t[0]:.4g}-{win.t[-1]:.4g} s:")
    say(f"  peak-to-peak: x {ptp['x'] * 1e6:.3f} um, y {ptp['y'] * 1e6:.3f} um, "
        f"z {ptp['z'] * 1e6:.3f} um, cage speed {ptp['cage_speed']:.3f} rad/s "
        f"(mean {cage_mean:.2f} rad/s)")
    say(f"  principal frequencies (Hz): x {hz(freqs['x'])}, y {hz(freqs['y'])}, "
        f"z {hz(freqs['z'])}, cage speed {hz(freqs['cage_speed'])}  "
        f"(resolution {1.0 / max(win.t[-1] - win.t[0], 1e-12):.3g} Hz)")
    say(f"  reference (Hz): shaft {ref['shaft_hz']:.1f}, ball pass N w_c {ref['ball_pass_outer_hz']:.1f}, "
        f"N (w - w_c) {ref['ball_pass_inner_hz']:.1f}")
    q_txt = "n/a" if qpi is None else f"{qpi:.3f}"
    say(f"  motion: {verdict} (quasi-periodicity index {q_txt}, threshold {args.qpi_threshold:g})")

    written = ["record.npz", "summary.json"]
    if not args.no_plots:
        written += _simulate_plots(rec, late, params, freqs, ref, qpi, out, shaft_section)
    (out / "summary.json").write_text(json.dumps(to_jsonable(dict(summary, files=written)),
                                                 indent=1) + "\n")
    say(f"  wrote {', '.join(written)} in {out}")
    return 0


def _simulate_plots(rec, late, params, freqs, ref, qpi, out: Path, shaft_section) -> list[str]:
    import numpy as np
    from matplotlib.figure import Figure

    from bearing_gym.analysis.spectra import power_spectrum

    title = op_text(params)
    t = rec.t
    written = []

    fig = Figure(figsize=(8, 8), layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    for ax, (k, f, unit) in zip(axes, (("x", 1e6, "um"), ("y", 1e6, "um"), ("z", 1e6, "um"),
                                       ("cage_speed", 1.0, "rad/s"))):
        ax.plot(t * 1e3, getattr(rec, k) * f, lw=0.6)
        ax.axvspan(t[0] * 1e3, t[late][0] * 1e3, color="0.9", lw=0)
        ax.set_ylabel(f"{k} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].set_title(f"time series (grey: first half, not summarised)\n{title}", fontsize=8)
    axes[-1].set_xlabel("t (ms)")
    fig.savefig(out / "timeseries.png", dpi=110)
    written.append("timeseries.png")

    fig = Figure(figsize=(9, 4.2), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    a1.plot(rec.x[late] * 1e6, rec.y[late] * 1e6, lw=0.5)
    a1.set_xlabel("x (um)")
    a1.set_ylabel("y (um)")
    a1.set_aspect("equal", adjustable="datalim")
    a2.plot(rec.x[late] * 1e6, rec.z[late] * 1e6, lw=0.5)
    a2.set_xlabel("x (um)")
    a2.set_ylabel("z (um)")
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    fig.suptitle(f"orbit, second half\n{title}", fontsize=8)
    fig.savefig(out / "orbit.png", dpi=110)
    written.append("orbit.png")

    fig = Figure(figsize=(8, 6), layout="constrained")
    axes = fig.subplots(2, 1)
    tl = t[late]
    top = [0.0, 0.0]
    for k in ("x", "y", "z"):
        try:
            f, p = power_spectrum(tl, getattr(rec, k)[late])
        except ValueError:
            continue
        axes[0].semilogy(f, np.maximum(p, 1e-40) * 1e12, lw=0.8, label=f"{k} (PSD, um^2/Hz)")
        top[0] = max(top[0], float(np.max(p)) * 1e12)
    try:
        f, p = power_spectrum(tl, rec.cage_speed[late])
        axes[1].semilogy(f, np.maximum(p, 1e-40), lw=0.8, color="C3", label="cage speed")
        top[1] = float(np.max(p))
    except ValueError:
        pass
    for ax, hi in zip(axes, top):
        if hi > 0:
            ax.set_ylim(hi * 1e-12, hi * 10)       # 12 decades: the noise floor is not news
        for (lab, v), ls in zip(ref.items(), (":", "--", "-.")):
            if v > 0 and math.isfinite(v):
                ax.axvline(v, color="0.4", ls=ls, lw=0.8, label=lab.replace("_hz", ""))
        ax.set_xlim(0, max(5 * max(ref.values()), 10.0))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("PSD of x, y, z (um^2/Hz)")
    axes[1].set_ylabel("PSD of cage speed ((rad/s)^2/Hz)")
    axes[1].set_xlabel("frequency (Hz)")
    axes[0].set_title(f"spectra, second half; principal x {freqs['x']:.1f} Hz, cage "
                      f"{freqs['cage_speed']:.1f} Hz\n{title}", fontsize=8)
    fig.savefig(out / "spectrum.png", dpi=110)
    written.append("spectrum.png")

    fig = Figure(figsize=(9, 4.2), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    try:
        pts = shaft_section(RecordWindow(rec, late), ("x", "y", "z")) * 1e6
    except ValueError:
        pts = np.empty((0, 3))
    a1.plot(pts[:, 0], pts[:, 1], "o", ms=3)
    a1.set_xlabel("x (um)")
    a1.set_ylabel("y (um)")
    a2.plot(pts[:, 0], pts[:, 2], "o", ms=3)
    a2.set_xlabel("x (um)")
    a2.set_ylabel("z (um)")
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    q = "n/a" if qpi is None else f"{qpi:.3f}"
    fig.suptitle(f"Poincare section once per shaft revolution ({len(pts)} points, "
                 f"quasi-periodicity index {q})\n{title}", fontsize=8)
    fig.savefig(out / "poincare.png", dpi=110)
    written.append("poincare.png")
    return written
