"""All the performance targets (docs/performance.md) in one run: a table, or one JSON object.

    python benchmarks/run_all.py            # table, ~3-5 min on a quiet 2-core machine
    python benchmarks/run_all.py --json     # one JSON object instead of the table
    python benchmarks/run_all.py --quick    # same keys, shorter runs (< 1 min)
    python benchmarks/run_all.py --out r.json   # table, and the JSON object written to r.json

Measured (every ratio within this one run):

``speedup_vs_numpy``
    NumPy-reference time / numba time for the same Newmark steps from the same states at the
    default dt (10 us), default params (20,000 rpm, 800 N): ``bench_integrator.bench_dt``
    (imported, not duplicated), its "same steps" ratio (three windows at the start, middle and
    end of its timed numba run). Its other ratio, NumPy windows / the whole numba run, is in the
    details (``speedup_numba_over_numpy_per_step``): it mixes different work per step when the
    windows need fewer force evaluations per step than the whole run (1.23 vs 1.50 here).
``real_time_factor``
    simulated seconds per wall second of bench_dt's timed numba run (0.05 s simulated after a
    5 ms warm-up, best of 5; one core: ``Simulator.advance`` is a serial kernel).
``dt_convergence_rel_err``
    the default params run from the static equilibrium to t = 0.15 s at the default dt and at
    dt/4; the steady peak-to-peak amplitudes of x, z and cage speed over t in [0.10, 0.15] s are
    compared (both runs sampled at the same instants, every default dt); the key is the largest
    relative change |A(dt) - A(dt/4)| / A(dt/4).
``env_steps_per_s``
    ``bench_env.single_rate``: single ``BearingPreloadEnv``, ``"paper"`` preset, control_dt_s =
    0.01, numba restricted to one thread (best of the repeats).
``vector_env_speedup_2_cores``
    ``bench_env.vector_rate`` (2 envs, 2 numba threads; env steps per second summed over the
    envs) / ``env_steps_per_s``, the two measured alternately in this run (best of each).
``rss_growth_mb``
    VmRSS (``/proc/self/status``) after a warm-up and after N more single-env steps (N =
    100,000, or 5,000 with --quick) of a ``"paper"`` env with control_dt_s = 0.001 (the smallest
    the env accepts; 100 Newmark steps per env step), reset every 250 steps as in an episode;
    ``gc.collect()`` before each reading.
``import_s``
    wall time of ``import bearing_gym`` in a fresh interpreter (numba cache warm: a first
    subprocess runs untimed); best of the repeats.
``first_reset_s``
    fresh interpreter, after ``import bearing_gym``: ``from bearing_gym.envs import
    BearingPreloadEnv``, ``BearingPreloadEnv()`` and ``reset(seed=0)`` (cache warm); the split
    and the first ``step`` are in the details.

Each key is compared with its target in ``targets_met``. Times are wall-clock; other load on
the machine only adds time, so the minimum over repeats is reported (the 1-min load average at
start and end is printed).
"""

from __future__ import annotations

import gc
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import numba  # noqa: E402

import bearing_gym  # noqa: E402
from bearing_gym.analysis.signals import peak_to_peak  # noqa: E402
from bearing_gym.task import EPISODE_STEPS  # noqa: E402
from bearing_gym.physics import Simulator  # noqa: E402
from bearing_gym.physics import ball as ball_mod  # noqa: E402
from bearing_gym.physics import rotor as rotor_mod  # noqa: E402

import bench_cli  # noqa: E402
import bench_env  # noqa: E402
import bench_integrator  # noqa: E402

DEFAULT_DT_S = bearing_gym.default_params().integrator.dt_s

