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
