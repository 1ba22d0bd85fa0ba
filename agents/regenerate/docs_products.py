"""The products under ``docs/`` (and the studies beside them): the leaderboard's results, its
score breakdowns, the chaos replicas, the tier-gap study, the learning curves, the trace figure,
the integrator's accuracy and the paper's reproduction. Declared as in
:mod:`agents.regenerate.catalogue`, which lists them after the references they read.
"""

from __future__ import annotations

import functools
import shlex
from pathlib import Path

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS

from agents.evaluation.trained import shipped_dirs
from agents.leaderboard import breakdown, learning_curves, profiles
from agents.paths import PRETRAINED_DIR
from agents.policies.mpc import DEFAULT_CANDIDATES_N
from agents import protocol as P
from agents.protocol import preload_grid
from agents.references import tier_gap
from agents.leaderboard.chaos import replica_path
import agents.regenerate.builders as B
from agents.regenerate.product import PART_OVERHEAD_S, STEP_CORE_S, Layout, Part, Product, env_cost
from agents.regenerate.profiles import Profile, trained_runs

__all__ = ["docs_products", "BOOTSTRAP_REP_S"]

#: core-seconds per row and bootstrap replication of the board's statistics (rliable: ~12 min
#: for 14 rows at 50,000 replications)
BOOTSTRAP_REP_S = 1e-3



def _row_of(run_dir: str) -> tuple[str, bool]:
    """The board row a run directory joins: (its algorithm's directory, whether it is an early row
    ``.../seed_<s>/by_<steps>``)."""
    p = Path(run_dir)
    return (p.parent.parent.name, True) if p.name.startswith("by_") else (p.parent.name, False)

def _board(prof: Profile, L) -> list[Product]:
    s = prof.board
    store, oracle = L.data / "reference_constants.json", L.data / "oracle_table.csv"
    out = L.docs / "results.json"
    models = " ".join(prof.model_dirs)
    if prof.model_dirs == trained_runs():
        models = ("agents/trained/*/seed_*" if P.PROTOCOL_VERSION < 2 else
                  f"agents/trained_v2/*/seed_* agents/trained_v2/*/seed_*/by_{P.V2_EARLY_ROW_STEPS}")
    command = f"python -m agents.leaderboard --tier TIER --model {models} --stored-references --keep-other-tiers"
    commit = functools.partial(B.commit_board_tier, out, prof.name, command, (s.bootstrap_reps, s.poi_reps),
                               data_dir=L.data)
    rows = 5 + len({_row_of(d) for d in prof.model_dirs})     # the references, one per algorithm and budget
    parts = tuple(Part(f"tier_{t}", B.board_tier, (t, s, prof.model_dirs, store, L.data, oracle),
                       env_cost(prof.board_for(t).episodes, s.episode_steps, 3 + len(prof.model_dirs))
                       + rows * s.bootstrap_reps * BOOTSTRAP_REP_S, commit) for t in prof.tiers)
    up = ("oracle_table",) + tuple(f"{k}:{t}" for t in prof.tiers for k in ("validation", "contextual", "references"))
    if prof.baselines:
        up += tuple(f"{k}:{t}" for t in prof.tiers for k in ("causal_mpc", "feedback"))
        up += tuple(f"speed_schedule:{t}:{k}" for t in prof.tiers for k in prof.baselines["kinds"])
    up += ("examples",) if _has_examples(prof) else ()
    board = Product("board", "the leaderboard: every learned run and reference on the test episodes of every tier",
                    (out, out.with_name("results_table.md")), parts, upstream=up,
                    settings={"tiers": prof.tiers, "models": prof.model_dirs, "settings": s},
                    sources=tuple(B.CHECKOUT / d for d in prof.model_dirs),
                    digest=functools.partial(B.board_digest, out),
                    command=command.replace("TIER", " ".join(prof.tiers)) + " (a tier at a time; the submissions kept "
                    "in docs/submissions/ added again)")
    png = L.docs / "performance_profiles.png"
    out_list = [board, Product("profiles", "the performance profiles of the board's rows (rliable), a panel per random "
                               "tier", (png,), (Part("profiles", profiles.main, (["--results", str(out), "--out", str(png)],),
                                                     60.0),),
                               upstream=("board",), kernel=False,
                               command="python -m agents.leaderboard.profiles")]
    for t in (t for t in prof.breakdown_tiers if t in prof.tiers):
        md = L.docs / f"score_breakdown_{t}.md"
        argv = ["--results", str(out), "--tier", t, "--row", prof.breakdown_row, "--out", str(md),
                "--references-dir", str(L.data)]
        out_list.append(Product(f"breakdown:{t}", f"{prof.breakdown_row}'s per-episode scores on {t} against the "
                                "scenarios", (md, md.with_suffix(".json")),
                                (Part("breakdown", breakdown.main, (argv,), PART_OVERHEAD_S),),
                                upstream=("board", f"references:{t}"), settings={"row": prof.breakdown_row},
                                command=f"python -m agents.leaderboard.breakdown --tier {t} --row "
                                        f"{shlex.quote(prof.breakdown_row)} --out docs/score_breakdown_{t}.md"))
    return out_list


