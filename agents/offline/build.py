"""Building a dataset from its recipe: its parts recorded (resumable: a part done by this kernel
for this recipe is kept; spread over processes or Ray), joined into a Minari dataset, and its
content checksum compared with the committed one.

The checksum is over what ``minari.load_dataset`` gives back, not over the HDF5 file (whose
bytes carry timestamps): per episode in order its id, then each array (observations, actions,
rewards, terminations, truncations, every info key in sorted order) as dtype, shape and
little-endian bytes, SHA-256. The same recipe on the same kernel gives the same checksum on any
CPU (the kernel, the random actions and the portable policies use no libm or BLAS).

The committed catalogue, ``agents/data/offline_datasets.json``, holds per dataset its recipe and
digest, the kernel, the checksum, its size and what the build cost (core-seconds of its parts).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import time
import warnings
from pathlib import Path
from typing import Any, Callable

import numpy as np

from agents.offline.collect import INFO_KEYS, collect_part, part_path, plans_digest, plans_missing, read_part
from agents.offline.recipes import PLANS_DIR, RECIPES, Recipe, recipe
from agents.paths import DATA_DIR, runs_dir

__all__ = ["CATALOGUE", "WORK_DIR", "parts_left", "collect", "episodes_of", "write_minari", "checksum",
           "build", "load_catalogue", "verify", "DatasetMismatch"]

CATALOGUE = DATA_DIR / "offline_datasets.json"
#: where the parts are recorded (runs/offline in a checkout, git-ignored: they are rebuilt from the recipes)
WORK_DIR = runs_dir("offline")


class DatasetMismatch(ValueError):
    """A rebuilt dataset whose checksum is not the committed one."""


def _fresh(path: Path, r: Recipe, plans_dir: Path = PLANS_DIR) -> bool:
    """A part recorded by this kernel for this recipe (the expert's: from the plan files there now)."""
    from bearing_gym.envs.provenance import kernel_hash
    try:
        meta, _ = read_part(path)
    except (OSError, ValueError):
        return False
    return (meta.get("recipe_sha") == r.digest() and meta.get("kernel_hash") == kernel_hash()
            and meta.get("plans_sha") == plans_digest(r, range(meta["first_seed"], meta["first_seed"] + meta["episodes"]),
                                                      plans_dir))


def _needed(r: Recipe, n: int | None = None) -> list[tuple[int, int]]:
    """The parts of ``r`` that hold its first ``n`` episodes (all: None)."""
    return [p for p in r.parts() if n is None or p[0] < r.first_seed + n]


def parts_left(r: Recipe, work_dir: Path = WORK_DIR, plans_dir: Path = PLANS_DIR) -> list[tuple[int, int]]:
    """The parts of ``r`` not yet recorded by this kernel for this recipe (a mixed dataset: the
    parts of its sources that hold the episodes it takes and are missing)."""
    if r.kind == "mixed":
        return [p for name, n in r.sources for p in _left(recipe(f"{r.tier}/{name}"), work_dir, plans_dir, n)]
    return _left(r, work_dir, plans_dir)


def _left(r: Recipe, work_dir: Path, plans_dir: Path, n: int | None = None) -> list[tuple[int, int]]:
    return [p for p in _needed(r, n) if not _fresh(part_path(r, *p, work_dir), r, plans_dir)]


def collect(r: Recipe, work_dir: Path = WORK_DIR, plans_dir: Path = PLANS_DIR, executor=None,
            processes: int | None = None, progress: bool = True) -> list[str]:
    """Record every missing part of ``r`` (of its sources, if mixed) on ``executor`` (default: a
    pool of ``processes`` spawned processes; agents' Ray executor spreads them over a cluster)."""
    from bearing_gym.analysis.sweeps import run_tasks
    todo = []
    for src, n in ([(recipe(f"{r.tier}/{name}"), k) for name, k in r.sources] if r.kind == "mixed" else [(r, None)]):
        if src.kind == "planner":
            last = src.first_seed + (src.episodes if n is None else n)
            gone = plans_missing(src, list(range(src.first_seed, last)), plans_dir)
            if gone:
                raise FileNotFoundError(f"{src.dataset_id}: {len(gone)} of {src.episodes} episodes have no plan yet "
                                        f"(first seed {gone[0]}); plan them first: `python -m agents.offline plan "
                                        f"--until HH:MM` (about a minute of a core each)")
        todo += [(src.dataset_id, first, k, str(work_dir), str(plans_dir)) for first, k in _left(src, work_dir, plans_dir, n)]
    if not todo:
        return []
    return run_tasks(collect_part, todo, executor=executor, max_workers=processes, progress=progress,
                     desc=f"{r.dataset_id}: parts")


def _episodes_of_parts(r: Recipe, work_dir: Path, limit: int | None = None,
                       plans_dir: Path = PLANS_DIR) -> list[dict[str, Any]]:
    out: list[dict[str, Any]] = []
    for first, n in _needed(r, limit):
        path = part_path(r, first, n, work_dir)
        if not _fresh(path, r, plans_dir):
            raise FileNotFoundError(f"{r.dataset_id}: part {path.name} is missing or stale; record it: "
                                    f"`python -m agents.offline build {r.tier}/{r.name}`")
        _, a = read_part(path)
        obs_at = act_at = 0
        for seed, length in zip(a["seeds"], a["lengths"]):
            length = int(length)
            ep = {"seed": int(seed),
                  "observations": a["observations"][obs_at:obs_at + length + 1],
                  "actions": a["actions"][act_at:act_at + length],
                  "rewards": a["rewards"][act_at:act_at + length],
                  "terminations": a["terminations"][act_at:act_at + length],
                  "truncations": a["truncations"][act_at:act_at + length],
                  "infos": {k: a[f"info/{k}"][obs_at:obs_at + length + 1] for k in INFO_KEYS}}
            obs_at += length + 1
            act_at += length
            out.append(ep)
            if limit is not None and len(out) == limit:
                return out
    return out


def episodes_of(r: Recipe, work_dir: Path = WORK_DIR, plans_dir: Path = PLANS_DIR) -> list[dict[str, Any]]:
    """Every episode of ``r`` from its recorded parts, in order (a mixed dataset: its sources' first
    episodes, source after source)."""
    if r.kind != "mixed":
        return _episodes_of_parts(r, work_dir, plans_dir=plans_dir)
    out = []
    for name, n in r.sources:
        got = _episodes_of_parts(recipe(f"{r.tier}/{name}"), work_dir, n, plans_dir)
        if len(got) < n:
            raise ValueError(f"{r.dataset_id}: source {name} has {len(got)} episodes, the recipe takes {n}")
        out += got
    return out


def write_minari(r: Recipe, episodes: list[dict[str, Any]], datasets_path: Path | None = None):
    """The Minari dataset of ``episodes`` (replacing one of the same id), under ``datasets_path``
    (default: Minari's, ``MINARI_DATASETS_PATH`` or ``~/.minari/datasets``)."""
    import gymnasium as gym

    import bearing_gym  # noqa: F401 - registers the env
    import minari
    from minari.data_collector.episode_buffer import EpisodeBuffer
    if datasets_path is not None:
        os.environ["MINARI_DATASETS_PATH"] = str(datasets_path)
    if r.dataset_id in minari.list_local_datasets():
        minari.delete_dataset(r.dataset_id)
    buffers = [EpisodeBuffer(id=k, seed=e["seed"], observations=e["observations"], actions=e["actions"],
                             rewards=list(e["rewards"]), terminations=list(e["terminations"]),
                             truncations=list(e["truncations"]), infos=dict(e["infos"]))
               for k, e in enumerate(episodes)]
    spec = gym.spec("BearingPreload-v0")
    env_spec = dataclasses.replace(spec, kwargs={**spec.kwargs, "tier": r.tier})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)       # no author e-mail, no separate eval env
        return minari.create_dataset_from_buffers(
            r.dataset_id, buffers, env=env_spec, algorithm_name=f"{r.kind}: {r.description}",
            author="bearing_gym", code_permalink="https://github.com/bearing-gym/bearing_gym (agents/offline)",
            description=(f"{r.description}. Tier {r.tier}, training scenarios {r.first_seed}.., {len(episodes)} "
                         f"episodes. Recipe {r.digest()}: `python -m agents.offline build {r.tier}/{r.name}`."),
            data_format="hdf5")


