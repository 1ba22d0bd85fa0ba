"""The task's definition in numbers (BearingPreload-v0): one control interval, one horizon and
the tier names, for the registration's time limit, training and evaluation alike. Imports nothing, so that
``import bearing_gym`` can register the env and scripts can build their options without
loading the env (the tiers' parts are in :mod:`bearing_gym.envs.tiers`)."""

#: The control interval (s): 6.7 shaft turns at 20,000 rpm, 3.3 at 10,000 rpm, enough Poincare
#: points for the quasi-periodicity index of one interval.
CONTROL_DT_S = 0.02

#: The horizon of every tier (control intervals): 3 s, enough for three events at least 0.5 s
#: apart and for the slow growth or decay (a few per second) of motion near a band edge.
EPISODE_STEPS = 150

#: The constrained variant's cost budget (docs/benchmark.md): at most this many quasi-periodic
#: control intervals per episode (the sum of ``info["cost"]``; 10 % of the horizon, 0.3 s), while
#: the reward without its vibration term (heat, fatigue, actuation) is maximised. Declared with
#: the variant, before any policy was scored on it.
COST_BUDGET_PER_EPISODE = 15.0

#: The difficulty tiers, easiest first; the default is the main benchmark.
TIER_NAMES = ("paper", "stationary", "transient", "field")
DEFAULT_TIER = "transient"

#: The env's integrator step (s) and Newmark equilibrium tolerance (m). The analysis tools keep
#: the library default (10 us, 1e-13 m): they resolve band edges and finite-difference Floquet
#: multipliers. At 25 us and 1e-10 m the Newmark iteration needs one bearing-force evaluation
#: per step instead of two, 3.3x less kernel time per simulated second, and the env's physics
#: stays within the accuracy bounds checked against dt/4 by ``benchmarks/bench_accuracy.py``
#: (critical preload, steady amplitudes, reward-map classification; docs/performance.md).
ENV_DT_S = 25e-6
ENV_NEWMARK_TOL_M = 1e-10
