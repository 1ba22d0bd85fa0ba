"""The planner (:mod:`agents.policies.planner`) on a tier's test episodes, resumable: one small JSON
file per episode, written as it finishes, so a run spread over sessions loses at most the episode
it was on.

    python -m agents.references.planner_runs --tier transient --status
    python -m agents.references.planner_runs --tier transient --until 14:20     # episodes while one can finish by then
    python -m agents.references.planner_runs --tier transient --next 5

Files: ``agents/data/planner_<tier>/seed_<seed>.json`` (the plan, its return, the hindsight
constant it started from, the search's cost, the kernel fingerprint and the planner settings).
An episode made by another kernel or with other settings counts as missing and is planned again;
one stored with the settings before the settle pass (``PlannerSettings.before_settle``) is
resumed: only the settle pass runs, and the plan is the one a whole run would give, bit for bit.
The test episodes are the protocol's (``TEST.start`` on, ``episodes_for_tier``). Where the tier's
test-reference sweep parts (:func:`agents.references.store.stored_hindsight`) already hold the
episode's hindsight constant, the planner starts from it instead of sweeping the grid again.
:func:`replay` runs the stored plans (and their hindsight constants) through the evaluation
loop: the planner's row of the leaderboard, checked bit for bit against the stored returns.
"""

from __future__ import annotations

import argparse
import json
import time
from datetime import datetime, timedelta
from pathlib import Path

from bearing_gym.envs.provenance import kernel_hash
from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

import numpy as np

from agents.clock import deadline
from agents.paths import DATA_DIR
from agents.evaluation.episodes import run_policies
from agents.evaluation.result import EvalResult
from agents.policies.planner import PlannerSettings, PlanResult, ScheduledPreload, plan_episode
from agents.protocol import TEST, TEST_EPISODES, episodes_for_tier
from agents.references.store import stored_hindsight

__all__ = ["planner_dir", "episode_path", "missing", "problems", "load_plans", "replay", "run", "main", "episodes_main", "fresh_run"]

#: the --until estimate before an episode of this run is done: a whole episode took 95-125 s on
#: average on `field` and `transient` on the 2-core development VM (the other core busy), a
#: resumed one (the settle pass alone) about a third of that
NOMINAL_EPISODE_S = 150.0


def planner_dir(tier: str, data_dir: Path = DATA_DIR) -> Path:
    return data_dir / f"planner_{tier}"


def episode_path(tier: str, seed: int, data_dir: Path = DATA_DIR) -> Path:
    return planner_dir(tier, data_dir) / f"seed_{seed}.json"


def _seeds(tier: str, episodes: int | None) -> list[int]:
    n = episodes_for_tier(tier, TEST_EPISODES if episodes is None else episodes)
    return [TEST.start + i for i in range(n)]


def fresh_run(path: Path, settings, episode_steps: int) -> bool:
    """Whether ``path`` holds a run of this kernel, these settings (``settings.as_dict()``) and
    episode length."""
    try:
        d = json.loads(path.read_text())
    except (OSError, ValueError):
        return False
    return (d.get("kernel_hash") == kernel_hash() and d.get("settings") == settings.as_dict()
            and d.get("episode_steps") == episode_steps)


def missing(tier: str, episodes: int | None = None, settings: PlannerSettings = PlannerSettings(),
            episode_steps: int = EPISODE_STEPS, data_dir: Path = DATA_DIR) -> list[int]:
    """The test seeds still to plan: absent, or made by another kernel or with other settings."""
    return [s for s in _seeds(tier, episodes) if not fresh_run(episode_path(tier, s, data_dir), settings, episode_steps)]


def problems(tier: str, episodes: int | None, settings: PlannerSettings, episode_steps: int,
             grid_step_n: float, data_dir: Path = DATA_DIR) -> list[str]:
    """What keeps the stored episodes from being what planning them now would write (empty:
    nothing; the regeneration's check for adopting them): an episode missing, made by another
    kernel, with other settings or episode length, or started from another hindsight constant
    than the stored sweep parts hold (the planner is deterministic in exactly these)."""
    out = []
    for seed in _seeds(tier, episodes):
        path = episode_path(tier, seed, data_dir)
        if not fresh_run(path, settings, episode_steps):
            out.append(f"seed {seed}: missing, or planned by another kernel, settings or episode length")
            continue
        d = json.loads(path.read_text())
        start = stored_hindsight(tier, seed, grid_step_n, episode_steps, data_dir)
        if start is None or (d.get("hindsight_preload_n"), d.get("hindsight_return")) != start:
            out.append(f"seed {seed}: started from {d.get('hindsight_preload_n')} N (return {d.get('hindsight_return')}), "
                       f"the sweep parts hold {start}")
    return out


def load_plans(tier: str, episodes: int | None = None, settings: PlannerSettings = PlannerSettings(),
               episode_steps: int = EPISODE_STEPS, data_dir: Path = DATA_DIR) -> list[PlanResult]:
    """Every test episode's plan, in seed order; ValueError naming the command if any is missing."""
    gone = missing(tier, episodes, settings, episode_steps, data_dir)
    if gone:
        raise ValueError(f"planner, tier {tier}: {len(gone)} test episode(s) not planned on this kernel "
                         f"(first seed {gone[0]}); run `python -m agents.references.planner_runs --tier {tier} --until HH:MM`")
    return [PlanResult.from_json(json.loads(episode_path(tier, s, data_dir).read_text())) for s in _seeds(tier, episodes)]


