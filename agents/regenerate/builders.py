"""The parts' work: thin calls of the library functions and commands that build each product
(the same ones the hand-run commands call), module-level so that they run in a worker process
or a Ray task, and the driver-side commits of parts that write into a shared file.

A part's own file is deleted before it is computed where its builder would otherwise keep a file
it judges fresh by its own, narrower check (a planner episode, a chaos replica): the regeneration
has decided that the part is to be computed again.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from agents.paths import PACKAGE_DIR

__all__ = ["reward_map", "stability_table", "start_bank", "validation_constant", "commit_validation",
           "contextual_fit", "planner_episode", "causal_mpc_episode", "feedback_fit", "speed_schedule_fit", "board_tier", "commit_board_tier", "chaos_replica", "chaos_summary",
           "commit_tier_gap", "evaluation_traces", "command", "examples", "example_files", "board_digest", "EXAMPLES",
           "CHECKOUT"]

#: where the hand-run scripts are (tests/data/make_golden.py, benchmarks/)
CHECKOUT = PACKAGE_DIR.parent
#: the open board's worked examples (examples/<name>.py writes runs/submissions/<name>.json)
EXAMPLES = ("numpy_rule", "cleanrl_actor")


def reward_map(csv_path: Path, grid: dict[str, Any]) -> None:
    """``python -m bearing_gym.envs.reward_map`` on ``grid`` (empty: the module's): the CSV and its PNG."""
    from bearing_gym.envs import reward_map as rm
    points = rm.reward_map(**grid, progress=lambda k, n: print(f"reward map: cell {k}/{n}", flush=True))
    rm.write_csv(points, csv_path)
    rm.plot(points, csv_path.with_suffix(".png"))


def stability_table(out: Path, grid: dict[str, Any]) -> None:
    """``python -m agents.policies.stability_table`` on ``grid`` (empty: the module's)."""
    from agents.policies import stability_table as st
    st.build(**grid, progress=False).save(out)


def start_bank(out: Path, tier: str, first: int, stop: int) -> None:
    """``python -m bearing_gym.envs.start_bank --tier T --seeds FIRST STOP --out OUT``."""
    from bearing_gym.envs import start_bank as sb
    sb.build(tier, range(first, stop), progress=True).save(out)


def validation_constant(tier: str, episodes: int, episode_steps: int, grid_step_n: float, store: Path | None = None):
    """``python -m agents.references --tier T --episodes N``'s choice (stored by :func:`commit_validation`).

    When ``store`` holds this tier's sweep on the same validation episodes and grid, made by this
    kernel with every per-episode return, and only its rule is not the protocol's (a new
    protocol's rule), the stored sweep is picked again by today's rule (``--rechoose``), nothing
    run: running it again would give the same bits."""
    from agents.protocol import VALIDATION, VALIDATION_RULE
    from agents.references.store import load_choice, only_the_rule_differs
    from agents.references.validation import choose_validation_constant, repicked
    if store is not None and only_the_rule_differs(tier, store, episodes, episode_steps, grid_step_n):
        choice = repicked(load_choice(tier, store), VALIDATION_RULE)
        print(f"validation {tier}: the stored sweep picked again by the rule {choice.rule}: {choice.preload_n:g} N "
              "(nothing run)")
        return choice
    return choose_validation_constant(tier, episodes, VALIDATION.start, episode_steps, grid_step_n,
                                      progress=f"validation sweep {tier}: {episodes} episodes")


def commit_validation(store: Path, choice) -> None:
    """Write one tier's choice into the store the tiers share (in the driver: one writer)."""
    from agents.references.store import save_choice
    save_choice(choice, store)


def contextual_fit(out: Path, tier: str, episodes: int, episode_steps: int, grid_step_n: float) -> None:
    """``python -m agents.references.contextual_fit --tier T --episodes N --out OUT``."""
    from agents.protocol import CONTEXTUAL_FIT_SEED
    from agents.references.contextual_fit import fit_contextual
    fit_contextual(tier, episodes, CONTEXTUAL_FIT_SEED, episode_steps, grid_step_n,
                   progress=f"contextual fit {tier}: {episodes} episodes").save(out)


def planner_episode(tier: str, seed: int, settings, episode_steps: int, data_dir: Path) -> None:
    """``python -m agents.references.planner_runs`` on one test episode."""
    from agents.references import planner_runs
    planner_runs.episode_path(tier, seed, data_dir).unlink(missing_ok=True)
    planner_runs.run(tier, [seed], settings, episode_steps, data_dir)


def causal_mpc_episode(tier: str, seed: int, settings, episode_steps: int, data_dir: Path) -> None:
    """``python -m agents.references.causal_mpc_runs`` on one test episode."""
    from agents.references import causal_mpc_runs
    causal_mpc_runs.episode_path(tier, seed, data_dir).unlink(missing_ok=True)
    causal_mpc_runs.run(tier, [seed], settings, episode_steps, data_dir)


def feedback_fit(out: Path, tier: str, episodes: int, rounds: int, episode_steps: int) -> None:
    """``python -m agents.references.feedback_fit --tier T --out OUT``."""
    from agents.references.feedback_fit import write_fit
    write_fit(tier, out, episodes, rounds, episode_steps, progress=None)


def speed_schedule_fit(out: Path, tier: str, kind: str, episodes: int, rounds: int, episode_steps: int,
                       store: Path) -> None:
    """``python -m agents.references.speed_schedule_fit --tier T --kind K --out OUT``."""
    from agents.references.speed_schedule_fit import write_fit
    write_fit(tier, kind, out, episodes, rounds, episode_steps, store, progress=None)


def board_tier(tier: str, settings, model_dirs: tuple[str, ...], store: Path, data_dir: Path,
               oracle_table: Path) -> tuple[str, dict[str, Any]]:
    """One tier of ``python -m agents.leaderboard --model ... --stored-references``: (tier, its
    object of results.json); :func:`commit_board_tier` writes it."""
    from agents.leaderboard.board import learned_groups, run_tier
    from agents.references.store import load_references
    groups = learned_groups([CHECKOUT / d for d in model_dirs], pretrained=False)
    return tier, run_tier(tier, settings, groups, store, data_dir, data_dir, stored=load_references(tier, data_dir),
                          oracle_table=oracle_table)


def commit_board_tier(out: Path, mode: str, command: str, reps: tuple[int, int], payload: tuple[str, dict],
                      data_dir: Path | None = None) -> None:
    """Put one tier into results.json (and its table), keeping the tiers of the same kernel,
    protocol and statistics written before (``--keep-other-tiers``); ``command``'s TIER is the tier.
    The submissions kept beside ``out`` for that tier are added again (scored against the
    references in ``data_dir``, default agents/data)."""
    from agents.leaderboard.results_file import header, kept_tiers, write
    tier, result = payload
    command = command.replace("TIER", tier)
    results = header(mode, command, *reps)
    kept: dict[str, Any] = {}
    if out.exists():
        try:
            kept = kept_tiers(json.loads(out.read_text()), results, [tier])
        except ValueError:                 # another kernel's or protocol's board: start afresh
            kept = {}
    results["tiers"][tier] = {**result, "command": command}
    from agents.submit.submission import readd_stored
    for line in readd_stored(results, out, [tier], **({} if data_dir is None else {"references_dir": data_dir})):
        print(f"board {tier}: submission {line}", flush=True)
    write(results, out, kept)


def board_digest(out: Path) -> str | None:
    """The board's digest without its submitted rows: ``python -m agents.submit add`` puts rows
    on the board that a rebuild adds again (from the files kept beside it), so they do not make
    the board stale."""
    import hashlib
    if not out.exists():
        return None
    results = json.loads(out.read_text())
    for t in results.get("tiers", {}).values():
        t["policies"] = {k: v for k, v in t.get("policies", {}).items() if v.get("kind") != "submitted"}
    return hashlib.sha256(json.dumps(results, sort_keys=True).encode()).hexdigest()[:16]


def chaos_replica(tier: str, episodes: int, episode_steps: int, replica: int, out: Path, store: Path,
                  pretrained_dir: Path) -> None:
    """One replica of ``python -m agents.leaderboard.chaos``."""
    from agents.leaderboard import chaos
    policies = chaos.default_policies(tier, pretrained_dir, store)
    chaos.replica_path(out, replica).unlink(missing_ok=True)
    chaos.run_replica(policies, tier, episodes, replica, out, episode_steps)


def chaos_summary(out: Path, tier: str, episodes: int, replicas: int, store: Path, data_dir: Path,
                  command: str) -> None:
    """The chaos summary of the replicas (driver; no simulation)."""
    from agents.leaderboard import chaos
    from agents.policies.scripted import ConstantPreload
    from agents.references.store import load_choice
    constant = ConstantPreload(load_choice(tier, store).preload_n)
    chaos.write_summary(out, tier, episodes, replicas, constant.name, constant.preload_n, command, data_dir)


def commit_tier_gap(out: Path, argv: list[str], row: dict[str, Any]) -> None:
    """Add one scenario of ``python -m agents.references.tier_gap`` to its file (the rows an
    earlier run with the same settings on this kernel left are kept until recomputed)."""
    from agents.references import tier_gap
    a = tier_gap.build_parser().parse_args(argv)
    settings = tier_gap.run_settings(a)
    rows = tier_gap.stored_rows(str(out), settings)
    rows[int(row["seed"])] = row
    seeds = [a.seed + i for i in range(a.episodes)]
    out.write_text(json.dumps(tier_gap.summarise(settings, seeds, [rows[s] for s in seeds if s in rows]), indent=1))


def evaluation_traces(out_png: Path, episodes: int, episode_steps: int, grid_step_n: float, store: Path,
                      stability: Path, oracle_table: Path, pretrained_dir: Path) -> None:
    """The trace figure of ``python -m agents.evaluate --pretrained --episodes N`` (its other
    report files are not stored)."""
    from agents.evaluation.episodes import TEST_SEED
    from agents.evaluation.trained import shipped_dirs
    from agents.leaderboard.compare import evaluate
    with tempfile.TemporaryDirectory() as tmp:
        evaluate(shipped_dirs(pretrained_dir), episodes, TEST_SEED, episode_steps, tmp, table_path=stability,
                 verbose=False, store_path=store, grid_step_n=grid_step_n, oracle_table=oracle_table)
        shutil.copyfile(Path(tmp) / "evaluation_traces.png", out_png)


def command(argv: list[str]) -> None:
    """Run a hand-run command (``python ...``) from the checkout, with this Python and this
    worker's numba threads; raise if it fails."""
    import numba
    env = {**os.environ, "NUMBA_NUM_THREADS": str(numba.get_num_threads()),
           "PYTHONPATH": os.pathsep.join(filter(None, [str(CHECKOUT), os.environ.get("PYTHONPATH")]))}
    print("running: " + " ".join(argv), flush=True)
    subprocess.run([sys.executable, *argv], cwd=CHECKOUT, env=env, check=True)


def examples(board: Path, tier: str = "transient") -> None:
    """Run the worked examples (``python examples/<name>.py``: each scores its policy on ``tier``'s
    test episodes and saves its submission) and keep their submissions beside ``board`` (the
    board's results.json, which adds them when it is built: :func:`commit_board_tier`)."""
    import numba

    from agents.submit.submission import load_submission, stored_path
    env = {**os.environ, "NUMBA_NUM_THREADS": str(numba.get_num_threads()),
           "PYTHONPATH": os.pathsep.join(filter(None, [str(CHECKOUT), os.environ.get("PYTHONPATH")]))}
    for name in EXAMPLES:
        with tempfile.TemporaryDirectory() as tmp:
            print(f"running: python examples/{name}.py", flush=True)
            subprocess.run([sys.executable, str(CHECKOUT / "examples" / f"{name}.py")], cwd=tmp, env=env, check=True,
                           stdout=subprocess.DEVNULL)
            made = Path(tmp) / "runs" / "submissions" / f"{name}.json"
            sub = load_submission(made)
            if sub["tier"] != tier:
                raise ValueError(f"examples/{name}.py scored tier {sub['tier']}, not {tier}")
            keep = stored_path(board, sub)
            keep.parent.mkdir(parents=True, exist_ok=True)
            shutil.move(made, keep)


def example_files(board: Path, tier: str = "transient") -> tuple[Path, ...]:
    """The worked examples' submissions as ``board`` keeps them (submissions/<tier>_<name>.json beside it)."""
    return tuple(board.parent / "submissions" / f"{tier}_{n}.json" for n in EXAMPLES)
