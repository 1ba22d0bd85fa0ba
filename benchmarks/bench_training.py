"""Training throughput: train.py's PPO and SAC, the evaluation, and where the time goes.

    python benchmarks/bench_training.py                      # table (tens of minutes on 2 cores)
    python benchmarks/bench_training.py --json               # one JSON object instead of the table
    python benchmarks/bench_training.py --quick              # same keys, a shrunken smoke run
    python benchmarks/bench_training.py --baseline ../base   # side by side with another checkout
    python benchmarks/bench_training.py --only ppo,eval      # some of the three measurements
    python benchmarks/bench_training.py --accuracy docs/bench_accuracy.json   # reuse its checks

Every measurement runs in a fresh interpreter (``training_worker.py``) with the measured tree first on
``sys.path`` (``PYTHONPATH=TREE``, cwd TREE). The worker uses only ``train.make_env``,
``train.hyperparams`` and the evaluation (``agents.leaderboard.compare`` and
``agents.evaluation.episodes``, or ``agents.evaluate`` in a checkout from before the agents
subpackages), so ``--baseline DIR`` can be any checkout (e.g.
``git worktree add ../base <commit>``) without this file: its measurements run from this
script, alternately with the current tree's (the order swapped every repeat), each tree with its
own numba cache (``--baseline-cache``, default ``DIR/.numba-cache``), and the best of
``--repeats`` is reported for each.

Measured (the current tree's best run; with a baseline also ``<key>_baseline`` and
``<key>_ratio`` = current / baseline for the three throughputs):

``ppo_steps_per_s``, ``sac_steps_per_s``
    env steps per second of ``model.learn`` with what train.py builds: ``train.make_env(2, 0,
    EPISODE_STEPS, DEFAULT_TIER)`` (the registered env's tier and horizon; 2 envs stepped by the
    batched kernel on 2 numba threads; with the start bank ``train.choose_start_bank("auto", ...)``
    picks, as train.py does, in a tree that has one - its size is in the JSON as ``start_bank``) in ``VecNormalize(norm_obs, norm_reward, clip_obs=10)``,
    ``PPO``/``SAC("MlpPolicy", seed=0, device="cpu", **train.hyperparams(algo))``, tensorboard
    logging when tensorboard is installed, ``torch.set_num_threads(1)``. A warm-up
    ``learn(--warmup-steps)`` (kernel compile or cache load, first resets; for SAC it covers
    ``learning_starts`` = 1000, so the timed window has its gradient steps) precedes the timed
    ``learn(--steps, reset_num_timesteps=False)``; steps are counted by ``model.num_timesteps``
    (PPO rounds up to whole rollouts of 512). train.py's validation and checkpoint callbacks are
    not run (validation is an evaluation: see the next key).
``eval_episodes_per_s``, ``eval_wall_s_per_100_episodes``
    ``agents.leaderboard.compare.evaluate(None, episodes=--eval-episodes)`` on the held-out test seeds: the
    scripted baselines and the constant-preload sweep (11 policies x K episodes of
    EPISODE_STEPS steps, batched through the native vector env), report files written to a
    temporary directory; episodes = policies x K, counted at ``run_policies``. After a warm-up
    ``run_policies`` on other seeds (kernel load). train.py's final evaluation also runs the
    trained policy (one more policy, same batch).
``share_{ppo,sac}_<part>``
    shares of the timed ``learn``'s wall time, from cheap timers in the timed run itself:
    ``physics_step`` the numba kernel called for env steps, ``physics_settle`` the kernel called
    by the settled start of each reset (``PreloadBatch._kernel`` inside ``settle``), both less
    their ``features`` (``window_features`` runs inside the kernel: timed afterwards on a
    recorded window, at full and at 1/20 length, applied to every kernel call's rows, divided
    by the threads that share the call); ``reset_load`` the static equilibrium of each new
    scenario (``PreloadBatch.load``); ``bearing_gym_python`` the rest of the time inside the
    innermost VecEnv's ``step_wait``/``reset``; the time outside it is split into ``torch``,
    ``sb3`` and ``other`` in the proportions a cProfile'd ``learn(--profile-steps)`` after the
    timed one gives (functions by file; tensor arithmetic written as operators in SB3's code
    runs no torch function cProfile can see and counts as ``sb3``; numpy and the standard
    library count as their caller). The kernel hooks use ``bearing_gym.envs.core.PreloadBatch``;
    a tree without it reports null shares (the throughputs do not depend on them).
``share_eval_{physics_step,physics_settle,reset_load}``
    the same kernel and static-equilibrium timers over the timed evaluation.

``accuracy``
    the accuracy of the env's integrator beside its speed: the three checks of
    ``bench_accuracy.py`` (critical preload, steady amplitudes, reward-map classification
    against dt/4, each with its bound), run after the timed measurements in this process
    (``--accuracy full``, the default; ``quick`` without the reward maps, the default with
    ``--quick``; ``none``), or read from a JSON file that ``bench_accuracy.py --out`` wrote.

Times are wall-clock and other load only adds time: the 1-min load average at the start and end
of every measurement is printed, and the best of the repeats is reported. ``--quick`` shrinks
everything (PPO ``n_steps`` 64, SAC ``learning_starts`` 64, 10-step evaluation episodes, one
repeat): a smoke run whose numbers are not comparable with a full run.
"""