def _chaos(prof: Profile, L) -> list[Product]:
    c = prof.chaos
    tier, steps = c["tier"], prof.board.episode_steps
    if tier not in prof.tiers:
        return []
    out, store = L.docs / f"chaos_{tier}.json", L.data / "reference_constants.json"
    command = f"python -m agents.leaderboard.chaos --tier {tier} --replicas {c['replicas']} --episodes {c['episodes']}"
    n_policies = 1 + len(shipped_dirs(PRETRAINED_DIR, required=False))
    parts = tuple(Part(f"replica_{r}", B.chaos_replica, (tier, c["episodes"], steps, r, out, store, PRETRAINED_DIR),
                       env_cost(c["episodes"], steps, n_policies)) for r in range(c["replicas"] + 1))
    return [Product(f"chaos:{tier}", "the test set again under a 1e-15 nudge of the settled start: how much of a "
                    "score is chaos", (out,) + tuple(replica_path(out, r) for r in range(c["replicas"] + 1)), parts,
                    upstream=(f"validation:{tier}", f"references:{tier}"), settings={**c, "episode_steps": steps},
                    sources=(PRETRAINED_DIR,),
                    finish=functools.partial(B.chaos_summary, out, tier, c["episodes"], c["replicas"], store, L.data,
                                             command), command=command)]


def _tier_gap(prof: Profile, L) -> list[Product]:
    g = prof.tier_gap
    out = L.docs / f"tier_gap_{g['tier']}.json"
    argv = ["--tier", g["tier"], "--seed", str(g["seed"]), "--episodes", str(g["episodes"]), "--grid-step",
            str(g["grid_step"]), "--horizon", str(g["horizon"]), "--replan-every", str(g["replan_every"])]
    mpc_steps = EPISODE_STEPS * len(DEFAULT_CANDIDATES_N) * g["horizon"] / g["replan_every"]
    cost = env_cost(1, EPISODE_STEPS, len(preload_grid(g["grid_step"])) + 1) + mpc_steps * STEP_CORE_S
    commit = functools.partial(B.commit_tier_gap, out, argv)
    parts = tuple(Part(f"seed_{g['seed'] + i}", tier_gap.scenario_gap,
                       ((g["tier"], g["seed"] + i, g["grid_step"], g["horizon"], g["replan_every"]),), cost, commit)
                  for i in range(g["episodes"]))
    return [Product(f"tier_gap:{g['tier']}", "MPC (true simulator) against the hindsight constant on tier-design "
                    "scenarios", (out,), parts, settings=g,
                    command="python -m agents.references.tier_gap " + " ".join(argv) + f" --out docs/{out.name}")]


