"""The leaderboard's results file: where a run writes it, its header (protocol, statistics,
command), which tiers of an earlier file it keeps, and writing it with its markdown table.

docs/results.json is the protocol's leaderboard; :func:`default_out` keeps every other run
(smoke, shipped policies alone, fewer episodes) out of it.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from bearing_gym.task import TIER_NAMES

from agents import protocol as P
from agents.paths import docs_dir, runs_dir
from agents.leaderboard import scoring
from agents.leaderboard.tables import to_markdown


__all__ = ["protocol_summary", "header", "default_out", "kept_tiers", "table_path", "write"]



def protocol_summary(version: int | None = None) -> dict[str, Any]:
    """The frozen protocol (:mod:`agents.protocol`) of ``version`` (default: the board's,
    ``PROTOCOL_VERSION``) as results.json records it."""
    from agents.policies.planner import PlannerSettings
    version = P.PROTOCOL_VERSION if version is None else version
    if version not in P.PROTOCOL_VALIDATION_RULES:
        raise ValueError(f"unknown protocol version {version}: agents.protocol defines "
                         f"{', '.join(map(str, P.PROTOCOL_VALIDATION_RULES))}")
    common = {"version": version, "test_episodes": P.TEST_EPISODES,
              "upper_reference": {"planner": PlannerSettings().as_dict(), "episodes": "every test episode"},
              "validation_constant_episodes": P.VALIDATION_CONSTANT_EPISODES,
              "validation_rule": P.PROTOCOL_VALIDATION_RULES[version],
              "contextual_fit_episodes": P.CONTEXTUAL_FIT_EPISODES}
    if version == 1:
        return {**common, "headline_algorithm": P.HEADLINE_ALGORITHM,
                "training_seeds": {a: list(P.training_seeds(a)) for a in P.ALGORITHMS},
                "step_budget_per_run": P.STEP_BUDGET_PER_RUN,
                "step_budget_chosen_from_throughput": P.STEP_BUDGET_CHOSEN_FROM_THROUGHPUT,
                "denominator_floor": scoring.DENOMINATOR_FLOOR}
    if version == 2:
        return {**common, "algorithms": list(P.V2_ALGORITHMS),
                "training_seeds": {a: list(P.v2_training_seeds()) for a in P.V2_ALGORITHMS},
                "step_budget_per_run": P.V2_STEP_BUDGET_PER_RUN, "early_row_steps": P.V2_EARLY_ROW_STEPS,
                "validation_episodes_in_training": P.V2_VALIDATION_EPISODES_IN_TRAINING,
                "validation_every_steps": P.VALIDATION_EVERY_STEPS, "start_bank_starts": P.V2_START_BANK_STARTS,
                "hyperparameters": "agents/hyperparams/v2/<algo>.yml (agents/tuning/<algo>.json: every trial)",
                "tuning": {"trials": P.TUNING_TRIALS, "steps_per_trial": P.TUNING_STEPS,
                           "validation_episodes": P.TUNING_VALIDATION_EPISODES,
                           "prune_after_steps": P.TUNING_PRUNE_AFTER_STEPS,
                           "startup_trials": P.TUNING_STARTUP_TRIALS, "random_trials": P.TUNING_RANDOM_TRIALS,
                           "value": f"mean of the last {P.TUNING_LAST_VALIDATIONS} validation scores"},
                "planner_settings_sha256": P.V2_PLANNER_SETTINGS_SHA256,
                "causal_mpc_settings_sha256": P.V2_CAUSAL_MPC_SETTINGS_SHA256,
                "feedback_tune_episodes": P.V2_FEEDBACK_TUNE_EPISODES,
                "schedule_fit_episodes": P.SCHEDULE_FIT_EPISODES,
                "denominator_floor": scoring.DENOMINATOR_FLOOR}
    raise ValueError(f"protocol version {version} has no summary here: add it beside 1 and 2")


def header(mode: str, command: str, bootstrap_reps: int, poi_reps: int) -> dict[str, Any]:
    """A results.json with no tier yet (``"tiers": {}``): the benchmark, the mode (``"full"``, ``"smoke"``, ...), the
    command, the kernel that computed it, the protocol and the statistics (what :func:`kept_tiers` compares)."""
    from bearing_gym.envs.provenance import kernel_hash, package_version
    return {"benchmark": "BearingPreload-v0", "mode": mode, "kernel_hash": kernel_hash(),
            "package_version": package_version(),
            "command": command.strip(), "protocol": protocol_summary(),
            "statistics": {"bootstrap_reps": bootstrap_reps, "poi_reps": poi_reps,
                           "iqm": "rliable.metrics.aggregate_iqm",
                           "intervals": "rliable.library.get_interval_estimates, 95 %, percentile"},
            "tiers": {}}


def default_out(smoke: bool, models_given: bool, protocol_size: bool = True) -> Path:
    """docs/results.json is the protocol's leaderboard: only a run of ``--model`` runs at the
    protocol's size on every tier it runs (``Settings.protocol_sized``) writes it by default; a smoke run goes
    to runs/leaderboard_smoke/, a board of the shipped policies alone to
    runs/leaderboard_pretrained/, a reduced run to runs/leaderboard_reduced/ (under the current
    directory: :func:`agents.paths.runs_dir`); docs/results.json only in a source checkout."""
    if smoke:
        return runs_dir("leaderboard_smoke", "results.json")
    if not models_given:
        return runs_dir("leaderboard_pretrained", "results.json")
    if not protocol_size:
        return runs_dir("leaderboard_reduced", "results.json")
    return docs_dir() / "results.json"


def kept_tiers(previous: dict[str, Any], results: dict[str, Any], tiers: list[str]) -> dict[str, Any]:
    """``--keep-other-tiers``: the tiers of an earlier results.json that this run does not
    recompute, each with the command that made it. Refused (ValueError naming what differs) if
    the earlier file was made for another benchmark, by another kernel (its ``kernel_hash``) or under another
    protocol, mode or statistics. It does not check which
    policies a kept tier ran or whether it kept to the protocol: each kept tier carries its own
    command, ``model_dirs`` and ``protocol_deviations``, and the table prints its command."""
    for key in ("benchmark", "kernel_hash", "mode", "protocol", "statistics"):
        if json.loads(json.dumps(previous.get(key))) != json.loads(json.dumps(results[key])):
            raise ValueError(f"the earlier results.json differs in {key!r}: its tiers cannot stand beside this run's; "
                             "run every tier again (without --keep-other-tiers)")
    return {t: {**v, "command": v.get("command", previous.get("command"))}
            for t, v in previous["tiers"].items() if t not in tiers}


def table_path(out: Path) -> Path:
    """The markdown table beside ``out``: results_table.md beside a results.json."""
    return out.with_name("results_table.md") if out.name == "results.json" else out.with_suffix(".md")


def write(results: dict[str, Any], out: Path, kept: dict[str, Any] | None = None) -> str:
    """Merge the ``kept`` tiers into ``results`` (in the benchmark's tier order), write it to
    ``out`` and the markdown table beside it; return the table."""
    merged = {**(kept or {}), **results["tiers"]}
    results["tiers"] = {t: merged[t] for t in TIER_NAMES if t in merged}
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(results, indent=1) + "\n")
    text = to_markdown(results)
    table_path(out).write_text(text)
    return text
