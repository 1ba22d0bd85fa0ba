"""The leaderboard's references computed on the seeds the protocol gives each: the
validation-chosen constant and the hindsight constant (:mod:`.validation`), the contextual fit
(:mod:`.contextual_fit`), the tier gap that shaped the tiers (:mod:`.tier_gap`), and the one store
they are kept in (:mod:`.store`). ``python -m agents.references`` rebuilds a tier's validation
constant."""
