"""``bearing-gym simulate``: run the Simulator at an operating point, print a summary and save
the record, the summary and the plots."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

from bearing_gym.serialization import to_jsonable

from .errors import CLIError, RunError, check_option, one_line
from .options import params_from_args
from .output import Out, RecordWindow, advance, op_text, params_dict

__all__ = ["cmd_simulate", "MIN_POINCARE_POINTS", "Verdict", "judge_motion", "simulate_figures",
           "spectrum_upper_limit"]

# A verdict needs at least this many once-per-turn Poincare points in EACH half of the analysed
# window: the spread of n points is known to about 1 / sqrt(2 (n - 1)), 24 % for 10.
MIN_POINCARE_POINTS = 10

_RECORD_FIELDS = ("t", "x", "y", "z", "theta_x", "theta_y", "x_dot", "y_dot", "z_dot",
                  "theta_x_dot", "theta_y_dot", "cage_speed", "cage_angle", "shaft_angle",
                  "bearing_force", "n_inner_contacts")


@dataclasses.dataclass(frozen=True)
class Verdict:
    """The motion of the analysed window: ``text`` (periodic, quasi-periodic, static or
    undetermined), the index of the window and of its two halves, the Poincare points of the
    window, and ``warning`` (None when the verdict holds)."""

    text: str
    qpi: float | None
    qpi_halves: tuple[float, float] | None
    poincare_points: int
    reliable: bool
    warning: str | None = None
    suggested_duration_s: float | None = None


def _classify(q: float, threshold: float) -> str:
    return "periodic (period-1)" if q < threshold else "quasi-periodic (or chaotic)"


def judge_motion(t, signals, shaft_speed_rad_s: float, threshold: float,
                 duration_s: float) -> Verdict:
    """Periodic or quasi-periodic, from the quasi-periodicity index of the analysed window
    ``t`` (the run's second half; ``duration_s`` is the whole run) -- and whether that verdict
    can be trusted.

    The run starts from the static equilibrium, so the rotor rings; the index of a window that
    still holds the decaying transient reads quasi-periodic for motion that settles to
    period-1. The verdict is given only when (1) each half of the window holds at least
    ``MIN_POINCARE_POINTS`` once-per-turn points and (2) the index of the whole window and of
    each half fall on the same side of ``threshold``: a transient that still rings makes the
    first half (or the drift across the halves) read higher than the second. Otherwise the
    verdict is "undetermined" with a warning saying why and a longer ``--duration`` to try.
    """
    import numpy as np

    from bearing_gym.analysis.signals import quasi_periodicity_index

    t = np.asarray(t, dtype=float)
    span = float(t[-1] - t[0]) if len(t) else 0.0
    if shaft_speed_rad_s <= 0:
        return Verdict("static (shaft not turning)", 0.0, None, 0, True)
    period = 2.0 * math.pi / shaft_speed_rad_s
    turns = span / period
    points = int(math.floor(turns + 1e-9)) + 1 if len(t) else 0
    try:
        qpi = quasi_periodicity_index(t, signals, shaft_speed_rad_s)
    except ValueError:
        qpi = None
    need_turns = 2 * MIN_POINCARE_POINTS          # turns in the window for 10 points per half
    need_duration = 2.0 * need_turns * period     # the window is the run's second half
    if qpi is None or turns < need_turns:
        longer = max(need_duration, 2.0 * duration_s)
        return Verdict(
            "undetermined (window too short for a verdict)", qpi, None, points, False,
            f"the analysed second half spans {turns:.1f} shaft turns ({points} Poincare "
            f"points); a verdict needs at least {need_turns} ({MIN_POINCARE_POINTS} per half "
            f"of the window), i.e. --duration of at least {need_duration:.3g} s at this speed; "
            f"rerun with e.g. --duration {_nice(longer)}", longer)
    half = len(t) // 2
    halves = (quasi_periodicity_index(t[:half], signals[:half], shaft_speed_rad_s),
              quasi_periodicity_index(t[half:], signals[half:], shaft_speed_rad_s))
    sides = {q < threshold for q in (qpi, *halves)}
    if len(sides) > 1:
        longer = 2.0 * duration_s
        return Verdict(
            f"undetermined (not settled; the window's index alone reads "
            f"{_classify(qpi, threshold).split(' (')[0]})",
            qpi, halves, points, False,
            f"the verdict is not settled: the index of the window ({qpi:.3f}) and of its halves "
            f"({halves[0]:.3f}, then {halves[1]:.3f}) fall on both sides of the threshold "
            f"{threshold:g}: the start transient is still decaying (or the motion sits at the "
            f"threshold); rerun with a longer --duration, e.g. {_nice(longer)}", longer)
    return Verdict(_classify(qpi, threshold), qpi, halves, points, True)


def _nice(seconds: float) -> str:
    """A round duration at least ``seconds`` (1, 2 or 5 times a power of ten), as text."""
    e = math.floor(math.log10(seconds))
    for m in (1, 2, 5, 10):
        if m * 10.0 ** e >= seconds * (1 - 1e-9):
            return f"{m * 10.0 ** e:g}"
    return f"{seconds:g}"  # pragma: no cover


def cmd_simulate(args, say: Out) -> int:
    import time

    import numpy as np

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
    judged = judge_motion(win.t, xyz, w, args.qpi_threshold, duration)
    qpi, verdict = judged.qpi, judged.text
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
                   motion=verdict, qpi_halves=judged.qpi_halves,
                   poincare_points=judged.poincare_points, verdict_reliable=judged.reliable,
                   warning=judged.warning, params=params_dict(params))

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
    if judged.warning:
        say(f"  warning: {judged.warning}")

    written = ["record.npz", "summary.json"]
    if not args.no_plots:
        for name, fig in simulate_figures(rec, late, params, freqs, ref, qpi).items():
            fig.savefig(out / name, dpi=110)
            written.append(name)
    (out / "summary.json").write_text(json.dumps(to_jsonable(dict(summary, files=written)),
                                                 indent=1) + "\n")
    say(f"  wrote {', '.join(written)} in {out}")
    return 0


def spectrum_upper_limit(f, psds, floor: float, refs) -> float:
    """The upper frequency limit (Hz) of a spectrum panel: 10 % beyond the highest frequency at
    which a plotted PSD is above the panel's ``floor`` or a reference line stands, but at most
    five times the highest reference (five ball-pass harmonics; broadband content beyond is
    not news) and at most the Nyquist frequency ``f[-1]``."""
    import numpy as np

    refs = [v for v in refs if v > 0 and math.isfinite(v)]
    last = 0.0
    for p in psds:
        above = np.nonzero(np.asarray(p) > floor)[0]
        if above.size:
            last = max(last, float(f[above[-1]]))
    hi = 1.1 * max([last, *refs, 10.0 / 1.1])
    if refs:
        hi = min(hi, 5.0 * max(refs))
    return float(min(hi, f[-1]))


_SERIES = (("x", 1e6, "x displacement (um)"), ("y", 1e6, "y displacement (um)"),
           ("z", 1e6, "z (axial) displacement (um)"), ("cage_speed", 1.0, "cage speed (rad/s)"))


def simulate_figures(rec, late, params, freqs, ref, qpi) -> dict:
    """The figures of ``simulate`` by file name (matplotlib Figures, drawn off-screen):
    time series, orbit, spectra and Poincare section of the record ``rec`` whose analysed
    window is the mask ``late``."""
    import numpy as np
    from matplotlib.figure import Figure

    from bearing_gym.analysis.poincare import shaft_section
    from bearing_gym.analysis.spectra import power_spectrum

    title = op_text(params)
    t = rec.t
    tl = t[late]
    window = f"t = {tl[0]:.3g}-{tl[-1]:.3g} s"
    figs = {}

    def hz(v: float) -> str:
        return "n/a" if not math.isfinite(v) else f"{v:.1f} Hz"

    fig = Figure(figsize=(8, 8), layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    for ax, (k, f, label) in zip(axes, _SERIES):
        ax.plot(t * 1e3, getattr(rec, k) * f, lw=0.6)
        ax.axvspan(t[0] * 1e3, tl[0] * 1e3, color="0.9", lw=0)
        ax.set_ylabel(label, fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].set_title(f"rotor displacement and cage speed over time (grey: first half, start "
                      f"transient, not summarised)\n{title}", fontsize=8)
    axes[-1].set_xlabel("time t (ms)")
    figs["timeseries.png"] = fig

    fig = Figure(figsize=(9, 4.2), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    a1.plot(rec.x[late] * 1e6, rec.y[late] * 1e6, lw=0.5)
    a1.set(xlabel="x displacement (um)", ylabel="y displacement (um)", title="radial (x-y)")
    a1.set_aspect("equal", adjustable="datalim")
    a2.plot(rec.x[late] * 1e6, rec.z[late] * 1e6, lw=0.5)
    a2.set(xlabel="x displacement (um)", ylabel="z (axial) displacement (um)",
           title="radial-axial (x-z)")
    for ax in (a1, a2):
        ax.title.set_fontsize(8)
        ax.grid(alpha=0.3)
    fig.suptitle(f"orbit of the rotor centre, second half ({window})\n{title}", fontsize=8)
    figs["orbit.png"] = fig

    fig = Figure(figsize=(8, 6), layout="constrained")
    axes = fig.subplots(2, 1)
    panels: list[tuple[np.ndarray, list]] = [(np.zeros(1), []), (np.zeros(1), [])]
    for k in ("x", "y", "z"):
        try:
            f, p = power_spectrum(tl, getattr(rec, k)[late])
        except ValueError:
            continue
        axes[0].semilogy(f, np.maximum(p, 1e-40) * 1e12, lw=0.8, label=f"{k}")
        panels[0] = (f, panels[0][1] + [p * 1e12])
    try:
        f, p = power_spectrum(tl, rec.cage_speed[late])
        axes[1].semilogy(f, np.maximum(p, 1e-40), lw=0.8, color="C3", label="cage speed")
        panels[1] = (f, [p])
    except ValueError:
        pass
    names = dict(shaft_hz="shaft speed", ball_pass_outer_hz="ball pass N w_c",
                 ball_pass_inner_hz="ball pass N (w - w_c)")
    for ax, (f, psds) in zip(axes, panels):
        hi = max((float(np.max(p)) for p in psds), default=0.0)
        if hi > 0:
            # at most 12 decades, and no lower than a decade below the spectrum's own floor
            # (its 1st percentile): the noise floor is not news
            floor = hi * 1e-12
            top_f = spectrum_upper_limit(f, psds, floor, ref.values())
            shown = np.concatenate([p[(f > 0) & (f <= top_f)] for p in psds])
            floor = max(floor, 0.1 * float(np.percentile(shown, 1))) if shown.size else floor
            ax.set_ylim(floor, hi * 10)
            ax.set_xlim(0, top_f)
        else:
            ax.text(0.5, 0.5, "no spectrum (window too short or signal constant)",
                    ha="center", va="center", transform=ax.transAxes)
            ax.set_xlim(0, max(1.1 * max(ref.values()), 10.0))
        for (lab, v), ls in zip(ref.items(), (":", "--", "-.")):
            if v > 0 and math.isfinite(v):
                ax.axvline(v, color="0.4", ls=ls, lw=0.8, label=names.get(lab, lab))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("PSD of x, y, z (um^2/Hz)")
    axes[1].set_ylabel("PSD of cage speed ((rad/s)^2/Hz)")
    for ax in axes:
        ax.set_xlabel("frequency (Hz)")
    axes[0].set_title(f"power spectral density, second half ({window}); principal frequency x "
                      f"{hz(freqs['x'])}, cage speed {hz(freqs['cage_speed'])}\n{title}",
                      fontsize=8)
    figs["spectrum.png"] = fig

    fig = Figure(figsize=(9, 4.2), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    try:
        pts = shaft_section(RecordWindow(rec, late), ("x", "y", "z")) * 1e6
    except ValueError:
        pts = np.empty((0, 3))
    a1.plot(pts[:, 0], pts[:, 1], "o", ms=3)
    a1.set(xlabel="x displacement (um)", ylabel="y displacement (um)")
    a2.plot(pts[:, 0], pts[:, 2], "o", ms=3)
    a2.set(xlabel="x displacement (um)", ylabel="z (axial) displacement (um)")
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
        if not len(pts):
            ax.text(0.5, 0.5, "no Poincare points: the window holds no full shaft turn",
                    ha="center", va="center", transform=ax.transAxes, fontsize=8)
    q = "n/a" if qpi is None else f"{qpi:.3f}"
    fig.suptitle(f"Poincare section once per shaft revolution, second half ({len(pts)} points, "
                 f"quasi-periodicity index {q})\n{title}", fontsize=8)
    figs["poincare.png"] = fig
    return figs
