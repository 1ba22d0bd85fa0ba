"""The causal MPC (:mod:`agents.policies.causal_mpc`) on a tier's test episodes, resumable: one
small JSON file per episode, written as it finishes.

    python -m agents.references.causal_mpc_runs --tier transient --status
    python -m agents.references.causal_mpc_runs --tier transient --until 14:20
    python -m agents.references.causal_mpc_runs --tier transient --next 5

Files: ``agents/data/causal_mpc_<tier>/seed_<seed>.json`` (the set-points applied, the return, the
cost, the kernel fingerprint and the settings). An episode made by another kernel or with other
settings counts as missing and is run again. :func:`replay` runs the stored set-points through
the evaluation loop: the board's row, checked bit for bit against the stored returns. Cost on the
2-core VM (one core, the other busy): about 11 s per `transient` episode.
"""

from __future__ import annotations

import json
import time
from datetime import datetime, timedelta
from pathlib import Path

from bearing_gym.envs.provenance import kernel_hash
from bearing_gym.task import EPISODE_STEPS

from agents.evaluation.episodes import run_policies
from agents.evaluation.result import EvalResult
from agents.paths import DATA_DIR
from agents.policies.causal_mpc import CausalMPCSettings, CausalPlan, plan_causal
from agents.policies.planner import ScheduledPreload
from agents.protocol import TEST, TEST_EPISODES, episodes_for_tier
from agents.references.planner_runs import episodes_main, fresh_run

__all__ = ["runs_dir", "episode_path", "test_seeds", "missing", "load_runs", "replay", "run", "main", "ROW_NAME"]

ROW_NAME = "causal MPC (true simulator, the present operating point held)"
#: the --until estimate before an episode of this run is done (s)
NOMINAL_EPISODE_S = 20.0


def runs_dir(tier: str, data_dir: Path = DATA_DIR) -> Path:
    return Path(data_dir) / f"causal_mpc_{tier}"


def episode_path(tier: str, seed: int, data_dir: Path = DATA_DIR) -> Path:
    return runs_dir(tier, data_dir) / f"seed_{seed}.json"


def test_seeds(tier: str, episodes: int | None = None) -> list[int]:
    """The tier's test seeds (the protocol's count, or the first ``episodes``)."""
    n = episodes_for_tier(tier, TEST_EPISODES if episodes is None else episodes)
    return [TEST.start + i for i in range(n)]


def missing(tier: str, episodes: int | None = None, settings: CausalMPCSettings = CausalMPCSettings(),
            episode_steps: int = EPISODE_STEPS, data_dir: Path = DATA_DIR) -> list[int]:
    """The test seeds still to run: absent, or made by another kernel or with other settings."""
    return [s for s in test_seeds(tier, episodes) if not fresh_run(episode_path(tier, s, data_dir), settings, episode_steps)]


def load_runs(tier: str, episodes: int | None = None, settings: CausalMPCSettings = CausalMPCSettings(),
              episode_steps: int = EPISODE_STEPS, data_dir: Path = DATA_DIR) -> list[CausalPlan]:
    """Every test episode's run, in seed order; ValueError naming the command if any is missing."""
    gone = missing(tier, episodes, settings, episode_steps, data_dir)
    if gone:
        raise ValueError(f"causal MPC, tier {tier}: {len(gone)} test episode(s) not run on this kernel with these "
                         f"settings (first seed {gone[0]}); run `python -m agents.references.causal_mpc_runs --tier "
                         f"{tier} --until HH:MM`")
    return [CausalPlan.from_json(json.loads(episode_path(tier, s, data_dir).read_text()))
            for s in test_seeds(tier, episodes)]


def replay(tier: str, runs: list[CausalPlan], episode_steps: int = EPISODE_STEPS,
           progress: str | None = None) -> EvalResult:
    """The stored set-points of consecutive test episodes through the evaluation loop (every
    metric of the row); RuntimeError unless each returns what the run stored, bit for bit."""
    seeds = [r.seed for r in runs]
    if seeds != list(range(seeds[0], seeds[0] + len(seeds))):
        raise ValueError(f"replay takes the runs of consecutive seeds, got {seeds[:3]}...")
    row, = run_policies([ScheduledPreload([r.plan_n for r in runs], name=ROW_NAME)], len(runs), seeds[0],
                        episode_steps, env_kwargs={"tier": tier}, progress=progress)
    bad = [k for k in range(len(runs)) if float(row.returns[k]) != float(runs[k].return_)]
    if bad:
        k = bad[0]
        raise RuntimeError(f"causal MPC, tier {tier} seed {seeds[k]}: replayed return {row.returns[k]!r}, stored "
                           f"{runs[k].return_!r} ({len(bad)} episode(s) differ): run it again")
    return row


def run(tier: str, seeds: list[int], settings: CausalMPCSettings = CausalMPCSettings(),
        episode_steps: int = EPISODE_STEPS, data_dir: Path = DATA_DIR, deadline: datetime | None = None) -> list[Path]:
    """Run ``seeds`` one by one, writing each file as it finishes; with ``deadline``, stop before an
    episode that would not finish by then (estimated from those done in this run)."""
    written: list[Path] = []
    spent: list[float] = []
    for n, seed in enumerate(seeds, 1):
        estimate = max(spent) if spent else NOMINAL_EPISODE_S
        if deadline is not None and datetime.now() + timedelta(seconds=estimate) > deadline:
            print(f"stopping: the next episode (~{estimate:.0f} s) would not finish by {deadline:%H:%M}")
            break
        t0 = time.perf_counter()
        res = plan_causal(tier, seed, episode_steps, settings)
        spent.append(time.perf_counter() - t0)
        path = episode_path(tier, seed, data_dir)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({"tier": tier, "kernel_hash": kernel_hash(), "episode_steps": episode_steps,
                                    **res.to_json()}) + "\n")
        written.append(path)
        print(f"[{n}/{len(seeds)}] {path}: return {res.return_:.2f}, {res.env_steps:,} env steps, {res.wall_s:.0f} s",
              flush=True)
    return written


def main(argv: list[str] | None = None) -> None:
    episodes_main(argv, "python -m agents.references.causal_mpc_runs", "causal MPC", missing, test_seeds, run)


if __name__ == "__main__":
    main()
