"""The benchmark's definition in numbers: one control interval, one horizon and the tier names,
for the registration's time limit, training and evaluation alike. Imports nothing, so that
``import bearing_gym`` can register the env and scripts can build their options without
loading the env (the tiers' parts are in :mod:`bearing_gym.envs.tiers`)."""

#: The control interval (s): 6.7 shaft turns at 20,000 rpm, 3.3 at 10,000 rpm, enough Poincare
#: points for the quasi-periodicity index of one interval.
CONTROL_DT_S = 0.02

#: The horizon of every tier (control intervals): 3 s, enough for three events at least 0.5 s
#: apart and for the slow growth or decay (a few per second) of motion near a band edge.
EPISODE_STEPS = 150

#: The difficulty tiers, easiest first; the default is the main benchmark.
TIER_NAMES = ("paper", "stationary", "transient", "field")
DEFAULT_TIER = "transient"
