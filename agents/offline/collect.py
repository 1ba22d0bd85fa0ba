"""Recording a dataset's episodes: one part (consecutive training scenarios under one behaviour)
through ``gym.make("BearingPreload-v0", tier=...)``, step by step, as a Minari user would run
the env, written to one ``.npz`` file.

Per episode of T steps a part holds T+1 observations (the reset's and every step's), T actions,
rewards, terminations and truncations, and T+1 values of each recorded ``info`` key (the keys
the env reports at the reset and at every step: the engineering quantities, ``cost``, ``qpi``,
the operating point; the reward's terms, which the reset has not, are left out: Minari wants
the same keys every step). The expert's episodes replay the planner's stored plans and are
checked against the plans' stored returns bit for bit.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Any

import numpy as np

from agents.offline.recipes import PLANS_DIR, Recipe, pretrained_dir, recipe
from agents.policies.planner import sequential_sum

__all__ = ["INFO_KEYS", "collect_part", "part_path", "read_part", "episode_policy", "plans_missing", "plan_expert",
           "plan_chunk", "plans_digest"]

#: the info keys recorded every step (the reset's keys; the env's docstring describes them)
INFO_KEYS = ("axial_stiffness_n_per_m", "cost", "friction_torque_n_m", "l10_life_h", "life_used_per_s",
             "max_inner_contact_load_n", "max_outer_contact_load_n", "nonsync_rms_um", "preload_n", "qpi",
             "quasi_periodic", "radial_load_n", "radial_stiffness_n_per_m", "setpoint_n", "shaft_speed_rpm", "t")


def part_path(r: Recipe, first: int, n: int, work_dir: Path) -> Path:
    return Path(work_dir) / r.tier / r.name / f"part_{first}_{n}.npz"


class _Random:
    """Uniform actions in [-1, 1] from ``numpy.random.default_rng(seed)`` (one generator per episode)."""

    def __init__(self, seed: int):
        self.rng = np.random.default_rng(seed)

    def act(self, obs: np.ndarray, first: bool) -> np.ndarray:
        return self.rng.uniform(-1.0, 1.0, size=(1,)).astype(np.float32)


class _Batched:
    """A batch policy of agents.policies (SB3's ``predict`` interface) on one env."""

    def __init__(self, policy: Any):
        self.policy, self.state = policy, None

    def act(self, obs: np.ndarray, first: bool) -> np.ndarray:
        a, self.state = self.policy.predict(obs[None, :], self.state, np.array([first]), deterministic=True)
        return np.asarray(a, dtype=np.float32).reshape(1)


def _plan_file(r: Recipe, seed: int, plans_dir: Path) -> Path:
    from agents.references import planner_runs
    return planner_runs.episode_path(r.tier, seed, plans_dir)


def _planner_settings(r: Recipe):
    """The planner's settings the recipe records: the benchmark's (protocol v2's frozen ones)."""
    from agents.policies.planner import PlannerSettings
    s = PlannerSettings()
    if s.as_dict() != r.policy["planner"]:
        raise ValueError(f"{r.dataset_id}: the recipe's planner settings are not the benchmark's; a recipe with "
                         "other settings is another dataset (a new name or version)")
    return s


def plans_missing(r: Recipe, seeds: list[int], plans_dir: Path = PLANS_DIR) -> list[int]:
    """The seeds of ``seeds`` with no plan by this kernel and the recipe's planner settings."""
    from agents.references import planner_runs
    from bearing_gym.task import EPISODE_STEPS
    s = _planner_settings(r)
    return [seed for seed in seeds if not planner_runs.fresh_run(_plan_file(r, seed, plans_dir), s, EPISODE_STEPS)]


def plan_expert(r: Recipe, seeds: list[int], plans_dir: Path = PLANS_DIR, deadline=None) -> list[Path]:
    """Plan the episodes of ``seeds`` that have no plan yet (agents.references.planner_runs, about
    a minute of a core each), each file written as it finishes."""
    from agents.references import planner_runs
    from bearing_gym.task import EPISODE_STEPS
    todo = plans_missing(r, seeds, plans_dir)
    return planner_runs.run(r.tier, todo, _planner_settings(r), EPISODE_STEPS, plans_dir, deadline) if todo else []


def plan_chunk(name: str, seeds: list[int], plans_dir: str, until: str | None) -> int:
    """:func:`plan_expert` on ``seeds`` in a worker process (module level: picklable); returns the
    episodes planned."""
    from agents.clock import deadline
    return len(plan_expert(recipe(name), seeds, Path(plans_dir), deadline(until) if until else None))


def plans_digest(r: Recipe, seeds, plans_dir: Path = PLANS_DIR) -> str | None:
    """SHA-256 of the plan files of ``seeds`` (None for a recipe that is not the planner's): a part
    replayed from other plans is another part."""
    if r.kind != "planner":
        return None
    import hashlib
    h = hashlib.sha256()
    for seed in seeds:
        path = _plan_file(r, seed, plans_dir)
        h.update(path.read_bytes() if path.exists() else b"missing")
    return h.hexdigest()


def episode_policy(r: Recipe, seed: int, plans_dir: Path = PLANS_DIR):
    """The behaviour of episode ``seed`` under recipe ``r`` (an object with ``act(obs, first)``)
    and the return it must reach (the planner's stored return; None for the others)."""
    if r.kind == "random":
        return _Random(seed), None
    if r.kind == "constant":
        from agents.policies.scripted import ConstantPreload
        return _Batched(ConstantPreload(float(r.policy["preload_n"]))), None
    if r.kind == "portable":
        from agents.policies.portable import PortablePolicy
        return _Batched(PortablePolicy.load(pretrained_dir(r.policy["pretrained"]))), None
    if r.kind == "planner":
        from agents.policies.planner import PlanResult, ScheduledPreload
        path = _plan_file(r, seed, plans_dir)
        if plans_missing(r, [seed], plans_dir):
            raise FileNotFoundError(f"no plan of {r.tier} seed {seed} by this kernel in {path}: plan the expert's "
                                    f"episodes first (`python -m agents.offline plan --until HH:MM`)")
        plan = PlanResult.from_json(json.loads(path.read_text()))
        return _Batched(ScheduledPreload([plan.plan_n], name="planner")), plan.return_
    raise ValueError(f"dataset {r.name}: a {r.kind} dataset is joined from others, not recorded")


def _episode(env, seed: int, behaviour) -> dict[str, Any]:
    obs, info = env.reset(seed=seed)
    rows = {"obs": [obs], "act": [], "rew": [], "term": [], "trunc": [], "info": [info]}
    done, first = False, True
    while not done:
        a = behaviour.act(obs, first)
        first = False
        obs, reward, terminated, truncated, info = env.step(a)
        rows["obs"].append(obs)
        rows["act"].append(a)
        rows["rew"].append(float(reward))
        rows["term"].append(bool(terminated))
        rows["trunc"].append(bool(truncated))
        rows["info"].append(info)
        done = terminated or truncated
    return rows


def collect_part(name: str, first: int, n: int, work_dir: str, plans_dir: str | None = None) -> str:
    """Record episodes ``first`` .. ``first + n - 1`` of dataset ``name`` and write the part
    (whole or not at all); returns its path. Module level: it runs in a worker process or a Ray task."""
    import gymnasium as gym

    import bearing_gym  # noqa: F401 - registers the env
    from bearing_gym.envs.provenance import kernel_hash
    r = recipe(name)
    plans = Path(plans_dir) if plans_dir is not None else PLANS_DIR
    t0 = time.time()
    env = gym.make("BearingPreload-v0", tier=r.tier)
    eps = []
    for seed in range(first, first + n):
        behaviour, want = episode_policy(r, seed, plans)
        ep = _episode(env, seed, behaviour)
        if want is not None and sequential_sum(ep["rew"]) != want:
            raise RuntimeError(f"{r.dataset_id} seed {seed}: the replayed plan returns {sequential_sum(ep['rew'])!r}, the plan stored "
                               f"{want!r}: the plan file is stale")
        eps.append(ep)
    env.close()
    arrays = {
        "seeds": np.arange(first, first + n, dtype=np.int64),
        "lengths": np.array([len(e["act"]) for e in eps], dtype=np.int64),
        "observations": np.concatenate([np.asarray(e["obs"], dtype=np.float32) for e in eps]),
        "actions": np.concatenate([np.asarray(e["act"], dtype=np.float32).reshape(-1, 1) for e in eps]),
        "rewards": np.concatenate([np.asarray(e["rew"], dtype=np.float64) for e in eps]),
        "terminations": np.concatenate([np.asarray(e["term"], dtype=bool) for e in eps]),
        "truncations": np.concatenate([np.asarray(e["trunc"], dtype=bool) for e in eps]),
    }
    for k in INFO_KEYS:
        dtype = bool if k == "quasi_periodic" else np.float64
        arrays[f"info/{k}"] = np.concatenate([np.asarray([i[k] for i in e["info"]], dtype=dtype) for e in eps])
    meta = {"dataset_id": r.dataset_id, "recipe_sha": r.digest(), "kernel_hash": kernel_hash(), "first_seed": first,
            "episodes": n, "plans_sha": plans_digest(r, range(first, first + n), plans), "wall_s": time.time() - t0}
    path = part_path(r, first, n, Path(work_dir))
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".tmp.npz")
    np.savez(tmp, meta=np.array(json.dumps(meta)), **arrays)
    os.replace(tmp, path)
    return str(path)


def read_part(path: Path) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """(its metadata, its arrays) of a part file (ValueError if it is not a whole part)."""
    import zipfile
    try:
        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            return meta, {k: z[k] for k in z.files if k != "meta"}
    except (zipfile.BadZipFile, EOFError, KeyError) as err:
        raise ValueError(f"{path}: not a whole part ({type(err).__name__}): record it again") from None
