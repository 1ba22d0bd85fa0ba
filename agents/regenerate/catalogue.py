"""The stored data products, declared: per product the files it writes, what it is made from,
the parts it splits into, their cost and the command it stands for; in dependency order
(upstream first). :func:`products` gives them for a profile and a root; the docs' table
(``--list``) is printed from it.

Costs are estimates in core-seconds (:func:`agents.regenerate.product.env_cost`: from the env
steps a part runs) or from measured runs (the planner: each tier's mean episode time on one core;
the map and table commands: their documented times).
"""

from __future__ import annotations

import functools

from bearing_gym.task import EPISODE_STEPS

from agents import protocol as P
from agents.leaderboard import reference_parts
from agents.policies.contextual import contextual_path
from agents.policies.oracle import build_table
from agents.policies.planner import PlannerSettings
from agents.references import planner_runs
from agents.references.store import only_the_rule_differs, parts_dir, references_path, validation_problems
import agents.regenerate.builders as B
from agents.regenerate.docs_products import docs_products
from agents.regenerate.product import (PART_OVERHEAD_S, SETTLE_STEPS, STEP_CORE_S, Layout, Part, Product, env_cost,
                                       json_entry_digest)
from agents.regenerate.profiles import Profile

__all__ = ["products", "PLANNER_EPISODE_S"]

#: the planner per test episode of the benchmark's length, core-seconds: the averages of the runs
#: stored on kernel 6ff3acfe31277804 (benchmark v2; planner_<tier>/seed_*.json, wall_s; one of two
#: workers each); v1's kernel 04bca561d3fb1e1e took 114, 95, 67 and 52 s
PLANNER_EPISODE_S = {"transient": 58.1, "field": 70.9, "stationary": 30.9, "paper": 30.1}


def _grid_size(step_n: float) -> int:
    return len(P.preload_grid(step_n))


def _maps(prof: Profile, L: Layout) -> list[Product]:
    from bearing_gym.envs import reward_map as rm
    from agents.policies import stability_table as st
    g = prof.reward_map
    cells = 1
    for k, default in (("speeds_rpm", rm.GRID_SPEEDS_RPM), ("radial_loads_n", rm.GRID_RADIAL_LOADS_N),
                       ("clearances_m", rm.GRID_CLEARANCES_M), ("eccentricities_m", rm.GRID_ECCENTRICITIES_M)):
        cells *= len(g.get(k, default))
    points = cells * len(g.get("preloads_n", rm.GRID_PRELOADS_N))
    map_csv = L.docs / "reward_map.csv"
    s = prof.stability_table
    chains = len(s.get("speeds", st.SPEEDS_RPM)) * len(s.get("radial_loads", st.RADIAL_LOADS_N)) \
        * len(s.get("clearances", st.CLEARANCES_M))
    bank = prof.start_bank
    bank_out = L.env_data / f"start_bank_{bank['tier']}.npz"
    golden = L.root / "tests" / "data" / "paper_golden.npz"
    return [
        Product("reward_map", "the stationary reward of every constant preload over a grid of operating points "
                "(CSV and figure)", (map_csv, map_csv.with_suffix(".png")),
                (Part("map", B.reward_map, (map_csv, g),
                      PART_OVERHEAD_S + points * (g.get("measure_intervals", rm.MEASURE_INTERVALS) + SETTLE_STEPS)
                      * STEP_CORE_S),), settings={"grid": g},
                command="python -m bearing_gym.envs.reward_map --out docs/reward_map.csv"),
        Product("oracle_table", "the reward map's best preload per cell (the oracle's table)",
                (L.data / "oracle_table.csv",),
                (Part("table", build_table, (map_csv, L.data / "oracle_table.csv"), 1.0),),
                upstream=("reward_map",), kernel=False, command="python -m agents.policies.oracle"),
        Product("stability_table", "critical preload over speed x radial load x clearance (the scripted policies' "
                "table)", (L.data / "stability_table.npz",),
                (Part("table", B.stability_table, (L.data / "stability_table.npz", s),
                      PART_OVERHEAD_S + chains * len(s.get("preloads", st.PRELOADS_N)) * 0.9),),
                settings={"grid": s}, command="python -m agents.policies.stability_table"),
        Product("golden", "the paper preset under a fixed action sequence (the env's golden test)", (golden,),
                (Part("golden", B.command, (["tests/data/make_golden.py", "--out", str(golden)],), 20.0),),
                command="python tests/data/make_golden.py"),
        Product("start_bank", f"the settled starts of {bank['tier']} seeds {bank['first']}-{bank['stop'] - 1} "
                "(train.py's default)", (bank_out,),
                (Part("bank", B.start_bank, (bank_out, bank["tier"], bank["first"], bank["stop"]),
                      env_cost(bank["stop"] - bank["first"], 0)),), settings=bank,
                command=f"python -m bearing_gym.envs.start_bank --tier {bank['tier']} --seeds {bank['first']} "
                        f"{bank['stop']} --out bearing_gym/data/start_bank_{bank['tier']}.npz"),
    ]


