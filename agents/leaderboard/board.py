"""The leaderboard: every learned policy and every reference on the protocol's test episodes,
as normalised scores with rliable statistics.

    python -m agents.leaderboard --smoke                 # the pipeline at a tiny budget (CI; ~1-2 min)
    python -m agents.leaderboard --pretrained            # shipped policies (agents/pretrained/<algo>/)
    python -m agents.leaderboard --model runs/sac_s0 runs/sac_s1000 ... --tier transient
    python -m agents.leaderboard --pretrained --stored-references    # minutes: references from agents/data

Per tier (``--tier``, default the benchmark's), on ``agents.protocol.TEST_EPISODES`` test
scenarios (seeds ``TEST.start`` on; one on a deterministic tier, ``paper``, where every seed
gives the same episode: :meth:`Settings.for_tier`):

1. the validation-chosen constant, read from ``agents/data/reference_constants.json``
   (``python -m agents.references`` builds it on validation seeds), and the hindsight best
   constant per episode of the 50 N grid (one sweep of the grid; the chosen constant's row is
   its run in that sweep);
2. the upper reference: the planner (:mod:`agents.policies.planner`: the true simulator and the
   episode's future) on every test episode, starting from the episode's hindsight constant;
3. the contextual constant (``agents/data/contextual_<tier>.json``, ``python -m agents.references.contextual_fit``),
   the oracle (reward map, nearest cell) and the learned policies: ``--model`` directories
   written by train.py (grouped by algorithm: one directory per training seed) and, with
   ``--pretrained``, the shipped policy of each algorithm in ``agents/pretrained/<algo>/``
   (``model.zip`` + ``vec_normalize.pkl``, or the portable export alone, as
   :func:`agents.evaluation.trained.load_trained` loads them);
   every learned policy runs on every tier asked for, its row named "... - trained on <tier>"
   on the others (every tier has the same observation space; on ``field`` a policy trained on
   ``transient`` loses its cage-speed features and meets sensor errors it never saw); only a row
   on the tier it was trained on can be the headline (one batch).

A run of the protocol's size stores the references (per episode) in
``agents/data/test_references_<tier>.json`` (:mod:`agents.references.store`);
``--stored-references`` reads them instead of computing them, runs the validation constant again
beside the policies and refuses a store whose returns it does not reproduce. The same store can
be built in parts spread over sessions: :mod:`agents.leaderboard.reference_parts`. When only the
references change (the planner run on more tiers or with a wider search), ``python -m
agents.leaderboard.rescore`` re-scores the rows' stored per-episode returns without running a policy.

Scores and statistics: :mod:`agents.leaderboard.scoring` (0 = the validation-chosen constant, 1 = the
planner's return on the episode, never below the hindsight constant's - a denominator floor of one quasi-periodic interval's cost, IQM with stratified-bootstrap 95 %
intervals and the probability of improvement over the validation constant, with rliable). It
writes ``results.json`` (:mod:`agents.leaderboard.results_file`; per tier and per policy: ``normalised_score_iqm``, ``ci_low``,
``ci_high``, ``n_seeds``, ``n_episodes`` and the raw metrics) and a markdown table beside it;
a full run with ``--model`` writes ``docs/results.json`` and ``docs/results_table.md`` (the
shipped policies alone, without ``--model``: ``runs/leaderboard_pretrained/``). Every departure from the
protocol (fewer episodes, a provisional stored constant, no planner) is listed in
``protocol_deviations`` and the tier is marked ``"protocol": false``.

``--smoke`` runs the same code on 2 test episodes of 3 intervals, with the validation constant
and the contextual fit computed on the spot at that size on coarse grids (written to the output
directory, not to agents/data), a planner with few candidates and few bootstrap replications: it checks the
pipeline, its numbers mean nothing.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES
from bearing_gym.envs.tiers import tier_is_deterministic

from agents import protocol as P
from agents.policies.contextual import DATA_DIR, ContextualConstant, contextual_path
from agents.references.contextual_fit import fit_contextual
from agents.leaderboard import baselines
from agents.leaderboard.tables import best_of_kind, board_pairwise, summarise, to_markdown
from agents.leaderboard.learned import LearnedGroup, inference, learned_groups, missing_v2_rows
from agents.evaluation.trained import PRETRAINED_DIR
from agents.evaluation.episodes import hindsight_preloads, run_policies, sweep_row
from agents.policies.oracle import TABLE_PATH as ORACLE_TABLE, MapOracle
from agents.policies.scripted import ConstantPreload
from agents.references.store import STORE_PATH, ValidationChoice, load_choice, save_choice
from agents.references.validation import choose_validation_constant, hindsight_grid, hindsight_reference
from agents.references.planner_runs import replay
from agents.policies.planner import plan_episode
from agents.leaderboard.results_file import default_out, header, kept_tiers, table_path, write
from agents.references.store import StoredReferences, load_references
from agents.leaderboard.settings import FULL, SMOKE, Settings
from agents.leaderboard.upper import PLANNER_ROW, planner_row, require_planner_settings, score_bounds, upper_fields

__all__ = ["PLANNER_ROW", "LearnedGroup", "learned_groups", "run_tier", "summarise",
           "to_markdown", "main"]

# -- one tier --------------------------------------------------------------------------------------
def _validation_choice(tier: str, s: Settings, store: Path, out_dir: Path, progress: bool) -> ValidationChoice:
    if not s.smoke:
        return load_choice(tier, store)
    choice = choose_validation_constant(tier, s.validation_episodes, P.VALIDATION.start, s.episode_steps,
                                        s.hindsight_grid_step_n,
                                        progress="smoke: validation constant" if progress else None)
    save_choice(choice, out_dir / "reference_constants.json")
    return choice


def _contextual(tier: str, s: Settings, contextual_dir: Path, out_dir: Path, progress: bool) -> ContextualConstant:
    if not s.smoke:
        return ContextualConstant.load(contextual_path(tier, contextual_dir))
    pol = fit_contextual(tier, s.contextual_episodes, P.CONTEXTUAL_FIT_SEED, s.episode_steps, s.contextual_grid_step_n,
                         progress="smoke: contextual fit" if progress else None)
    pol.save(contextual_path(tier, out_dir))
    return pol


def _references(tier: str, s: Settings, choice: ValidationChoice, seeds: range, progress: bool,
                stored: StoredReferences | None) -> StoredReferences:
    """The validation constant, hindsight and planner rows on the test episodes: the stored ones,
    or computed (the planner on every episode, from the sweep's hindsight constants)."""
    shape = f"{s.episodes} test episodes of {s.episode_steps} steps"
    if stored is not None:
        refs = stored.first(s.episodes)
        if refs.seeds != tuple(seeds) or refs.episode_steps != s.episode_steps:
            raise ValueError(f"the stored test references of tier {tier} are for seeds {refs.seeds[0]}.. of "
                             f"{refs.episode_steps} steps, not {seeds.start}.. of {s.episode_steps}")
        if refs.validation_preload_n != choice.preload_n:
            raise ValueError(f"the stored test references of tier {tier} score the validation constant "
                             f"{refs.validation_preload_n:.0f} N, the store now holds {choice.preload_n:.0f} N: "
                             f"rebuild them with `python -m agents.leaderboard --tier {tier}`")
        if refs.hindsight_grid_step_n != s.hindsight_grid_step_n:
            raise ValueError(f"the stored hindsight reference of tier {tier} searched a {refs.hindsight_grid_step_n:g} N "
                             f"grid, these settings a {s.hindsight_grid_step_n:g} N one")
        if s.planner is None:                    # scored against the hindsight constant alone
            return dataclasses.replace(refs, planner=None, planner_settings=None, planner_wall_s_per_episode=None)
        require_planner_settings(refs, s.planner_settings())
        return refs
    extra = (choice.preload_n,)
    hindsight, sweep = hindsight_reference(tier, s.episodes, seeds.start, s.episode_steps, s.hindsight_grid_step_n,
                                           extra_n=extra,
                                           progress=f"{tier} stage 1/{_stages(s, None)}: constant sweep x {shape}"
                                           if progress else None)
    planner = wall = None
    if s.planner is not None:
        held = hindsight_preloads(sweep, hindsight_grid(s.hindsight_grid_step_n, extra))
        plans = []
        for k, seed in enumerate(seeds):
            if progress:
                print(f"{tier} stage 2/{_stages(s, None)}: planner, episode {k + 1} of {s.episodes}", flush=True)
            plans.append(plan_episode(tier, seed, s.episode_steps, s.planner,
                                      hindsight=(held[k], float(hindsight.returns[k]))))
        planner = replay(tier, plans, s.episode_steps)
        wall = float(np.mean([p.wall_s for p in plans]))
    return StoredReferences(tier, tuple(seeds), s.episode_steps, choice.preload_n, s.hindsight_grid_step_n,
                            sweep_row(sweep, choice.preload_n), hindsight, planner, s.planner_settings(), wall)


def _stages(s: Settings, stored: StoredReferences | None) -> int:
    """How many stages a tier's board runs, so that its progress lines count up to it: the
    policies alone with stored references; else the sweep, the planner (if any), the policies."""
    return 1 if stored is not None else (3 if s.planner is not None else 2)


def run_tier(tier: str, s: Settings, groups: list[LearnedGroup], store: Path = STORE_PATH,
             contextual_dir: Path = DATA_DIR, out_dir: Path = Path("."),
             progress: bool = True, stored: StoredReferences | None = None,
             save_references_to: Path | None = None, oracle_table: Path = ORACLE_TABLE) -> dict[str, Any]:
    """Every reference and learned row of ``tier``, as the tier's object of results.json.

    With ``stored`` the validation constant, hindsight and planner rows are the stored ones
    (:mod:`agents.references.store`; the validation constant runs again beside the policies
    and must reproduce its stored returns); else they are computed, and written to
    ``save_references_to`` if given. The oracle's row reads its table from ``oracle_table``."""
    t0 = time.time()
    if stored is not None:             # another kernel's store: refuse before running anything
        stored.check_kernel(f"python -m agents.leaderboard --tier {tier}")
    s = s.for_tier(tier)
    deterministic = tier_is_deterministic(tier)
    protocol_s = FULL.for_tier(tier)     # the protocol's test episodes on this tier
    deviations: list[str] = []
    choice = _validation_choice(tier, s, store, out_dir, progress)
    deviations += [f"validation constant: {p}" for p in choice.protocol_problems()]
    contextual = _contextual(tier, s, contextual_dir, out_dir, progress)
    seeds = P.held_out_seeds(s.episodes)
    refs = _references(tier, s, choice, seeds, progress, stored)
    if stored is None and save_references_to is not None:
        refs.save(save_references_to)
    # the score's 0 and 1 (checked before the policies run)
    r0, r1 = score_bounds(refs)
    shape = f"{s.episodes} test episodes of {s.episode_steps} steps"
    live_constant = [ConstantPreload(choice.preload_n)] if stored is not None else []
    industry = baselines.industry_policies(tier, contextual_dir)
    policies = live_constant + [contextual, MapOracle(oracle_table)] + industry + [p for g in groups for p in g.policies]
    ran = run_policies(policies, s.episodes, seeds.start, s.episode_steps, env_kwargs={"tier": tier},
                       progress=f"{tier} stage {_stages(s, stored)}/{_stages(s, stored)}: {len(policies)} policies x {shape}"
                       if progress else None)
    if live_constant:
        refs.check_fresh(ran[0].returns, f"python -m agents.leaderboard --tier {tier}")
        ran = ran[1:]
    contextual_res, oracle_res = ran[0], ran[1]
    industry_res, learned_res = ran[2:2 + len(industry)], ran[2 + len(industry):]
    reps = dict(bootstrap_reps=s.bootstrap_reps, poi_reps=s.poi_reps)

    rows: dict[str, dict] = {}
    rows[f"validation constant ({choice.preload_n:.0f} N)"] = summarise(
        "reference", [refs.validation_constant], r0, r1, **reps, preload_n=choice.preload_n)
    rows[f"hindsight constant ({refs.hindsight_grid_step_n:g} N grid)"] = summarise(
        "reference", [refs.hindsight], r0, r1, **reps)
    rows["contextual constant"] = summarise("reference", [contextual_res], r0, r1, **reps,
                                            features="squares" if contextual.squares else "linear",
                                            fit=contextual.meta)
    rows["oracle (reward map, nearest cell)"] = summarise("reference", [oracle_res], r0, r1, **reps)
    for policy, res in zip(industry, industry_res):
        rows[policy.name] = summarise(baselines.INDUSTRY_KIND, [res], r0, r1, **reps,
                                      versus={"contextual constant": contextual_res})
    mpc = baselines.causal_mpc_row(tier, s.episodes, s.episode_steps, contextual_dir)
    if mpc is not None:
        rows[mpc.name] = summarise(baselines.MODEL_BASED_KIND, [mpc], r0, r1, **reps,
                                   versus={"contextual constant": contextual_res})
    if P.PROTOCOL_VERSION >= 2:
        deviations += [f"missing baseline: {m}" for m in baselines.missing(tier, s.episodes, s.episode_steps,
                                                                            contextual_dir)]
    if refs.planner is not None:
        rows[PLANNER_ROW] = planner_row(refs, r0, r1, **reps)
    k = 0
    for g in groups:                # also those trained on another tier, named so (row_name)
        runs = learned_res[k:k + len(g.policies)]
        k += len(g.policies)
        headline = P.PROTOCOL_VERSION < 2 and g.algo == P.HEADLINE_ALGORITHM and not g.shipped and g.tier == tier
        rows[g.row_name(tier)] = summarise("learned", runs, r0, r1, **reps, versus={"contextual constant": contextual_res},
                                 algo=g.algo, training_seeds=g.seeds,
                                 timesteps=g.timesteps, train_wall_s=g.train_wall_s, model_dirs=g.dirs,
                                 headline=headline, inference=inference(g.policies),
                                 early_row_steps=g.early_row_steps)
        if P.PROTOCOL_VERSION >= 2:
            want = P.V2_SEEDS if g.algo in P.V2_ALGORITHMS else None
        else:
            want = len(P.training_seeds(g.algo)) if g.algo in P.ALGORITHMS else None
        if not g.shipped and want is not None and len(g.policies) < want:
            deviations.append(f"{g.row_name(tier)}: {len(g.policies)} training seeds (the protocol: {want})")
        other = sorted({v for v in g.protocols if v != P.PROTOCOL_VERSION})
        if not g.shipped and other:
            deviations.append(f"{g.row_name(tier)}: runs of protocol {', '.join(map(str, other))} "
                              f"(the board's: {P.PROTOCOL_VERSION})")
    if P.PROTOCOL_VERSION >= 2 and not s.smoke and s.protocol_sized(tier):
        deviations += missing_v2_rows(groups) + baselines.not_the_protocols(tier, contextual_dir, store)
    pairwise = board_pairwise(rows, r0, r1, s.poi_reps)
    if s.episodes < protocol_s.episodes:
        deviations.append(f"{s.episodes} test episodes (the protocol: {protocol_s.episodes})")
    upper, upper_deviations = upper_fields(refs, r0, r1, protocol_s.planner_settings())
    deviations += upper_deviations
    if s.episode_steps != EPISODE_STEPS:
        deviations.append(f"{s.episode_steps}-step episodes (the benchmark: {EPISODE_STEPS})")
    if s.smoke:
        deviations.insert(0, "smoke run: tiny budget, the numbers mean nothing")
    return {"episodes": s.episodes, "seeds": [seeds.start, seeds[-1]], "episode_steps": s.episode_steps,
            "deterministic": deterministic,
            **({"deterministic_note": f"every seed gives this tier the same episode (scenario and sensor draw nothing "
                                      f"at random), so one test episode stands for the protocol's {P.TEST_EPISODES}; "
                                      "the validation episode is then the test episode, so the validation constant is "
                                      "the hindsight constant, and unless the planner beats it the denominator is the floor: "
                                      "scores are return differences in units of one quasi-periodic interval's cost; "
                                      "the intervals of the learned rows cover the training seeds only"}
               if deterministic else {}),
            "protocol": not deviations, "protocol_deviations": deviations,
            "validation_constant": {"preload_n": choice.preload_n, "episodes": choice.episodes,
                                    "seeds": [choice.seeds[0], choice.seeds[-1]], "grid_step_n": choice.grid_step_n,
                                    "episode_steps": choice.episode_steps},
            "references": "stored (agents/data, checked against the validation constant run again)" if stored
            else "computed in this run",
            **upper, "policies": rows, "pairwise_improvement": pairwise,
            "best_industry_row": best_of_kind(rows, baselines.INDUSTRY_KIND), "wall_s": time.time() - t0}


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="python -m agents.leaderboard",
                                 description="The leaderboard: learned policies and references as normalised scores.")
    ap.add_argument("--smoke", action="store_true", help="the pipeline at a tiny budget (2 episodes); for CI")
    ap.add_argument("--tier", nargs="+", choices=TIER_NAMES, default=[DEFAULT_TIER])
    ap.add_argument("--model", nargs="+", default=[], help="train.py run directories (one per training seed)")
    ap.add_argument("--pretrained", action="store_true", help="add the shipped policies of agents/pretrained/<algo>/")
    ap.add_argument("--pretrained-dir", default=str(PRETRAINED_DIR))
    ap.add_argument("--episodes", type=int, help=f"test episodes (default: the protocol's {P.TEST_EPISODES}; "
                                                 "fewer is recorded as a deviation; a deterministic tier runs one)")
    ap.add_argument("--no-planner", action="store_true",
                    help="score against the hindsight constant alone (a deviation; the planner costs ~1-2 min per episode "
                         "when the references are computed, not stored)")
    ap.add_argument("--store", default=str(STORE_PATH), help="stored validation-chosen constants")
    ap.add_argument("--contextual-dir", default=str(DATA_DIR), help="fitted contextual constants")
    ap.add_argument("--stored-references", action="store_true",
                    help="take the validation constant, hindsight and planner rows from agents/data/test_references_<tier>.json "
                         "(written by a protocol run of this command or joined from parts) instead of computing them: "
                         "minutes, not the hours the planner costs")
    ap.add_argument("--references-dir", default=str(DATA_DIR), help="where the stored test references are")
    ap.add_argument("--keep-other-tiers", action="store_true",
                    help="keep the tiers of the existing results.json at --out that this run does not compute "
                         "(same protocol, mode and statistics, or refused); each tier records its command")
    ap.add_argument("--out", help="results.json path (default: docs/results.json for a full run with --model; "
                                  "runs/leaderboard_smoke/results.json with --smoke; "
                                  "runs/leaderboard_pretrained/results.json for the shipped policies alone; "
                                  "runs/leaderboard_reduced/results.json when --episodes or --no-planner leave the "
                                  "protocol's size on a tier); "
                                  "the markdown table goes beside it")
    return ap