TARGETS = {
    "speedup_vs_numpy": (">=", 200.0, "numba >= 200x the NumPy reference per Newmark step"),
    "real_time_factor": (">=", 1.0, "real-time factor >= 1 (20,000 rpm, 800 N, default dt, one core)"),
    "dt_convergence_rel_err": ("<", 0.01, "steady p-p of x, z, cage speed within 1 % of dt/4"),
    "env_steps_per_s": (">=", 100.0, ">= 100 single-env steps/s at 10 ms control interval, one core"),
    "vector_env_speedup_2_cores": (">=", 1.8, "vector env (2 envs, 2 threads) >= 1.8x the single env"),
    "rss_growth_mb": ("<", 5.0, "RSS flat: < 5 MB growth over the env steps"),
    "import_s": ("<", 1.0, "import bearing_gym < 1 s (warm cache)"),
    "first_reset_s": ("<", 10.0, "first reset < 10 s (warm cache)"),
}

SETTINGS = {
    "full": dict(integrator=bench_integrator.SETTINGS["full"], conv_t_end_s=0.15, conv_from_s=0.10,
                 env_control_dt_s=0.01, env_steps=60, env_repeats=3, rss_control_dt_s=0.001,
                 rss_steps=100_000, rss_warmup_steps=1000, rss_samples=10, rss_episode_steps=EPISODE_STEPS,
                 subprocess_repeats=3),
    "quick": dict(integrator=bench_integrator.SETTINGS["quick"], conv_t_end_s=0.15,
                  conv_from_s=0.10, env_control_dt_s=0.01, env_steps=10, env_repeats=2,
                  rss_control_dt_s=0.001, rss_steps=5_000, rss_warmup_steps=200, rss_samples=5,
                  rss_episode_steps=EPISODE_STEPS, subprocess_repeats=1),
}


# ---------------------------------------------------------------------------------------------
def rss_mb() -> float:
    """Resident set size of this process (MB), from /proc/self/status (VmRSS)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    import resource   # fallback: peak RSS (kB on Linux)
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _diagnostics(scal_before, scal_after, bo_before, bo_after, n_steps):
    """(force evaluations per Newmark step, Newton iterations per ball per evaluation)."""
    evals = float(scal_after[..., rotor_mod.S_N_EVAL].sum() - scal_before[..., rotor_mod.S_N_EVAL].sum())
    res = float(bo_after[..., ball_mod.B_NITER].sum() - bo_before[..., ball_mod.B_NITER].sum())
    n_balls = bo_after.shape[-2]
    if evals <= 0 or n_steps <= 0:
        return float("nan"), float("nan")
    return evals / n_steps, res / (evals * n_balls)


# ---------------------------------------------------------------------------------------------
def bench_integrator_default_dt(cfg: dict) -> dict:
    """bench_integrator's Newmark benchmark at the default dt only (numba vs NumPy)."""
    return bench_integrator.bench_dt(DEFAULT_DT_S * 1e6, cfg["integrator"])


def dt_convergence(cfg: dict) -> dict:
    """Steady peak-to-peak of x, z and cage speed at the default dt and at dt/4."""
    t_end, t_from = cfg["conv_t_end_s"], cfg["conv_from_s"]
    out = {"t_window_s": [t_from, t_end], "runs": {}}
    amps = {}
    for label, factor in (("dt", 1), ("dt/4", 4)):
        dt = DEFAULT_DT_S / factor
        sim = Simulator(bearing_gym.default_params(dt_s=dt))
        t0 = time.perf_counter()
        rec = sim.advance(t_end, record_every=factor)       # samples every default dt in both
        wall = time.perf_counter() - t0
        t = rec.t
        after = t_from - 0.25 * DEFAULT_DT_S
        a = {"x_um": peak_to_peak(rec.x, t, after) * 1e6,
             "z_um": peak_to_peak(rec.z, t, after) * 1e6,
             "cage_speed_rad_s": peak_to_peak(rec.cage_speed, t, after)}
        amps[label] = a
        out["runs"][label] = {"dt_us": dt * 1e6, "steps": int(round(t_end / dt)), "wall_s": wall,
                              "real_time_factor_0_to_t_end": t_end / wall,
                              "samples_in_window": int(np.sum(t >= after)),
                              "peak_to_peak": a}
    rel = {k: abs(amps["dt"][k] - amps["dt/4"][k]) / abs(amps["dt/4"][k]) for k in amps["dt"]}
    out["rel_change"] = rel
    out["max_rel_change"] = max(rel.values())
    return out