from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
TREE = HERE.parent
sys.path.insert(0, str(HERE))

import bench_cli  # noqa: E402
from training_worker import EVAL_PARTS, PARTS, Timers, shares  # noqa: E402

KINDS = ("ppo", "sac", "eval")
PART_LABELS = {"physics_step": "physics kernel, env steps", "physics_settle": "physics kernel, settled start",
               "features": "window features (estimate)", "reset_load": "reset: static equilibrium",
               "bearing_gym_python": "bearing_gym Python", "torch": "torch", "sb3": "SB3",
               "other": "other"}
THROUGHPUT = {"ppo": "ppo_steps_per_s", "sac": "sac_steps_per_s", "eval": "eval_episodes_per_s"}

SETTINGS = {
    "full": dict(warmup_steps=1000, steps=5000, profile_steps=2000, eval_episodes=20,
                 eval_episode_steps=None, repeats=2, overrides={}),
    "quick": dict(warmup_steps=256, steps=128, profile_steps=64, eval_episodes=2,
                  eval_episode_steps=10, repeats=1,
                  overrides={"ppo": {"n_steps": 64}, "sac": {"learning_starts": 64}}),
}



def tree_info(path: Path) -> dict:
    def git(*args):
        r = subprocess.run(["git", "-C", str(path), *args], capture_output=True, text=True, timeout=10)
        return r.stdout.strip() if r.returncode == 0 else None
    changed = git("status", "--porcelain", "--untracked-files=no")
    return {"path": str(path), "commit": git("rev-parse", "--short", "HEAD"),
            "uncommitted_changes": None if changed is None else bool(changed)}


def machine() -> dict:
    return bench_cli.machine_info(packages=False)


def run_worker(tree: Path, cache: str | None, spec: dict) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree))
    if cache:
        env["NUMBA_CACHE_DIR"] = cache
    with tempfile.TemporaryDirectory(prefix="bench_training_") as tmp:
        out = Path(tmp) / "result.json"
        spec = dict(spec, tree=str(tree), out=str(out))
        r = subprocess.run([sys.executable, str(HERE / "training_worker.py"), json.dumps(spec)],
                           cwd=str(tree), env=env, capture_output=True, text=True)
        if r.returncode != 0 or not out.exists():
            raise RuntimeError(f"{spec['kind']} measurement in {tree} failed ({r.returncode}):\n{r.stderr[-3000:]}")
        return json.loads(out.read_text())


def run(quick: bool, baseline: Path | None, baseline_cache: str | None, repeats: int | None,
        kinds: tuple, cfg_overrides: dict, log=None) -> dict:
    mode = "quick" if quick else "full"
    cfg = {**SETTINGS[mode], **{k: v for k, v in cfg_overrides.items() if v is not None}}
    repeats = repeats or cfg["repeats"]
    trees = {"current": (TREE, os.environ.get("NUMBA_CACHE_DIR"))}
    if baseline is not None:
        trees["baseline"] = (baseline, baseline_cache or str(baseline / ".numba-cache"))
    res = {"mode": mode, "machine": machine(), "load_1min_at_start": os.getloadavg()[0],
           "trees": {name: {**tree_info(path), "numba_cache_dir": cache} for name, (path, cache) in trees.items()},
           "settings": {**{k: v for k, v in cfg.items() if k != "repeats"}, "repeats": repeats},
           "runs": []}
    t_start = time.perf_counter()
    order = list(trees)
    for rep in range(repeats):
        for kind in kinds:
            for name in (order if rep % 2 == 0 else order[::-1]):
                spec = dict(kind=kind, profile_steps=cfg["profile_steps"] if rep == 0 else 0,
                            **{k: cfg[k] for k in ("warmup_steps", "steps", "eval_episodes",
                                                   "eval_episode_steps", "overrides")})
                if log:
                    log(f"[{time.perf_counter() - t_start:6.0f} s] repeat {rep + 1}/{repeats}: {kind} in {name} "
                        f"(load {os.getloadavg()[0]:.2f})")
                r = run_worker(trees[name][0], trees[name][1], spec)
                r.update(tree_name=name, repeat=rep)
                res["runs"].append(r)
    res["total_wall_s"] = time.perf_counter() - t_start
    res["load_1min_at_end"] = os.getloadavg()[0]
    summarize(res, kinds)
    return res


