"""The public scoring API: any policy on a tier's test episodes, scored as the board scores it.

    from agents.submit import score
    result = score(my_policy, tier="transient", name="my method")     # ~1 min on 2 cores
    print(result.markdown())
    result.save("my_method.json", algorithm="...", training_steps=..., training_seeds=[...],
                library="...", code="https://...")

:func:`score` runs the policy (one per training seed if given a list) on the tier's test episodes
through the native vector env, beside the contextual constant (the board's test of whether a
policy does more than pick one preload from the first observation), and scores the returns
against the stored references (``agents/data/test_references_<tier>.json``: the validation
constant is 0, the planner 1) with the board's own functions and statistics, so the row equals
the one the board computes for the same actions, bit for bit (``tests/agents/submit``). It needs
the env and the ``score`` extra (rliable), not torch.

``variant="constrained"`` scores the constrained variant instead (:mod:`agents.submit.constrained`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.envs.provenance import kernel_hash
from bearing_gym.task import COST_BUDGET_PER_EPISODE, DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from agents import protocol as P
from agents.extras import require_extra
from agents.evaluation.episodes import run_policies
from agents.evaluation.result import EvalResult
from agents.leaderboard.settings import FULL
from agents.leaderboard.tables import summarise
from agents.leaderboard.upper import PLANNER_ROW, planner_row, score_bounds
from agents.paths import DATA_DIR
from agents.policies.contextual import ContextualConstant, contextual_path
from agents.references.store import StoredReferences
from agents.submit.adapters import as_policies
from agents.submit.constrained import constrained_row
from agents.submit.rows import submitted_row, test_references

__all__ = ["score", "Scored", "VARIANTS"]

#: "standard": the benchmark's reward, normalised scores; "constrained": the reward without its
#: vibration term, the quasi-periodic intervals as a cost under COST_BUDGET_PER_EPISODE
VARIANTS = ("standard", "constrained")


@dataclass
class Scored:
    """What :func:`score` returns: the row, the runs it was computed from and what they were run
    against. :meth:`save` writes the submission file; :meth:`markdown` the row beside the
    references."""

    tier: str
    name: str
    variant: str
    row: dict[str, Any]
    results: list[EvalResult] = field(repr=False)
    contextual: EvalResult = field(repr=False)
    references: StoredReferences = field(repr=False)
    bootstrap_reps: int = FULL.bootstrap_reps
    poi_reps: int = FULL.poi_reps
    kernel_hash: str = field(default_factory=kernel_hash)
    protocol_version: int = P.PROTOCOL_VERSION

    @property
    def seeds(self) -> tuple[int, ...]:
        return self.references.seeds

    @property
    def protocol_sized(self) -> bool:
        """Whether it ran every test episode of the protocol on its tier (a board takes it)."""
        return len(self.seeds) == FULL.for_tier(self.tier).episodes

    def reference_rows(self) -> dict[str, dict[str, Any]]:
        """The validation constant, hindsight constant and planner rows of the same episodes."""
        if self.variant == "constrained":
            from agents.submit.constrained import reference_rows
            return reference_rows(self.references, bootstrap_reps=self.bootstrap_reps)
        r0, r1 = score_bounds(self.references)
        reps = dict(bootstrap_reps=self.bootstrap_reps, poi_reps=self.poi_reps)
        rows = {f"validation constant ({self.references.validation_preload_n:.0f} N)":
                summarise("reference", [self.references.validation_constant], r0, r1, **reps),
                f"hindsight constant ({self.references.hindsight_grid_step_n:g} N grid)":
                summarise("reference", [self.references.hindsight], r0, r1, **reps)}
        if self.references.planner is not None:
            rows[PLANNER_ROW] = planner_row(self.references, r0, r1, **reps)
        return rows

    def markdown(self) -> str:
        """The row beside the references on the same episodes (the board's table for one tier)."""
        from agents.submit.table import scored_markdown
        return scored_markdown(self)

    def submission(self, algorithm: str, training_steps: int | None = None, training_seeds: list[int] | None = None,
                   library: str = "", library_version: str = "", code: str = "", notes: str = "",
                   privileged: bool = False) -> dict[str, Any]:
        """The submission file's content (:mod:`agents.submit.submission`)."""
        from agents.submit.submission import make_submission
        return make_submission(self, algorithm=algorithm, training_steps=training_steps,
                               training_seeds=training_seeds, library=library, library_version=library_version,
                               code=code, notes=notes, privileged=privileged)

    def save(self, path: str | Path, algorithm: str, **meta: Any) -> Path:
        """Write the submission file (JSON) to ``path``; ``meta`` as for :meth:`submission`."""
        from agents.submit.submission import write_submission
        return write_submission(self.submission(algorithm, **meta), path)


def score(policy: Any, tier: str = DEFAULT_TIER, *, name: str = "submitted policy", batched: bool = True,
          episodes: int | None = None, variant: str = "standard", references_dir: str | Path = DATA_DIR,
          contextual_dir: str | Path = DATA_DIR, num_threads: int | None = None, progress: bool = True,
          bootstrap_reps: int = FULL.bootstrap_reps, poi_reps: int = FULL.poi_reps) -> Scored:
    """Score ``policy`` on ``tier``'s test episodes as the board does (module docstring).

    ``policy``: a callable (a batch of observations ``(n, 15)`` float32 -> ``n`` actions in
    [-1, 1]; with ``batched=False`` one observation -> one action), an object with SB3's
    ``predict``, an SB3 model, a train.py run directory, or a list of them, one per training seed
    (:func:`agents.submit.adapters.as_policy`). ``episodes``: the first test episodes only (default
    the protocol's: 100, one on ``paper``); fewer is for trying things out, and a board refuses it.
    ``variant``: ``"standard"`` or ``"constrained"``. ``num_threads``: numba threads for the env
    (default all). Progress lines unless ``progress=False``."""
    require_extra("scoring a policy", "score")
    if tier not in TIER_NAMES:
        raise ValueError(f"tier must be one of {', '.join(TIER_NAMES)}, got {tier!r}")
    if variant not in VARIANTS:
        raise ValueError(f"variant must be one of {', '.join(VARIANTS)}, got {variant!r}")
    protocol_episodes = FULL.for_tier(tier).episodes
    n = protocol_episodes if episodes is None else episodes
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= protocol_episodes:
        raise ValueError(f"episodes must be a whole number in [1, {protocol_episodes}] (tier {tier}'s test episodes), "
                         f"got {episodes!r}")
    refs = test_references(tier, int(n), Path(references_dir))
    policies = as_policies(policy, name, batched)
    contextual = ContextualConstant.load(contextual_path(tier, Path(contextual_dir)))
    env_kwargs: dict[str, Any] = {"tier": tier}
    if variant == "constrained":
        from bearing_gym.envs.reward import constrained_reward
        env_kwargs["reward"] = constrained_reward()
    label = f"scoring {name!r} on {tier}: {len(policies)} run(s) x {n} test episodes" if progress else None
    ran = run_policies([contextual] + policies, int(n), refs.seeds[0], EPISODE_STEPS, env_kwargs=env_kwargs,
                       num_threads=num_threads, progress=label)
    contextual_res, results = ran[0], ran[1:]
    meta = {"n_runs": len(results)}
    if n < protocol_episodes:
        meta["protocol_deviations"] = [f"{n} test episodes (the protocol: {protocol_episodes}): the protocol's board "
                                       "refuses it"]
    if variant == "constrained":
        row = constrained_row(results, COST_BUDGET_PER_EPISODE, bootstrap_reps, **meta)
    else:
        row = submitted_row(results, contextual_res.returns, refs, bootstrap_reps, poi_reps, **meta)
    return Scored(tier, name, variant, row, results, contextual_res, refs, bootstrap_reps, poi_reps)
