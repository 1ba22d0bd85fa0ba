"""The protocol's seed ranges are disjoint, and every script draws from the range it claims."""

import pytest

from agents import protocol


def test_ranges_are_disjoint_and_the_check_catches_an_overlap():
    protocol.check_disjoint()
    with pytest.raises(ValueError, match="a .* and b .* overlap"):
        protocol.check_disjoint({"a": range(0, 10), "b": range(5, 20)})


def test_tier_design_measurement_uses_its_own_range():
    from agents import tier_gap
    seed = tier_gap.build_parser().get_default("seed")
    assert protocol.range_of(seed) == "tier_design"
    assert protocol.range_of(seed + 19) == "tier_design"


def test_train_and_evaluate_draw_from_their_ranges():
    import train
    from agents.evaluate import TEST_SEED
    assert protocol.range_of(TEST_SEED) == "test"
    assert protocol.range_of(train.build_parser().get_default("val_seed")) == "validation"
    assert protocol.range_of(train.build_parser().get_default("seed")) == "train"


def test_training_and_evaluation_use_the_registered_definition():
    import gymnasium as gym

    import train
    from agents.evaluate import build_parser as evaluate_parser
    from bearing_gym.benchmark import DEFAULT_TIER, EPISODE_STEPS
    spec = gym.spec("BearingPreload-v0")
    assert spec.max_episode_steps == EPISODE_STEPS
    assert gym.make("BearingPreload-v0").unwrapped.tier == DEFAULT_TIER
    for parser in (train.build_parser(), evaluate_parser()):
        assert parser.get_default("episode_steps") == EPISODE_STEPS
        assert parser.get_default("tier") == DEFAULT_TIER
