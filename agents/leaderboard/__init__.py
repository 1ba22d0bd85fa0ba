"""The leaderboard: its settings (:mod:`.settings`), the board run (:mod:`.board`), scoring and
statistics (:mod:`.scoring`), tables (:mod:`.tables`), the results file (:mod:`.results_file`),
per-episode breakdowns (:mod:`.breakdown`), learning curves (:mod:`.learning_curves`), chaos
replicas (:mod:`.chaos`), the test references computed in parts (:mod:`.reference_parts`) and the
side-by-side comparison of given models with baselines and references (:mod:`.compare`).
``python -m agents.leaderboard`` runs the board."""