def env_throughput(cfg: dict) -> dict:
    """Single env on one numba thread vs the vector env (2 envs) on 2 threads, alternately."""
    cdt, steps = cfg["env_control_dt_s"], cfg["env_steps"]
    n_threads_default = numba.config.NUMBA_NUM_THREADS
    singles, vec2, vec1, single_default = [], [], [], []
    for _ in range(cfg["env_repeats"]):
        numba.set_num_threads(1)
        singles.append(bench_env.single_rate(cdt, steps))
        if n_threads_default >= 2:
            vec2.append(bench_env.vector_rate(cdt, steps, 2))
        vec1.append(bench_env.vector_rate(cdt, steps, 1))
    # what a user gets without restricting numba: the single env on numba's default threads
    numba.set_num_threads(n_threads_default)
    single_default.append(bench_env.single_rate(cdt, steps))
    out = {"control_dt_s": cdt, "steps_per_measurement": steps, "repeats": cfg["env_repeats"],
           "newmark_steps_per_env_step": int(round(cdt / DEFAULT_DT_S)),
           "single_env_steps_per_s_1_thread_all": singles,
           "single_env_steps_per_s_1_thread": max(singles),
           "single_env_steps_per_s_default_threads": max(single_default),
           "numba_default_threads": n_threads_default,
           "vector_env_steps_per_s_1_thread": max(vec1),
           "vector_env_steps_per_s_2_threads": max(vec2) if vec2 else float("nan"),
           "vector_env_steps_per_s_2_threads_all": vec2}
    out["vector_speedup_2_threads_vs_single"] = out["vector_env_steps_per_s_2_threads"] / out["single_env_steps_per_s_1_thread"]
    out["vector_speedup_2_threads_vs_1_thread"] = out["vector_env_steps_per_s_2_threads"] / out["vector_env_steps_per_s_1_thread"]
    out.update(env_step_profile(cdt, steps, cfg["env_repeats"]))
    return out


def env_step_profile(cdt: float, steps: int, repeats: int) -> dict:
    """Share of a single-env step spent in the numba step kernel (best of the repeats), and the
    kernel's work counts over all of them (one thread)."""
    from bearing_gym.envs import BearingPreloadEnv
    numba.set_num_threads(1)
    env = BearingPreloadEnv(scenario="paper", control_dt_s=cdt)
    env.reset(seed=0)
    a = np.array([0.0], dtype=np.float32)
    env.step(a)
    b = env.batch
    sp = b.setpoint.copy()
    active = np.array([True])
    scal0, bo0 = b.scal.copy(), b.ball_out.copy()
    env_walls, kernel_walls = [], []
    for _ in range(repeats):            # alternately: whole env steps, kernel calls only
        t0 = time.perf_counter()
        for _ in range(steps):
            env.step(a)
        env_walls.append((time.perf_counter() - t0) / steps)
        t0 = time.perf_counter()
        for _ in range(steps):
            b.step(sp, active)
        kernel_walls.append((time.perf_counter() - t0) / steps)
    env_wall, kernel_wall = min(env_walls), min(kernel_walls)
    n_newmark = 2 * repeats * steps * b.n_sub * b.steps_per_sub
    evals, newton = _diagnostics(scal0, b.scal, bo0, b.ball_out, n_newmark)
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    return {"profile_env_step_ms": env_wall * 1e3, "profile_kernel_ms": kernel_wall * 1e3,
            "profile_python_overhead_ms": (env_wall - kernel_wall) * 1e3,
            "profile_kernel_us_per_newmark_step": kernel_wall / (b.n_sub * b.steps_per_sub) * 1e6,
            "profile_newmark_iters_per_step": evals, "profile_newton_it_per_ball": newton}


