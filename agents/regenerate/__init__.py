"""One command that rebuilds every stored number: ``python -m agents.regenerate``.

The stored data products (the reward map and the tables made from it, the golden trajectory,
the start bank, each tier's validation constant, contextual fit, hindsight sweep, planner runs
and merged test references, the leaderboard, its breakdowns, the chaos replicas, the tier-gap
study, the figures, the integrator's accuracy and the reproduction) are declared in
:mod:`agents.regenerate.catalogue` and :mod:`agents.regenerate.docs_products` with what each is
made from; :mod:`agents.regenerate.manifest` records what they were built from
(``agents/data/regeneration.json``) and says which are stale and why;
:mod:`agents.regenerate.scheduler` builds what is not fresh, in dependency order, its parts over
worker processes or a Ray cluster, resumable part by part; :mod:`agents.regenerate.profiles`
sizes it (``full``, ``tiny``); :mod:`agents.regenerate.cli` is the command. docs/regeneration.md
tells how to use it.
"""

from agents.regenerate.cli import main, plan, regenerate
from agents.regenerate.profiles import FULL, PROFILES, TINY, Profile

__all__ = ["main", "plan", "regenerate", "FULL", "TINY", "PROFILES", "Profile"]
