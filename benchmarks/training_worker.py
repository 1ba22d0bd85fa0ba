"""The training-throughput measurement itself (``benchmarks/bench_training.py`` runs it): one
measurement in a fresh interpreter with the measured tree first on ``sys.path``, timers hooked
into the kernel calls, the feature cost, the cProfile split of the time outside the env.

    python benchmarks/training_worker.py SPEC_JSON        # writes its result to SPEC["out"]

Uses only ``train.make_env``, ``train.hyperparams`` and the evaluation of the measured tree, so a
baseline checkout without this file can be measured (see bench_training.py's docstring).
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


PARTS = ("physics_step", "physics_settle", "features", "reset_load", "bearing_gym_python",
         "torch", "sb3", "other")
EVAL_PARTS = ("physics_step", "physics_settle", "reset_load")


class Timers:
    """Wall time in the env's kernel calls (steps / settled start), in ``PreloadBatch.load`` and
    in the innermost VecEnv, with the rows each kernel call recorded (for the features)."""

    def __init__(self):
        self.hooked = False
        self.reset()

    def reset(self):
        self.s = dict.fromkeys(("kernel_step", "kernel_settle", "load", "env"), 0.0)
        self.calls = {"step": [], "settle": []}     # per kernel call: (active envs, rows, threads)
        self.in_settle = 0

    def hook_physics(self) -> bool:
        try:
            import numba

            from bearing_gym.envs.core import PreloadBatch
        except ImportError:
            return False
        if not all(callable(getattr(PreloadBatch, n, None)) for n in ("_kernel", "settle", "load")):
            return False
        timers, kernel, settle, load = self, PreloadBatch._kernel, PreloadBatch.settle, PreloadBatch.load

        def timed_kernel(batch, setpoints, active, *args, **kw):
            t0 = time.perf_counter()
            kernel(batch, setpoints, active, *args, **kw)
            which = "settle" if timers.in_settle else "step"
            timers.s["kernel_" + which] += time.perf_counter() - t0
            try:
                rows = batch.rows[active]
                timers.calls[which].append((len(rows), int(rows.sum()), numba.get_num_threads()))
            except (AttributeError, IndexError, TypeError):
                pass

        def timed_settle(batch, *args, **kw):
            timers.in_settle += 1
            try:
                return settle(batch, *args, **kw)
            finally:
                timers.in_settle -= 1

        def timed_load(batch, *args, **kw):
            t0 = time.perf_counter()
            try:
                return load(batch, *args, **kw)
            finally:
                timers.s["load"] += time.perf_counter() - t0

        PreloadBatch._kernel, PreloadBatch.settle, PreloadBatch.load = timed_kernel, timed_settle, timed_load
        self.hooked = True
        return True

    def hook_vec_env(self, venv) -> None:
        """Time the innermost SB3 VecEnv's step_wait and reset (instance attributes)."""
        from stable_baselines3.common.vec_env import VecEnvWrapper
        inner = venv
        while isinstance(inner, VecEnvWrapper):
            inner = inner.venv
        for name in ("step_wait", "reset"):
            inner.__dict__[name] = self._timed(getattr(inner, name))
        self.inner = inner

    def _timed(self, fn):
        def wrapper(*args, **kw):
            t0 = time.perf_counter()
            try:
                return fn(*args, **kw)
            finally:
                self.s["env"] += time.perf_counter() - t0
        return wrapper

    def features_s(self, cost) -> dict:
        """Estimated wall time of the window features in the kernel calls: ``cost(rows)`` per
        window; the envs of a call share its threads."""
        if cost is None:
            return None
        out = {}
        for which, calls in self.calls.items():
            total = 0.0
            for n, rows, threads in calls:
                if n:
                    total += (n * cost[0] + rows * cost[1]) / max(1, min(n, threads))
            out[which] = total
        return out


