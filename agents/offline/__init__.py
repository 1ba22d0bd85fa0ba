"""Offline datasets of the dear simulator's rollouts in Minari's format, rebuilt bit for bit from
their recipes (agents.offline.recipes), and the offline baselines trained on them
(agents.offline.d3rlpy_baselines; docs/offline.md).

    python -m agents.offline list                      # the datasets, their size, cost and checksum
    python -m agents.offline plan --until 18:00        # the expert's plans (the dear part), resumable
    python -m agents.offline build transient/expert    # record, join into Minari, check the checksum
"""
