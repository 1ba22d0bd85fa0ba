"""train.py's evaluation: the run just trained and the shipped policies on the leaderboard.

After training, ``train.py`` (README command 1) puts its fresh model beside the shipped policies
(``agents/pretrained/<algo>/``) and every reference on its ``--eval-episodes`` test episodes
(the first test seeds of :mod:`agents.protocol`) and prints the leaderboard table with
normalised scores (:func:`agents.leaderboard.board.run_tier`). The expensive references (hindsight
sweep, planner) come from ``agents/data/test_references_<tier>.json``, stored by the full
leaderboard run and checked there against the validation constant run again, so the
evaluation takes minutes; without a store (another episode length, a tier not yet run) they
are computed here (the hindsight sweep; no planner, whose ~1.5 min per episode is no demo's)
and the evaluation takes longer. A tier with
no validation-chosen constant or no fitted contextual baseline gets the per-baseline report
of :func:`agents.leaderboard.compare.evaluate` instead.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from bearing_gym.task import EPISODE_STEPS
from bearing_gym.envs.tiers import tier_is_deterministic

from agents import protocol as P
from agents.protocol import preload_grid
from agents.policies.contextual import ContextualConstant, contextual_path
from agents.evaluation.trained import PRETRAINED_DIR, shipped_dirs
from agents.leaderboard.settings import FULL
from agents.leaderboard.board import learned_groups, run_tier
from agents.references.store import load_choice
from agents.leaderboard.results_file import header, table_path, write
from agents.references.store import load_references


__all__ = ["evaluate_run", "BOARD_BOOTSTRAP_REPS"]

#: bootstrap replications of the after-training board (the full leaderboard uses rliable's 50,000)
BOARD_BOOTSTRAP_REPS = 5_000


#: the rate the after-training estimate assumes: env steps per second of a batched constant
#: sweep on the 2-core development machine (the sweep's own progress lines then measure it)
SWEEP_ENV_STEPS_PER_S = 150.0


def _recompute_note(reason: str, episodes: int, episode_steps: int) -> str:
    """What the fallback recomputes and how long it will take, said before it starts."""
    constants = len(preload_grid(P.HINDSIGHT_GRID_STEP_N))
    steps = constants * episodes * episode_steps
    return (f"note: {reason}; computing the references here instead: the hindsight sweep, {constants} constant "
            f"preloads x {episodes} episodes x {episode_steps} steps = {steps:,} env steps, about "
            f"{steps / SWEEP_ENV_STEPS_PER_S / 60:.0f} min at {SWEEP_ENV_STEPS_PER_S:.0f} env steps/s (a 2-core "
            "machine; its progress lines say how long is left); no planner (its ~1.5 min per episode is no "
            "demo's): the upper reference is the hindsight constant")


def _missing_reference(tier: str) -> str | None:
    try:
        load_choice(tier)
        ContextualConstant.load(contextual_path(tier))
    except (LookupError, FileNotFoundError) as err:
        return str(err)
    return None


def evaluate_run(model_dir: str | Path, episodes: int, tier: str, episode_steps: int = EPISODE_STEPS,
                 pretrained_dir: Path = PRETRAINED_DIR, progress_every_s: float = 30.0) -> dict[str, Any] | None:
    """The board of ``model_dir``'s fresh model, the shipped policies and the references on the
    first ``episodes`` test seeds; writes ``leaderboard.md`` and ``leaderboard.json`` into
    ``model_dir`` and prints the table. Returns the tier's results (None when it fell back to
    the per-baseline report)."""
    out = Path(model_dir)
    episodes = P.episodes_for_tier(tier, episodes)      # 1 on a deterministic tier: the others are copies
    missing = _missing_reference(tier)
    if missing is None and episodes < 2 and not tier_is_deterministic(tier):
        missing = f"{episodes} episode: an interval needs two"
    if missing is not None:
        from agents.evaluation.episodes import TEST_SEED
        from agents.leaderboard.compare import evaluate
        print(f"note: no leaderboard for tier {tier} ({missing}); the per-baseline report instead", flush=True)
        evaluate(out, episodes=episodes, seed=TEST_SEED, episode_steps=episode_steps, tier=tier,
                 progress_every_s=progress_every_s)
        return None
    stored = None
    if episode_steps == EPISODE_STEPS:
        try:
            stored = load_references(tier)
        except (FileNotFoundError, ValueError) as err:     # none stored, or a store of an older format
            print(_recompute_note(str(err), episodes, episode_steps), flush=True)
        if stored is not None and episodes > len(stored.seeds):
            print(_recompute_note(f"{episodes} episodes asked, {len(stored.seeds)} stored", episodes, episode_steps),
                  flush=True)
            stored = None
    s = dataclasses.replace(FULL, episodes=episodes, episode_steps=episode_steps,
                            planner=FULL.planner if stored is not None and stored.planner is not None else None,
                            bootstrap_reps=BOARD_BOOTSTRAP_REPS, poi_reps=max(200, BOARD_BOOTSTRAP_REPS // 10))
    shipped = bool(shipped_dirs(pretrained_dir, required=False))
    groups = learned_groups([out], pretrained=shipped, pretrained_dir=pretrained_dir)
    fresh = groups[0]
    steps = fresh.timesteps[0]
    fresh.name = f"{fresh.algo.upper()} (this run, {steps:,} steps: a demo)" if steps else f"{fresh.algo.upper()} (this run)"
    if not shipped:
        print(f"note: no shipped policies in {pretrained_dir}/<algo>/: the board has this run and the references only",
              flush=True)
    try:
        result = run_tier(tier, s, groups, stored=stored)
    except (ValueError, RuntimeError) as err:      # a stale or mismatched store: not worth the training
        if stored is None:
            raise
        print(_recompute_note(str(err), episodes, episode_steps), flush=True)
        result = run_tier(tier, dataclasses.replace(s, planner=None), groups, stored=None)
    results = {**header("after training (train.py)", f"python train.py ... --out {out}", s.bootstrap_reps, s.poi_reps),
               "tiers": {tier: result}}
    board = out / "leaderboard.json"
    text = write(results, board)
    note = (f"\nThe shipped rows are the leaderboard's policies (docs/results.md: "
            f"{P.episodes_for_tier(tier, P.TEST_EPISODES)} test episodes, every training seed); this run's row is a "
            f"short demo on {episodes} of those episodes.\n")
    with table_path(board).open("a") as f:      # leaderboard.md, beside it
        f.write(note)
    print(text + note, flush=True)
    return result
