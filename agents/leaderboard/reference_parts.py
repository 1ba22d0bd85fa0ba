"""The stored test references built in parts, so that the hour they cost can be spread over
working sessions (each part committed as it finishes) instead of one run that a session's end
would lose.

    python -m agents.leaderboard.reference_parts --tier transient --status        # which parts are done
    python -m agents.leaderboard.reference_parts --tier transient --next 3        # compute the next 3 missing parts
    python -m agents.leaderboard.reference_parts --tier transient --until 05:40   # parts while one can finish by then
    python -m agents.leaderboard.reference_parts --tier transient --merge         # -> agents/data/test_references_<tier>.json

The parts are the full leaderboard's references (:func:`agents.leaderboard.board._references` computes
the same in one go) cut along the test episodes: ``sweep`` parts run the hindsight grid (which
holds the validation-chosen constant) on ``SWEEP_PART_EPISODES`` consecutive test episodes,
``mpc`` parts the MPC reference on ``MPC_PART_EPISODES`` of the MPC subset (``--processes`` in
parallel). Every episode's scenario comes from its own seed, so a part's rows equal those of
the one-go run; the leaderboard checks it anyway, running the validation constant again on all
episodes (:meth:`agents.references.store.StoredReferences.check_fresh`). Parts live in
``agents/data/test_references_<tier>_parts/`` (small JSON files); ``--merge`` refuses a set
with a part missing or computed with other settings.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import time
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.task import DEFAULT_TIER, TIER_NAMES
from bearing_gym.envs.provenance import kernel_hash

from agents.policies import mpc as mpc_module
from agents import protocol as P
from agents.evaluation.result import EvalResult
from agents.evaluation.episodes import sweep_row
from agents.leaderboard.settings import FULL, Settings
from agents.references.store import STORE_PATH, load_choice
from agents.references.validation import hindsight_reference, run_mpc
from agents.references.store import DATA_DIR, StoredReferences, result_from_json, result_to_json


__all__ = ["SWEEP_PART_EPISODES", "MPC_PART_EPISODES", "parts_dir", "plan", "missing", "compute_part", "merge", "main"]

SWEEP_PART_EPISODES = 10     # 35 constants x 10 episodes x 150 steps: about 6 min on 2 cores
MPC_PART_EPISODES = 2        # two MPC episodes, one per core
#: what ``--until`` assumes a part of a kind takes before one has been timed (generous)
NOMINAL_PART_S = {"sweep": 420.0, "mpc": 120.0}   # measured on 2 cores: sweep parts 4.7-5.6 min, mpc parts 0.8-0.9 min


def parts_dir(tier: str, data_dir: Path = DATA_DIR) -> Path:
    return Path(data_dir) / f"test_references_{tier}_parts"


def plan(s: Settings = FULL) -> list[tuple[str, int, int]]:
    """Every part as (kind, first test seed, episodes): the sweep parts, then the MPC parts."""
    seeds = P.held_out_seeds(s.episodes)
    m = min(s.mpc_episodes, s.episodes)
    out = [("sweep", seeds[k], min(SWEEP_PART_EPISODES, s.episodes - k)) for k in range(0, s.episodes, SWEEP_PART_EPISODES)]
    out += [("mpc", seeds[k], min(MPC_PART_EPISODES, m - k)) for k in range(0, m, MPC_PART_EPISODES)]
    return out


def _path(tier: str, kind: str, first: int, n: int, data_dir: Path) -> Path:
    return parts_dir(tier, data_dir) / f"{kind}_{first}_{n}.json"


def _tier_settings(tier: str, s: Settings | None) -> Settings:
    """``s``, or the protocol's settings on ``tier`` (one episode of each kind on a deterministic tier)."""
    return FULL.for_tier(tier) if s is None else s


