"""The evaluation protocol, written down before any evaluation on it: seed ranges, episode
counts, the reference grids, training seeds and the step budget.

Every env seed a script uses comes from one of these disjoint ranges (``check_disjoint`` and
``tests/agents/test_protocol.py`` hold them apart):

* ``TRAIN``: training envs (``train.py --seed s`` seeds env i with s + i; their later episodes
  draw from the envs' own generators) and the scenarios the contextual baseline is fitted on
  (``CONTEXTUAL_FIT_SEED``, a block of its own inside TRAIN);
* ``VALIDATION``: checkpoint selection and every choice made while developing (hyperparameters,
  the best constant preload of :mod:`agents.references.validation`);
* ``TIER_DESIGN``: measurements that shaped the benchmark itself (``agents.references.tier_gap``: does a
  tier need closed-loop control?);
* ``TEST``: the held-out evaluation of the leaderboard; fresh, never used while developing.
  (The earlier test range, 100000+, was looked at during development and is retired:
  ``RETIRED``.)

The leaderboard (:mod:`agents.leaderboard`) runs ``TEST_EPISODES`` test scenarios per tier
(seeds ``TEST.start`` on; one on a deterministic tier, where every seed gives the same episode:
:func:`episodes_for_tier`), the upper reference (the planner) on every one of them, every
learned algorithm with the training seeds of :func:`training_seeds` and the step budget
``STEP_BUDGET_PER_RUN``. ``check_protocol`` (run at import) checks that these numbers fit the
ranges and the minimums of the protocol.
"""

from __future__ import annotations

import math
from typing import Any


__all__ = ["PROTOCOL_VERSION", "TRAIN", "VALIDATION", "TIER_DESIGN", "TEST", "RETIRED", "RANGES", "check_disjoint",
           "range_of", "TEST_EPISODES", "VALIDATION_CONSTANT_EPISODES",
           "CONTEXTUAL_FIT_EPISODES", "CONTEXTUAL_FIT_SEED", "HINDSIGHT_GRID_STEP_N",
           "VALIDATION_GRID_STEP_N", "CONTEXTUAL_GRID_STEP_N", "ALGORITHMS", "HEADLINE_ALGORITHM",
           "HEADLINE_SEEDS", "OTHER_SEEDS", "RUN_SEED_STRIDE", "STEP_BUDGET_PER_RUN",
           "STEP_BUDGET_CHOSEN_FROM_THROUGHPUT", "VALIDATION_EPISODES_IN_TRAINING", "VALIDATION_EVERY_STEPS",
           "SCHEDULE_FIT_EPISODES", "SCHEDULE_FIT_SEED", "SCHEDULE_FIT_ROUNDS", "TUNING_TRIALS", "TUNING_STEPS", "TUNING_VALIDATION_EPISODES", "TUNING_STARTUP_TRIALS",
           "TUNING_PRUNE_AFTER_STEPS", "TUNING_LAST_VALIDATIONS", "TUNING_SAMPLER_SEED", "TUNING_RANDOM_TRIALS", "TUNING_TRAIN_SEED", "VALIDATION_RULES", "PROTOCOL_VALIDATION_RULES", "VALIDATION_RULE", "TUNING_VALIDATION_RULE", "TUNING_PROTOCOL_VERSION",
           "V2_ALGORITHMS", "V2_SEEDS", "V2_STEP_BUDGET_PER_RUN", "V2_EARLY_ROW_STEPS", "V2_VALIDATION_EPISODES_IN_TRAINING",
           "V2_START_BANK_STARTS", "V2_VALIDATION_RULE", "V2_PLANNER_SETTINGS_SHA256", "V2_CAUSAL_MPC_SETTINGS_SHA256",
           "V2_FEEDBACK_TUNE_EPISODES", "V2_FEEDBACK_TUNE_ROUNDS", "v2_training_seeds",
           "OFFLINE_DATASET_SEED", "OFFLINE_DATASET_SEEDS",
           "training_seeds", "held_out_seeds", "validation_seeds", "episodes_for_tier",
           "preload_grid", "check_protocol"]