def _best(runs: list, kind: str, tree: str):
    rate = "episodes_per_s" if kind == "eval" else "steps_per_s"
    mine = [r for r in runs if r["kind"] == kind and r["tree_name"] == tree]
    return max(mine, key=lambda r: r[rate]) if mine else None


def summarize(res: dict, kinds: tuple) -> None:
    """Top-level keys from the runs: best of the repeats per tree, ratios, shares."""
    runs = res["runs"]
    for kind, key in THROUGHPUT.items():
        for tree, suffix in (("current", ""), ("baseline", "_baseline")):
            if tree not in res["trees"]:
                continue
            b = _best(runs, kind, tree)
            res[key + suffix] = None if b is None else b["episodes_per_s" if kind == "eval" else "steps_per_s"]
            if kind == "eval":
                res["eval_wall_s_per_100_episodes" + suffix] = None if b is None else b["wall_s_per_100_episodes"]
        if "baseline" in res["trees"]:
            cur, base = res[key], res[key + "_baseline"]
            res[key + "_ratio"] = cur / base if cur and base else None
    for algo in ("ppo", "sac"):
        b = _best(runs, algo, "current")
        prof = next((r["profile"] for r in runs if r["kind"] == algo and r["tree_name"] == "current"
                     and r.get("profile")), None)
        for part in PARTS:
            share = None
            if b is not None:
                share = b["shares"][part]
                if share is None and part in ("torch", "sb3", "other") and prof:
                    # the best run was not profiled: the profiled run's proportions
                    share = shares(b["wall_s"], _stub_timers(b), b["features_s"], prof["category_s"])[part]
            res[f"share_{algo}_{part}"] = share
    ev = _best(runs, "eval", "current")
    for part in EVAL_PARTS:
        res[f"share_eval_{part}"] = None if ev is None else ev["shares"][part]


def _stub_timers(run: dict):
    t = Timers()
    t.s, t.hooked = run["timers_s"], True
    return t


# ---------------------------------------------------------------------------------------------
def _fmt(v, spec="{:.2f}"):
    return "n/a" if v is None or (isinstance(v, float) and not math.isfinite(v)) else spec.format(v)


