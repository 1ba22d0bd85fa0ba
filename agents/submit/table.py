"""A scored policy's row beside the references of the same episodes, as markdown."""

from __future__ import annotations

from typing import Any

__all__ = ["scored_markdown"]


def _poi(p: Any) -> str:
    return "-" if p is None else f"{p[0]:.2f} [{p[1]:.2f}, {p[2]:.2f}]"


def _standard(name: str, r: dict[str, Any]) -> str:
    poi = [r["probability_of_improvement"], r["poi_ci_low"], r["poi_ci_high"]]
    return (f"| {name} | {r['n_seeds']} | {r['n_episodes']} | {r['normalised_score_iqm']:.3f} "
            f"[{r['ci_low']:.3f}, {r['ci_high']:.3f}] | {100 * r['above_one_fraction']:.0f} % | {_poi(poi)} "
            f"| {_poi(r.get('poi_over', {}).get('contextual constant'))} | {r['mean_return']:.2f} "
            f"| {100 * r['quasi_periodic_fraction']:.1f} % | {r['heat_cost']:.2f} | {r['fatigue_cost']:.2f} "
            f"| {r['terminated_episodes']} |")


def _constrained(name: str, r: dict[str, Any]) -> str:
    left = r.get("terminated_episodes_left_out")
    return (f"| {name} | {r['n_seeds']} | {r['n_episodes']}{f' ({left} terminated left out)' if left else ''} "
            f"| {r['constrained_return_mean']:.2f} [{r['return_ci_low']:.2f}, {r['return_ci_high']:.2f}] "
            f"| {r['cost_mean']:.1f} [{r['cost_ci_low']:.1f}, {r['cost_ci_high']:.1f}] "
            f"| {100 * r['within_budget_fraction']:.0f} % |")


def scored_markdown(scored: Any) -> str:
    """The table of :meth:`agents.submit.api.Scored.markdown`."""
    refs = scored.reference_rows()
    seeds = scored.seeds
    head = [f"## {scored.name} on `{scored.tier}` ({scored.variant})", "",
            f"{len(seeds)} test episodes (seeds {seeds[0]}..{seeds[-1]}), kernel {scored.kernel_hash}, protocol "
            f"version {scored.protocol_version}."]
    for d in scored.row.get("protocol_deviations", []):
        head.append(f"**Not the protocol:** {d}.")
    if scored.variant == "constrained":
        budget = scored.row["cost_budget"]
        head += ["", f"Constrained variant: the return without the vibration term (heat, fatigue, actuation), the "
                 f"cost = quasi-periodic intervals per episode, budget {budget:g}; means with 95 % stratified-"
                 "bootstrap intervals.", "",
                 "| policy | seeds | episodes | constrained return [95 % CI] | cost [95 % CI] | within budget |",
                 "|---|---|---|---|---|---|"]
        lines = [_constrained(n, r) for n, r in refs.items()] + [_constrained(scored.name, scored.row)]
    else:
        head += ["", "Normalised score: 0 = the validation constant, 1 = the planner (as on the board); IQM with 95 % "
                 "stratified-bootstrap intervals.", "",
                 "| policy | seeds | episodes | normalised score IQM [95 % CI] | > 1 | P(> constant) "
                 "| P(> contextual) | mean return | time quasi-periodic | heat cost | fatigue cost | terminated |",
                 "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        lines = [_standard(n, r) for n, r in refs.items()] + [_standard(scored.name, scored.row)]
    return "\n".join(head + lines) + "\n"
