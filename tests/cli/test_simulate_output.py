"""The output of `bearing-gym simulate` and the sweep maps (issue 16): a verdict only when the analysed window
can carry one, the radial load's resultant, where a JSON file went, and figures whose axes are
labelled and sized to their data."""

import json
import math
from collections import deque
from types import SimpleNamespace

import numpy as np
import pytest

from bearing_gym import cli
from bearing_gym.analysis import sweeps
from bearing_gym.analysis.signals import QPI_THRESHOLD, quasi_periodicity_index
from bearing_gym.cli import simulate
from bearing_gym.envs.rendering import draw_frame

W = 20000 * 2 * math.pi / 60          # shaft speed (rad/s) of the synthetic signals


def _signals(duration_s, transient=0.0, tau_s=0.05, quasi=0.0, dt=1e-5):
    """The second half of a run of ``duration_s``: a period-1 orbit (x, y, z), plus a decaying
    oscillation at an incommensurate frequency (``transient``, relative amplitude at t = 0) and
    a steady one (``quasi``)."""
    t = np.arange(0.0, duration_s + dt / 2, dt)
    w2 = W * (math.sqrt(5) - 1) / 2
    extra = transient * np.exp(-t / tau_s) + quasi
    xyz = np.column_stack([np.cos(W * t) + extra * np.cos(w2 * t),
                           np.sin(W * t) + extra * np.sin(w2 * t),
                           0.1 * np.cos(2 * W * t) + 0.1 * extra * np.cos(w2 * t)])
    late = t >= duration_s / 2
    return t[late], xyz[late]


def test_a_settled_period_1_orbit_and_a_steady_quasi_periodic_one_get_their_verdicts():
    t, xyz = _signals(0.5)
    v = simulate.judge_motion(t, xyz, W, QPI_THRESHOLD, 0.5)
    assert v.reliable and v.warning is None and v.text == "periodic (period-1)"
    assert v.qpi < QPI_THRESHOLD and max(v.qpi_halves) < QPI_THRESHOLD
    t, xyz = _signals(0.5, quasi=0.8)
    v = simulate.judge_motion(t, xyz, W, QPI_THRESHOLD, 0.5)
    assert v.reliable and v.text == "quasi-periodic (or chaotic)"
    assert min(v.qpi, *v.qpi_halves) >= QPI_THRESHOLD


def test_a_ringing_transient_gives_no_verdict_but_a_warning_with_a_longer_duration():
    duration = 0.3
    t, xyz = _signals(duration, transient=100.0, tau_s=0.03)
    half = len(t) // 2
    first = quasi_periodicity_index(t[:half], xyz[:half], W)
    second = quasi_periodicity_index(t[half:], xyz[half:], W)
    assert first >= QPI_THRESHOLD > second          # the case of the issue: it is settling
    v = simulate.judge_motion(t, xyz, W, QPI_THRESHOLD, duration)
    assert not v.reliable and v.text.startswith("undetermined (not settled")
    assert "--duration" in v.warning and v.suggested_duration_s > duration
    # long enough, the same transient has died out and the verdict is period-1
    t, xyz = _signals(2.0, transient=100.0, tau_s=0.03)
    v = simulate.judge_motion(t, xyz, W, QPI_THRESHOLD, 2.0)
    assert v.reliable and v.text == "periodic (period-1)"


def test_a_window_with_too_few_poincare_points_gives_no_verdict():
    period = 2 * math.pi / W
    shortest = 4 * simulate.MIN_POINCARE_POINTS * period      # the window is the second half
    for duration, reliable in ((0.9 * shortest, False), (1.1 * shortest, True)):
        t, xyz = _signals(duration)
        v = simulate.judge_motion(t, xyz, W, QPI_THRESHOLD, duration)
        assert v.reliable == reliable, (duration, v)
        if not reliable:
            assert v.text.startswith("undetermined") and f"{shortest:.3g} s" in v.warning
    t, xyz = _signals(0.01)
    v = simulate.judge_motion(t, xyz, 0.0, QPI_THRESHOLD, 0.01)
    assert v.reliable and v.text.startswith("static")


@pytest.fixture(scope="module")
def run_800n(tmp_path_factory):
    """simulate at 800 N: the issue's short run (0.1 s) and the default 0.5 s."""
    out = {}
    for duration in ("0.1", "0.5"):
        d = tmp_path_factory.mktemp(f"sim{duration}")
        argv = ["simulate", "--duration", duration, "--rpm", "20000", "--preload", "800",
                "--clearance-um", "4", "--out", str(d)]
        assert cli.main(argv + ["-q"]) == 0
        out[duration] = d
    return out