def _feature_cost(venv_inner, repeats: int = 200):
    """(seconds per window, seconds per row) of ``window_features``, fitted on env 0's last
    recorded window at its full length and at 1/20 of it (best of ``repeats`` each)."""
    try:
        import numpy as np

        from bearing_gym.envs.features import N_FEATURES, window_features
        batch = venv_inner.venv.batch
        rec, rows = batch.rec[0], int(batch.rows[0])
    except (ImportError, AttributeError):
        return None
    if rows < 40:
        return None
    out = np.zeros(N_FEATURES)
    times = {}
    for r in (rows, rows // 20):
        window_features(rec, r, out)
        best = float("inf")
        for _ in range(repeats):
            t0 = time.perf_counter()
            window_features(rec, r, out)
            best = min(best, time.perf_counter() - t0)
        times[r] = best
    per_row = max(0.0, (times[rows] - times[rows // 20]) / (rows - rows // 20))
    return max(0.0, times[rows] - per_row * rows), per_row


def _profile_categories(prof, tree: str) -> dict:
    """Seconds per category (torch, sb3, bearing_gym, other) of a cProfile run: functions by
    their file; builtins by name if torch's, else, like functions of numpy, gymnasium and the
    standard library, by their callers (in proportion to the time each caller spent in them)."""
    import pstats
    stats = pstats.Stats(prof).stats
    tree = os.path.realpath(tree) + os.sep

    def own(key):
        path, _, name = key
        if path == "~":
            return "torch" if "torch" in name else None
        if f"{os.sep}torch{os.sep}" in path:
            return "torch"
        if f"{os.sep}stable_baselines3{os.sep}" in path:
            return "sb3"
        if os.path.realpath(path).startswith(tree + "bearing_gym" + os.sep):
            return "bearing_gym"
        return None

    memo: dict = {}

    def split(key, depth=0):
        cat = own(key)
        if cat:
            return {cat: 1.0}
        if key in memo:
            return memo[key]
        memo[key] = {"other": 1.0}                  # a cycle or too deep: other
        callers = stats.get(key, (0, 0, 0, 0, {}))[4]
        total = sum(v[2] for v in callers.values())
        if depth > 30 or total <= 0:
            return memo[key]
        acc: dict = {}
        for caller, v in callers.items():
            for c, f in split(caller, depth + 1).items():
                acc[c] = acc.get(c, 0.0) + f * v[2] / total
        memo[key] = acc
        return acc

    out = {"torch": 0.0, "sb3": 0.0, "bearing_gym": 0.0, "other": 0.0}
    for key, (_, _, tt, _, _) in stats.items():
        for c, f in split(key).items():
            out[c] += tt * f
    return out


def shares(wall: float, timers: Timers, feats: dict, outside_split: dict | None) -> dict:
    """The timed run's wall time split into PARTS (fractions; None where not measurable)."""
    s = timers.s
    out = dict.fromkeys(PARTS)
    if timers.hooked:
        f = feats or {"step": 0.0, "settle": 0.0}          # not estimated: left in the kernel
        out["features"] = (f["step"] + f["settle"]) / wall if feats else None
        out["physics_step"] = (s["kernel_step"] - f["step"]) / wall
        out["physics_settle"] = (s["kernel_settle"] - f["settle"]) / wall
        out["reset_load"] = s["load"] / wall
        out["bearing_gym_python"] = (s["env"] - s["kernel_step"] - s["kernel_settle"] - s["load"]) / wall
    outside = (wall - s["env"]) / wall
    if outside_split:
        total = sum(outside_split[c] for c in ("torch", "sb3", "other"))
        for c in ("torch", "sb3", "other"):
            out[c] = outside * outside_split[c] / total if total > 0 else None
    return out


def _train_measurement(spec: dict) -> dict:
    import cProfile

    import torch
    from stable_baselines3 import PPO, SAC
    from stable_baselines3.common.vec_env import VecNormalize

    import train
    from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS

    torch.set_num_threads(1)                     # as train.py
    algo = spec["kind"]
    timers = Timers()
    # train.py's default start bank, in a tree that has one (older trees settle every start)
    bank = (train.choose_start_bank("auto", DEFAULT_TIER, EPISODE_STEPS)
            if hasattr(train, "choose_start_bank") else None)
    env = train.make_env(n_envs=2, seed=0, episode_steps=EPISODE_STEPS, tier=DEFAULT_TIER,
                         **({"start_bank": bank} if bank is not None else {}))
    timers.hook_vec_env(env)
    env = VecNormalize(env, norm_obs=True, norm_reward=True, clip_obs=10.0)
    try:
        import tensorboard  # noqa: F401
        tb = tempfile.mkdtemp(prefix="bench_training_tb_")
    except ImportError:
        tb = None
    hp = {**train.hyperparams(algo), **spec["overrides"].get(algo, {})}
    model = {"ppo": PPO, "sac": SAC}[algo]("MlpPolicy", env, seed=0, device="cpu", verbose=0,
                                            tensorboard_log=tb, **hp)
    t0 = time.perf_counter()
    model.learn(total_timesteps=spec["warmup_steps"], progress_bar=False)
    warmup_s = time.perf_counter() - t0
    timers.hook_physics()
    timers.reset()
    n0 = model.num_timesteps
    load_start = os.getloadavg()[0]
    t0 = time.perf_counter()
    model.learn(total_timesteps=spec["steps"], reset_num_timesteps=False, progress_bar=False)
    wall = time.perf_counter() - t0
    load_end = os.getloadavg()[0]
    steps = model.num_timesteps - n0
    timed = dict(timers.s)
    calls = {k: len(v) for k, v in timers.calls.items()}
    feats = timers.features_s(_feature_cost(timers.inner))
    outside_split, profile = None, None
    if spec["profile_steps"] > 0:
        timers.reset()
        prof = cProfile.Profile()
        n1 = model.num_timesteps
        t1 = time.perf_counter()
        prof.enable()
        model.learn(total_timesteps=spec["profile_steps"], reset_num_timesteps=False, progress_bar=False)
        prof.disable()
        pwall = time.perf_counter() - t1
        outside_split = _profile_categories(prof, spec["tree"])
        profile = {"steps": model.num_timesteps - n1, "wall_s": pwall,
                   "steps_per_s": (model.num_timesteps - n1) / pwall, "env_s": timers.s["env"],
                   "category_s": outside_split}
    timers.s = timed
    if tb:
        shutil.rmtree(tb, ignore_errors=True)
    return {"steps": int(steps), "wall_s": wall, "steps_per_s": steps / wall, "warmup_s": warmup_s,
            "warmup_steps": int(n0), "load_1min_timed_start": load_start, "load_1min_timed_end": load_end,
            "timers_s": timed, "kernel_calls": calls, "features_s": feats,
            "shares": shares(wall, timers, feats, outside_split), "profile": profile,
            "hyperparams": {k: repr(v) for k, v in hp.items()},
            "start_bank": None if bank is None else f"{len(bank)} settled starts of tier {bank.tier}"}


def _eval_measurement(spec: dict) -> dict:
    try:                                # the loop (agents.evaluation.episodes) apart from the report
        from agents.evaluation import episodes as loop
        from agents.leaderboard import compare as ev
    except ImportError:                 # a baseline checkout of the flat agents/: agents.evaluate held both
        import agents.evaluate as ev
        loop = ev
    from agents import ConstantPreload        # in both layouts (the flat agents/ too)
    from bearing_gym.task import EPISODE_STEPS

    episode_steps = spec["eval_episode_steps"] or EPISODE_STEPS
    t0 = time.perf_counter()        # kernel load on seeds that are not the test seeds
    ev.run_policies([ConstantPreload(800.0)], 2, 10_000_000, 2)
    warmup_s = time.perf_counter() - t0
    timers = Timers()
    timers.hook_physics()
    counted = {"episodes": 0, "run_policies_s": 0.0}
    run_policies = ev.run_policies

    def counting(policies, episodes, *args, **kw):
        t = time.perf_counter()
        try:
            return run_policies(policies, episodes, *args, **kw)
        finally:
            counted["episodes"] += len(policies) * episodes
            counted["run_policies_s"] += time.perf_counter() - t

    ev.run_policies = loop.run_policies = counting     # the policies' batch and the constant sweep's
    load_start = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="bench_training_eval_") as out:
        t0 = time.perf_counter()
        results = ev.evaluate(None, episodes=spec["eval_episodes"], seed=ev.TEST_SEED,
                              episode_steps=episode_steps, out_dir=out, verbose=False)
        wall = time.perf_counter() - t0
    load_end = os.getloadavg()[0]
    episodes = counted["episodes"] or (len(results) - 2) * spec["eval_episodes"]
    s = timers.s
    return {"episodes": int(episodes), "episode_steps": episode_steps, "wall_s": wall,
            "episodes_per_s": episodes / wall, "wall_s_per_100_episodes": 100.0 * wall / episodes,
            "warmup_s": warmup_s, "run_policies_s": counted["run_policies_s"],
            "load_1min_timed_start": load_start, "load_1min_timed_end": load_end,
            "timers_s": dict(s),
            "shares": {part: s[key] / wall if timers.hooked else None for part, key in
                       zip(EVAL_PARTS, ("kernel_step", "kernel_settle", "load"))}}


def worker(spec: dict) -> dict:
    tree = os.path.realpath(spec["tree"])
    sys.path[:] = [tree] + [p for p in sys.path if os.path.realpath(p or ".") not in (str(HERE), tree)]
    os.chdir(tree)
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    import bearing_gym
    import numba
    import stable_baselines3
    import torch

    import agents
    import train
    for mod in (bearing_gym, agents, train):        # the tree measured, not an installed copy
        if not os.path.realpath(mod.__file__).startswith(tree + os.sep):
            raise RuntimeError(f"{mod.__name__} imported from {mod.__file__}, not from {tree}")
    res = (_eval_measurement if spec["kind"] == "eval" else _train_measurement)(spec)
    res.update(kind=spec["kind"], tree=tree, load_1min_start=load0, load_1min_end=os.getloadavg()[0],
               process_wall_s=time.perf_counter() - t0, numba_cache_dir=bearing_gym.NUMBA_CACHE_DIR,
               versions={"torch": torch.__version__, "stable_baselines3": stable_baselines3.__version__,
                         "numba": numba.__version__, "numba_threads": numba.config.NUMBA_NUM_THREADS})
    return res


if __name__ == "__main__":
    spec = json.loads(sys.argv[1])
    Path(spec["out"]).write_text(json.dumps(worker(spec)))
