"""The stored test references built in parts, so that the hours they cost can be spread over
working sessions (each part committed as it finishes) instead of one run that a session's end
would lose.

    python -m agents.leaderboard.reference_parts --tier transient --status        # what is done
    python -m agents.leaderboard.reference_parts --tier transient --next 3        # the next 3 missing sweep parts
    python -m agents.leaderboard.reference_parts --tier transient --until 05:40   # sweep parts while one can finish by then
    python -m agents.leaderboard.reference_parts --tier transient --validation-row   # the validation constant's row
    python -m agents.leaderboard.reference_parts --tier transient --merge         # -> agents/data/test_references_<tier>.json

The parts are the full leaderboard's references (:func:`agents.leaderboard.board._references`
computes the same in one go) cut along the test episodes: ``sweep`` parts run the hindsight grid
on ``SWEEP_PART_EPISODES`` consecutive test episodes and record each episode's hindsight
constant; the upper reference, the planner, is planned one episode at a time by
:mod:`agents.references.planner_runs` (which starts from those hindsight constants); the lower
one, the validation-chosen constant, is run on every test episode once (``--validation-row``,
``validation_row.json``). The hindsight does not depend on the validation constant: the constant
is chosen on the same grid (VALIDATION_GRID_STEP_N = HINDSIGHT_GRID_STEP_N), so a new validation
rule re-runs one constant, not the sweep and the planner. Every episode's scenario comes from
its own seed, so a part's rows equal those of the one-go run; the leaderboard checks it anyway,
running the validation constant again on all episodes
(:meth:`agents.references.store.StoredReferences.check_fresh`). Parts live in
``agents/data/test_references_<tier>_parts/`` (small JSON files); ``--merge`` refuses a set with a
part or a planned episode missing or made with other settings, and replays every plan and
hindsight constant through the evaluation loop (the planner's row with all its metrics), checked
bit for bit against the stored returns (``--without-planner``: the store without the planner,
whose board then scores against the hindsight constant, a protocol deviation).
"""

from __future__ import annotations

import argparse
import json
import os
import time
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.task import DEFAULT_TIER, TIER_NAMES
from bearing_gym.envs.provenance import kernel_hash

from agents import protocol as P
from agents.evaluation.result import EvalResult
from agents.evaluation.episodes import hindsight_preloads
from agents.leaderboard.settings import FULL, Settings
from agents.references import planner_runs
from agents.references.store import STORE_PATH, load_choice, parts_dir
from agents.references.validation import hindsight_grid, hindsight_reference
from agents.references.store import DATA_DIR, StoredReferences, result_from_json, result_to_json


__all__ = ["SWEEP_PART_EPISODES", "parts_dir", "plan", "missing", "compute_part", "validation_row_path",
           "compute_validation_row", "validation_row_problems", "merge", "main"]

SWEEP_PART_EPISODES = 10     # 35 constants x 10 episodes x 150 steps: about 6 min on 2 cores
#: what ``--until`` assumes a part takes before one has been timed (generous; measured on 2 cores: 4.7-5.6 min)
NOMINAL_PART_S = 420.0


def plan(s: Settings = FULL) -> list[tuple[str, int, int]]:
    """Every part as (kind, first test seed, episodes)."""
    seeds = P.held_out_seeds(s.episodes)
    return [("sweep", seeds[k], min(SWEEP_PART_EPISODES, s.episodes - k)) for k in range(0, s.episodes, SWEEP_PART_EPISODES)]


def _path(tier: str, kind: str, first: int, n: int, data_dir: Path) -> Path:
    return parts_dir(tier, data_dir) / f"{kind}_{first}_{n}.json"


def _tier_settings(tier: str, s: Settings | None) -> Settings:
    """``s``, or the protocol's settings on ``tier`` (one episode of each kind on a deterministic tier)."""
    return FULL.for_tier(tier) if s is None else s


def missing(tier: str, s: Settings | None = None, data_dir: Path = DATA_DIR) -> list[tuple[str, int, int]]:
    """The parts still to compute: absent, or made by another kernel (they are computed again)."""
    here = kernel_hash()

    def fresh(path: Path) -> bool:
        """Made by this kernel, and not a part of the definition before the sweep was decoupled from
        the validation constant (its grid held that constant too)."""
        try:
            d = json.loads(path.read_text())
        except (OSError, ValueError):
            return False
        return d.get("kernel_hash") == here and "validation_preload_n" not in d
    return [p for p in plan(_tier_settings(tier, s)) if not fresh(_path(tier, *p, data_dir))]


def _settings(tier: str, s: Settings) -> dict[str, Any]:
    """What every part of a set must share: the kernel (its fingerprint), the episodes' length and
    the grid."""
    return {"tier": tier, "kernel_hash": kernel_hash(), "episode_steps": s.episode_steps,
            "hindsight_grid_step_n": s.hindsight_grid_step_n}


