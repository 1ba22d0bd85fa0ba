"""The integrator's status codes and their messages (physics/status.py)."""

import pytest

from bearing_gym.physics import ball, rotor
from bearing_gym.physics.status import STATUS_TEXT, ST_OK, status_text


def test_every_code_the_kernels_return_has_one_message():
    codes = {ball.BALL_OK, ball.BALL_NOT_CONVERGED, ball.BALL_SINGULAR,
             rotor.ST_NEWMARK_NOT_CONVERGED, rotor.ST_DIVERGED}
    assert codes == set(STATUS_TEXT)
    assert status_text(ST_OK) == "ok"
    assert len(set(STATUS_TEXT.values())) == len(STATUS_TEXT)      # no two codes read alike


def test_unknown_code_is_named():
    with pytest.raises(ValueError, match="unknown integrator status code 7"):
        status_text(7)
