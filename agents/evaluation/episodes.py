"""Running policies on episodes: one batched loop for scripted and learned controllers alike.

:func:`run_policies` runs every policy on the same scenarios (env i of the batch is seeded
``seed + i``, so every policy meets the same ones) and returns one
:class:`agents.evaluation.result.EvalResult` per policy: every episode's return, each reward
term, the fraction of control intervals spent quasi-periodic (index > QPI_THRESHOLD = 0.1), the
mean preload, the episodes that terminated early and the safe-RL cost (the sum of ``info["cost"]``).
:func:`constant_sweep` runs a grid of constant preloads the same way, :func:`hindsight_constant` picks the best of them per episode.
"""

from __future__ import annotations

import time
from typing import Any, Callable

import numpy as np

from bearing_gym.envs import BearingPreloadVectorEnv
from bearing_gym.envs.reward import REWARD_TERMS

from agents.evaluation.result import EvalResult
from agents.policies.scripted import ConstantPreload, Policy
from agents.protocol import TEST


TEST_SEED = TEST.start      # first held-out test seed (agents.protocol keeps the ranges apart)


class _Progress:
    """Plain progress lines (they read the same in a terminal and in a log file): the first at
    once, then at most one per ``every_s`` seconds, and the last when done."""

    def __init__(self, label: str | None, total: int, every_s: float = 30.0):
        self.label, self.total, self.every_s = label, total, every_s
        self.t0 = self.last = time.monotonic()
        if label:
            print(f"{label}: step 0/{total}", flush=True)
        if label and ":" in label:        # "name: what it runs" -> later lines say only "name"
            self.label = label.split(":")[0]

    def update(self, done: int) -> None:
        now = time.monotonic()
        if not self.label or (done < self.total and now - self.last < self.every_s):
            return
        self.last = now
        el = now - self.t0
        eta = "" if done >= self.total else f", about {el / max(done, 1) * (self.total - done) / 60:.1f} min left"
        print(f"{self.label}: step {done}/{self.total} ({100 * done / self.total:.0f} %), "
              f"{el / 60:.1f} min{eta}", flush=True)


def run_policies(policies: list[Policy], episodes: int, seed: int, episode_steps: int,
                 env_kwargs: dict | None = None, num_threads: int | None = None,
                 progress: str | None = None, progress_every_s: float = 30.0,
                 perturb: Callable[[Any, list[int]], None] | None = None) -> list[EvalResult]:
    """Run every policy on ``episodes`` scenarios (seeds seed .. seed+episodes-1), all in one
    batched env (policies x episodes environments).

    ``perturb(venv, seeds)``, if given, is called once after the reset, before the first action:
    it may change the settled physics state of the envs (``agents.leaderboard.chaos`` nudges it by 1e-15).

    An episode that terminates early (the integrator diverged) ends there: its return, reward
    terms, quasi-periodic fraction and mean preload cover the steps it ran, and
    ``EvalResult.terminated`` marks it. With ``progress`` (a label), a line ``label: step k/N``
    is printed at the start, at most every ``progress_every_s`` seconds, and at the end."""
    n_pol = len(policies)
    n = n_pol * episodes
    venv = BearingPreloadVectorEnv(num_envs=n, max_episode_steps=None, episode_steps=episode_steps,
                                   num_threads=num_threads, **(env_kwargs or {}))
    seeds = [seed + (i % episodes) for i in range(n)]
    obs, _ = venv.reset(seed=seeds)
    if perturb is not None:
        perturb(venv, seeds)
    first_obs = np.array(obs, copy=True)
    alive = np.ones(n, dtype=bool)
    terminated = np.zeros(n, dtype=bool)
    ret = np.zeros(n)
    terms = {k: np.zeros(n) for k in REWARD_TERMS}
    qp = np.zeros(n)
    preload_sum = np.zeros(n)
    vibration_sum = np.zeros(n)
    cost = np.zeros(n)
    steps = np.zeros(n)
    states: list[Any] = [None] * n_pol
    starts = np.ones(episodes, dtype=bool)
    keys = ("t", "preload_n", "setpoint_n", "qpi", "shaft_speed_rpm", "radial_load_n")
    traces = [{k: [] for k in keys + ("ptp_x_um",)} for _ in range(n_pol)]
    first_scenarios = [venv.scenarios[p * episodes] for p in range(n_pol)]
    report = _Progress(progress, episode_steps, progress_every_s)
    for k in range(episode_steps):
        actions = np.zeros((n, 1), dtype=np.float32)
        for p, pol in enumerate(policies):
            sl = slice(p * episodes, (p + 1) * episodes)
            if hasattr(pol, "set_conditions"):          # an oracle: told the true operating point
                speed, radial, clearance, eccentricity = venv.operating_points()
                pol.set_conditions(speed[sl], radial[sl], clearance[sl], eccentricity[sl])
            act, states[p] = pol.predict(obs[sl], state=states[p], episode_start=starts, deterministic=True)
            actions[sl] = np.asarray(act, dtype=np.float32).reshape(episodes, 1)
        starts = np.zeros(episodes, dtype=bool)
        obs, rew, term, trunc, info = venv.step(actions)
        # every env still alive was stepped (only ended ones are autoreset), so its info is there
        ret[alive] += rew[alive]
        for key in REWARD_TERMS:
            terms[key][alive] += info[f"reward_{key}"][alive]
        qp[alive] += info["quasi_periodic"][alive]
        preload_sum[alive] += info["preload_n"][alive]
        vibration_sum[alive] += info["nonsync_rms_um"][alive]
        cost[alive] += info["cost"][alive]
        steps[alive] += 1
        for p in range(n_pol):
            b = p * episodes
            if not alive[b]:          # the traced episode has ended: what follows is a new one
                continue
            tr = traces[p]
            for key in keys:
                tr[key].append(info[key][b])
            tr["ptp_x_um"].append(obs[b, 0] * 100.0)
        terminated |= alive & term
        alive &= ~term
        report.update(k + 1)
        if not alive.any():           # all ended early; the next step would only autoreset them
            if progress:
                print(f"{report.label}: every episode ended early, by step {k + 1}/{episode_steps}", flush=True)
            break
    out = []
    for p, pol in enumerate(policies):
        sl = slice(p * episodes, (p + 1) * episodes)
        out.append(EvalResult(pol.name, ret[sl].copy(), {k: v[sl].copy() for k, v in terms.items()},
                              qp[sl] / np.maximum(steps[sl], 1), preload_sum[sl] / np.maximum(steps[sl], 1),
                              {k: np.array(v) for k, v in traces[p].items()},
                              terminated=terminated[sl].copy(), scenario=first_scenarios[p],
                              first_obs=first_obs[sl], vibration_um=vibration_sum[sl] / np.maximum(steps[sl], 1),
                              cost=cost[sl].copy()))
    return out


