"""Alias kept for one version: ``python -m agents.evaluate`` is :mod:`agents.leaderboard.compare`
(running policies is :mod:`agents.evaluation`)."""

from agents.leaderboard.compare import main

if __name__ == "__main__":
    main()