def _update(h, x: np.ndarray) -> None:
    x = np.ascontiguousarray(x)
    x = x.astype(x.dtype.newbyteorder("<"), copy=False)     # little-endian bytes on every host
    h.update(f"{x.dtype.str}{x.shape}".encode())
    h.update(x.tobytes())


def checksum(dataset) -> str:
    """SHA-256 of a loaded Minari dataset's content (module docstring)."""
    h = hashlib.sha256()
    for ep in dataset.iterate_episodes():
        h.update(str(int(ep.id)).encode())
        for x in (ep.observations, ep.actions, ep.rewards, ep.terminations, ep.truncations):
            _update(h, np.asarray(x))
        for k in sorted(ep.infos):
            _update(h, np.asarray(ep.infos[k]))
    return h.hexdigest()


def load_catalogue(path: Path = CATALOGUE) -> dict[str, Any]:
    if not Path(path).exists():
        return {"about": "The offline datasets: per Minari id its recipe, the kernel, the content checksum of a build, "
                         "its size and cost (agents.offline; docs/offline.md).", "datasets": {}}
    return json.loads(Path(path).read_text())


def _libraries() -> dict[str, str]:
    """The versions of what writes and reads the data (a checksum that moves with one names it)."""
    from importlib.metadata import version
    return {name: version(name) for name in ("minari", "h5py", "gymnasium", "numpy")}