def _references(prof: Profile, L: Layout, tier: str) -> list[Product]:
    """The validation constant, the contextual fit and the test references of ``tier`` (the
    hindsight sweep and the planner do not depend on the validation constant: a new validation
    rule re-runs its row alone)."""
    s = prof.board_for(tier)
    store = L.data / "reference_constants.json"
    v_episodes, c_episodes = prof.validation_for(tier), prof.contextual_for(tier)
    grid = _grid_size(s.hindsight_grid_step_n)
    planner = s.planner or PlannerSettings()
    sweep_parts = reference_parts.plan(s)
    seeds = list(P.held_out_seeds(s.episodes))
    steps = s.episode_steps
    ctx_out = contextual_path(tier, L.data)
    test = {"tier": tier, "episodes": s.episodes, "episode_steps": steps}
    return [
        Product(f"validation:{tier}", f"the validation-chosen constant of {tier} (its entry in the store)", (store,),
                (Part("choice", B.validation_constant, (tier, v_episodes, steps, s.hindsight_grid_step_n, store),
                      PART_OVERHEAD_S if only_the_rule_differs(tier, store, v_episodes, steps, s.hindsight_grid_step_n)
                      else env_cost(v_episodes, steps, grid), functools.partial(B.commit_validation, store)),),
                settings={"tier": tier, "episodes": v_episodes, "first_seed": P.VALIDATION.start,
                          "episode_steps": steps, "grid_step_n": s.hindsight_grid_step_n, "rule": P.VALIDATION_RULE},
                digest=functools.partial(json_entry_digest, store, "tiers", tier),
                verify=functools.partial(validation_problems, tier, store, v_episodes, steps, s.hindsight_grid_step_n),
                command=f"python -m agents.references --tier {tier} --episodes {v_episodes}"),
        Product(f"contextual:{tier}", f"the contextual constant's fit on {tier} training-range scenarios", (ctx_out,),
                (Part("fit", B.contextual_fit, (ctx_out, tier, c_episodes, steps, prof.contextual_grid_step_n),
                      env_cost(c_episodes, steps, _grid_size(prof.contextual_grid_step_n))),),
                settings={"tier": tier, "episodes": c_episodes, "first_seed": P.CONTEXTUAL_FIT_SEED,
                          "episode_steps": steps, "grid_step_n": prof.contextual_grid_step_n},
                command=f"python -m agents.references.contextual_fit --tier {tier} --episodes {c_episodes}"),
        Product(f"sweep:{tier}", f"the hindsight sweep of the {tier} test episodes, in parts",
                tuple(parts_dir(tier, L.data) / f"{k}_{first}_{n}.json" for k, first, n in sweep_parts),
                tuple(Part(f"{k}_{first}_{n}", reference_parts.compute_part, (tier, k, first, n, s, L.data),
                           env_cost(n, steps, grid)) for k, first, n in sweep_parts),
                settings={**test, "grid_step_n": s.hindsight_grid_step_n, "part_episodes": reference_parts.SWEEP_PART_EPISODES},
                command=f"python -m agents.leaderboard.reference_parts --tier {tier} --until HH:MM"),
        Product(f"validation_row:{tier}", f"the validation constant on every {tier} test episode (the board's 0)",
                (reference_parts.validation_row_path(tier, L.data),),
                (Part("row", reference_parts.compute_validation_row, (tier, s, store, L.data), env_cost(s.episodes, steps)),),
                upstream=(f"validation:{tier}",), settings=test,
                command=f"python -m agents.leaderboard.reference_parts --tier {tier} --validation-row"),
        Product(f"planner:{tier}", f"the planner on every {tier} test episode, one file per episode",
                tuple(planner_runs.episode_path(tier, seed, L.data) for seed in seeds),
                tuple(Part(f"seed_{seed}", B.planner_episode, (tier, seed, planner, steps, L.data),
                           PART_OVERHEAD_S + PLANNER_EPISODE_S.get(tier, 114.0) * steps / EPISODE_STEPS) for seed in seeds),
                upstream=(f"sweep:{tier}",), settings={**test, "planner": planner},
                verify=functools.partial(planner_runs.problems, tier, s.episodes, planner, steps, planner.grid_step_n,
                                         L.data),
                command=f"python -m agents.references.planner_runs --tier {tier} --until HH:MM"),
        Product(f"references:{tier}", f"the stored test references of {tier} (sweep and planner merged, every plan "
                "replayed)", (references_path(tier, L.data),),
                (Part("merge", reference_parts.merge, (tier, s, L.data, store, True, True), env_cost(s.episodes, steps, 2)),),
                upstream=(f"validation_row:{tier}", f"sweep:{tier}", f"planner:{tier}"), settings=test,
                command=f"python -m agents.leaderboard.reference_parts --tier {tier} --merge"),
    ]