def print_table(res: dict) -> None:
    m = res["machine"]
    print(f"machine: {m['cpu_model']}, {m['logical_cpus']} logical CPUs; Python {m['python']}; mode {res['mode']}; "
          f"total wall time {res['total_wall_s']:.0f} s; 1-min load {res['load_1min_at_start']:.2f} at start, "
          f"{res['load_1min_at_end']:.2f} at end")
    for name, t in res["trees"].items():
        print(f"{name:8s} tree: {t['path']} at {t['commit']}{' (uncommitted changes)' if t['uncommitted_changes'] else ''}")
    s = res["settings"]
    print(f"settings: warm-up {s['warmup_steps']} steps, timed {s['steps']} steps, profiled {s['profile_steps']} steps; "
          f"evaluation {s['eval_episodes']} episodes per policy; best of {s['repeats']}"
          + (f"; quick overrides {s['overrides']}" if s["overrides"] else ""))
    print()
    print(f"{'run':4s} {'measurement':11s} {'tree':8s} {'rate':>10s} {'unit':14s} {'timed wall':>10s} "
          f"{'load start -> end (timed)':>26s}")
    for r in res["runs"]:
        ev = r["kind"] == "eval"
        rate, unit = (r["episodes_per_s"], "episodes/s") if ev else (r["steps_per_s"], "env steps/s")
        print(f"{r['repeat'] + 1:<4d} {r['kind']:11s} {r['tree_name']:8s} {rate:10.3f} {unit:14s} {r['wall_s']:9.1f}s "
              f"{r['load_1min_start']:8.2f} -> {r['load_1min_end']:.2f} ({r['load_1min_timed_start']:.2f} -> "
              f"{r['load_1min_timed_end']:.2f})")
    print()
    base = "baseline" in res["trees"]
    keys = list(THROUGHPUT.values()) + ["eval_wall_s_per_100_episodes"]
    print(f"{'key':30s} {'current':>10s}" + (f" {'baseline':>10s} {'ratio':>7s}" if base else ""))
    for k in keys:
        line = f"{k:30s} {_fmt(res.get(k), '{:10.3f}'):>10s}"
        if base:
            ratio = _fmt(res.get(k + "_ratio"), "{:.2f}x") if k + "_ratio" in res else ""
            line += f" {_fmt(res.get(k + '_baseline'), '{:10.3f}'):>10s} {ratio:>7s}"
        print(line)
    print()
    print("share of the timed learn's wall time (current tree, best run):")
    print(f"  {'part':32s} {'PPO':>8s} {'SAC':>8s}")
    for part in PARTS:
        print(f"  {PART_LABELS[part]:32s} " + " ".join(
            f"{_fmt(None if res.get(f'share_{a}_{part}') is None else 100 * res[f'share_{a}_{part}'], '{:7.1f}%'):>8s}"
            for a in ("ppo", "sac")))
    if res.get("accuracy"):
        import bench_accuracy
        print()
        print("\n".join(bench_accuracy.table_lines(res["accuracy"])))
    ev = _best(res["runs"], "eval", "current")
    if ev is not None and ev["shares"]["physics_step"] is not None:
        sh = ev["shares"]
        print(f"evaluation (current tree): {ev['episodes']} episodes of {ev['episode_steps']} steps in {ev['wall_s']:.1f} s "
              f"(run_policies {ev['run_policies_s']:.1f} s); physics kernel {100 * sh['physics_step']:.1f} % in steps, "
              f"{100 * sh['physics_settle']:.1f} % in settled starts, static equilibrium {100 * sh['reset_load']:.1f} %")


def accuracy(how: str, log=None) -> dict | None:
    """The accuracy checks of bench_accuracy.py for the current tree (see ``accuracy`` above)."""
    import bench_accuracy
    if how == "none":
        return None
    if how in ("full", "quick"):
        if log:
            log(f"accuracy checks ({how}) ...")
        return bench_accuracy.run(quick=how == "quick")
    path = Path(how)
    if not path.exists():
        raise SystemExit(f"--accuracy {how}: not full, quick or none, and no such file")
    return json.loads(path.read_text())


def main(argv=None) -> int:
    ap = bench_cli.parser(__doc__, "shrunken smoke run, same keys")
    ap.add_argument("--baseline", metavar="DIR", type=Path, help="checkout to compare with, side by side")
    ap.add_argument("--baseline-cache", metavar="DIR", help="its numba cache (default DIR/.numba-cache)")
    ap.add_argument("--repeats", type=int, help="runs per measurement and tree, best kept (default 2, quick 1)")
    ap.add_argument("--only", default=",".join(KINDS), help="comma-separated subset of ppo,sac,eval")
    ap.add_argument("--steps", type=int, help="timed env steps per training measurement (default 5000)")
    ap.add_argument("--warmup-steps", type=int, help="untimed env steps before them (default 1000)")
    ap.add_argument("--profile-steps", type=int, help="cProfile'd env steps after them, first repeat only "
                    "(default 2000; 0: no torch/SB3 split)")
    ap.add_argument("--eval-episodes", type=int, help="evaluation episodes per policy (default 20)")
    ap.add_argument("--accuracy", metavar="full|quick|none|FILE",
                    help="accuracy checks beside the speed (default full, quick with --quick), or "
                         "a JSON file written by bench_accuracy.py --out")
    a = ap.parse_args(argv)
    kinds = tuple(k for k in KINDS if k in a.only.split(","))
    if not kinds or set(a.only.split(",")) - set(KINDS):
        ap.error(f"--only takes a comma-separated subset of {','.join(KINDS)}")
    if a.baseline is not None and not (a.baseline / "train.py").exists():
        ap.error(f"--baseline {a.baseline}: no train.py there (a checkout of this repository?)")
    log = None if a.json else (lambda s: print(s, file=sys.stderr, flush=True))
    res = run(a.quick, a.baseline.resolve() if a.baseline else None, a.baseline_cache, a.repeats, kinds,
              {"steps": a.steps, "warmup_steps": a.warmup_steps, "profile_steps": a.profile_steps,
               "eval_episodes": a.eval_episodes}, log)
    res["accuracy"] = accuracy(a.accuracy or ("quick" if a.quick else "full"), log)
    bench_cli.emit(res, a, print_table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