def test_simulate_warns_instead_of_a_verdict_from_a_short_run(run_800n, capsys):
    short = json.loads((run_800n["0.1"] / "summary.json").read_text())
    assert short["motion"].startswith("undetermined") and not short["verdict_reliable"]
    assert "--duration" in short["warning"]
    assert short["poincare_points"] < 2 * simulate.MIN_POINCARE_POINTS
    full = json.loads((run_800n["0.5"] / "summary.json").read_text())
    assert full["verdict_reliable"] == (full["warning"] is None)
    q, halves = full["quasi_periodicity_index"], full["qpi_halves"]
    if full["verdict_reliable"]:
        assert full["motion"] == ("periodic (period-1)" if q < QPI_THRESHOLD
                                  else "quasi-periodic (or chaotic)")
        assert len({v < QPI_THRESHOLD for v in (q, *halves)}) == 1
    # the warning is printed under the motion line
    assert cli.main(["simulate", "--duration", "0.1", "--out", str(run_800n["0.1"]),
                     "--no-plots"]) == 0
    lines = capsys.readouterr().out.splitlines()
    i = next(k for k, line in enumerate(lines) if line.strip().startswith("motion:"))
    assert lines[i + 1].strip().startswith("warning:") and "--duration" in lines[i + 1]


def _record(path):
    d = np.load(path / "record.npz")
    return SimpleNamespace(**{k: d[k] for k in d.files if d[k].ndim >= 1})


def _figures(run_dir):
    import bearing_gym
    from bearing_gym.analysis.spectra import ball_pass_frequency, ball_pass_frequency_inner

    rec = _record(run_dir)
    params = bearing_gym.default_params(shaft_speed_rpm=20000, axial_preload_n=800,
                                        clearance_inner_m=4e-6, clearance_outer_m=4e-6)
    late = rec.t >= rec.t[0] + 0.5 * (rec.t[-1] - rec.t[0])
    w, cage = params.shaft_speed_rad_s, float(np.mean(rec.cage_speed[late]))
    ref = dict(shaft_hz=w / (2 * math.pi), ball_pass_outer_hz=ball_pass_frequency(cage, params.geometry.n_balls),
               ball_pass_inner_hz=ball_pass_frequency_inner(w, cage, params.geometry.n_balls))
    freqs = dict(x=math.nan, y=math.nan, z=math.nan, cage_speed=math.nan)
    return simulate.simulate_figures(rec, late, params, freqs, ref, 0.05), ref


def test_spectrum_axis_ends_where_the_data_and_the_reference_lines_end(run_800n):
    figs, ref = _figures(run_800n["0.5"])
    assert sorted(figs) == ["orbit.png", "poincare.png", "spectrum.png", "timeseries.png"]
    ax = figs["spectrum.png"].axes[0]                   # displacement PSD
    lo, hi = ax.get_xlim()
    floor = ax.get_ylim()[0]
    psd_lines = [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2]
    last = max(float(ln.get_xdata()[np.nonzero(ln.get_ydata() > floor)[0][-1]]) for ln in psd_lines)
    nyquist = max(float(ln.get_xdata()[-1]) for ln in psd_lines)
    edge = max(last, max(ref.values()))
    assert lo == 0 and max(ref.values()) < hi <= 1.1 * edge + 1e-6
    assert hi < 0.5 * nyquist and hi <= 5 * max(ref.values())
    assert (hi - last) / hi < 0.25                  # at most a quarter of the axis without data
    assert figs["spectrum.png"].axes[1].get_xlim()[1] <= 5 * max(ref.values()) + 1e-6


def test_every_simulate_figure_has_a_title_and_labelled_axes_with_units(run_800n):
    figs, _ = _figures(run_800n["0.5"])
    for name, fig in figs.items():
        titles = [fig._suptitle.get_text() if fig._suptitle else ""]
        titles += [ax.get_title() for ax in fig.axes]
        assert any(t.strip() for t in titles), name
        for ax in fig.axes:
            assert "(" in ax.get_ylabel() and ")" in ax.get_ylabel(), (name, ax.get_ylabel())
            assert ax.get_lines() or ax.collections or ax.texts, name     # nothing empty
            assert "_" not in ax.get_ylabel(), (name, ax.get_ylabel())
        assert any(ax.get_xlabel() for ax in fig.axes), name


def test_spectrum_upper_limit_rule():
    f = np.linspace(0, 50000, 5001)
    psd = np.where(f < 2000, 1.0, 1e-20)
    assert simulate.spectrum_upper_limit(f, [psd], 1e-12, [300.0, 1000.0]) == pytest.approx(1.1 * 1990)
    assert simulate.spectrum_upper_limit(f, [psd], 1e-12, [300.0, 3000.0]) == pytest.approx(3300)
    flat = np.ones_like(f)                              # broadband to Nyquist: five harmonics
    assert simulate.spectrum_upper_limit(f, [flat], 1e-12, [300.0, 3000.0]) == pytest.approx(15000)


def _rows():
    base = dict(label="20000rpm", shaft_speed_rpm=20000.0, radial_load_x_n=0.0, clearance_m=4e-6,
                ptp_x_m=6e-5, ptp_z_m=1e-6, cage_ptp_rad_s=4.0)
    # period-1; quasi-periodic; index below the threshold but Floquet-unstable
    cases = [(1000, 0.02, True), (900, 0.03, True), (700, 0.5, False), (600, 0.9, False),
             (800, 0.5 * QPI_THRESHOLD, False)]
    rows = [dict(base, axial_preload_n=float(p), qpi=q, periodic=per) for p, q, per in cases]
    rows += [dict(r, label="10000rpm", shaft_speed_rpm=10000.0) for r in rows]
    return rows