#: measured on kernel 6ff3acfe31277804 (one core, the other busy), on transient: the causal MPC per
#: test episode (agents/data/causal_mpc_transient/seed_*.json, wall_s), the feedback rule's fit (50
#: validation episodes, 2 rounds) and a speed schedule's (50 training episodes, 2 rounds)
CAUSAL_MPC_EPISODE_S = 10.7
FEEDBACK_FIT_S = 1014.0
SCHEDULE_FIT_S = 1208.0


def _baselines(prof: Profile, L: Layout, tier: str) -> list[Product]:
    """The industry and model-based rows' data of ``tier`` (agents.leaderboard.baselines): the causal
    MPC's runs, the tuned feedback rule, the fitted speed schedules."""
    from agents.policies.causal_mpc import CausalMPCSettings
    from agents.references import causal_mpc_runs, feedback_fit, speed_schedule_fit
    s, b = prof.board_for(tier), prof.baselines
    steps, mpc = s.episode_steps, CausalMPCSettings()
    seeds = causal_mpc_runs.test_seeds(tier, s.episodes)
    scale = steps / EPISODE_STEPS
    fb_n = P.episodes_for_tier(tier, b["feedback_episodes"])
    sch_n = P.episodes_for_tier(tier, b["schedule_episodes"])
    fb_out = feedback_fit.feedback_path(tier, L.data)
    store = L.data / "reference_constants.json"

    def mpc_problems() -> list[str]:
        return [f"seed {seed}: missing, or run by another kernel or settings"
                for seed in causal_mpc_runs.missing(tier, s.episodes, mpc, steps, L.data)]
    out = [
        Product(f"causal_mpc:{tier}", f"the causal MPC on every {tier} test episode, one file per episode",
                tuple(causal_mpc_runs.episode_path(tier, seed, L.data) for seed in seeds),
                tuple(Part(f"seed_{seed}", B.causal_mpc_episode, (tier, seed, mpc, steps, L.data),
                           PART_OVERHEAD_S + CAUSAL_MPC_EPISODE_S * scale) for seed in seeds),
                settings={"tier": tier, "episodes": s.episodes, "episode_steps": steps, "mpc": mpc.as_dict()},
                verify=mpc_problems,
                command=f"python -m agents.references.causal_mpc_runs --tier {tier} --until HH:MM"),
        Product(f"feedback:{tier}", f"the feedback rule tuned on {tier} validation episodes", (fb_out,),
                (Part("fit", B.feedback_fit, (fb_out, tier, fb_n, b["feedback_rounds"], steps),
                      PART_OVERHEAD_S + FEEDBACK_FIT_S * fb_n / 50 * b["feedback_rounds"] / 2 * scale),),
                settings={"tier": tier, "episodes": fb_n, "rounds": b["feedback_rounds"], "episode_steps": steps,
                          "candidates": {k: list(v) for k, v in feedback_fit.CANDIDATES.items()},
                          "fixed": feedback_fit.fixed_settings()},
                verify=functools.partial(feedback_fit.fit_problems, tier, fb_out, fb_n, b["feedback_rounds"], steps),
                command=f"python -m agents.references.feedback_fit --tier {tier}")]
    for kind in b["kinds"]:
        path = speed_schedule_fit.schedule_path(tier, kind, L.data)
        out.append(Product(
            f"speed_schedule:{tier}:{kind}", f"the {kind} speed schedule fitted on {tier} training episodes", (path,),
            (Part("fit", B.speed_schedule_fit, (path, tier, kind, sch_n, b["schedule_rounds"], steps, store),
                  PART_OVERHEAD_S + SCHEDULE_FIT_S * sch_n / 50 * b["schedule_rounds"] / 2 * scale),),
            upstream=(f"validation:{tier}",),
            settings={"tier": tier, "kind": kind, "episodes": sch_n, "rounds": b["schedule_rounds"],
                      "episode_steps": steps, "first_seed": P.SCHEDULE_FIT_SEED,
                      "grid_step_n": P.CONTEXTUAL_GRID_STEP_N, "start_rule": P.V2_VALIDATION_RULE,
                      "candidates": speed_schedule_fit.candidates()},
            verify=functools.partial(speed_schedule_fit.fit_problems, tier, kind, path, sch_n, b["schedule_rounds"],
                                     steps, store),
            command=f"python -m agents.references.speed_schedule_fit --tier {tier} --kind {kind}"))
    return out


def products(prof: Profile, layout: Layout) -> list[Product]:
    """Every product of ``prof`` written under ``layout``, upstream first."""
    out = _maps(prof, layout)
    for tier in prof.tiers:
        out += _references(prof, layout, tier) + (_baselines(prof, layout, tier) if prof.baselines else [])
    out += docs_products(prof, layout)
    return out