#: The protocol's version: a submission (:mod:`agents.submit`) made under another is refused by the
#: board. 1: 100k env steps, hand-set hyperparameters (archived in docs/archive/protocol1/).
#: 2: the V2_ numbers below (300k env steps, tuned hyperparameters, five algorithms x five seeds).
PROTOCOL_VERSION = 2

TRAIN = range(0, 50_000)
VALIDATION = range(50_000, 60_000)
RETIRED = range(100_000, 110_000)
TIER_DESIGN = range(200_000, 210_000)
TEST = range(300_000, 310_000)

RANGES = {"train": TRAIN, "validation": VALIDATION, "retired": RETIRED, "tier_design": TIER_DESIGN,
          "test": TEST}

# -- episode counts ------------------------------------------------------------------------------
#: Test episodes per tier (seeds TEST.start .. TEST.start + TEST_EPISODES - 1), every policy and
#: reference on the same scenarios.
TEST_EPISODES = 100
#: Validation episodes on which the best constant preload is chosen (seeds VALIDATION.start on).
VALIDATION_CONSTANT_EPISODES = 50
#: Training-range scenarios the contextual baseline is fitted on (seeds CONTEXTUAL_FIT_SEED on).
CONTEXTUAL_FIT_EPISODES = 100
#: First seed of the contextual fit: inside TRAIN, above every training run's seed block.
CONTEXTUAL_FIT_SEED = TRAIN.start + 40_000

# -- the constant-preload grids over the actuator's whole range ----------------------------------
#: The hindsight best constant per episode searches this grid (N).
HINDSIGHT_GRID_STEP_N = 50.0
#: The validation-chosen constant is chosen on the same grid (so it is one of the hindsight's
#: candidates and the hindsight constant never scores below it).
VALIDATION_GRID_STEP_N = HINDSIGHT_GRID_STEP_N
#: How the validation-chosen constant (the board's "0") is chosen from the grid's mean returns on the
#: VALIDATION_CONSTANT_EPISODES validation episodes. "best_mean" (protocol 1): the highest mean; on
#: a plateau (v1: 1500/1600/1850 N within 1 reward unit) it flips with the last bits. "one_se_largest"
#: (protocol 2, stated before it was computed, the protocol issue's own example; Breiman's
#: one-standard-error rule): the largest preload whose mean return is within one standard error
#: (of the best candidate's mean over the episodes, ddof 1) of the best mean; larger preload is the
#: conservative side of every quasi-periodic window of the map. Tuning (run before the v2 bump)
#: normalises with protocol 2's rule already: TUNING_VALIDATION_RULE.
VALIDATION_RULES = ("best_mean", "one_se_largest")
#: each protocol version's rule; the board's is its version's
PROTOCOL_VALIDATION_RULES = {1: "best_mean", 2: "one_se_largest"}
VALIDATION_RULE = PROTOCOL_VALIDATION_RULES[PROTOCOL_VERSION]
TUNING_VALIDATION_RULE = "one_se_largest"
#: The protocol version the hyperparameter search serves (its optuna studies and ymls are v2's).
TUNING_PROTOCOL_VERSION = 2
#: The contextual baseline predicts the return of each constant of this coarser grid (N).
CONTEXTUAL_GRID_STEP_N = 100.0

# -- training runs --------------------------------------------------------------------------------
#: The learned baselines (the names of train.py's --algo; ppo_lstm is sb3-contrib's RecurrentPPO,
#: RL Zoo's name for it).
ALGORITHMS = ("ppo", "sac", "ppo_lstm")
#: The headline algorithm, fixed before any run: SAC, the algorithm of the earlier claim that
#: the leaderboard re-examines.
HEADLINE_ALGORITHM = "sac"
HEADLINE_SEEDS = 5
OTHER_SEEDS = 3
#: train.py's validation during a protocol run (checkpoint selection and the learning curves):
#: this many episodes, one per eval env, on the first validation seeds (a subset of the
#: VALIDATION_CONSTANT_EPISODES whose references the store holds), every this many env steps.
VALIDATION_EPISODES_IN_TRAINING = 20
VALIDATION_EVERY_STEPS = 10_000
#: Run k of an algorithm trains with seed TRAIN.start + k * RUN_SEED_STRIDE; train.py seeds its env
#: i with seed + i, so runs with up to RUN_SEED_STRIDE envs keep their seed blocks apart.
RUN_SEED_STRIDE = 1_000