def compute_part(tier: str, kind: str, first: int, n: int, s: Settings | None = None,
                 data_dir: Path = DATA_DIR) -> Path:
    """Compute one sweep part (the hindsight grid on ``n`` test episodes from seed ``first``) and
    write it; returns its path."""
    if kind != "sweep":
        raise ValueError(f"kind must be 'sweep', got {kind!r} (the planner's episodes: agents.references.planner_runs)")
    s = _tier_settings(tier, s)
    t0 = time.time()
    hindsight, sweep = hindsight_reference(tier, n, first, s.episode_steps, s.hindsight_grid_step_n)
    path = _path(tier, kind, first, n, data_dir)
    _write(path, {**_settings(tier, s), "kind": kind, "first_seed": first, "episodes": n,
                  "rows": {"hindsight": result_to_json(hindsight)},
                  "hindsight_preload_n": hindsight_preloads(sweep, hindsight_grid(s.hindsight_grid_step_n)),
                  "wall_s": time.time() - t0})
    return path


def _write(path: Path, payload: dict[str, Any]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")                 # a part is there whole or not at all
    tmp.write_text(json.dumps(payload) + "\n")
    os.replace(tmp, path)


def validation_row_path(tier: str, data_dir: Path = DATA_DIR) -> Path:
    return parts_dir(tier, data_dir) / "validation_row.json"


def compute_validation_row(tier: str, s: Settings | None = None, store: Path = STORE_PATH,
                           data_dir: Path = DATA_DIR) -> Path:
    """The stored validation constant (by the protocol's rule) on every test episode of ``tier``,
    written to :func:`validation_row_path`; returns the path."""
    from agents.evaluation.episodes import constant_sweep
    s = _tier_settings(tier, s)
    choice = load_choice(tier, store)
    seeds = P.held_out_seeds(s.episodes)
    t0 = time.time()
    (row,) = constant_sweep([choice.preload_n], s.episodes, seeds[0], s.episode_steps, env_kwargs={"tier": tier})
    path = validation_row_path(tier, data_dir)
    _write(path, {**_settings(tier, s), "first_seed": seeds[0], "episodes": s.episodes, "preload_n": choice.preload_n,
                  "rule": choice.rule, "row": result_to_json(row), "wall_s": time.time() - t0})
    return path


def validation_row_problems(tier: str, s: Settings | None = None, store: Path = STORE_PATH,
                            data_dir: Path = DATA_DIR) -> list[str]:
    """What keeps the stored validation row from being today's (empty: nothing): absent, or made
    by another kernel, on other episodes or for another constant than the store's choice."""
    s = _tier_settings(tier, s)
    path = validation_row_path(tier, data_dir)
    try:
        d = json.loads(path.read_text())
    except (OSError, ValueError):
        return [f"no validation row in {path}"]
    choice = load_choice(tier, store)
    head = {k: v for k, v in _settings(tier, s).items() if k != "hindsight_grid_step_n"}   # the row needs no grid
    want = {**head, "first_seed": P.held_out_seeds(s.episodes)[0], "episodes": s.episodes,
            "preload_n": choice.preload_n, "rule": choice.rule}
    return [f"{path.name} has {k} = {d.get(k)!r}, today's is {v!r}" for k, v in want.items() if d.get(k) != v]


def merge(tier: str, s: Settings | None = None, data_dir: Path = DATA_DIR, store: Path = STORE_PATH,
          with_planner: bool = True, progress: bool = False) -> Path:
    """Join every part (and, ``with_planner``, every planned episode, replayed) into the stored
    references of ``tier`` (references_path) and save them."""
    s = _tier_settings(tier, s)
    todo = missing(tier, s, data_dir)
    if todo:
        raise FileNotFoundError(f"{len(todo)} parts of tier {tier} are missing (first: {todo[0][0]} from seed "
                                f"{todo[0][1]}); compute them with `python -m agents.leaderboard.reference_parts --tier {tier} --next {len(todo)}`")
    want = _settings(tier, s)
    layout = plan(s)
    parts = [json.loads(_path(tier, *p, data_dir).read_text()) for p in layout]
    for (kind, first, n), part in zip(layout, parts):
        name = f"part {kind} from seed {first}"
        if (part["kind"], part["first_seed"], part["episodes"]) != (kind, first, n):
            raise ValueError(f"{name}: its file holds {part['kind']} from seed {part['first_seed']} "
                             f"({part['episodes']} episodes)")
        for k, v in want.items():
            if part.get(k) != v:
                raise ValueError(f"{name} has {k} = {part.get(k)}, the settings now {v}: delete "
                                 f"{_path(tier, kind, first, n, data_dir)} and compute it again")
        for row, r in part["rows"].items():
            if len(r["returns"]) != n:
                raise ValueError(f"{name}: its {row} row has {len(r['returns'])} episodes, not {n}")

    stale = validation_row_problems(tier, s, store, data_dir)
    if stale:
        raise ValueError(f"the validation constant's row of tier {tier}: {stale[0]}; compute it again: "
                         f"`python -m agents.leaderboard.reference_parts --tier {tier} --validation-row`")
    vrow = json.loads(validation_row_path(tier, data_dir).read_text())
    if vrow["preload_n"] not in hindsight_grid(s.hindsight_grid_step_n):
        raise ValueError(f"tier {tier}: the validation constant {vrow['preload_n']:g} N is not on the hindsight grid "
                         f"(step {s.hindsight_grid_step_n:g} N), so the hindsight row would not bound it")

    def joined(row: str) -> EvalResult:
        return EvalResult.concat([result_from_json(p["rows"][row]) for p in parts])
    seeds = P.held_out_seeds(s.episodes)
    hindsight = joined("hindsight")
    planner = planner_settings = wall = None
    if with_planner:
        if s.planner is None:
            raise ValueError("these settings have no planner; merge --without-planner")
        plans = planner_runs.load_plans(tier, s.episodes, s.planner, s.episode_steps, data_dir)
        stored_h = np.array([p.hindsight_return for p in plans])
        if not np.array_equal(stored_h, hindsight.returns):
            k = int(np.flatnonzero(stored_h != hindsight.returns)[0])
            raise ValueError(f"planner, tier {tier} seed {seeds[k]}: it started from a hindsight return of "
                             f"{stored_h[k]!r}, the sweep parts hold {hindsight.returns[k]!r}: delete "
                             f"{planner_runs.episode_path(tier, seeds[k], data_dir)} and plan it again "
                             f"(`python -m agents.references.planner_runs --tier {tier} --next 1`)")
        below = [k for k, p in enumerate(plans) if not p.return_ >= p.hindsight_return]
        if below:
            k = below[0]
            raise ValueError(f"planner, tier {tier} seed {seeds[k]}: its return {plans[k].return_!r} is below its "
                             f"hindsight constant's {plans[k].hindsight_return!r}, which it cannot be: plan it again")
        planner = planner_runs.replay(tier, plans, s.episode_steps,
                                      progress=f"{tier}: replaying {len(plans)} plans" if progress else None)
        planner_settings = s.planner_settings()
        wall = float(np.mean([p.wall_s for p in plans]))
    refs = StoredReferences(tier, tuple(seeds), s.episode_steps, vrow["preload_n"], s.hindsight_grid_step_n,
                            result_from_json(vrow["row"]), hindsight, planner, planner_settings, wall)
    return refs.save(data_dir)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="The stored test references of a tier, computed in parts.")
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--status", action="store_true", help="which parts are done")
    g.add_argument("--next", type=int, metavar="K", help="compute the next K missing parts")
    g.add_argument("--until", metavar="HH:MM", help="compute parts while the next can finish before this time")
    g.add_argument("--validation-row", action="store_true",
                   help="run the stored validation constant on every test episode (the board's 0)")
    g.add_argument("--merge", action="store_true", help="join the parts and the planned episodes into "
                                                         "agents/data/test_references_<tier>.json")
    ap.add_argument("--without-planner", action="store_true",
                    help="--merge without the planner (its board scores against the hindsight constant: a deviation)")
    ap.add_argument("--data-dir", default=str(DATA_DIR))
    a = ap.parse_args(argv)
    if a.next is not None and a.next < 1:
        ap.error(f"--next must be >= 1, got {a.next}")
    data_dir = Path(a.data_dir)
    s = _tier_settings(a.tier, None)     # one episode of each kind on a deterministic tier
    todo = missing(a.tier, s, data_dir=data_dir)
    if a.status:
        done = len(plan(s)) - len(todo)
        unplanned = planner_runs.missing(a.tier, s.episodes, s.planner, s.episode_steps, data_dir)
        print(f"tier {a.tier}: {done}/{len(plan(s))} sweep parts done in {parts_dir(a.tier, data_dir)}"
              + (f"; next: {todo[0][0]} from seed {todo[0][1]}" if todo else "")
              + f"; planner: {s.episodes - len(unplanned)}/{s.episodes} episodes"
              + ("" if todo or unplanned else "; merge them: --merge"))
        return 0
    if a.validation_row:
        print(f"wrote {compute_validation_row(a.tier, s, data_dir=data_dir)}")
        return 0
    if a.merge:
        print(f"wrote {merge(a.tier, s, data_dir=data_dir, with_planner=not a.without_planner, progress=True)}")
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
    took, timed = NOMINAL_PART_S, False           # the longest part so far
    for part in todo[:a.next] if a.next is not None else todo:
        if deadline is not None and datetime.now() + timedelta(seconds=1.2 * took) > deadline:
            print(f"stopping before {part[0]} from seed {part[1]}: it would not finish by {a.until}")
            break
        t0 = time.time()
        path = compute_part(a.tier, *part, s, data_dir=data_dir)
        took = (time.time() - t0) if not timed else max(took, time.time() - t0)
        timed = True
        print(f"{path} ({(time.time() - t0) / 60:.1f} min)", flush=True)
    left = missing(a.tier, s, data_dir=data_dir)
    print(f"{len(left)} parts left" if left else
          f"every sweep part done; the planner's episodes: `python -m agents.references.planner_runs --tier {a.tier} "
          f"--until HH:MM`, then `python -m agents.leaderboard.reference_parts --tier {a.tier} --merge`")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
