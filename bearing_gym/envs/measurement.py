"""What one control interval measured: the record every reward and sensor model reads.

The step kernel writes raw features of each environment's last control interval
(:mod:`.features`, SI units); the env adds the operating point and the actuator state and hands
one :class:`StepMeasurement` (arrays over the environments stepped) to the reward model and to
the sensor model. A custom reward or sensor reads whatever it needs from it; nothing else of the
env's internals.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bearing_gym.analysis.signals import QPI_THRESHOLD

from .features import (F_CAGE_MEAN, F_CAGE_PTP, F_MEAN_X, F_NS_RMS, F_PTP_X, F_QPI, F_RMS_X)

__all__ = ["StepMeasurement"]


@dataclass(frozen=True)
class StepMeasurement:
    """One control interval of B environments (each array has length B unless noted).

    ``features`` (B, N_FEATURES) are the raw window features in SI units (columns ``F_*`` of
    :mod:`bearing_gym.envs.features`); the properties below name them. ``preload_before_n`` is
    the actual preload at the start of the interval, ``steps_left`` the control intervals left
    in the episode after this one (for a termination penalty), ``terminated`` whether the
    integrator failed in this interval, ``preload_range_n`` the actuator's (min, max). At reset, ``preload_before_n == preload_n`` and
    ``steps_left`` is the whole horizon.
    """

    features: np.ndarray
    preload_n: np.ndarray
    preload_before_n: np.ndarray
    setpoint_n: np.ndarray
    shaft_speed_rad_s: np.ndarray
    radial_load_n: np.ndarray
    kinematic_cage_speed_rad_s: np.ndarray
    t_s: np.ndarray
    steps_left: np.ndarray
    terminated: np.ndarray
    preload_range_n: tuple[float, float] = (300.0, 2000.0)

    @property
    def qpi(self) -> np.ndarray:
        """Quasi-periodicity index of the interval (:mod:`bearing_gym.analysis.signals`)."""
        return self.features[:, F_QPI]

    @property
    def quasi_periodic(self) -> np.ndarray:
        """``qpi > QPI_THRESHOLD``: the one classification used everywhere in the package."""
        return self.qpi > QPI_THRESHOLD

    @property
    def nonsync_rms_m(self) -> np.ndarray:
        """RMS of the non-synchronous displacement (m), see :mod:`.features`."""
        return self.features[:, F_NS_RMS]

    @property
    def ptp_m(self) -> np.ndarray:
        """(B, 3) peak-to-peak x, y, z (m)."""
        return self.features[:, F_PTP_X:F_PTP_X + 3]

    @property
    def rms_m(self) -> np.ndarray:
        """(B, 3) RMS of x, y, z about their means (m)."""
        return self.features[:, F_RMS_X:F_RMS_X + 3]

    @property
    def mean_displacement_m(self) -> np.ndarray:
        """(B, 3) mean x, y, z (m): the static offsets a displacement probe reads."""
        return self.features[:, F_MEAN_X:F_MEAN_X + 3]

    @property
    def cage_speed_mean_rad_s(self) -> np.ndarray:
        return self.features[:, F_CAGE_MEAN]

    @property
    def cage_speed_ptp_rad_s(self) -> np.ndarray:
        return self.features[:, F_CAGE_PTP]

    def __len__(self) -> int:
        return int(self.features.shape[0])
