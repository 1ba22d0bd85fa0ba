"""What one control interval measured: the record every reward and sensor model reads.

The step kernel writes raw features of each environment's last control interval
(:mod:`.features`, SI units) and its contact state (:mod:`.contact`: contact loads, bearing
stiffness); the env adds the operating point, the actuator state, the fatigue life used and the
friction torque and hands one :class:`StepMeasurement` (arrays over the environments stepped)
to the reward model and to the sensor model. A custom reward or sensor reads whatever it needs
from it; nothing else of the env's internals.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bearing_gym.analysis.signals import QPI_THRESHOLD

from .contact import (C_AXIAL_STIFFNESS, C_INNER_Q3_MEAN, C_MAX_INNER_N, C_MAX_OUTER_N, C_OUTER_Q10_3_MEAN,
                      C_RADIAL_STIFFNESS)
from .features import (F_CAGE_MEAN, F_CAGE_PTP, F_MEAN_X, F_NS_RMS, F_PTP_X, F_QPI, F_RMS_X)

__all__ = ["StepMeasurement"]


@dataclass(frozen=True)
class StepMeasurement:
    """One control interval of B environments (each array has length B unless noted).

    ``features`` (B, N_FEATURES) are the raw window features in SI units (columns ``F_*`` of
    :mod:`bearing_gym.envs.features`) and ``contact`` (B, N_CONTACT) the interval's contact
    state (columns ``C_*`` of :mod:`bearing_gym.envs.contact`: contact loads from every Newmark
    step, the bearing stiffness); the properties below name them. ``life_used_per_s`` is the
    fraction of the bearing's L10 rating life the interval used per second of running
    (Lundberg-Palmgren from its contact loads, :mod:`bearing_gym.physics.rating`; 1/s),
    ``friction_torque_n_m`` Palmgren's load-dependent friction torque M_1 at its preload and
    radial load (N m). ``preload_before_n`` is the actual preload at the start of the interval,
    ``steps_left`` the control intervals left in the episode after this one (for a termination
    penalty), ``terminated`` whether the integrator failed in this interval, ``preload_range_n``
    the actuator's (min, max). At reset, ``preload_before_n == preload_n`` and ``steps_left`` is
    the whole horizon.
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
    contact: np.ndarray
    life_used_per_s: np.ndarray
    friction_torque_n_m: np.ndarray
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

    @property
    def max_inner_contact_load_n(self) -> np.ndarray:
        """The largest inner-race contact load of the interval (N)."""
        return self.contact[:, C_MAX_INNER_N]

    @property
    def max_outer_contact_load_n(self) -> np.ndarray:
        """The largest outer-race contact load of the interval (N; centrifugal force included)."""
        return self.contact[:, C_MAX_OUTER_N]

    @property
    def inner_q3_mean(self) -> np.ndarray:
        """Mean over the interval's steps and balls of Q_i^3 (N^3)."""
        return self.contact[:, C_INNER_Q3_MEAN]

    @property
    def outer_q10_3_mean(self) -> np.ndarray:
        """Mean over the interval's steps and balls of Q_o^(10/3) (N^(10/3))."""
        return self.contact[:, C_OUTER_Q10_3_MEAN]

    @property
    def radial_stiffness_n_per_m(self) -> np.ndarray:
        """(K_xx + K_yy) / 2 of the bearing at the interval's mean displacement (N/m)."""
        return self.contact[:, C_RADIAL_STIFFNESS]

    @property
    def axial_stiffness_n_per_m(self) -> np.ndarray:
        """K_zz of the bearing at the interval's mean displacement (N/m)."""
        return self.contact[:, C_AXIAL_STIFFNESS]

    def __len__(self) -> int:
        return int(self.features.shape[0])
