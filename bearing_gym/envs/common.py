"""Logic shared by the single and the vector environment (one place, so both behave alike)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from bearing_gym.physics.rotor import ST_OK

from .core import PreloadBatch
from .observation import ObservationModel
from .reward import REWARD_TERMS, RewardModel
from .scenario import Scenario

_TERMINATION_TEXT = {
    1: "ball equilibrium did not converge",
    2: "ball equilibrium Jacobian singular",
    3: "Newmark iterations did not converge",
    4: "integrator diverged (displacement beyond limit or not finite)",
}


def configure(env, scenario, control_dt_s: float, actuator, reward, observation, params,
              episode_steps: int, obs_noise_std, num_envs: int) -> None:
    """Set the components every preload env has (single or vector) on ``env``: scenario
    distribution, actuator, reward and observation models, the physics batch and the spaces'
    single-env shapes. Validates the arguments shared by both envs."""
    from bearing_gym.params import _check_real

    from .actuator import PreloadActuator
    from .scenario import scenario_distribution
    _check_real("control_dt_s", control_dt_s, 1e-3, 1.0)
    if isinstance(episode_steps, bool) or not isinstance(episode_steps, (int, np.integer)) or episode_steps < 1:
        raise ValueError(f"episode_steps must be an integer >= 1, got {episode_steps!r}")
    env.scenario_dist = scenario_distribution(scenario)
    env.actuator = actuator or PreloadActuator()
    env.reward_model = reward or RewardModel()
    obs_model = observation or ObservationModel()
    if obs_noise_std is not None:
        obs_model = ObservationModel(noise_std=_check_real("obs_noise_std", obs_noise_std, 0.0, 10.0))
    env.observation_model = obs_model
    env.episode_steps = int(episode_steps)
    env._batch = PreloadBatch(num_envs, params, control_dt_s, env.actuator)
    env.control_dt_s = env._batch.control_dt_s


def check_actions(actions: np.ndarray, n: int) -> np.ndarray:
    """Validate a batch of actions (n, 1) in [-1, 1]; raise ValueError naming the problem."""
    a = np.asarray(actions, dtype=np.float64)
    if a.size != n:
        raise ValueError(f"action must have {n} element(s) (shape ({n}, 1) or ({n},) for a batch), got shape {a.shape}")
    a = a.reshape(n)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"action contains NaN or infinity: {a.tolist()}; actions must be finite numbers in [-1, 1]")
    if np.any(a < -1.0) or np.any(a > 1.0):
        raise ValueError(f"action {a.tolist()} is outside the action space [-1, 1]; scale it (the env does not clip)")
    return a


def reset_one(batch: PreloadBatch, b: int, rng: np.random.Generator, dist, episode_s: float,
              options: Mapping[str, Any] | None) -> Scenario:
    """Draw (or take from options) env b's scenario and start it at its static equilibrium."""
    opts = dict(options or {})
    if "scenario" in opts:
        sc = opts.pop("scenario")
        if not isinstance(sc, Scenario):
            raise ValueError(f"options['scenario'] must be a Scenario, got {type(sc).__name__}")
        scenario = dataclasses.replace(sc, **dist_pinned(opts)) if opts else sc
    else:
        scenario = dist.sample(rng, episode_s, opts or None)
    batch.load(b, scenario)
    return scenario


def dist_pinned(opts: Mapping[str, Any]) -> dict[str, Any]:
    from .scenario import _check_pinned
    return _check_pinned(opts)


def initial_observation(batch: PreloadBatch, idx: np.ndarray, obs_model: ObservationModel,
                        rngs) -> np.ndarray:
    """Observation at reset: no motion yet (interval features zero), the static offsets of the
    equilibrium the rotor starts at, actual preload and speed."""
    from bearing_gym.analysis.window import F_CAGE_MEAN, F_MEAN_X
    from bearing_gym.physics.rotor import S_CAGE_SPEED
    feats = np.zeros((len(idx), batch.feats.shape[1]))
    feats[:, F_CAGE_MEAN] = batch.scal[idx, S_CAGE_SPEED]
    feats[:, F_MEAN_X:F_MEAN_X + 3] = batch.X[idx, 0:3]
    a = batch.actuator
    return obs_model.build(feats, batch.preload[idx], batch.setpoint[idx], batch.omega()[idx],
                           batch.gamma_cos_a0, a.min_preload_n, a.max_preload_n, rngs)


def step_outputs(batch: PreloadBatch, idx: np.ndarray, preload_before: np.ndarray,
                 obs_model: ObservationModel, reward_model: RewardModel, rngs):
    """Observations, rewards, terminations and infos of envs ``idx`` after a kernel step."""
    a = batch.actuator
    omega = batch.omega()[idx]
    status = batch.status[idx]
    feats = batch.feats[idx]
    obs = obs_model.build(feats, batch.preload[idx], batch.setpoint[idx], omega,
                          batch.gamma_cos_a0, a.min_preload_n, a.max_preload_n, rngs)
    qpi = feats[:, 8]
    terms = reward_model.terms(qpi, batch.preload[idx], preload_before, omega,
                               batch.radial_load_n()[idx])
    reward = sum(terms[k] for k in REWARD_TERMS)
    terminated = status != ST_OK
    reward = np.where(terminated, reward - reward_model.termination_penalty, reward)
    infos = []
    for i, b in enumerate(idx):
        info = {f"reward_{k}": float(terms[k][i]) for k in REWARD_TERMS}
        info.update(preload_n=float(batch.preload[b]), setpoint_n=float(batch.setpoint[b]),
                    shaft_speed_rpm=float(omega[i] * 30.0 / np.pi),
                    radial_load_n=float(batch.radial_load_n()[b]), qpi=float(qpi[i]),
                    quasi_periodic=bool(qpi[i] > 0.3), t=float(batch.t_episode[b]))
        if terminated[i]:
            info["termination_reason"] = _TERMINATION_TEXT.get(int(status[i]), f"status {int(status[i])}")
        infos.append(info)
    return obs, reward.astype(np.float64), terminated, infos
