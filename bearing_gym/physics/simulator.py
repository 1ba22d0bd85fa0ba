"""The Simulator: a stateful wrapper around the numba integrator (paper eqs 3-35)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from bearing_gym.params import BearingParams
from bearing_gym.units import rad_s_to_rpm, rpm_to_rad_s
from bearing_gym.validation import check_real

from .ball import B_CTRL, B_VR_PREV, B_VR_PREV2, B_VZ_PREV, B_VZ_PREV2, N_BALL_OUT
from .bearing import bearing_force, cage_speed
from .equilibrium import static_equilibrium
from .layout import (I_CX, I_DT, O_OMEGA, O_PX, O_PY, O_PZ, pack_params)
from .rotor import (N_REC, N_SCAL, R_CAGE_ANGLE, R_CAGE_SPEED, R_F, R_N_INNER, R_SHAFT, R_T, R_V,
                    R_X, S_A_PREV, S_A_PREV2, S_CAGE_SPEED, S_T, integrate,
                    solve_acceleration)
from .status import status_text

__all__ = ["Simulator", "SimulatorState", "SimulationRecord", "SimulationError"]



class SimulationError(RuntimeError):
    """The integrator could not complete a step (see the message for the reason)."""

    def __init__(self, message: str, record: "SimulationRecord"):
        super().__init__(message)
        self.record = record


@dataclass
class SimulatorState:
    """Complete dynamic state; ``Simulator.state`` returns a copy, assigning one restores it."""

    X: np.ndarray            # x, y, z, theta_x, theta_y
    V: np.ndarray            # their velocities
    A: np.ndarray            # their accelerations
    scal: np.ndarray         # t, shaft angle, cage angle, cage speed
    psi_b: np.ndarray        # ball spin angles (eq 15)
    ball_v: np.ndarray       # ball centre displacements (v_r, v_z)
    ball_out: np.ndarray     # per-ball contact state

    def copy(self) -> "SimulatorState":
        return SimulatorState(*(getattr(self, f).copy() for f in
                                ("X", "V", "A", "scal", "psi_b", "ball_v", "ball_out")))

    @property
    def t(self) -> float:
        return float(self.scal[S_T])


@dataclass
class SimulationRecord:
    """Time series returned by :meth:`Simulator.advance` (SI units; angles in rad)."""

    data: np.ndarray = field(repr=False)
    status: str = "ok"

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def __len__(self) -> int:
        return self.data.shape[0]

    t = property(lambda s: s.data[:, R_T])
    x = property(lambda s: s.data[:, R_X])
    y = property(lambda s: s.data[:, R_X + 1])
    z = property(lambda s: s.data[:, R_X + 2])
    theta_x = property(lambda s: s.data[:, R_X + 3])
    theta_y = property(lambda s: s.data[:, R_X + 4])
    x_dot = property(lambda s: s.data[:, R_V])
    y_dot = property(lambda s: s.data[:, R_V + 1])
    z_dot = property(lambda s: s.data[:, R_V + 2])
    theta_x_dot = property(lambda s: s.data[:, R_V + 3])
    theta_y_dot = property(lambda s: s.data[:, R_V + 4])
    displacement = property(lambda s: s.data[:, R_X:R_X + 5], doc="(n, 5) x, y, z, theta_x, theta_y")
    velocity = property(lambda s: s.data[:, R_V:R_V + 5])
    cage_speed = property(lambda s: s.data[:, R_CAGE_SPEED], doc="cage speed omega_c (rad/s), eq 7")
    cage_angle = property(lambda s: s.data[:, R_CAGE_ANGLE], doc="cage angle psi_c (rad), eq 8")
    shaft_angle = property(lambda s: s.data[:, R_SHAFT])
    bearing_force = property(lambda s: s.data[:, R_F:R_F + 5], doc="(n, 5) F_x, F_y, F_z, M_x, M_y")
    n_inner_contacts = property(lambda s: s.data[:, R_N_INNER].astype(int))


class Simulator:
    """Time integration of the 5-DOF rotor / ball-bearing model of Bai & Xu (2006).

    >>> sim = Simulator(default_params(shaft_speed_rpm=20000))   # doctest: +SKIP
    >>> rec = sim.advance(0.2, record_every=10)                  # doctest: +SKIP

    The state starts at the static equilibrium (:func:`static_equilibrium`) with zero velocity
    and the consistent acceleration. Axial preload, radial loads and shaft speed can be changed
    between calls to :meth:`advance`. The damping coefficients are fixed when the Simulator is
    built (``params.damping``; see :class:`bearing_gym.params.Damping`).
    """

    def __init__(self, params: BearingParams):
        if not isinstance(params, BearingParams):
            raise TypeError(f"params must be a BearingParams (use bearing_gym.default_params()), got {type(params).__name__}")
        self.params = params
        self._equilibrium = None
        self._packed = pack_params(params)
        if params.damping.coefficients is None:
            self._packed.prm[I_CX:I_CX + 5] = self._damping_from_stiffness(params)
        n = params.geometry.n_balls
        self._state = SimulatorState(np.zeros(5), np.zeros(5), np.zeros(5), np.zeros(N_SCAL),
                                     np.zeros(n), np.zeros((n, 2)), np.zeros((n, N_BALL_OUT)))
        self.reset()

    # --- construction helpers -----------------------------------------------------------------
    @property
    def equilibrium(self):
        """Static equilibrium of the construction parameters (computed once, lazily)."""
        if self._equilibrium is None:
            self._equilibrium = static_equilibrium(self.params)
        return self._equilibrium

    def _damping_from_stiffness(self, params: BearingParams) -> np.ndarray:
        zeta = params.damping.damping_ratio
        if zeta == 0.0:
            return np.zeros(5)
        k_diag = np.maximum(np.diag(self.equilibrium.stiffness), 0.0)
        r = params.rotor
        mass = np.array([r.mass_kg] * 3 + [r.inertia_radial_kg_m2] * 2)
        return 2.0 * zeta * np.sqrt(k_diag * mass)

    @property
    def packed_params(self):
        """The parameters as the kernels take them (:class:`~bearing_gym.physics.layout.PackedParams`,
        with this simulator's damping): for code that runs the kernels on its own arrays, such as
        the environment's batch. Treat as read-only; copy before changing."""
        return self._packed

    @property
    def damping_coefficients(self) -> np.ndarray:
        """(5,) viscous damping of x, y, z (N s/m) and theta_x, theta_y (N m s/rad)."""
        return self._packed.prm[I_CX:I_CX + 5].copy()

    # --- state --------------------------------------------------------------------------------
    def reset(self, state: SimulatorState | None = None) -> SimulatorState:
        """Restore ``state`` or, by default, start at the static equilibrium at t = 0."""
        if state is not None:
            self.state = state
            return self.state
        eq = self.equilibrium
        prm = self._packed.prm
        s = self._state
        s.X[:] = eq.U
        s.V[:] = 0.0
        s.scal[:] = 0.0
        s.psi_b[:] = 0.0
        s.ball_v[:, 0] = eq.ball_displacement_r
        s.ball_v[:, 1] = eq.ball_displacement_z
        s.ball_out[:] = 0.0
        s.ball_out[:, B_CTRL] = eq.inner_race_control.astype(float)
        F = np.zeros(5)
        p = self._packed
        st = bearing_force(s.X, 0.0, 0.0, s.psi_b, prm, p.op[O_OMEGA], p.race_wav, p.ball_wav, p.ball_phase,
                           p.ball_size, s.ball_v, s.ball_out, F)
        if st != 0:
            raise SimulationError(f"initial bearing force failed: {status_text(st)}", None)
        s.ball_out[:, B_VR_PREV] = s.ball_v[:, 0]     # at rest: no extrapolation on step 1
        s.ball_out[:, B_VZ_PREV] = s.ball_v[:, 1]
        s.ball_out[:, B_VR_PREV2] = s.ball_v[:, 0]
        s.ball_out[:, B_VZ_PREV2] = s.ball_v[:, 1]
        omega = p.op[O_OMEGA]
        s.scal[S_CAGE_SPEED] = cage_speed(s.ball_out, s.psi_b.shape[0], eq.cage_speed_ratio * omega)
        solve_acceleration(F, _zero_gamma(prm), p.op, 1.0, 0.0, s.V, s.A)   # shaft angle 0
        s.scal[S_A_PREV:S_A_PREV + 5] = s.A              # no extrapolation on the first step
        s.scal[S_A_PREV2:S_A_PREV2 + 5] = s.A
        return self.state

    @property
    def state(self) -> SimulatorState:
        return self._state.copy()

    @state.setter
    def state(self, value: SimulatorState) -> None:
        if not isinstance(value, SimulatorState):
            raise TypeError("state must be a SimulatorState (from Simulator.state)")
        for f in ("X", "V", "A", "scal", "psi_b", "ball_v", "ball_out"):
            dst = getattr(self._state, f)
            src = np.asarray(getattr(value, f), dtype=np.float64)
            if src.shape != dst.shape:
                raise ValueError(f"state.{f} must have shape {dst.shape}, got {src.shape}")
            dst[:] = src

    @property
    def t(self) -> float:
        return float(self._state.scal[S_T])

    # --- operating point (settable between advance calls) -------------------------------------
    @property
    def axial_preload_n(self) -> float:
        return float(self._packed.op[O_PZ])

    @axial_preload_n.setter
    def axial_preload_n(self, value: float) -> None:
        self._packed.op[O_PZ] = check_real("axial_preload_n", value, 0.0, 1e6)

    @property
    def radial_load_x_n(self) -> float:
        return float(self._packed.op[O_PX])

    @radial_load_x_n.setter
    def radial_load_x_n(self, value: float) -> None:
        self._packed.op[O_PX] = check_real("radial_load_x_n", value, -1e6, 1e6)

    @property
    def radial_load_y_n(self) -> float:
        return float(self._packed.op[O_PY])

    @radial_load_y_n.setter
    def radial_load_y_n(self, value: float) -> None:
        self._packed.op[O_PY] = check_real("radial_load_y_n", value, -1e6, 1e6)

    @property
    def shaft_speed_rpm(self) -> float:
        return float(rad_s_to_rpm(self._packed.op[O_OMEGA]))

    @shaft_speed_rpm.setter
    def shaft_speed_rpm(self, value: float) -> None:
        self._packed.op[O_OMEGA] = rpm_to_rad_s(check_real("shaft_speed_rpm", value, 0.0, 200000.0))

    @property
    def dt_s(self) -> float:
        return float(self._packed.prm[I_DT])

    # --- integration --------------------------------------------------------------------------
    def advance(self, duration_s: float, record_every: int = 1, *,
                raise_on_error: bool = True) -> SimulationRecord:
        """Integrate for ``duration_s`` (rounded to a whole number of steps of ``dt_s``) and
        return every ``record_every``-th step. On an integrator failure raise
        :class:`SimulationError` (or, with ``raise_on_error=False``, return the rows computed so
        far with ``record.status`` saying why)."""
        duration_s = check_real("duration_s", duration_s, 0.0, 1e6)
        if isinstance(record_every, bool) or not isinstance(record_every, (int, np.integer)) or record_every < 1:
            raise ValueError(f"record_every must be an integer >= 1, got {record_every!r}")
        dt = self.dt_s
        n_steps = int(round(duration_s / dt))
        rec = np.empty((n_steps // int(record_every), N_REC))
        p = self._packed
        s = self._state
        status, done, rows = integrate(p.prm, p.op, p.race_wav, p.ball_wav, p.ball_phase, p.ball_size,
                                       s.X, s.V, s.A, s.scal, s.psi_b, s.ball_v, s.ball_out,
                                       n_steps, int(record_every), rec)
        record = SimulationRecord(rec[:rows], status_text(status))
        if status != 0 and raise_on_error:
            raise SimulationError(
                f"integration stopped at t = {self.t:.6g} s after {done} of {n_steps} steps: "
                f"{status_text(status)}", record)
        return record


def _zero_gamma(prm: np.ndarray) -> np.ndarray:
    """Copy of prm with Newmark gamma = 0, so solve_acceleration gives M a = F + P - (C+G) v."""
    from .layout import I_NGAMMA
    q = prm.copy()
    q[I_NGAMMA] = 0.0
    return q