#: Environment steps per training run, equal for every algorithm and seed, chosen from the
#: measured throughput before any run (benchmarks/bench_training.py on the idle 2-core machine,
#: commit e3fb64b: PPO 102, SAC 92 env steps/s; RecurrentPPO is slower): 100,000 steps are
#: ~16 min of PPO and ~18 min of SAC training plus ten validations, so the protocol's 11 runs
#: (5 SAC, 3 PPO, 3 RecurrentPPO) take ~4 h of the 2-core machine, each run fits one working
#: session (the unit of work that survives), and the README's main job (one PPO run at this
#: budget) trains for about a quarter of an hour. It is half the 200k steps of the earlier SAC
#: claim: the leaderboard reports what this budget buys, not what a longer run might.
STEP_BUDGET_PER_RUN = 100_000
STEP_BUDGET_CHOSEN_FROM_THROUGHPUT = True


# -- the speed schedules (agents.references.speed_schedule_fit), fitted on training seeds -----------
#: The spindle makers' practice as baselines: 2- and 3-level speed switches and a speed table,
#: each fitted by coordinate ascent (SCHEDULE_FIT_ROUNDS rounds over its thresholds and levels, the
#: CONTEXTUAL_GRID_STEP_N preload grid) of the mean return on the contextual fit's training
#: scenarios (the same data the contextual constant is fitted on).
SCHEDULE_FIT_EPISODES = 50
SCHEDULE_FIT_SEED = CONTEXTUAL_FIT_SEED
SCHEDULE_FIT_ROUNDS = 2

# -- protocol v2's hyperparameter search (agents.training.tuning), fixed before any trial ----------
#: Per algorithm (agents.training.search_spaces.ALGORITHMS) the same budget: TUNING_TRIALS trials of
#: at most TUNING_STEPS env steps on the benchmark's tier, validated every VALIDATION_EVERY_STEPS
#: on TUNING_VALIDATION_EPISODES validation episodes (seeds VALIDATION.start on, whose references
#: the store holds: the test seeds tune nothing); optuna's median pruner stops a trial whose score
#: falls below the median of the earlier trials at the same step, once TUNING_STARTUP_TRIALS trials
#: have completed and after TUNING_PRUNE_AFTER_STEPS steps (never at a trial's last validation);
#: TPE sampler (multivariate) seeded TUNING_SAMPLER_SEED + the trials so far, its first
#: TUNING_RANDOM_TRIALS draws at random. A trial's score: the IQM of its normalised validation scores (0 the validation
#: constant, 1 the hindsight constant, the board's floor); its objective the mean of its last
#: TUNING_LAST_VALIDATIONS scores. Trial k trains with seed TUNING_TRAIN_SEED + k * RUN_SEED_STRIDE
#: (inside TRAIN, apart from the protocol's runs and the contextual fit). 16 x 60k = 0.96 M env
#: steps per algorithm at most, ~2 h of the 2-core machine at ~130 env steps/s.
TUNING_TRIALS = 16
TUNING_STEPS = 60_000
TUNING_VALIDATION_EPISODES = 20
TUNING_STARTUP_TRIALS = 5
TUNING_PRUNE_AFTER_STEPS = 20_000
TUNING_LAST_VALIDATIONS = 3
TUNING_SAMPLER_SEED = 0
#: TPE draws this many trials at random before it models the results
TUNING_RANDOM_TRIALS = 5
TUNING_TRAIN_SEED = TRAIN.start + 20_000


