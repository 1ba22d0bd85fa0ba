"""The speed schedules (the spindle makers' practice): the preload each gives at a speed."""

import numpy as np
import pytest

from agents.policies.speed_schedule import SPEED_SCALE_RPM, SpeedSchedule


def test_a_switch_changes_level_at_its_thresholds():
    s = SpeedSchedule((15000.0, 20000.0), (1600.0, 1000.0, 500.0))
    np.testing.assert_array_equal(s.preload_n([10000, 14999, 15000, 19999, 20000, 25000]),
                                  [1600, 1600, 1000, 1000, 500, 500])
    obs = np.zeros((2, 15), np.float32)
    obs[:, 11] = np.array([12000, 21000]) / SPEED_SCALE_RPM
    a, _ = s.predict(obs)
    np.testing.assert_allclose(300 + (a[:, 0] + 1) / 2 * 1700, [1600, 500], rtol=0, atol=1e-3)
    assert s.name == "speed switch (3 levels)"


def test_a_table_is_linear_between_knots_and_held_beyond():
    t = SpeedSchedule((10000.0, 20000.0, 25000.0), (1800.0, 800.0, 600.0), interpolate=True)
    np.testing.assert_allclose(t.preload_n([5000, 10000, 15000, 20000, 22500, 30000]),
                               [1800, 1800, 1300, 800, 700, 600])
    assert SpeedSchedule.from_json(t.to_json()).to_json() == t.to_json()


@pytest.mark.parametrize("args,match", [
    (((20000.0, 15000.0), (1, 2, 3)), "increasing"),
    (((15000.0,), (1000.0,)), "one level more than thresholds"),
    (((15000.0,), (1000.0, 2500.0)), r"levels_n must be in \[300"),
])
def test_a_bad_schedule_is_refused_by_name(args, match):
    with pytest.raises(ValueError, match=match):
        SpeedSchedule(*args)
    with pytest.raises(ValueError, match="at least 2"):
        SpeedSchedule((15000.0,), (1000.0,), interpolate=True)