def constant_sweep(preloads_n, episodes: int, seed: int, episode_steps: int, **kw) -> list[EvalResult]:
    """Every constant preload of ``preloads_n`` on the same scenarios (seeds seed ..
    seed+episodes-1), in one batch (``kw`` as for :func:`run_policies`)."""
    return run_policies([ConstantPreload(float(p)) for p in preloads_n], episodes, seed, episode_steps, **kw)


def sweep_row(sweep: list[EvalResult], preload_n: float) -> EvalResult | None:
    """The sweep's result for the constant ``preload_n`` (None if it was not swept)."""
    name = ConstantPreload(preload_n).name
    return next((r for r in sweep if r.name == name), None)


def hindsight_preloads(sweep: list[EvalResult], preloads_n) -> list[float]:
    """Each episode's hindsight best constant (first best on ties, as :func:`hindsight_constant`
    picks it) of ``sweep``, the result of :func:`constant_sweep` over ``preloads_n``."""
    names = [ConstantPreload(float(p)).name for p in preloads_n]
    if [r.name for r in sweep] != names:
        raise ValueError(f"the sweep's rows {[r.name for r in sweep][:3]}... are not those of {names[:3]}...")
    pick = np.argmax(np.array([r.returns for r in sweep]), axis=0)
    return [float(preloads_n[k]) for k in pick]


def hindsight_constant(sweep: list[EvalResult]) -> EvalResult:
    """Per scenario, the best of the swept constant preloads chosen with hindsight (knowing the
    scenario's outcome): a clairvoyant reference that no fixed-preload practice can beat."""
    returns = np.array([r.returns for r in sweep])          # (candidates, episodes)
    pick = np.argmax(returns, axis=0)
    cols = np.arange(returns.shape[1])

    def chosen(values: list[np.ndarray]) -> np.ndarray:
        return np.array(values)[pick, cols]

    first = sweep[int(pick[0])]     # the trace is the first scenario's: its chosen constant
    terminated = chosen([np.zeros(len(r.returns), bool) if r.terminated is None else r.terminated for r in sweep])
    vibration = (None if any(r.vibration_um is None for r in sweep)
                 else chosen([r.vibration_um for r in sweep]))
    return EvalResult("best constant per scenario (hindsight)", returns[pick, cols],
                      {k: chosen([r.terms[k] for r in sweep]) for k in REWARD_TERMS},
                      chosen([r.qp_fraction for r in sweep]), chosen([r.mean_preload for r in sweep]),
                      trace=first.trace, terminated=terminated, scenario=first.scenario,
                      trace_label=f"hindsight: {first.name}", vibration_um=vibration)
