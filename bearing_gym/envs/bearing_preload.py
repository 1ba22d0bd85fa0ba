"""``BearingPreload-v0``: axial-preload control of a high-speed ball-bearing spindle."""

from __future__ import annotations

import os
from collections import deque
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from bearing_gym.params import BearingParams

from .composition import DEFAULTS, PreloadTask, TaskParts, check_actions
from .start_bank import env_scenario, install_for
from .rendering import HumanWindow, draw_frame, latest_frame_path, record_interval, rgb_frame

__all__ = ["BearingPreloadEnv", "latest_frame_path"]


class BearingPreloadEnv(TaskParts, gym.Env):
    """
    ## Description

    A rigid spindle rotor runs on an angular-contact ball bearing whose axial preload is
    adjustable (the Bai & Xu 2006 5-DOF model: Hertz contacts, clearance, waviness, ball
    centrifugal force and gyroscopic moment, time-varying cage speed). With too little preload the
    periodic (once-per-revolution) response loses stability in a Neimark-Sacker (secondary Hopf)
    bifurcation and the rotor vibrates quasi-periodically, with non-synchronous amplitudes of
    tens of micrometres. Too much preload costs friction heat and fatigue life. The stability
    map is not one boundary: with radial load and clearance there are isolated period-1 windows
    and quasi-periodic bands above them (``docs/reward_map.png``), and it moves with shaft speed,
    radial load, clearance, rotor unbalance and waviness. The controller has to find the cheapest period-1
    preload of the operating point it is in and follow it when the operating point changes.

    Each ``step`` advances the physics (Newmark-beta, dt = 25 us with a 1e-10 m equilibrium
    tolerance: ``bearing_gym.task.ENV_DT_S``, checked against dt/4 in
    ``benchmarks/bench_accuracy.py``) by one control interval
    (``control_dt_s``, 20 ms: 6.7 shaft turns at 20,000 rpm, enough Poincare points for the
    quasi-periodicity index of one interval).

    ## Action Space

    ``Box(-1, 1, (1,), float32)``: the preload set-point, mapped linearly onto
    [``min_preload_n``, ``max_preload_n``] of the actuator (300-2000 N). The actual preload
    follows the set-point through a first-order lag (20 ms) with a slew-rate limit (20 kN/s).
    A NaN or out-of-range action raises ``ValueError``, a string or None ``TypeError`` (no
    silent clipping; SB3 clips/squashes its own samples into the Box).

    ## Observation Space

    ``Box(-10, 10, (15,), float32)`` from the sensor model (:mod:`bearing_gym.envs.observation`
    has what a real spindle measures and the sensor errors), named by
    ``bearing_gym.envs.FEATURE_NAMES``; per control interval:

    ==  ====================  ========================================================  =========
    #   name                  what                                                      scaling
    ==  ====================  ========================================================  =========
    0   ``ptp_x``             peak-to-peak displacement x                               / 100 um
    1   ``ptp_y``             peak-to-peak displacement y                               / 100 um
    2   ``ptp_z``             peak-to-peak displacement z (axial)                       / 100 um
    3   ``rms_x``             RMS of x about its mean                                   / 50 um
    4   ``rms_y``             RMS of y about its mean                                   / 50 um
    5   ``rms_z``             RMS of z about its mean                                   / 50 um
    6   ``cage_speed_ratio``  mean cage speed / kinematic cage speed - 1                x 10
    7   ``cage_speed_ptp``    peak-to-peak cage speed / kinematic cage speed            x 10
    8   ``qpi``               quasi-periodicity index (period-1 ~0.001-0.03; > 0.1      none
                              quasi-periodic)
    9   ``preload``           actual axial preload                                      300-2000 N -> [-1, 1]
    10  ``setpoint``          last preload set-point (= the last action)                300-2000 N -> [-1, 1]
    11  ``shaft_speed``       shaft speed                                               / 25,000 rpm
    12  ``radial_offset``     mean radial displacement (carries the radial load)        / 100 um
    13  ``axial_offset``      mean axial displacement (carries clearance and preload)   / 100 um
    14  ``nonsync_rms``       RMS of the non-synchronous displacement (what the reward  / 10 um
                              charges for)
    ==  ====================  ========================================================  =========

    The ``field`` tier adds probe noise, runout and a drifting offset, and drops the cage-speed
    sensor (features 6-7 read 0).

    ## Rewards

    :class:`~bearing_gym.envs.reward.VibrationFirstReward` (its module docstring gives the
    reason for every weight): per interval, minus the sum of

    * vibration ``q (1 + min(a, 100 um) / 10 um)``: q = 1 if the interval is quasi-periodic
      (index > ``QPI_THRESHOLD`` = 0.1) else 0, a the RMS of the non-synchronous displacement
      (x, y, z after removing the shaft-synchronous series up to 3x);
    * heat ``h = 0.5 (P / 2000 N)^1.33 (n / 25,000 rpm)`` (Palmgren: friction heat ~ P^1.33 n);
    * fatigue ``C(0.5 u / u_ref, 1 - h)``: u the fraction of the bearing's L10 life the
      interval used per second, Lundberg-Palmgren from the model's contact loads at every
      Newmark step (each ball's inner and outer load, its centrifugal force included:
      ``bearing_gym.physics.rating``), u_ref the same at the costliest corner of the envelope
      (2000 N, 25,000 rpm, 500 N radial, 30 um clearance; static equilibrium); C a smooth
      cap, x up to 0.9 of the room 1 - h, then bending below it (``envs.reward.smooth_cap``);
    * actuation ``0.1 |Delta P| / 1700 N``;
    * termination (integrator failure): the worst cost of an interval times (1 + intervals left),
      so a crash never pays.

    Heat + fatigue cost less than 1 (0.975 at the costliest corner of the envelope), a quasi-periodic
    interval at least 1: vibration first, then heat and life, then actuation. Each term is in
    ``info`` as ``reward_vibration``, ``reward_heat``, ``reward_fatigue``, ``reward_actuation``,
    ``reward_termination``; ``info`` also has ``qpi`` (the true index, without sensor errors),
    ``quasi_periodic`` (bool), ``nonsync_rms_um`` (um), ``preload_n`` and ``setpoint_n`` (N),
    ``shaft_speed_rpm``, ``radial_load_n`` (N) and ``t`` (s into the episode), and what a
    spindle engineer checks of the interval: ``radial_stiffness_n_per_m`` and
    ``axial_stiffness_n_per_m`` (N/m, the bearing's at the mean displacement),
    ``max_inner_contact_load_n`` and ``max_outer_contact_load_n`` (N), ``life_used_per_s``
    (fraction of the L10 life per second), ``l10_life_h`` (h, the L10 life at the interval's
    loads and speed) and ``friction_torque_n_m`` (N m, Palmgren's load term);
    ``docs/environment.md`` defines each. Every ``info`` key but the reward terms and ``cost`` is
    privileged: a benchmark policy reads the observation only (docs/benchmark.md);
    :class:`~bearing_gym.envs.PrivilegedObservation` appends the hidden scenario parameters to the
    observation for research that wants them.

    **Cost** (safe RL): ``info["cost"]``, a float in every step's info and 0.0 in the reset info:
    1.0 if the interval was quasi-periodic, else 0.0; on termination 1 + the intervals left. The
    constrained variant maximises ``reward=constrained_reward()`` (this reward without its
    vibration term) with at most ``COST_BUDGET_PER_EPISODE`` = 15 quasi-periodic intervals per
    episode (``bearing_gym.task``; docs/benchmark.md).

    ## Starting State

    The scenario is drawn by the tier (or pinned by ``reset(options=...)``). The rotor starts
    from the static equilibrium of the initial operating point and initial preload, and
    ``reset`` runs it until it has settled (:meth:`bearing_gym.envs.core.PreloadBatch.settle`:
    1.46 s of simulated warm-up, with a damping aid where the motion is period-1; cached per
    operating point): the first observation and the first reward describe steady motion, not
    the ringing of the start. The reset info has the settled interval's ``qpi`` and
    ``nonsync_rms_um``.

    With ``start_bank`` the scenarios are a start bank's (drawn uniformly from the env's
    generator) and a reset copies the bank's settled start instead of settling (the same bits).

    ## Episode End

    Truncation after ``max_episode_steps`` = ``EPISODE_STEPS`` = 150 intervals (3 s), the
    registration's TimeLimit. Termination if the integrator fails (``info["termination_reason"]``
    says why); the observation stays finite.

    ## Arguments

    ``gymnasium.make("BearingPreload-v0", tier="transient", scenario=None, actuator=None,
    observation=None, reward=None, params=None, control_dt_s=0.02, episode_steps=150,
    render_mode=None, render_dir=None, start_bank=None)``

    * ``tier``: ``"paper"``, ``"stationary"``, ``"transient"`` (the main benchmark, default) or
      ``"field"`` (:mod:`bearing_gym.envs.tiers` says what each asks of a policy).
    * ``scenario``, ``actuator``, ``observation``, ``reward``: replace the tier's part with your
      own object (protocols in :mod:`bearing_gym.envs.parts` and the parts' modules); a
      dataclass part with an ``entry_point`` survives ``env.spec.to_json()``. ``scenario`` also
      takes a tier name (its scenarios) or a :class:`~bearing_gym.envs.Scenario`.
      ``reset(options={...})`` pins scenario fields (``shaft_speed_rpm``, ``radial_load_n``,
      ``clearance_m``, ``initial_preload_n``, ... or ``scenario=Scenario(...)``); an unknown
      option raises ``ValueError``.
    * ``params``: base :class:`~bearing_gym.params.BearingParams` (bearing, rotor, damping,
      integrator); default :func:`bearing_gym.envs.env_params` (the library's
      ``default_params`` with the env's 25 us step). Build yours with ``env_params(...)`` to
      keep that step; ``default_params(...)`` gives the analysis tools' 10 us.
      The rotor damping is one set of coefficients for every episode and preload (a property
      of the spindle): ``params.damping.coefficients`` if given, else the 2 % ratio referred to
      the stiffness at the base operating point (:func:`bearing_gym.envs.core.rotor_damping`).
    * ``control_dt_s``, ``episode_steps``: the control interval and the horizon that places the
      scenario's events in time (keep them at the defaults for the benchmark).
    * ``render_mode``: ``"rgb_array"``: ``render()`` returns the frame (H x W x 3 uint8);
      ``"human"``: ``reset()`` and ``step()`` draw the frame themselves (``render()`` returns
      None), see *Rendering*.
    * ``start_bank``: ``"shipped"`` (the package's bank of the tier: ``transient``'s training seeds
      0-2047), the path of a bank (``python -m bearing_gym.envs.start_bank``) or a
      :class:`~bearing_gym.envs.start_bank.StartBank`: episodes draw its scenarios and start from
      its settled states (a reset costs ~0.5 env steps instead of ~36: ``benchmarks/bench_reset.py``). Refused if another kernel
      made it or it was made for another tier, horizon or env settings, and with ``scenario``.
      Off by default: its scenarios are training scenarios only.
    * ``render_dir``: with ``render_mode="human"``, also save every frame there as
      ``frame_00000.png``, ``frame_00001.png``, ... (numbered over the env's life).

    ## Rendering

    A frame has three panels: the x-y orbit of the last control interval, the Poincare section
    (x, z once per shaft turn, last 2000 points) and the preload and set-point over the last
    500 intervals; in ``"human"`` mode its title gives t, preload, set-point and the
    quasi-periodicity index. ``"human"`` opens a matplotlib window when an interactive backend
    can open one (a display is available, or ``MPLBACKEND`` names one) and updates it after
    every step, pausing ``1 / metadata["render_fps"]`` s. Without one (a headless machine, the
    Agg backend) it writes the frames as PNG files instead: to ``render_dir`` if given, else
    the latest frame to ``<temp dir>/bearing_gym_frames/latest.png`` (overwritten each step; a warning
    names the path once). Closing the window stops the drawing, not the episode.

    ## Version History

    * v0 (the open board): ``info["cost"]`` (the quasi-periodic indicator, the safe-RL cost
      channel; 0.0 at reset), the constrained variant's ``constrained_reward()``
      (``VibrationFirstReward(vibration_weight=0)``), ``start_bank=`` and the privileged
      observation wrapper. The benchmark's observations, rewards and bits are unchanged (kernel
      6ff3acfe31277804).
    * v0 (benchmark v2: the fatigue term and the engineering ``info``): the fatigue term is the
      fraction of the L10 life used per second by Lundberg-Palmgren from the contact loads the
      model computes (inner and outer, every Newmark step, the balls' centrifugal force
      included), relative to the costliest corner of the envelope (now with its largest
      clearance), and capped smoothly so that heat + fatigue stay below 1; it was ISO 281's
      bearing-level ``(0.41 F_r + 0.87 P)^3 n``, which leaves the centrifugal force out and so
      overstated what preload does to life (at 25,000 rpm the fatigue cost is now 0.34-0.54
      whatever the preload, at 10,000 rpm about 0.001). On the reward map's 81 cells the best
      preload moves in 2 (docs/environment.md). ``info`` gains the bearing's radial and axial
      stiffness, the largest inner and outer contact loads, the life used, the L10 life and
      the friction torque; ``StepMeasurement`` gains ``contact``, ``life_used_per_s`` and
      ``friction_torque_n_m``; the integrator's scalar state accumulates the contact loads.
      The kernel costs 0.46x per ``transient`` step at the same accuracy (the ball Newton stops
      on its error estimate, the Hertz constant from a per-bearing polynomial, the waviness of
      all balls by rotation: docs/performance.md), which changes the last bits once more.
    * v0 (portable kernel): the same definition, now the same bits on every CPU: nothing that
      feeds the state, the observation or the reward calls libm, NumPy's SIMD transcendentals or
      BLAS/LAPACK (``bearing_gym.physics.portable_math``; docs/model.md). The last bits of every
      trajectory changed once (a quasi-periodic episode's return by a few per cent), and the
      ``field`` tier's probe-offset drift draws its normals by Box-Muller from the generator's
      uniforms instead of NumPy's ziggurat. A ``control_dt_s`` that is not a whole number of
      actuator updates, or an actuator ``update_interval_s`` that is not a whole number of
      integrator steps, is refused with the nearest valid values (it was rounded silently).
    * v0 (redefined in place before the first release): the integrator step of the env is
      25 us with a 1e-10 m Newmark tolerance (was 10 us, 1e-13 m: 3.3x less kernel time, the
      accuracy bounds of ``benchmarks/bench_accuracy.py`` hold); the reward is about vibration
      (quasi-periodic gate and non-synchronous amplitude instead of the normalised index; heat
      and fatigue on the envelope's scale; a termination costs at least any continuation), the
      start is settled, difficulty tiers (``tier=``, default ``"transient"``) replace the
      ``"randomized"`` scenario, the horizon is 150 intervals in registration, training and
      evaluation alike, the observation has the non-synchronous RMS (15 features), the parts
      are swappable objects and the rotor damping is fixed by the base parameters (it was
      referred to each episode's initial operating point).
    * v0 (first cut): 14 features, reward -(2 qpi + 0.3 heat + 0.1 fatigue + 0.1 |Delta P|),
      start at the static equilibrium, 250-interval registration horizon.
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 10}

    def __init__(self, tier: str = DEFAULTS["tier"], scenario: Any = None, actuator: Any = None,
                 observation: Any = None, reward: Any = None, params: BearingParams | None = None,
                 control_dt_s: float = DEFAULTS["control_dt_s"], episode_steps: int = DEFAULTS["episode_steps"],
                 render_mode: str | None = None, render_dir: str | os.PathLike | None = None,
                 start_bank: Any = None):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        scenario, bank = env_scenario(start_bank, scenario, tier)
        self.task = PreloadTask.build(tier, scenario, actuator, observation, reward, params, control_dt_s,
                                      episode_steps, num_envs=1)
        install_for(bank, self.task)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(1,), dtype=np.float32)
        self.observation_space = self.observation_model.space
        self.render_mode = render_mode
        self.render_dir = None if render_dir is None else Path(render_dir)
        self._window: HumanWindow | None = None      # render_mode="human", made on the first frame
        self._history: deque = deque(maxlen=500)
        self._poincare: deque = deque(maxlen=2000)
        self._idx = np.array([0])
        self._active = np.array([True])
        self._steps = 0
        self.scenario = None
        if self.episode_steps != DEFAULTS["episode_steps"]:
            gym.logger.warn(f"episode_steps={self.episode_steps} is not the benchmark's horizon "
                            f"({DEFAULTS['episode_steps']}); with gym.make pass max_episode_steps="
                            f"{self.episode_steps} too, or the registered time limit ends the episode elsewhere")

    @property
    def steps_taken(self) -> int:
        """Control intervals since the last reset."""
        return self._steps

    # ------------------------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.scenario = self.task.reset(self._idx, [self.np_random], options)[0]
        self._steps = 0
        self._history.clear()
        self._poincare.clear()
        obs, infos = self.task.reset_outputs(self._idx, [self.np_random])
        if self.render_mode == "human":
            self._render_human()
        return obs[0], infos[0]

    def step(self, action):
        if self.scenario is None:
            raise RuntimeError("call reset() before step()")
        a = check_actions(action, 1, single=True)
        b = self.batch
        before = b.preload[self._idx].copy()
        b.step(self.actuator.setpoint_n(a), self._active)
        self._steps += 1
        steps_left = np.array([max(self.episode_steps - self._steps, 0)])
        obs, reward, terminated, infos = self.task.step_outputs(self._idx, before, steps_left, [self.np_random])
        if self.render_mode is not None:
            self._remember()
        if self.render_mode == "human":
            self._render_human()
        return obs[0], float(reward[0]), bool(terminated[0]), False, infos[0]

    # ------------------------------------------------------------------------------------------
    def _remember(self) -> None:
        orbit = record_interval(self.batch, 0, self._history, self._poincare)
        if orbit is not None:
            self._orbit = orbit

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        return rgb_frame(getattr(self, "_orbit", None), self._poincare, self._history)

    def _draw(self, fig) -> None:
        """The three panels of a frame, drawn on ``fig``."""
        draw_frame(fig, getattr(self, "_orbit", None), self._poincare, self._history)

    # ------------------------------------------------------------------------------------------
    def _render_human(self) -> None:
        """Draw the frame in the window, and/or save it as PNG (see *Rendering*)."""
        if self._window is None:
            self._window = HumanWindow(self.render_dir, self.metadata["render_fps"], warn=gym.logger.warn)
        self._window.show(self._draw, self._title())

    def _title(self) -> str:
        if not self._history:
            return f"t = 0 s, preload {float(self.batch.preload[0]):.0f} N (reset)"
        t, p, sp, q = self._history[-1]
        return (f"t = {t:.2f} s, preload {p:.0f} N, set-point {sp:.0f} N, "
                f"quasi-periodicity index {q:.3f}")

    @property
    def human_render_target(self) -> str | None:
        """Where ``render_mode="human"`` draws, once the first frame is out: ``"window"``, the
        frames folder (``render_dir``), the latest-frame PNG (headless, no ``render_dir``), or
        None (not human mode, nothing drawn yet, or the window was closed)."""
        if self.render_mode != "human" or self._window is None:
            return None
        return self._window.target

    def close(self) -> None:
        if self._window is not None:
            self._window.close()
        super().close()
