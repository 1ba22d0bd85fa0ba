"""bearing_gym.validation and bearing_gym.units."""

import math

import numpy as np
import pytest

from bearing_gym.units import rad_s_to_rpm, rpm_to_rad_s
from bearing_gym.validation import check_bool, check_int, check_real, check_real_tuple


def test_check_real_names_the_quantity_and_its_range():
    assert check_real("x", np.float32(2.5), 0.0, 3.0) == 2.5
    with pytest.raises(ValueError, match=r"^dt_s must be in \(0, 0.001\], got 0$"):
        check_real("dt_s", 0, 0.0, 1e-3, low_open=True)
    with pytest.raises(ValueError, match=r"x must be finite and in \[0, inf\)"):
        check_real("x", math.nan, 0.0)
    for bad in (True, "1", None):
        with pytest.raises(ValueError, match="x must be a real number"):
            check_real("x", bad)


def test_check_int_bool_and_tuple():
    assert check_int("n", np.int64(4), 3, 5) == 4
    with pytest.raises(ValueError, match=r"n must be an integer in \[3, 5\], got 6"):
        check_int("n", 6, 3, 5)
    with pytest.raises(ValueError, match="n must be an integer"):
        check_int("n", 4.0, 3, 5)
    assert check_bool("on", np.bool_(False)) is False
    with pytest.raises(ValueError, match="on must be True or False, got 1"):
        check_bool("on", 1)
    assert check_real_tuple("a", [1, 2.5]) == (1.0, 2.5)
    with pytest.raises(ValueError, match=r"a\[1\] must be in \[0, 1\]"):
        check_real_tuple("a", [0.5, 2.0], 0.0, 1.0)


def test_rpm_conversions_invert_each_other():
    assert rpm_to_rad_s(60.0) == pytest.approx(2 * math.pi, rel=1e-15)
    assert rpm_to_rad_s(20000.0) == 20000.0 * 2.0 * math.pi / 60.0     # the same rounding
    rpm = np.array([0.0, 1000.0, 20000.0])
    np.testing.assert_allclose(rad_s_to_rpm(rpm_to_rad_s(rpm)), rpm, rtol=1e-15)