# -- protocol v2 (issue 44): every number of its runs, fixed in a commit before the first one -------
#: The board is built from these runs since PROTOCOL_VERSION became 2 (protocol 1 is archived).
#: The learned baselines, each tuned by agents.training.tuning (its chosen yml in
#: agents/hyperparams/v2/<algo>.yml; train.py --protocol 2 reads it), V2_SEEDS training seeds each
#: (TRAIN.start + k * RUN_SEED_STRIDE, k < V2_SEEDS: the same first seeds as protocol 1).
V2_ALGORITHMS = ("sac", "tqc", "crossq", "ppo", "ppo_lstm")
V2_SEEDS = 5
#: Env steps per run, equal for every algorithm and seed: the issue's 300k (the tuning's 60k-step
#: trials cannot show a need beyond their own length; SAC's protocol-1 curves still rose at 100k).
V2_STEP_BUDGET_PER_RUN = 300_000
#: Each run's test rows at this point too (sample efficiency; protocol 1's budget): the checkpoint
#: validation selects among those up to it, besides the one it selects over the whole run.
V2_EARLY_ROW_STEPS = 100_000
#: Checkpoint selection (best mean validation return) on this many validation episodes (seeds
#: VALIDATION.start on, one per eval env), every VALIDATION_EVERY_STEPS env steps.
V2_VALIDATION_EPISODES_IN_TRAINING = 50
#: The training start bank: settled starts of training seeds 0 .. V2_START_BANK_STARTS - 1, drawn
#: each once before any repeats (train.py), at least the episodes of a run (V2_STEP_BUDGET_PER_RUN
#: / EPISODE_STEPS = 2000): no run meets a start twice.
V2_START_BANK_STARTS = 2048
#: The board's "0": the validation constant by this rule (VALIDATION_RULES).
V2_VALIDATION_RULE = PROTOCOL_VALIDATION_RULES[2]
#: The references frozen with the protocol: the sha256 (first 16 hex digits) of the settings'
#: JSON (sort_keys) - the planner's (agents.policies.planner.PlannerSettings().as_dict(), the
#: settings of the stored v2 plans) and the causal MPC's (CausalMPCSettings().digest());
#: tests/agents/test_protocol.py checks the code's defaults against them. A further widening of
#: the planner is developed on tier-design seeds and is a new protocol version.
V2_PLANNER_SETTINGS_SHA256 = "465614cd1d790a53"
V2_CAUSAL_MPC_SETTINGS_SHA256 = "4ecfeda8a1ee8eb6"
#: The feedback rule's tuning (agents.references.feedback_fit): coordinate ascent of its mean
#: return on the first V2_FEEDBACK_TUNE_EPISODES validation episodes, V2_FEEDBACK_TUNE_ROUNDS rounds.
V2_FEEDBACK_TUNE_EPISODES = 50
V2_FEEDBACK_TUNE_ROUNDS = 2


def check_disjoint(ranges: dict[str, range] = RANGES) -> None:
    """Raise ValueError naming the first two ranges that overlap."""
    items = sorted(ranges.items(), key=lambda kv: kv[1].start)
    for (name_a, a), (name_b, b) in zip(items, items[1:]):
        if a.stop > b.start:
            raise ValueError(f"seed ranges {name_a} [{a.start}, {a.stop}) and {name_b} "
                             f"[{b.start}, {b.stop}) overlap")


def range_of(seed: int) -> str | None:
    """The name of the range that holds ``seed`` (None if none does)."""
    for name, r in RANGES.items():
        if seed in r:
            return name
    return None


def training_seeds(algo: str) -> tuple[int, ...]:
    """The seeds of ``algo``'s training runs: HEADLINE_SEEDS for the headline algorithm,
    OTHER_SEEDS for the others, every one in TRAIN (the same first seeds for every algorithm)."""
    if algo not in ALGORITHMS:
        raise ValueError(f"unknown algorithm {algo!r}: the protocol's are {', '.join(ALGORITHMS)}")
    n = HEADLINE_SEEDS if algo == HEADLINE_ALGORITHM else OTHER_SEEDS
    return tuple(TRAIN.start + k * RUN_SEED_STRIDE for k in range(n))


def _block(first: int, episodes: int, within: range, name: str) -> range:
    if episodes < 1:
        raise ValueError(f"episodes must be >= 1, got {episodes}")
    block = range(first, first + episodes)
    if block.start not in within or block[-1] not in within:
        raise ValueError(f"{name} seeds {block.start}..{block[-1]} leave the {name} range "
                         f"[{within.start}, {within.stop}): use fewer episodes or another first seed")
    return block


def held_out_seeds(episodes: int = TEST_EPISODES) -> range:
    """The leaderboard's test seeds."""
    return _block(TEST.start, episodes, TEST, "test")