def rss_growth(cfg: dict) -> dict:
    from bearing_gym.envs import BearingPreloadEnv
    numba.set_num_threads(1)
    env = BearingPreloadEnv(scenario="paper", control_dt_s=cfg["rss_control_dt_s"])
    a = np.array([0.0], dtype=np.float32)
    ep = cfg["rss_episode_steps"]
    env.reset(seed=0)
    k = 0

    def run(n):
        nonlocal k
        for _ in range(n):
            if k and k % ep == 0:
                env.reset()
            env.step(a)
            k += 1
    run(cfg["rss_warmup_steps"])
    gc.collect()
    start = rss_mb()
    n, m = cfg["rss_steps"], cfg["rss_samples"]
    series = [(0, start)]
    t0 = time.perf_counter()
    done = 0
    for i in range(1, m + 1):
        chunk = n * i // m - done
        run(chunk)
        done += chunk
        gc.collect()
        series.append((done, rss_mb()))
    wall = time.perf_counter() - t0
    end = series[-1][1]
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    return {"control_dt_s": env.control_dt_s, "steps": n, "warmup_steps": cfg["rss_warmup_steps"],
            "resets": done // ep, "rss_start_mb": start, "rss_end_mb": end,
            "rss_growth_mb": end - start, "rss_max_mb": max(r for _, r in series),
            "rss_series_mb": [[s, round(r, 2)] for s, r in series], "wall_s": wall,
            "env_steps_per_s": n / wall}


_IMPORT_CODE = """
import json, time
t0 = time.perf_counter()
import bearing_gym
print(json.dumps({"import_s": time.perf_counter() - t0}))
"""

_RESET_CODE = """
import json, time
import numpy as np
import bearing_gym
t0 = time.perf_counter()
from bearing_gym.envs import BearingPreloadEnv
t1 = time.perf_counter()
env = BearingPreloadEnv()
t2 = time.perf_counter()
env.reset(seed=0)
t3 = time.perf_counter()
env.step(np.zeros(1, dtype=np.float32))
t4 = time.perf_counter()
print(json.dumps({"import_envs_s": t1 - t0, "construct_s": t2 - t1, "reset_s": t3 - t2,
                  "first_reset_s": t3 - t0, "first_step_s": t4 - t3}))
"""


