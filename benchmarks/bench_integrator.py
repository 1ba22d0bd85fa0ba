"""Speed of the numba bearing-force kernel and Newmark integrator, against the plain-NumPy
reference of ``numpy_reference.py``.

    python benchmarks/bench_integrator.py            # table, ~30 s on a 2-core machine
    python benchmarks/bench_integrator.py --json     # one JSON object instead of the table
    python benchmarks/bench_integrator.py --quick    # same keys, shorter runs (~5 s)

Configuration: ``bearing_gym.default_params(dt_s=dt)`` (Table 1 bearing, 20,000 rpm, 800 N axial
preload, e = 10 um unbalance, damping from the static stiffness), started at the static
equilibrium. Measured:

* bearing-force evaluation, warm ball states (every ball starts at its converged solution, so
  each ball needs one residual evaluation): numba timed inside an njit loop and from Python,
  NumPy reference from Python;
* Newmark steps for dt in {1, 2, 5, 10} us: numba (``Simulator.advance`` over 0.05 s simulated,
  after a warm-up that also triggers compilation) and the NumPy reference over three short
  windows taken at the start, middle and end of that run, each started from the numba state
  there (the trajectories are compared: the NumPy code follows the numba iteration path); numba
  is timed on those window steps too, which gives the like-for-like ("same steps") speed-up.
  Newmark iterations per step and ball residual (Newton) evaluations per ball per force
  evaluation are read from the integrator's diagnostic counters (``rotor.S_N_EVAL``,
  ``ball.B_NITER``) over the timed numba run; with a package version without them, from the
  NumPy windows (which also report their own counts, and numba is timed on those windows too).

Times are wall-clock ``time.perf_counter``; each timing is repeated and the minimum reported
(other load on the machine can only add time; the medians are in the JSON output).
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from numba import njit  # noqa: E402

import bearing_gym  # noqa: E402
from bearing_gym.physics import Simulator  # noqa: E402
from bearing_gym.physics import ball as ball_mod  # noqa: E402
from bearing_gym.physics import rotor as rotor_mod  # noqa: E402
from bearing_gym.physics.bearing import bearing_force  # noqa: E402

import bench_cli  # noqa: E402
from numpy_reference import NumpyModel, ball_state_from_arrays, state_from_simulator  # noqa: E402

DTS_US = (1.0, 2.0, 5.0, 10.0)
NUMPY_WINDOWS = (0.0, 0.5, 1.0)   # where in the timed numba run the NumPy windows start

SETTINGS = {
    # simulated seconds: warm-up (compile + leave the first transient), timed run, repeats
    # numpy_steps: steps per NumPy window (three windows per dt)
    # *_repeats: timed repetitions, the minimum is reported (the median is in the JSON too)
    "full": dict(warmup_s=0.005, numba_run_s=0.05, numba_repeats=5, numpy_steps=150,
                 numpy_repeats=2, window_repeats=20, force_repeats=5, force_loop=10000,
                 force_py_calls=2000, numpy_force_calls=100),
    "quick": dict(warmup_s=0.002, numba_run_s=0.01, numba_repeats=2, numpy_steps=15,
                  numpy_repeats=1, window_repeats=3, force_repeats=2, force_loop=2000,
                  force_py_calls=300, numpy_force_calls=20),
}


# ---------------------------------------------------------------------------------------------
machine_info = bench_cli.machine_info


@njit(cache=False)
def _force_loop(n, U, prm, omega, race_wav, ball_wav, ball_phase, ball_size, psi_b, ball_v, ball_out, F):
    """n bearing-force evaluations at the same U (warm ball states), inside numba."""
    worst = 0
    for _ in range(n):
        st = bearing_force(U, 0.0, 0.0, psi_b, prm, omega, race_wav, ball_wav, ball_phase, ball_size,
                           ball_v, ball_out, F)
        if st > worst:
            worst = st
    return worst


def _best_of(repeats: int, fn) -> tuple[float, float]:
    """(min, median) wall time of ``repeats`` calls of fn(). The minimum is the statistic
    reported: other load on the machine only ever adds time."""
    walls = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        walls.append(time.perf_counter() - t0)
    return min(walls), statistics.median(walls)


def bench_force(cfg: dict) -> dict:
    sim = Simulator(bearing_gym.default_params())
    s = sim.state
    p = sim._packed
    U = s.X.copy()
    F = np.zeros(5)
    args = (p.prm, p.op[0], p.race_wav, p.ball_wav, p.ball_phase, p.ball_size, s.psi_b, s.ball_v,
            s.ball_out, F)
    assert _force_loop(10, U, *args) == 0                  # compile
    F_numba = F.copy()
    reps = cfg["force_repeats"]
    n = cfg["force_loop"]
    loop_min, loop_med = _best_of(reps, lambda: _force_loop(n, U, *args))
    n_py = cfg["force_py_calls"]

    def python_calls():
        for _ in range(n_py):
            bearing_force(U, 0.0, 0.0, s.psi_b, p.prm, p.op[0], p.race_wav, p.ball_wav, p.ball_phase,
                          p.ball_size, s.ball_v, s.ball_out, F)
    py_min, _ = _best_of(reps, python_calls)

    model = NumpyModel(sim.params, damping=sim.damping_coefficients)
    balls = ball_state_from_arrays(s.ball_v, s.ball_out)
    F_np, st = model.bearing_force(U, 0.0, 0.0, s.psi_b, balls)   # warm-up, and the check
    assert st == 0
    n_np = cfg["numpy_force_calls"]

    def numpy_calls():
        for _ in range(n_np):
            model.bearing_force(U, 0.0, 0.0, s.psi_b, balls)
    model.reset_counters()
    np_min, np_med = _best_of(reps, numpy_calls)
    c = model.counters
    scale = np.array([1, 1, 1, 1 / model.r_p, 1 / model.r_p])
    rel = float(np.max(np.abs((F_np - F_numba) * scale)) / np.max(np.abs(F_numba * scale)))
    numba_us = loop_min / n * 1e6
    numpy_us = np_min / n_np * 1e6
    return {
        "numba_us_per_eval_njit_loop": numba_us,
        "numba_us_per_eval_njit_loop_median": loop_med / n * 1e6,
        "numba_us_per_eval_python_call": py_min / n_py * 1e6,
        "numpy_us_per_eval": numpy_us,
        "numpy_us_per_eval_median": np_med / n_np * 1e6,
        "speedup_numba_over_numpy": numpy_us / numba_us,
        "ball_residuals_per_ball_per_eval": c["ball_residuals"] / (c["force_evals"] * model.n),
        "numpy_newton_passes_per_eval": c["newton_passes"] / c["force_evals"],
        "max_rel_diff_numpy_vs_numba": rel,
        "n_balls": model.n,
    }


def _numba_diagnostics(before, after, n_steps):
    """(force evaluations per step, ball residual evaluations per ball per force evaluation)
    between two SimulatorStates, from the integrator's diagnostic counters (``rotor.S_N_EVAL``,
    ``ball.B_NITER``), or None if this version of the package has no such counters."""
    s_n_eval = getattr(rotor_mod, "S_N_EVAL", None)
    b_niter = getattr(ball_mod, "B_NITER", None)
    if s_n_eval is None or b_niter is None:
        return None
    evals = after.scal[s_n_eval] - before.scal[s_n_eval]
    residuals = float(np.sum(after.ball_out[:, b_niter] - before.ball_out[:, b_niter]))
    if evals <= 0:
        return None
    return evals / n_steps, residuals / (evals * after.ball_out.shape[0])


def bench_dt(dt_us: float, cfg: dict) -> dict:
    dt = dt_us * 1e-6
    params = bearing_gym.default_params(dt_s=dt)
    t0 = time.perf_counter()
    sim = Simulator(params)
    setup_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    sim.advance(cfg["warmup_s"], record_every=1000)          # compiles on the first dt
    warmup_wall = time.perf_counter() - t0
    start = sim.state

    # numba: repeated runs of numba_run_s simulated seconds from the same warmed-up state
    n_steps = int(round(cfg["numba_run_s"] / dt))

    def numba_run():
        sim.state = start
        rec = sim.advance(n_steps * dt, record_every=max(1, n_steps // 10))
        assert rec.ok, rec.status
    wall, wall_med = _best_of(cfg["numba_repeats"], numba_run)
    numba_us_step = wall / n_steps * 1e6
    numba_counts = _numba_diagnostics(start, sim.state, n_steps)

    # NumPy reference over short windows sampled at the start, middle and end of the timed run,
    # each from the numba state at that time; numba runs the same steps for the comparison and
    # for the per-residual cost
    k = cfg["numpy_steps"]
    model = NumpyModel(params, damping=sim.damping_coefficients)
    numpy_wall = numba_window_wall = rel = 0.0
    counts = {key: 0 for key in model.counters}
    for frac in NUMPY_WINDOWS:
        sim.state = start
        if frac > 0:
            sim.advance(round(frac * n_steps) * dt, record_every=n_steps)
        here = sim.state
        result = {}

        def numpy_window():
            model.reset_counters()
            rs = state_from_simulator(here)
            result["out"] = model.advance(rs, k, record=True)
        numpy_wall += _best_of(cfg["numpy_repeats"], numpy_window)[0]
        status, done, hist = result["out"]
        assert status == 0, status
        for key in counts:
            counts[key] += model.counters[key]
        sim.state = here
        ref = sim.advance(k * dt, record_every=1).displacement
        rel = max(rel, float(np.max(np.max(np.abs(hist - ref), axis=0)
                                    / np.max(np.abs(ref), axis=0))))

        def numba_window():
            sim.state = here
            sim.advance(k * dt, record_every=k)
        numba_window_wall += _best_of(cfg["window_repeats"], numba_window)[0]
    c = counts
    numpy_us_step = numpy_wall / c["steps"] * 1e6
    np_evals_per_step = c["newmark_iters"] / c["steps"]
    np_residuals_per_ball = c["ball_residuals"] / (c["force_evals"] * model.n)
    if numba_counts is not None:      # exact counts over the whole timed numba run
        evals_per_step, residuals_per_ball = numba_counts
        count_source = "numba diagnostics over the timed run"
    else:                             # package without the diagnostics: the NumPy windows
        evals_per_step, residuals_per_ball = np_evals_per_step, np_residuals_per_ball
        count_source = "NumPy windows"
    return {
        "dt_us": dt_us,
        "numba_steps_timed": n_steps,
        "numba_simulated_s": n_steps * dt,
        "numba_wall_s_min": wall,
        "numba_wall_s_median": wall_med,
        "numba_us_per_step": numba_us_step,
        "numba_us_per_step_median": wall_med / n_steps * 1e6,
        "numba_real_time_factor": dt / (numba_us_step * 1e-6),
        "numba_us_per_force_eval_in_step": numba_us_step / evals_per_step,
        "numpy_steps_timed": c["steps"],
        "numpy_us_per_step": numpy_us_step,
        "numpy_real_time_factor": dt / (numpy_us_step * 1e-6),
        "numpy_us_per_force_eval_in_step": numpy_wall / c["force_evals"] * 1e6,
        "speedup_numba_over_numpy_per_step": numpy_us_step / numba_us_step,
        # like for like: numba timed on the very steps the NumPy windows computed (same states,
        # same force evaluations); the ratio above divides by the whole numba run, whose work
        # per step can differ from the windows' (e.g. a transient needing more iterations)
        "speedup_numba_over_numpy_same_steps": numpy_wall / numba_window_wall,
        "newmark_iters_per_step": evals_per_step,
        "ball_residuals_per_ball_per_eval": residuals_per_ball,
        "counts_from": count_source,
        "numba_us_per_ball_residual": numba_us_step / (evals_per_step * model.n
                                                       * residuals_per_ball),
        "numpy_windows_newmark_iters_per_step": np_evals_per_step,
        "numpy_windows_ball_residuals_per_ball_per_eval": np_residuals_per_ball,
        "numpy_newton_passes_per_eval": c["newton_passes"] / c["force_evals"],
        "numba_us_per_step_numpy_windows": numba_window_wall / c["steps"] * 1e6,
        "numba_us_per_ball_residual_numpy_windows": numba_window_wall / c["ball_residuals"] * 1e6,
        "max_rel_diff_numpy_vs_numba_trajectory": rel,
        "simulator_setup_s": setup_s,
        "warmup_wall_s": warmup_wall,
    }


def run(quick: bool) -> dict:
    cfg = SETTINGS["quick" if quick else "full"]
    t_start = time.perf_counter()
    out = {"machine": machine_info(),
           "config": {"mode": "quick" if quick else "full", "shaft_speed_rpm": 20000.0,
                      "axial_preload_n": 800.0, **cfg}}
    out["newmark"] = [bench_dt(dt, cfg) for dt in DTS_US]   # first one also compiles
    out["force_eval"] = bench_force(cfg)
    out["total_wall_s"] = time.perf_counter() - t_start
    out["load_average_1min_at_end"] = round(os.getloadavg()[0], 2)
    return out


def print_table(r: dict) -> None:
    m, f = r["machine"], r["force_eval"]
    print(f"machine: {m['cpu_model']}, {m['logical_cpus']} logical CPUs, 1-min load at start "
          f"{m['load_average_1min_at_start']}; Python {m['python']}, NumPy {m['numpy']}, numba "
          f"{m['numba']}; bearing_gym {m['bearing_gym']} ({m['git_commit']}"
          f"{', modified' if m.get('package_has_uncommitted_changes') else ''}); mode {r['config']['mode']}")
    print()
    print(f"Bearing-force evaluation, default params (20,000 rpm, 800 N), {f['n_balls']} balls, warm "
          f"ball states ({f['ball_residuals_per_ball_per_eval']:.2f} residual evaluations per ball):")
    print(f"  numba, njit loop      {f['numba_us_per_eval_njit_loop']:9.2f} us")
    print(f"  numba, Python call    {f['numba_us_per_eval_python_call']:9.2f} us")
    print(f"  NumPy reference       {f['numpy_us_per_eval']:9.1f} us   (numba {f['speedup_numba_over_numpy']:.0f}x "
          f"faster; max rel diff of F {f['max_rel_diff_numpy_vs_numba']:.1e})")
    print()
    print("Newmark steps (best of the repeats; NumPy reference from the same states as numba)")
    cols = [("dt", "us", "{:.0f}"),
            ("numba", "us/step", "{:.2f}"), ("numba", "RT factor", "{:.4f}"), ("numba", "us/eval", "{:.2f}"),
            ("NumPy", "us/step", "{:.0f}"), ("NumPy", "RT factor", "{:.5f}"), ("NumPy", "us/eval", "{:.0f}"),
            ("speed-up", "per step", "{:.0f}x"), ("speed-up", "same steps", "{:.0f}x"),
            ("Newmark", "it/step", "{:.2f}"),
            ("Newton", "it/ball", "{:.2f}"), ("Newton", "passes", "{:.2f}"),
            ("numba us", "/residual", "{:.3f}"), ("traj", "rel diff", "{:.1e}")]
    keys = ["dt_us", "numba_us_per_step", "numba_real_time_factor", "numba_us_per_force_eval_in_step",
            "numpy_us_per_step", "numpy_real_time_factor", "numpy_us_per_force_eval_in_step",
            "speedup_numba_over_numpy_per_step", "speedup_numba_over_numpy_same_steps",
            "newmark_iters_per_step",
            "ball_residuals_per_ball_per_eval", "numpy_newton_passes_per_eval",
            "numba_us_per_ball_residual", "max_rel_diff_numpy_vs_numba_trajectory"]
    rows = [[fmt.format(d[k]) for (_, _, fmt), k in zip(cols, keys)] for d in r["newmark"]]
    widths = [max(len(a), len(b), *(len(row[i]) for row in rows)) for i, (a, b, _) in enumerate(cols)]
    print("  ".join(a.rjust(w) for (a, _, _), w in zip(cols, widths)))
    print("  ".join(b.rjust(w) for (_, b, _), w in zip(cols, widths)))
    print("  ".join("-" * w for w in widths))
    for row in rows:
        print("  ".join(x.rjust(w) for x, w in zip(row, widths)))
    d0 = r["newmark"][0]
    print()
    print("RT factor: simulated seconds per wall second. us/eval: step time / force evaluations per step.")
    print("speed-up per step: NumPy us/step (windows) / numba us/step (whole timed run); same steps: NumPy")
    print("time / numba time on the same window steps from the same states (like for like).")
    print("Newmark it/step: fixed-point iterations (= bearing-force evaluations) per step; Newton it/ball:")
    print(f"ball residual evaluations per ball per force evaluation (from: {r['newmark'][0]['counts_from']});")
    print("numba us/residual: numba step time / residual evaluations per step. NumPy: three windows at the")
    print("start, middle and end of the timed numba run, each started from the numba state there; passes:")
    print("vectorised Newton passes per force evaluation (= the most iterations any ball needs). traj rel")
    print("diff: max over DOFs and windows of max|X_numpy - X_numba| / max|X_numba|. Times: minimum over")
    print("repeats (other load can only add time; medians are in the --json output).")
    print(f"numba: {d0['numba_simulated_s']:g} s simulated per repeat x {r['config']['numba_repeats']} repeats "
          f"after {r['config']['warmup_s']:g} s warm-up; NumPy: {d0['numpy_steps_timed']} steps per dt. "
          f"Total wall time {r['total_wall_s']:.1f} s; 1-min load at end {r['load_average_1min_at_end']}.")


def main(argv=None) -> int:
    a = bench_cli.parser(__doc__, "shorter runs, same keys", out=False).parse_args(argv)
    bench_cli.emit(run(a.quick), a, print_table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