def missing(tier: str, s: Settings | None = None, data_dir: Path = DATA_DIR) -> list[tuple[str, int, int]]:
    """The parts still to compute: absent, or made by another kernel (they are computed again)."""
    here = kernel_hash()

    def fresh(path: Path) -> bool:
        try:
            return json.loads(path.read_text()).get("kernel_hash") == here
        except (OSError, ValueError):
            return False
    return [p for p in plan(_tier_settings(tier, s)) if not fresh(_path(tier, *p, data_dir))]


def _settings(tier: str, s: Settings, preload_n: float) -> dict[str, Any]:
    """What every part of a set must share: the kernel (its fingerprint) and the MPC's source too
    (the stale check at evaluation runs the validation constant again, which would not notice a
    changed MPC)."""
    return {"tier": tier, "kernel_hash": kernel_hash(), "episode_steps": s.episode_steps, "validation_preload_n": preload_n,
            "hindsight_grid_step_n": s.hindsight_grid_step_n,
            "mpc_settings": s.mpc_settings(),
            "mpc_source_sha1": hashlib.sha1(Path(mpc_module.__file__).read_bytes()).hexdigest()}


def compute_part(tier: str, kind: str, first: int, n: int, s: Settings | None = None, store: Path = STORE_PATH,
                 data_dir: Path = DATA_DIR, processes: int = 2) -> Path:
    """Compute one part and write it; returns its path."""
    s = _tier_settings(tier, s)
    choice = load_choice(tier, store)
    t0 = time.time()
    head = _settings(tier, s, choice.preload_n)
    if kind == "sweep":
        hindsight, sweep = hindsight_reference(tier, n, first, s.episode_steps, s.hindsight_grid_step_n,
                                               extra_n=(choice.preload_n,))
        rows = {"validation constant": result_to_json(sweep_row(sweep, choice.preload_n)),
                "hindsight": result_to_json(hindsight)}
        wall = None
    elif kind == "mpc":
        res, walls = run_mpc(tier, range(first, first + n), s.episode_steps, s.mpc, processes)
        rows, wall = {"mpc": result_to_json(res)}, [float(w) for w in walls]
    else:
        raise ValueError(f"kind must be 'sweep' or 'mpc', got {kind!r}")
    path = _path(tier, kind, first, n, data_dir)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")                 # a part is there whole or not at all
    tmp.write_text(json.dumps({**head, "kind": kind, "first_seed": first, "episodes": n, "rows": rows,
                               "mpc_wall_s": wall, "processes": processes if kind == "mpc" else None,
                               "wall_s": time.time() - t0}) + "\n")
    os.replace(tmp, path)
    return path