def _subprocess_json(code: str) -> dict:
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                       env=dict(os.environ), cwd=str(HERE.parent))
    if r.returncode != 0:
        raise RuntimeError(f"subprocess failed ({r.returncode}): {r.stderr[-2000:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def startup_times(cfg: dict) -> dict:
    """import and first reset in fresh interpreters, numba cache warm (one untimed run each)."""
    warm = _subprocess_json(_RESET_CODE)                 # fills/loads the cache, warms the OS cache
    _subprocess_json(_IMPORT_CODE)
    imports = [_subprocess_json(_IMPORT_CODE) for _ in range(cfg["subprocess_repeats"])]
    resets = [_subprocess_json(_RESET_CODE) for _ in range(cfg["subprocess_repeats"])]
    best = min(resets, key=lambda d: d["first_reset_s"])
    return {"import_s": min(d["import_s"] for d in imports),
            "import_s_all": [d["import_s"] for d in imports],
            "first_reset_s": best["first_reset_s"],
            "first_reset_split_s": {k: best[k] for k in ("import_envs_s", "construct_s", "reset_s")},
            "first_step_s": best["first_step_s"],
            "first_reset_s_all": [d["first_reset_s"] for d in resets],
            "untimed_warm_run": warm,
            "numba_cache_dir": bearing_gym.NUMBA_CACHE_DIR}


# ---------------------------------------------------------------------------------------------
def _met(key: str, value: float) -> bool:
    op, target, _ = TARGETS[key]
    if not math.isfinite(value):
        return False
    if key == "rss_growth_mb":
        return abs(value) < target
    return value >= target if op == ">=" else value < target


def run(quick: bool) -> dict:
    mode = "quick" if quick else "full"
    cfg = SETTINGS[mode]
    t_start = time.perf_counter()
    machine = bench_integrator.machine_info()
    machine["numba_threading_layer_default_threads"] = numba.config.NUMBA_NUM_THREADS
    details = {}
    timings = {}

    def timed(name, fn):
        t0 = time.perf_counter()
        details[name] = fn(cfg)
        timings[name] = time.perf_counter() - t0

    timed("integrator", bench_integrator_default_dt)
    timed("dt_convergence", dt_convergence)
    timed("env", env_throughput)
    timed("rss", rss_growth)
    timed("startup", startup_times)
    try:
        machine["numba_threading_layer"] = numba.threading_layer()
    except ValueError:
        machine["numba_threading_layer"] = None
    i, e = details["integrator"], details["env"]
    out = {
        "speedup_vs_numpy": i["speedup_numba_over_numpy_same_steps"],
        "real_time_factor": i["numba_real_time_factor"],
        "dt_convergence_rel_err": details["dt_convergence"]["max_rel_change"],
        "env_steps_per_s": e["single_env_steps_per_s_1_thread"],
        "vector_env_speedup_2_cores": e["vector_speedup_2_threads_vs_single"],
        "rss_growth_mb": details["rss"]["rss_growth_mb"],
        "import_s": details["startup"]["import_s"],
        "first_reset_s": details["startup"]["first_reset_s"],
    }
    out["targets"] = {k: f"{op} {v:g}" for k, (op, v, _) in TARGETS.items()}
    out["targets_met"] = {k: _met(k, out[k]) for k in TARGETS}
    out["mode"] = mode
    out["machine"] = machine
    out["details"] = details
    out["section_wall_s"] = timings
    out["total_wall_s"] = time.perf_counter() - t_start
    out["load_average_1min_at_start"] = machine["load_average_1min_at_start"]
    out["load_average_1min_at_end"] = round(os.getloadavg()[0], 2)
    return out


def print_table(r: dict) -> None:
    m, d = r["machine"], r["details"]
    print(f"machine: {m['cpu_model']}, {m['logical_cpus']} logical CPUs; Python {m['python']}, "
          f"NumPy {m['numpy']}, numba {m['numba']} (threading layer {m.get('numba_threading_layer')}); "
          f"bearing_gym {m['bearing_gym']} ({m['git_commit']}"
          f"{', modified' if m.get('package_has_uncommitted_changes') else ''}); mode {r['mode']}")
    print(f"1-min load average: {r['load_average_1min_at_start']} at start, "
          f"{r['load_average_1min_at_end']} at end; total wall time {r['total_wall_s']:.1f} s")
    print()
    fmt = {"speedup_vs_numpy": "{:.0f}x", "real_time_factor": "{:.3f}",
           "dt_convergence_rel_err": "{:.2e}", "env_steps_per_s": "{:.1f}",
           "vector_env_speedup_2_cores": "{:.2f}x", "rss_growth_mb": "{:+.2f} MB",
           "import_s": "{:.3f} s", "first_reset_s": "{:.2f} s"}
    w = max(len(k) for k in TARGETS)
    print(f"{'key':{w}s}  {'measured':>12s}  {'target':>9s}  met")
    print(f"{'-' * w}  {'-' * 12}  {'-' * 9}  ---")
    for k in TARGETS:
        print(f"{k:{w}s}  {fmt[k].format(r[k]):>12s}  {r['targets'][k]:>9s}  "
              f"{'yes' if r['targets_met'][k] else 'NO'}")
    print()
    i = d["integrator"]
    print(f"Newmark step at dt = {i['dt_us']:g} us (20,000 rpm, 800 N), timed run: numba "
          f"{i['numba_us_per_step']:.2f} us ({i['newmark_iters_per_step']:.2f} force evals/step, "
          f"{i['ball_residuals_per_ball_per_eval']:.2f} Newton it/ball/eval, "
          f"{i['numba_us_per_ball_residual']:.3f} us/residual)")
    print(f"  NumPy windows ({i['numpy_steps_timed']} steps, "
          f"{i['numpy_windows_newmark_iters_per_step']:.2f} force evals/step): NumPy "
          f"{i['numpy_us_per_step']:.0f} us/step, numba on the same steps "
          f"{i['numba_us_per_step_numpy_windows']:.2f} us/step -> {i['speedup_numba_over_numpy_same_steps']:.0f}x "
          f"(vs the whole numba run: {i['speedup_numba_over_numpy_per_step']:.0f}x); "
          f"traj rel diff {i['max_rel_diff_numpy_vs_numba_trajectory']:.1e}")
    c = d["dt_convergence"]
    print(f"dt convergence, steady peak-to-peak over t in [{c['t_window_s'][0]:g}, {c['t_window_s'][1]:g}] s:")
    print(f"  {'dt (us)':>8s}  {'x (um)':>12s}  {'z (um)':>12s}  {'cage speed (rad/s)':>18s}  wall (s)")
    for label, run_ in c["runs"].items():
        a = run_["peak_to_peak"]
        print(f"  {run_['dt_us']:8.2f}  {a['x_um']:12.6f}  {a['z_um']:12.6f}  "
              f"{a['cage_speed_rad_s']:18.6f}  {run_['wall_s']:.2f}")
    rc = c["rel_change"]
    print(f"  {'rel diff':>8s}  {rc['x_um']:12.2e}  {rc['z_um']:12.2e}  {rc['cage_speed_rad_s']:18.2e}")
    e = d["env"]
    print(f"env, \"paper\" preset, control_dt_s = {e['control_dt_s']:g} ({e['newmark_steps_per_env_step']} "
          f"Newmark steps/env step), best of {e['repeats']} x {e['steps_per_measurement']} steps:")
    print(f"  single env, 1 numba thread          {e['single_env_steps_per_s_1_thread']:8.1f} steps/s")
    print(f"  single env, {e['numba_default_threads']} numba threads (default)  "
          f"{e['single_env_steps_per_s_default_threads']:8.1f} steps/s")
    print(f"  vector env, 2 envs, 1 thread        {e['vector_env_steps_per_s_1_thread']:8.1f} env steps/s")
    print(f"  vector env, 2 envs, 2 threads       {e['vector_env_steps_per_s_2_threads']:8.1f} env steps/s "
          f"({e['vector_speedup_2_threads_vs_single']:.2f}x single, "
          f"{e['vector_speedup_2_threads_vs_1_thread']:.2f}x vector on 1 thread)")
    print(f"  profile (1 thread): env step {e['profile_env_step_ms']:.2f} ms = kernel "
          f"{e['profile_kernel_ms']:.2f} ms + Python {e['profile_python_overhead_ms']:.2f} ms; "
          f"{e['profile_kernel_us_per_newmark_step']:.2f} us/Newmark step, "
          f"{e['profile_newmark_iters_per_step']:.2f} force evals/step, "
          f"{e['profile_newton_it_per_ball']:.2f} Newton it/ball")
    s = d["rss"]
    print(f"RSS: {s['rss_start_mb']:.1f} MB at start, {s['rss_end_mb']:.1f} MB after {s['steps']:,} env steps "
          f"(control_dt_s = {s['control_dt_s']:g}, {s['resets']} resets, {s['wall_s']:.0f} s, "
          f"{s['env_steps_per_s']:.0f} steps/s); max {s['rss_max_mb']:.1f} MB")
    print("  series (steps, MB): " + ", ".join(f"({a}, {b:.1f})" for a, b in s["rss_series_mb"]))
    st = d["startup"]
    sp = st["first_reset_split_s"]
    print(f"startup (fresh interpreter, warm cache): import bearing_gym {st['import_s']:.3f} s; "
          f"first reset {st['first_reset_s']:.2f} s (import envs {sp['import_envs_s']:.2f}, construct "
          f"{sp['construct_s']:.3f}, reset {sp['reset_s']:.2f}); first step {st['first_step_s']:.2f} s")


def main(argv=None) -> int:
    a = bench_cli.parser(__doc__, "shorter runs (< 1 min), same keys").parse_args(argv)
    bench_cli.emit(run(a.quick), a, print_table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