def validation_seeds(episodes: int = VALIDATION_CONSTANT_EPISODES, first: int = VALIDATION.start) -> range:
    """Validation seeds from ``first`` on (raises if they leave VALIDATION)."""
    return _block(first, episodes, VALIDATION, "validation")


#: The offline datasets (agents.offline): their episodes are the training scenarios
#: OFFLINE_DATASET_SEED .. + OFFLINE_DATASET_SEEDS - 1 (every dataset on the same scenarios, from
#: the first), a block of TRAIN of their own, after the contextual fit's.
OFFLINE_DATASET_SEED = TRAIN.start + 45_000
OFFLINE_DATASET_SEEDS = 1_000


def preload_grid(step_n: float, min_n: float | None = None, max_n: float | None = None) -> tuple[float, ...]:
    """Constant preloads from the actuator's minimum to its maximum (both included) every
    ``step_n`` newtons; the maximum is appended if ``step_n`` does not divide the range.
    ``min_n``/``max_n`` default to the default actuator's range (300-2000 N)."""
    if min_n is None or max_n is None:
        from bearing_gym.envs.actuator import PreloadActuator
        act = PreloadActuator()
        min_n = act.min_preload_n if min_n is None else min_n
        max_n = act.max_preload_n if max_n is None else max_n
    if not (step_n > 0 and math.isfinite(step_n)):
        raise ValueError(f"step_n must be a positive number of newtons, got {step_n}")
    if not max_n > min_n:
        raise ValueError(f"max_n ({max_n}) must exceed min_n ({min_n})")
    n = int(math.floor((max_n - min_n) / step_n + 1e-9))
    grid = [float(min_n + k * step_n) for k in range(n + 1)]
    if max_n - grid[-1] > 1e-6:
        grid.append(float(max_n))
    return tuple(grid)


def episodes_for_tier(tier: str, episodes: int, minimum: int = 1) -> int:
    """How many of the protocol's ``episodes`` a run on ``tier`` takes: all of them, or on a
    deterministic tier (every seed gives the same episode,
    :func:`bearing_gym.envs.tiers.tier_is_deterministic`: ``paper``) ``min(episodes, minimum)``
    (at least 1 unless ``episodes`` is 0) - the others would be copies. ``minimum`` is what the
    consumer needs (the contextual fit's ridge needs 3 rows)."""
    from bearing_gym.envs.tiers import tier_is_deterministic
    return min(episodes, max(1, minimum)) if tier_is_deterministic(tier) else episodes


def v2_training_seeds() -> tuple[int, ...]:
    """Protocol v2's training seeds (the same for every algorithm)."""
    return tuple(TRAIN.start + k * RUN_SEED_STRIDE for k in range(V2_SEEDS))