def merge(tier: str, s: Settings | None = None, data_dir: Path = DATA_DIR, store: Path = STORE_PATH) -> Path:
    """Join every part into the stored references of ``tier`` (references_path) and save them."""
    s = _tier_settings(tier, s)
    todo = missing(tier, s, data_dir)
    if todo:
        raise FileNotFoundError(f"{len(todo)} parts of tier {tier} are missing (first: {todo[0][0]} from seed "
                                f"{todo[0][1]}); compute them with `python -m agents.leaderboard.reference_parts --tier {tier} --next {len(todo)}`")
    want = _settings(tier, s, load_choice(tier, store).preload_n)
    layout = plan(s)
    parts = [json.loads(_path(tier, *p, data_dir).read_text()) for p in layout]
    for (kind, first, n), part in zip(layout, parts):
        name = f"part {kind} from seed {first}"
        if (part["kind"], part["first_seed"], part["episodes"]) != (kind, first, n):
            raise ValueError(f"{name}: its file holds {part['kind']} from seed {part['first_seed']} "
                             f"({part['episodes']} episodes)")
        for k, v in want.items():
            if k == "mpc_source_sha1" and kind != "mpc":
                continue
            if part.get(k) != v:
                raise ValueError(f"{name} has {k} = {part.get(k)}, the settings now {v}: delete "
                                 f"{_path(tier, kind, first, n, data_dir)} and compute it again")
        for row, r in part["rows"].items():
            if len(r["returns"]) != n:
                raise ValueError(f"{name}: its {row} row has {len(r['returns'])} episodes, not {n}")
    sweeps = [p for p in parts if p["kind"] == "sweep"]
    mpcs = [p for p in parts if p["kind"] == "mpc"]

    def joined(ps: list[dict], row: str) -> EvalResult:
        return EvalResult.concat([result_from_json(p["rows"][row]) for p in ps])
    walls = [w for p in mpcs for w in p["mpc_wall_s"]]
    seeds = P.held_out_seeds(s.episodes)
    refs = StoredReferences(tier, tuple(seeds), s.episode_steps, want["validation_preload_n"], s.hindsight_grid_step_n,
                            joined(sweeps, "validation constant"), joined(sweeps, "hindsight"),
                            joined(mpcs, "mpc") if mpcs else None, want["mpc_settings"],
                            float(np.mean(walls)) if walls else None)
    return refs.save(data_dir)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="The stored test references of a tier, computed in parts.")
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--status", action="store_true", help="which parts are done")
    g.add_argument("--next", type=int, metavar="K", help="compute the next K missing parts")
    g.add_argument("--until", metavar="HH:MM", help="compute parts while the next can finish before this time")
    g.add_argument("--merge", action="store_true", help="join the parts into agents/data/test_references_<tier>.json")
    ap.add_argument("--processes", type=int, default=2, help="parallel MPC episodes (default %(default)d)")
    ap.add_argument("--data-dir", default=str(DATA_DIR))
    a = ap.parse_args(argv)
    if a.next is not None and a.next < 1:
        ap.error(f"--next must be >= 1, got {a.next}")
    data_dir = Path(a.data_dir)
    s = _tier_settings(a.tier, None)     # one episode of each kind on a deterministic tier
    todo = missing(a.tier, s, data_dir=data_dir)
    if a.status:
        done = len(plan(s)) - len(todo)
        print(f"tier {a.tier}: {done}/{len(plan(s))} parts done in {parts_dir(a.tier, data_dir)}"
              + (f"; next: {todo[0][0]} from seed {todo[0][1]}" if todo else "; merge them: --merge"))
        return 0
    if a.merge:
        print(f"wrote {merge(a.tier, s, data_dir=data_dir)}")
        return 0
    deadline = None
    if a.until:
        try:
            hh, mm = (int(x) for x in a.until.split(":"))
            deadline = datetime.now().replace(hour=hh, minute=mm, second=0, microsecond=0)
        except ValueError:
            raise SystemExit(f"--until takes a time of today as HH:MM, got {a.until!r}") from None
        if deadline <= datetime.now():
            raise SystemExit(f"--until {a.until} has passed (now {datetime.now():%H:%M}); give a later time today")
        print(f"computing parts of tier {a.tier} while the next can finish by {deadline:%Y-%m-%d %H:%M}", flush=True)
    took = dict(NOMINAL_PART_S)           # the longest part of each kind so far
    timed: set[str] = set()
    for part in todo[:a.next] if a.next is not None else todo:
        if deadline is not None and datetime.now() + timedelta(seconds=1.2 * took[part[0]]) > deadline:
            print(f"stopping before {part[0]} from seed {part[1]}: it would not finish by {a.until}")
            break
        t0 = time.time()
        path = compute_part(a.tier, *part, s, data_dir=data_dir, processes=a.processes)
        took[part[0]] = (time.time() - t0) if part[0] not in timed else max(took[part[0]], time.time() - t0)
        timed.add(part[0])
        print(f"{path} ({(time.time() - t0) / 60:.1f} min)", flush=True)
    left = missing(a.tier, s, data_dir=data_dir)
    print(f"{len(left)} parts left" if left else f"every part done: `python -m agents.leaderboard.reference_parts --tier {a.tier} --merge`")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