def _cost_s(r: Recipe, work_dir: Path) -> float:
    if r.kind == "mixed":
        return 0.0
    return float(sum(read_part(part_path(r, *p, work_dir))[0]["wall_s"] for p in r.parts()))


def build(name: str, work_dir: Path = WORK_DIR, plans_dir: Path = PLANS_DIR, datasets_path: Path | None = None,
          executor=None, processes: int | None = None, record: bool = False, catalogue: Path = CATALOGUE,
          log: Callable[[str], None] = print) -> dict[str, Any]:
    """Record what is missing, write the Minari dataset and check its checksum against the
    catalogue's (``record``: write this build's entry instead, for a new or changed recipe).
    Returns the entry. Raises :class:`DatasetMismatch` on a different checksum."""
    import minari
    from bearing_gym.envs.provenance import kernel_hash
    r = recipe(name)
    t0 = time.time()
    collect(r, work_dir, plans_dir, executor, processes)
    ds = write_minari(r, episodes_of(r, work_dir, plans_dir), datasets_path)
    ds = minari.load_dataset(r.dataset_id)
    entry = {"recipe": r.as_json(), "recipe_sha": r.digest(), "kernel_hash": kernel_hash(), "checksum": checksum(ds),
             "episodes": int(ds.total_episodes), "steps": int(ds.total_steps),
             "bytes": int(sum(f.stat().st_size for f in Path(ds.spec.data_path).rglob("*") if f.is_file())),
             "parts_core_s": round(_cost_s(r, work_dir), 1), "libraries": _libraries()}
    cat = load_catalogue(catalogue)
    old = cat["datasets"].get(r.dataset_id)
    if record:
        cat["datasets"][r.dataset_id] = entry
        cat["datasets"] = dict(sorted(cat["datasets"].items()))
        Path(catalogue).write_text(json.dumps(cat, indent=1) + "\n")
        log(f"{r.dataset_id}: recorded checksum {entry['checksum'][:16]} ({entry['episodes']} episodes, "
            f"{entry['steps']:,} steps, {entry['bytes'] / 1e6:.1f} MB) in {catalogue}")
    elif old is None:
        raise DatasetMismatch(f"{r.dataset_id} is not in {catalogue}; record a first build with --record")
    else:
        _compare(r, old, entry)
        log(f"{r.dataset_id}: checksum {entry['checksum'][:16]} equals the committed one ({time.time() - t0:.0f} s)")
    return entry


def _compare(r: Recipe, old: dict[str, Any], new: dict[str, Any]) -> None:
    for key, why in (("recipe_sha", "the recipe changed since the committed build (record the new one)"),
                     ("kernel_hash", "another kernel made the committed build (rebuild it on that kernel, or "
                                     "record this one)"),
                     ("checksum", "the same recipe on the same kernel gave other data: a bug, or a part file edited "
                                  "by hand (delete runs/offline and build again)")):
        if old.get(key) != new.get(key):
            libs = [f"{k} {old.get('libraries', {}).get(k)} -> {v}" for k, v in new.get("libraries", {}).items()
                    if old.get("libraries", {}).get(k) not in (None, v)]
            raise DatasetMismatch(f"{r.dataset_id}: {key} {str(new.get(key))[:16]} is not the committed "
                                  f"{str(old.get(key))[:16]}: {why}"
                                  + (f" (the libraries differ too: {', '.join(libs)})" if libs else ""))


def verify(name: str, catalogue: Path = CATALOGUE) -> str:
    """Load ``name`` from Minari's local store and check its checksum against the catalogue's;
    returns the checksum."""
    import minari
    r = recipe(name)
    old = load_catalogue(catalogue)["datasets"].get(r.dataset_id)
    if old is None:
        raise DatasetMismatch(f"{r.dataset_id} is not in {catalogue}")
    got = checksum(minari.load_dataset(r.dataset_id))
    if got != old["checksum"]:
        raise DatasetMismatch(f"{r.dataset_id}: the local dataset's checksum {got[:16]} is not the committed "
                              f"{old['checksum'][:16]}: build it again (`python -m agents.offline build {r.tier}/{r.name}`)")
    return got


def all_names() -> list[str]:
    return list(RECIPES)
