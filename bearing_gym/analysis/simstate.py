"""Helpers shared by the Floquet and Lyapunov tools: the (X, V) phase-space vector of a
:class:`~bearing_gym.physics.Simulator` state, its scaling, and perturbed states with a
consistent acceleration.

The rotor state of eq 35 is (X, V) = (x, y, z, θx, θy, and their velocities), 10 numbers. The
Simulator state also holds the Newmark acceleration A, the time/shaft angle/cage angle/cage
speed, the ball spin angles (eq 15) and the quasi-static ball solutions (eq 31, warm starts).
For the ODE (X, V) the acceleration is not a state but a function of it,
A = M⁻¹(F(X) + P + unbalance − (C + G) V); a perturbed state therefore gets its acceleration
recomputed (:func:`perturbed_state`), so that the first Newmark step of a perturbed run
integrates the perturbed ODE and not a state with a stale acceleration.
"""

from __future__ import annotations

import math

import numpy as np

from bearing_gym.physics import Simulator, SimulatorState
from bearing_gym.physics.bearing import bearing_force
from bearing_gym.physics.layout import (I_NGAMMA, I_RP, O_OMEGA, O_PX, O_PY, O_PZ, PackedParams,
                                        pack_params)
from bearing_gym.physics.portable_math import sincos
from bearing_gym.physics.rotor import S_CAGE, S_SHAFT, solve_acceleration
from bearing_gym.units import rpm_to_rad_s

__all__ = ["STATE_LABELS", "state_vector", "state_scale", "StatePerturber", "shaft_period_steps"]

STATE_LABELS = ("x", "y", "z", "theta_x", "theta_y",
                "x_dot", "y_dot", "z_dot", "theta_x_dot", "theta_y_dot")


def state_vector(state: SimulatorState) -> np.ndarray:
    """(10,) vector (X, V) of a Simulator state."""
    return np.concatenate([state.X, state.V])


def state_scale(sim: Simulator) -> np.ndarray:
    """(10,) natural units of (X, V): 1 m for x, y, z, 1/r_p for the tilts (a tilt θ moves the
    groove-centre locus by r_p θ), and the same divided by 1/ω for the velocities (a velocity
    v ~ ω X at the shaft frequency). Dividing a perturbation by this vector makes its
    components comparable; eigenvalues do not depend on it."""
    rp = float(pack_params(sim.params).prm[I_RP])
    w = max(rpm_to_rad_s(sim.shaft_speed_rpm), 1.0)
    pos = np.array([1.0, 1.0, 1.0, 1.0 / rp, 1.0 / rp])
    return np.concatenate([pos, pos * w])


def shaft_period_steps(sim: Simulator) -> tuple[int, float]:
    """Number of time steps in one shaft period 2π/ω and the period (s) they span.

    Raises ValueError at zero speed (no stroboscopic section exists) or if one period is
    shorter than 4 steps."""
    w = rpm_to_rad_s(sim.shaft_speed_rpm)
    if w <= 0:
        raise ValueError("the shaft is not turning: a stroboscopic section needs shaft_speed_rpm > 0")
    n = int(round(2.0 * math.pi / w / sim.dt_s))
    if n < 4:
        raise ValueError(f"one shaft period is only {n} time steps; reduce dt_s")
    return n, n * sim.dt_s


class StatePerturber:
    """Builds Simulator states whose (X, V) are set to given values, with the acceleration made
    consistent with the equations of motion (eq 35) at the new (X, V).

    The ball solutions are re-solved from the base state's warm start; the time, shaft angle,
    cage angle and cage speed and the ball spin angles are those of the base state.
    """

    def __init__(self, sim: Simulator):
        self.sim = sim
        packed = pack_params(sim.params, sim.damping_coefficients)
        prm = packed.prm.copy()
        prm[I_NGAMMA] = 0.0        # solve_acceleration then gives M a = F + P - (C + G) v
        op = packed.op.copy()      # the simulator's operating point now (damping factors 1)
        op[O_PZ] = sim.axial_preload_n
        op[O_PX] = sim.radial_load_x_n
        op[O_PY] = sim.radial_load_y_n
        op[O_OMEGA] = rpm_to_rad_s(sim.shaft_speed_rpm)
        self._packed = PackedParams(prm, packed.race_wav, packed.ball_wav, packed.ball_phase,
                                    packed.ball_size, op)
        self._F = np.zeros(5)

    def make(self, base: SimulatorState, vector: np.ndarray) -> SimulatorState:
        """Copy of ``base`` with (X, V) = ``vector`` (10,) and a consistent acceleration."""
        vector = np.asarray(vector, dtype=float)
        if vector.shape != (10,):
            raise ValueError(f"vector must have shape (10,), got {vector.shape}")
        st = base.copy()
        st.X[:] = vector[:5]
        st.V[:] = vector[5:]
        p = self._packed
        status = bearing_force(st.X, st.scal[S_CAGE], st.scal[S_SHAFT], st.psi_b, p.prm, p.op[O_OMEGA],
                               p.race_wav, p.ball_wav, p.ball_phase, p.ball_size, st.ball_v,
                               st.ball_out, self._F)
        if status != 0:
            raise RuntimeError(f"ball equilibrium failed (status {status}) at the perturbed "
                               "state; use a smaller perturbation")
        sin_shaft, cos_shaft = sincos(st.scal[S_SHAFT])
        solve_acceleration(self._F, p.prm, p.op, cos_shaft, sin_shaft, st.V, st.A)
        return st