def check_protocol(**overrides: Any) -> None:
    """Raise ValueError naming the first broken rule of the protocol: disjoint ranges, at least
    100 test episodes per tier, at least 5 training seeds for the
    headline algorithm and 3 for the others, training seeds and the contextual fit in TRAIN and
    apart. ``overrides`` replace module constants by name (for tests)."""
    g = {**globals(), **overrides}
    check_disjoint(g["RANGES"])
    if g["TEST_EPISODES"] < 100:
        raise ValueError(f"TEST_EPISODES must be >= 100 (the issue's minimum), got {g['TEST_EPISODES']}")
    if g["HEADLINE_SEEDS"] < 5 or g["OTHER_SEEDS"] < 3:
        raise ValueError("the headline algorithm needs >= 5 training seeds and the others >= 3, got "
                         f"{g['HEADLINE_SEEDS']} and {g['OTHER_SEEDS']}")
    if g["HEADLINE_ALGORITHM"] not in g["ALGORITHMS"]:
        raise ValueError(f"HEADLINE_ALGORITHM {g['HEADLINE_ALGORITHM']!r} is not in ALGORITHMS")
    train = g["TRAIN"]
    runs = max(g["HEADLINE_SEEDS"], g["OTHER_SEEDS"])
    last_run_block_end = train.start + runs * g["RUN_SEED_STRIDE"]
    fit = range(g["CONTEXTUAL_FIT_SEED"], g["CONTEXTUAL_FIT_SEED"] + g["CONTEXTUAL_FIT_EPISODES"])
    if last_run_block_end > train.stop or fit.start < train.start or fit.stop > train.stop:
        raise ValueError("training seed blocks and the contextual fit must lie inside TRAIN")
    if fit.start < last_run_block_end:
        raise ValueError(f"the contextual fit seeds {fit.start}.. overlap the training runs' seed blocks "
                         f"(up to {last_run_block_end}): raise CONTEXTUAL_FIT_SEED")
    tuning = range(g["TUNING_TRAIN_SEED"], g["TUNING_TRAIN_SEED"] + g["TUNING_TRIALS"] * g["RUN_SEED_STRIDE"])
    if tuning.start < last_run_block_end or tuning.stop > fit.start:
        raise ValueError(f"the tuning trials' seed blocks {tuning.start}..{tuning.stop - 1} must lie between the "
                         "training runs' blocks and the contextual fit")
    if not 1 <= g["TUNING_VALIDATION_EPISODES"] <= g["VALIDATION_CONSTANT_EPISODES"]:
        raise ValueError("TUNING_VALIDATION_EPISODES must be in [1, VALIDATION_CONSTANT_EPISODES] (stored references)")
    if not 1 <= g["TUNING_LAST_VALIDATIONS"] <= g["TUNING_STEPS"] // g["VALIDATION_EVERY_STEPS"]:
        raise ValueError("TUNING_LAST_VALIDATIONS must be at least 1 and at most the validations of a trial")
    if not 1 <= g["VALIDATION_EPISODES_IN_TRAINING"] <= g["VALIDATION_CONSTANT_EPISODES"]:
        raise ValueError("VALIDATION_EPISODES_IN_TRAINING must be in [1, VALIDATION_CONSTANT_EPISODES]: the learning "
                         "curves score them against the stored validation references")
    from bearing_gym.task import EPISODE_STEPS
    if g["V2_START_BANK_STARTS"] * EPISODE_STEPS < g["V2_STEP_BUDGET_PER_RUN"]:
        raise ValueError("V2_START_BANK_STARTS must cover a run's episodes (V2_STEP_BUDGET_PER_RUN / the episode "
                         "length): a run would meet a start twice")
    if not g["V2_EARLY_ROW_STEPS"] <= g["V2_STEP_BUDGET_PER_RUN"] or g["V2_EARLY_ROW_STEPS"] % g["VALIDATION_EVERY_STEPS"]:
        raise ValueError("V2_EARLY_ROW_STEPS must be a validation point within the budget")
    if not 1 <= g["V2_VALIDATION_EPISODES_IN_TRAINING"] <= g["VALIDATION_CONSTANT_EPISODES"]:
        raise ValueError("V2_VALIDATION_EPISODES_IN_TRAINING must be in [1, VALIDATION_CONSTANT_EPISODES]")
    if not 1 <= g["V2_FEEDBACK_TUNE_EPISODES"] <= len(g["VALIDATION"]):
        raise ValueError("V2_FEEDBACK_TUNE_EPISODES must fit the validation range")
    if g["V2_VALIDATION_RULE"] not in g["VALIDATION_RULES"]:
        raise ValueError(f"V2_VALIDATION_RULE must be one of {g['VALIDATION_RULES']}")
    if g["TRAIN"].start + g["V2_SEEDS"] * g["RUN_SEED_STRIDE"] > g["TUNING_TRAIN_SEED"]:
        raise ValueError("protocol v2's run seed blocks must end below the tuning trials' blocks")
    offline = range(g["OFFLINE_DATASET_SEED"], g["OFFLINE_DATASET_SEED"] + g["OFFLINE_DATASET_SEEDS"])
    if offline.start < fit.stop or offline.start < tuning.stop or offline.stop > train.stop:
        raise ValueError(f"the offline datasets' seeds {offline.start}..{offline.stop - 1} must lie in TRAIN after the "
                         "training runs', the tuning trials' and the contextual fit's blocks")
    for name in ("TEST_EPISODES", "VALIDATION_CONSTANT_EPISODES"):
        rng = g["TEST"] if name == "TEST_EPISODES" else g["VALIDATION"]
        if g[name] > len(rng):
            raise ValueError(f"{name} ({g[name]}) exceeds its seed range ({len(rng)} seeds)")


check_protocol()