def _figures(prof: Profile, L) -> list[Product]:
    store = L.data / "reference_constants.json"
    out: list[Product] = []
    if prof.learning_curves and DEFAULT_TIER in prof.tiers:
        png = L.docs / "learning_curves.png"
        runs = [str(B.CHECKOUT / d) for d in prof.learning_curves]
        out.append(Product("learning_curves", "validation score against env steps of the trained runs",
                           (png, png.with_suffix(".json")),
                           (Part("curves", learning_curves.main, ([*runs, "--store", str(store), "--out", str(png)],),
                                 60.0),),
                           upstream=(f"validation:{DEFAULT_TIER}",), kernel=False,
                           sources=tuple(B.CHECKOUT / d for d in prof.learning_curves),
                           command="python -m agents.leaderboard.learning_curves "
                                   + ("agents/trained/*/seed_*" if P.PROTOCOL_VERSION < 2 else "agents/trained_v2/*/seed_*")))
    if DEFAULT_TIER in prof.tiers:
        t = prof.traces
        png = L.docs / "evaluation_traces.png"
        grid = len(preload_grid(t["grid_step_n"]))
        out.append(Product("evaluation_traces", "the shipped policies' and baselines' traces on the first test "
                           "episode (docs/training.md)", (png,),
                           (Part("figure", B.evaluation_traces,
                                 (png, t["episodes"], prof.board.episode_steps, t["grid_step_n"], store,
                                  L.data / "stability_table.npz", L.data / "oracle_table.csv", PRETRAINED_DIR),
                                 env_cost(t["episodes"], prof.board.episode_steps, grid + 6)),),
                           upstream=(f"validation:{DEFAULT_TIER}", "oracle_table", "stability_table"),
                           settings={**t, "episode_steps": prof.board.episode_steps}, sources=(PRETRAINED_DIR,),
                           command=f"python -m agents.evaluate --pretrained --episodes {t['episodes']}"))
    if prof.bench_accuracy:
        js = L.docs / "bench_accuracy.json"
        out.append(Product("bench_accuracy", "the env integrator against a four times smaller step (critical preload, "
                           "amplitudes, map classification)", (js,),
                           (Part("bench", B.command, (["benchmarks/bench_accuracy.py", "--json", "--out", str(js)],),
                                 1500.0),),
                           command="python benchmarks/bench_accuracy.py --json --out docs/bench_accuracy.json"))
    if prof.reproduction:
        d = L.docs / "reproduction"
        out.append(Product("reproduction", "the reproduction of Bai & Xu (2006): figures, summary.json, the report",
                           (d, L.docs / "reproduction.md"),
                           (Part("reproduce", B.command, (["-m", "bearing_gym.reproduction", "--out", str(d), "--report",
                                                           str(L.docs / "reproduction.md"), "--no-progress"],), 600.0),),
                           command="python -m bearing_gym.reproduction"))
    return out


def _has_examples(prof: Profile) -> bool:
    return prof.examples and DEFAULT_TIER in prof.tiers


def _examples(prof: Profile, L) -> list[Product]:
    """The worked examples' submissions, kept beside the board (which adds them when built)."""
    if not _has_examples(prof):
        return []
    board = L.docs / "results.json"
    cost = len(B.EXAMPLES) * (env_cost(prof.board_for(DEFAULT_TIER).episodes, prof.board.episode_steps, 2)
                              + prof.board.bootstrap_reps * BOOTSTRAP_REP_S * 2)
    return [Product("examples", f"the open board's worked examples scored on {DEFAULT_TIER} (submissions the board "
                    "adds: docs/benchmark.md)", B.example_files(board, DEFAULT_TIER),
                    (Part("examples", B.examples, (board, DEFAULT_TIER), cost),),
                    upstream=(f"references:{DEFAULT_TIER}", f"contextual:{DEFAULT_TIER}"),
                    sources=(B.CHECKOUT / "examples",),
                    command="python examples/<name>.py; the files kept in docs/submissions/")]


def docs_products(prof: Profile, layout: Layout) -> list[Product]:
    """The products under ``docs/`` of ``prof``, upstream first (after the references)."""
    return (_examples(prof, layout) + _board(prof, layout) + _chaos(prof, layout) + _tier_gap(prof, layout)
            + _figures(prof, layout))