def _labels(fig):
    out = []
    for ax in fig.axes:
        out += [ax.get_xlabel(), ax.get_ylabel()]
    return [s for s in out if s]


def test_map_axes_are_words_with_units_and_the_classes_are_marked():
    rows = _rows()
    per, qp, other = sweeps.point_classes(rows)
    assert (per.sum(), qp.sum(), other.sum()) == (4, 4, 2)
    assert all(r["qpi"] >= QPI_THRESHOLD for r, m in zip(rows, qp) if m)
    fig = sweeps.plot_stability_map(rows, "shaft_speed_rpm")
    ax = fig.axes[0]
    assert ax.get_ylabel() == "shaft speed (rpm)" and ax.get_xlabel() == "axial preload P_z (N)"
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("period-1" in t and t.endswith(f": {per.sum()}") for t in legend)
    assert any("quasi-periodic" in t and f"{QPI_THRESHOLD:g}" in t and t.endswith(f": {qp.sum()}")
               for t in legend)
    assert sorted(len(c.get_offsets()) for c in ax.collections) == sorted(
        int(m.sum()) for m in (per, qp, other))
    assert f"{QPI_THRESHOLD:g}" in fig.axes[1].get_ylabel()              # colour bar
    assert ax.get_title()
    for label in _labels(fig):
        assert "_rad_s" not in label and "_rpm" not in label and not label.endswith("_m")

    fig = sweeps.plot_sweep(rows, ("ptp_x_m", "cage_ptp_rad_s", "qpi"))
    assert [a.get_ylabel() for a in fig.axes] == ["x peak-to-peak (um)",
                                                  "cage speed peak-to-peak (rad/s)",
                                                  "quasi-periodicity index (dimensionless)"]
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(t.startswith("period-1") for t in legend)
    assert any(t.startswith("quasi-periodic") for t in legend)
    thresholds = [ln for ln in fig.axes[2].get_lines() if list(ln.get_ydata()) == [QPI_THRESHOLD] * 2]
    assert len(thresholds) == 1 and fig.axes[0].get_title()


def test_unknown_columns_are_labelled_from_their_unit_suffix():
    assert sweeps.column_label("floquet_max_angle_deg") == ("floquet max angle (deg)", 1.0)
    assert sweeps.column_label("wall_s") == ("wall (s)", 1.0)
    assert sweeps.column_label("ptp_y_m")[1] == 1e6


def test_the_reset_frame_says_what_it_is_instead_of_empty_axes():
    from matplotlib.figure import Figure

    fig = Figure()
    draw_frame(fig, None, deque(), deque())
    assert len(fig.axes) == 3
    for ax in fig.axes:
        texts = " ".join(t.get_text() for t in ax.texts)
        assert texts.strip() and ax.get_title() and ax.get_xlabel() and ax.get_ylabel()
        assert not list(ax.get_xticks()) and not list(ax.get_yticks())
    assert "reset" in " ".join(t.get_text() for t in fig.axes[0].texts)
    # with data, the panels draw it and carry no note
    fig = Figure()
    orbit = np.column_stack([np.cos(np.linspace(0, 6, 50)), np.sin(np.linspace(0, 6, 50)),
                             np.zeros(50)]) * 1e-5
    draw_frame(fig, orbit, deque([(1e-5, 2e-6)]), deque([(0.02, 1000.0, 1000.0, 0.01)]))
    assert all(ax.get_lines() and not ax.texts for ax in fig.axes)
    # the first step's single preload sample is visible (a marker: a line needs two points)
    assert all(ln.get_marker() not in (None, "None", "") for ln in fig.axes[2].get_lines())


def test_radial_load_says_both_axes_and_the_resultant(tmp_path, capsys):
    assert cli.main(["equilibrium", "--radial-load", "200"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert "P_x = 200 N, P_y = 200 N" in first
    assert f"resultant {math.hypot(200, 200):.4g} N at 45 deg" in first
    assert cli.main(["equilibrium"]) == 0
    assert "resultant" not in capsys.readouterr().out.splitlines()[0]
    assert cli.main(["equilibrium", "--help"]) == 0
    help_text = " ".join(capsys.readouterr().out.split())
    assert "EACH of the x and y axes" in help_text and "P_x = P_y" in help_text


def test_equilibrium_json_says_where_it_wrote(tmp_path, capsys):
    path = tmp_path / "eq.json"
    assert cli.main(["equilibrium", "--json", str(path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last == f"wrote the results as JSON to {path}" and path.is_file()
    assert cli.main(["equilibrium", "--json", str(path), "-q"]) == 0
    assert capsys.readouterr().out == ""
    assert cli.main(["equilibrium", "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["params"]        # stdout is only the JSON
