"""Batch of environments' physics: the arrays the shared step kernel works on.

:class:`PreloadBatch` holds, for B environments, the packed parameters, the integrator state,
the scenario schedule, the actuator state and a record buffer. ``load(b, scenario)`` starts
environment b at the static equilibrium of its scenario's initial operating point (a
:class:`~bearing_gym.physics.Simulator` does the set-up, so the physics is configured exactly as
everywhere else); ``step(setpoints, active)`` runs :func:`.kernel.step_batch` once.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from bearing_gym.analysis.window import N_FEATURES
from bearing_gym.params import BearingParams, RaceWaviness, Waviness, default_params
from bearing_gym.physics import Simulator
from bearing_gym.physics.ball import N_BALL_OUT
from bearing_gym.physics.layout import I_DT, N_PRM
from bearing_gym.physics.rotor import N_REC, N_SCAL

from .actuator import PreloadActuator
from .kernel import step_batch, step_batch_serial
from .scenario import Scenario

MAX_RACE_TERMS = 4


def scenario_params(base: BearingParams, scenario: Scenario) -> BearingParams:
    """Physics parameters of a scenario's initial operating point."""
    wav = base.waviness
    if scenario.waviness_amplitude_m > 0.0:
        rw = RaceWaviness(orders=(scenario.waviness_order,), radial_amplitudes_m=(scenario.waviness_amplitude_m,))
        wav = Waviness(inner=rw, outer=rw, balls=base.waviness.balls)
    fx0, fy0 = scenario.schedule_array()[4:6]
    return base.replace(
        shaft_speed_rpm=scenario.speed_start_rpm, clearance_inner_m=scenario.clearance_m,
        clearance_outer_m=scenario.clearance_m, eccentricity_m=scenario.eccentricity_m,
        axial_preload_n=scenario.initial_preload_n, radial_load_x_n=float(fx0),
        radial_load_y_n=float(fy0), waviness=wav)


class PreloadBatch:
    def __init__(self, num_envs: int, base_params: BearingParams | None, control_dt_s: float,
                 actuator: PreloadActuator):
        self.base = base_params if base_params is not None else default_params()
        self.actuator = actuator
        self.n = num_envs
        dt = self.base.integrator.dt_s
        self.steps_per_sub = max(1, int(round(actuator.update_interval_s / dt)))
        sub = self.steps_per_sub * dt
        self.n_sub = max(1, int(round(control_dt_s / sub)))
        self.control_dt_s = self.n_sub * sub
        nb = self.base.geometry.n_balls
        B = num_envs
        self.prm = np.zeros((B, N_PRM))
        self.race_wav = np.zeros((B, MAX_RACE_TERMS, 5))
        self.n_race = np.zeros(B, dtype=np.int64)
        n_bw = len([a for a in self.base.waviness.balls.amplitudes_m if a != 0.0])
        self.ball_wav = np.zeros((B, n_bw, 2))
        self.n_ball = np.zeros(B, dtype=np.int64)
        self.ball_phase = np.zeros((B, nb, n_bw))
        self.ball_size = np.zeros((B, nb))
        self.X = np.zeros((B, 5))
        self.V = np.zeros((B, 5))
        self.A = np.zeros((B, 5))
        self.scal = np.zeros((B, N_SCAL))
        self.psi_b = np.zeros((B, nb))
        self.ball_v = np.zeros((B, nb, 2))
        self.ball_out = np.zeros((B, nb, N_BALL_OUT))
        self.env_state = np.zeros((B, 3))      # preload, setpoint, t_episode
        self.sched = np.zeros((B, 9))
        self.act = actuator.as_array()
        self.rec = np.zeros((B, self.n_sub * self.steps_per_sub + 1, N_REC))
        self.rows = np.zeros(B, dtype=np.int64)
        self.status = np.zeros(B, dtype=np.int64)
        self.feats = np.zeros((B, N_FEATURES))
        self.scenarios: list[Scenario | None] = [None] * B
        self.damping = np.zeros((B, 5))
        g = self.base.geometry
        self.gamma_cos_a0 = g.diameter_ratio * math.cos(g.contact_angle_rad)

    @property
    def dt_s(self) -> float:
        return float(self.base.integrator.dt_s)

    def load(self, b: int, scenario: Scenario) -> None:
        """Start env ``b`` at the static equilibrium of ``scenario`` at t = 0."""
        params = scenario_params(self.base, scenario)
        sim = Simulator(params)
        p = sim._packed
        self.prm[b] = p.prm
        nr = p.race_wav.shape[0]
        if nr > MAX_RACE_TERMS:
            raise ValueError(f"at most {MAX_RACE_TERMS} race-waviness terms are supported in the env, got {nr}")
        self.race_wav[b] = 0.0
        self.race_wav[b, :nr] = p.race_wav
        self.n_race[b] = nr
        nbw = p.ball_wav.shape[0]
        self.ball_wav[b, :nbw] = p.ball_wav
        self.ball_phase[b, :, :nbw] = p.ball_phase
        self.n_ball[b] = nbw
        self.ball_size[b] = p.ball_size
        s = sim._state
        self.X[b], self.V[b], self.A[b] = s.X, s.V, s.A
        self.scal[b], self.psi_b[b], self.ball_v[b], self.ball_out[b] = s.scal, s.psi_b, s.ball_v, s.ball_out
        self.env_state[b] = (scenario.initial_preload_n, scenario.initial_preload_n, 0.0)
        self.sched[b] = scenario.schedule_array()
        self.scenarios[b] = scenario
        self.damping[b] = sim.damping_coefficients
        self.status[b] = 0
        self.feats[b] = 0.0

    def step(self, setpoints: np.ndarray, active: np.ndarray) -> None:
        self.env_state[active, 1] = setpoints[active]
        kernel = step_batch if self.n > 1 else step_batch_serial
        kernel(active, self.prm, self.race_wav, self.n_race, self.ball_wav, self.n_ball,
                   self.ball_phase, self.ball_size, self.X, self.V, self.A, self.scal, self.psi_b,
                   self.ball_v, self.ball_out, self.env_state, self.sched, self.act, self.n_sub,
                   self.steps_per_sub, self.rec, self.rows, self.status, self.feats)

    @property
    def preload(self) -> np.ndarray:
        """Actual preload (N) of each env (a view)."""
        return self.env_state[:, 0]

    @property
    def setpoint(self) -> np.ndarray:
        return self.env_state[:, 1]

    @property
    def t_episode(self) -> np.ndarray:
        return self.env_state[:, 2]

    def omega(self) -> np.ndarray:
        from bearing_gym.physics.layout import I_OMEGA
        return self.prm[:, I_OMEGA].copy()

    def radial_load_n(self) -> np.ndarray:
        from bearing_gym.physics.layout import I_PX, I_PY
        return np.hypot(self.prm[:, I_PX], self.prm[:, I_PY])

    def window(self, b: int) -> np.ndarray:
        """The last control interval's record rows of env b (R_* columns)."""
        return self.rec[b, :self.rows[b]]
