"""The protocol's seed ranges are disjoint, and every script draws from the range it claims."""

import numpy as np
import pytest

from agents import protocol


def test_ranges_are_disjoint_and_the_check_catches_an_overlap():
    protocol.check_disjoint()
    with pytest.raises(ValueError, match="a .* and b .* overlap"):
        protocol.check_disjoint({"a": range(0, 10), "b": range(5, 20)})


def test_tier_design_measurement_uses_its_own_range():
    from agents.references import tier_gap
    seed = tier_gap.build_parser().get_default("seed")
    assert protocol.range_of(seed) == "tier_design"
    assert protocol.range_of(seed + 19) == "tier_design"


def test_train_and_evaluate_draw_from_their_ranges():
    import train
    from agents.evaluation.episodes import TEST_SEED
    assert protocol.range_of(TEST_SEED) == "test"
    assert protocol.range_of(train.build_parser().get_default("val_seed")) == "validation"
    assert protocol.range_of(train.build_parser().get_default("seed")) == "train"


def test_training_and_evaluation_use_the_registered_definition():
    import gymnasium as gym

    import train
    from agents.leaderboard.compare import build_parser as evaluate_parser
    from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS
    spec = gym.spec("BearingPreload-v0")
    assert spec.max_episode_steps == EPISODE_STEPS
    assert gym.make("BearingPreload-v0").unwrapped.tier == DEFAULT_TIER
    for parser in (train.build_parser(), evaluate_parser()):
        assert parser.get_default("episode_steps") == EPISODE_STEPS
        assert parser.get_default("tier") == DEFAULT_TIER


def test_the_protocol_numbers_meet_the_minimums_and_the_check_catches_breaches():
    protocol.check_protocol()
    assert protocol.TEST_EPISODES >= 100
    for overrides, message in (({"TEST_EPISODES": 99}, "TEST_EPISODES"),
                               ({"HEADLINE_SEEDS": 4}, "got 4 and 3"),
                               ({"OTHER_SEEDS": 2}, "got 5 and 2"),
                               ({"CONTEXTUAL_FIT_SEED": 2_000}, "overlap the training runs")):
        with pytest.raises(ValueError, match=message):
            protocol.check_protocol(**overrides)


def test_training_seeds_come_from_train_in_separate_blocks():
    headline = protocol.training_seeds(protocol.HEADLINE_ALGORITHM)
    assert len(headline) == protocol.HEADLINE_SEEDS >= 5
    for algo in protocol.ALGORITHMS:
        seeds = protocol.training_seeds(algo)
        assert len(seeds) >= 3 and all(protocol.range_of(s) == "train" for s in seeds)
        assert np.all(np.diff(seeds) >= protocol.RUN_SEED_STRIDE)
        assert max(seeds) + protocol.RUN_SEED_STRIDE <= protocol.CONTEXTUAL_FIT_SEED
    with pytest.raises(ValueError, match="unknown algorithm"):
        protocol.training_seeds("dqn")


def test_the_references_draw_from_their_ranges():
    from agents.references import contextual_fit as contextual
    from agents.references import validation as references
    from agents.leaderboard.settings import FULL
    seeds = protocol.held_out_seeds(FULL.episodes)
    assert FULL.episodes == protocol.TEST_EPISODES and protocol.range_of(seeds[0]) == protocol.range_of(seeds[-1]) == "test"
    assert protocol.range_of(references.build_parser().get_default("seed")) == "validation"
    fit = contextual.build_parser()
    first = fit.get_default("seed")
    last = first + contextual.fit_episodes("transient") - 1      # what the command runs when --episodes is not given
    assert fit.get_default("episodes") is None and protocol.range_of(first) == protocol.range_of(last) == "train"
    assert contextual.fit_episodes("transient") == protocol.CONTEXTUAL_FIT_EPISODES
    assert contextual.fit_episodes("paper") == contextual.MIN_FIT_EPISODES
    with pytest.raises(ValueError, match="leave the test range"):
        protocol.held_out_seeds(len(protocol.TEST) + 1)


def test_a_deterministic_tier_takes_one_episode_of_each_count():
    """Only the paper tier gives every seed the same episode (tests/envs/test_parts.py checks
    that against the simulation); there one episode, or the consumer's minimum, stands for the
    protocol's count."""
    assert protocol.episodes_for_tier("paper", protocol.TEST_EPISODES) == 1
    assert protocol.episodes_for_tier("paper", protocol.CONTEXTUAL_FIT_EPISODES, minimum=3) == 3
    assert protocol.episodes_for_tier("paper", 0) == 0
    for tier in ("stationary", "transient", "field"):
        assert protocol.episodes_for_tier(tier, protocol.TEST_EPISODES) == protocol.TEST_EPISODES


def test_the_shipped_start_bank_holds_training_seeds_only():
    """The env's start_bank="shipped" draws only scenarios of training seeds: never a validation
    or test scenario (docs/benchmark.md, the rules)."""
    from bearing_gym.envs import start_bank as banks
    bank = banks.load(banks.shipped_path("transient"), check_kernel=False)
    assert bank.seeds and all(protocol.range_of(s) == "train" for s in bank.seeds)


def test_protocol_v2_freezes_its_references_and_fits_its_bank():
    """The planner's and the causal MPC's default settings are the ones whose digests protocol v2
    stored before its runs (a change of either is a new protocol version), and v2's rules hold:
    the start bank covers a run's episodes, the run seeds end below the tuning blocks."""
    import hashlib
    import json

    from agents.policies.causal_mpc import CausalMPCSettings
    from agents.policies.planner import PlannerSettings
    from bearing_gym.task import EPISODE_STEPS
    planner = hashlib.sha256(json.dumps(PlannerSettings().as_dict(), sort_keys=True).encode()).hexdigest()[:16]
    assert planner == protocol.V2_PLANNER_SETTINGS_SHA256
    assert CausalMPCSettings().digest() == protocol.V2_CAUSAL_MPC_SETTINGS_SHA256
    assert protocol.V2_START_BANK_STARTS * EPISODE_STEPS >= protocol.V2_STEP_BUDGET_PER_RUN
    assert set(protocol.V2_ALGORITHMS) >= {"sac", "tqc", "crossq", "ppo", "ppo_lstm"} and protocol.V2_SEEDS >= 5
    assert max(protocol.v2_training_seeds()) + protocol.RUN_SEED_STRIDE <= protocol.TUNING_TRAIN_SEED
    with pytest.raises(ValueError, match="meet a start twice"):
        protocol.check_protocol(V2_START_BANK_STARTS=protocol.V2_STEP_BUDGET_PER_RUN // EPISODE_STEPS - 1)
    with pytest.raises(ValueError, match="validation point"):
        protocol.check_protocol(V2_EARLY_ROW_STEPS=105_000)