def main(argv: list[str] | None = None) -> dict[str, Any]:
    a = build_parser().parse_args(argv)
    s = SMOKE if a.smoke else FULL
    if a.episodes is not None:
        if a.episodes < 2:
            raise SystemExit("--episodes must be >= 2 (an interval over episodes needs two; a deterministic tier "
                             "runs one whatever --episodes says)")
        s = dataclasses.replace(s, episodes=a.episodes)
    if a.no_planner:
        s = dataclasses.replace(s, planner=None)
    out = Path(a.out) if a.out else default_out(a.smoke, bool(a.model),
                                                    protocol_size=all(s.protocol_sized(t) for t in a.tier))
    out.parent.mkdir(parents=True, exist_ok=True)     # fail before the run, not after it
    t0 = time.time()
    groups = learned_groups(a.model, a.pretrained, Path(a.pretrained_dir))
    command = "python -m agents.leaderboard " + " ".join(argv if argv is not None else sys.argv[1:])
    results = header("smoke" if s.smoke else "full", command, s.bootstrap_reps, s.poi_reps)
    kept: dict[str, Any] = {}
    if a.keep_other_tiers and out.exists():
        try:
            kept = kept_tiers(json.loads(out.read_text()), results, a.tier)
        except ValueError as e:
            raise SystemExit(f"--keep-other-tiers: {e}") from None
    for tier in a.tier:
        stored = load_references(tier, Path(a.references_dir)) if a.stored_references else None
        results["tiers"][tier] = run_tier(tier, s, groups, Path(a.store), Path(a.contextual_dir), out.parent,
                                          stored=stored,
                                          save_references_to=Path(a.references_dir) if s.protocol_sized(tier) else None)
        results["tiers"][tier]["command"] = results["command"]
    results["wall_s"] = time.time() - t0
    text = write(results, out, kept)
    print(text)
    print(f"wrote {out} and {table_path(out)} ({results['wall_s'] / 60:.1f} min)")
    stored = sorted((out.parent / "submissions").glob("*.json"))
    if stored:           # agents.submit keeps them there; the board does not import it (a higher layer)
        print(f"{len(stored)} submission(s) kept beside {out} are not on this rebuilt board: "
              f"`python -m agents.submit readd --board {out}` adds those it still takes")
    return results


if __name__ == "__main__":
    main()