def replay(tier: str, plans: list[PlanResult], episode_steps: int = EPISODE_STEPS,
           progress: str | None = None) -> EvalResult:
    """The plans of consecutive test episodes (``plans[0].seed`` on) run through the evaluation
    loop as the planner's row, every metric of it; raises unless each plan and each hindsight
    constant return what the planner stored, bit for bit."""
    seeds = [p.seed for p in plans]
    if seeds != list(range(seeds[0], seeds[0] + len(seeds))):
        raise ValueError(f"replay takes the plans of consecutive seeds, got {seeds[:3]}...")
    T = episode_steps
    held = [np.full(T, p.hindsight_preload_n) for p in plans]
    planner, hindsight = run_policies([ScheduledPreload([p.plan_n for p in plans]),
                                       ScheduledPreload(held, name="hindsight constant (the planner's start)")],
                                      len(plans), seeds[0], T, env_kwargs={"tier": tier}, progress=progress)
    for what, got, want in (("plan", planner.returns, [p.return_ for p in plans]),
                            ("hindsight constant", hindsight.returns, [p.hindsight_return for p in plans])):
        bad = [k for k in range(len(plans)) if float(got[k]) != float(want[k])]
        if bad:
            k = bad[0]
            raise RuntimeError(f"planner, tier {tier} seed {seeds[k]}: its {what} replayed returns {got[k]!r}, the "
                               f"stored {want[k]!r} ({len(bad)} episode(s) differ): plan it again")
    return planner


def run(tier: str, seeds: list[int], settings: PlannerSettings = PlannerSettings(), episode_steps: int = EPISODE_STEPS,
        data_dir: Path = DATA_DIR, deadline: datetime | None = None) -> list[Path]:
    """Plan ``seeds`` one by one, writing each file as it finishes; with ``deadline``, stop before
    an episode that would not finish by then (estimated from those done in this run)."""
    written = []
    spent: list[float] = []
    for seed in seeds:
        if deadline is not None:
            estimate = max(spent) if spent else NOMINAL_EPISODE_S
            if datetime.now() + timedelta(seconds=estimate) > deadline:
                print(f"stopping: the next episode (~{estimate / 60:.1f} min) would not finish by {deadline:%H:%M}")
                break
        t0 = time.perf_counter()
        path = episode_path(tier, seed, data_dir)
        if settings.settles and fresh_run(path, settings.before_settle(), episode_steps):
            # the search up to the settle pass is stored: only the settle pass runs (the same bits)
            res = plan_episode(tier, seed, episode_steps, settings,
                               resume=PlanResult.from_json(json.loads(path.read_text())))
        else:
            res = plan_episode(tier, seed, episode_steps, settings,
                               hindsight=stored_hindsight(tier, seed, settings.grid_step_n, episode_steps, data_dir))
        spent.append(time.perf_counter() - t0)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({"tier": tier, "kernel_hash": kernel_hash(), "episode_steps": episode_steps,
                                    **res.to_json()}) + "\n")
        written.append(path)
        print(f"{path}: return {res.return_:.2f} (hindsight {res.hindsight_preload_n:.0f} N: "
              f"{res.hindsight_return:.2f}; +{res.return_ - res.hindsight_return:.2f}), {res.accepted} of "
              f"{res.decisions} decisions changed the plan, {res.env_steps:,} env steps, {res.wall_s:.0f} s"
              + (" (hindsight from the stored sweep)" if res.hindsight_from == "stored" else ""), flush=True)
    return written


def episodes_main(argv: list[str] | None, prog: str, what: str, missing_fn, seeds_fn, run_fn) -> None:
    """The command line of a per-episode reference run (``--status | --next K | --until HH:MM``):
    ``missing_fn(tier, episodes, data_dir=)``, ``seeds_fn(tier, episodes)``, ``run_fn(tier, seeds,
    data_dir=, deadline=)``."""
    ap = argparse.ArgumentParser(prog=prog, description=f"The {what} on a tier's test episodes, one file per episode.")
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    ap.add_argument("--episodes", type=int, help="first N test episodes (default: the protocol's)")
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--status", action="store_true", help="how many episodes are done")
    g.add_argument("--next", type=int, metavar="K", help="run the next K missing episodes")
    g.add_argument("--until", metavar="HH:MM", help="run episodes while one can finish before this time")
    ap.add_argument("--data-dir", default=str(DATA_DIR))
    a = ap.parse_args(argv)
    data_dir = Path(a.data_dir)
    todo = missing_fn(a.tier, a.episodes, data_dir=data_dir)
    total = len(seeds_fn(a.tier, a.episodes))
    if a.status:
        print(f"{what}, tier {a.tier}: {total - len(todo)} of {total} test episodes done on this kernel"
              + (f"; next seed {todo[0]}" if todo else ""))
        return
    run_fn(a.tier, todo if a.next is None else todo[:a.next], data_dir=data_dir,
           deadline=deadline(a.until) if a.until else None)


def main(argv: list[str] | None = None) -> None:
    episodes_main(argv, "python -m agents.references.planner_runs", "planner", missing, _seeds, run)


if __name__ == "__main__":
    main()
