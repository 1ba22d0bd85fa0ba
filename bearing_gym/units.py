"""Unit conversions used across the package (the physics works in SI: rad/s, m, N)."""

from __future__ import annotations

import math

__all__ = ["rpm_to_rad_s", "rad_s_to_rpm"]


def rpm_to_rad_s(rpm):
    """Shaft speed in rad/s from rpm (works on floats and NumPy arrays)."""
    return rpm * math.pi / 30.0


def rad_s_to_rpm(rad_s):
    """Shaft speed in rpm from rad/s (works on floats and NumPy arrays)."""
    return rad_s * 30.0 / math.pi
