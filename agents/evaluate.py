"""Evaluate preload controllers side by side on the same held-out scenarios.

    python -m agents.evaluate --model DIR [DIR ...] [--episodes 20] [--tier transient] [--seed 300000]
    python -m agents.evaluate --pretrained [--episodes 20]      # the shipped policies of agents/pretrained/

Runs the trained policy in each DIR (``model.zip`` + ``vec_normalize.pkl`` from ``train.py``;
several DIRs put PPO and SAC side by side) and every scripted baseline on the same seeds (env i
of the batch is seeded ``seed + i``, so every policy meets the same scenarios): among them the
best constant preload chosen on the validation seeds (read from
``agents/data/reference_constants.json``, never chosen on these episodes) and, per scenario, the
best constant of a 50 N grid over the actuator's whole range with hindsight. It writes
``DIR/evaluation.md``, ``DIR/evaluation.csv``, ``DIR/evaluation_episodes.csv`` (every episode's
return per policy) and ``DIR/evaluation_traces.png``. Per policy: mean return with a 95 % confidence interval
(Student t over episodes), the mean of each reward term, the fraction of control intervals spent
quasi-periodic (index > QPI_THRESHOLD = 0.1), the mean preload and the number of episodes that terminated early
(the integrator diverged: the episode ends there, its return holds the termination penalty).
The report is :mod:`agents.eval_report`; a policy's results, :class:`agents.eval_result.EvalResult`.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from bearing_gym.envs import BearingPreloadVectorEnv
from bearing_gym.envs.reward import REWARD_TERMS
from bearing_gym.benchmark import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from .eval_report import write_report
from .eval_result import EvalResult
from .oracle import MapOracle
from .policies import ConstantPreload, FeedbackRule, Policy, SpeedScheduledPreload
from .protocol import HINDSIGHT_GRID_STEP_N, TEST, preload_grid
from .reference_store import STORE_PATH, ValidationChoice, load_choice, rebuild_command
from .results_file import ROOT
from .stability_table import StabilityTable

TEST_SEED = TEST.start      # first held-out test seed (agents.protocol keeps the ranges apart)
#: The algorithms load_trained knows: train.py's --algo -> (module, class).
ALGORITHM_CLASSES = {"ppo": ("stable_baselines3", "PPO"), "sac": ("stable_baselines3", "SAC"),
                     "ppo_lstm": ("sb3_contrib", "RecurrentPPO")}
#: The shipped policies: ``<algo>/`` directories of model.zip + vec_normalize.pkl (+ config.json).
PRETRAINED_DIR = Path(__file__).with_name("pretrained")


def shipped_dirs(pretrained_dir: Path = PRETRAINED_DIR, required: bool = True) -> list[Path]:
    """The shipped policies' directories (``pretrained_dir/<algo>/`` holding a model.zip), sorted;
    if there is none: FileNotFoundError saying what to do, or [] when not ``required``."""
    found = sorted(p for p in pretrained_dir.glob("*") if (p / "model.zip").exists()) if pretrained_dir.exists() else []
    if not found and required:
        raise FileNotFoundError(f"--pretrained: no shipped policy in {pretrained_dir}/<algo>/ (each needs model.zip "
                                "and vec_normalize.pkl, as train.py writes them); copy the best run of each "
                                "algorithm there, or leave out --pretrained")
    return found


class SB3Policy(Policy):
    """A trained SB3 model behind the scripted-policy interface (observations normalised with
    the saved VecNormalize statistics, deterministic actions)."""

    def __init__(self, model, obs_rms=None, clip_obs: float = 10.0, epsilon: float = 1e-8, name: str = "trained"):
        super().__init__()
        self.model, self.obs_rms, self.clip_obs, self.epsilon = model, obs_rms, clip_obs, epsilon
        self.name = name

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        o = np.asarray(obs, dtype=np.float32)
        if self.obs_rms is not None:
            o = np.clip((o - self.obs_rms.mean) / np.sqrt(self.obs_rms.var + self.epsilon),
                        -self.clip_obs, self.clip_obs).astype(np.float32)
        act, state = self.model.predict(o, state=state, episode_start=episode_start, deterministic=deterministic)
        return np.clip(act, -1.0, 1.0), state


def load_trained(model_dir: str | Path, algo: str | None = None, portable: bool = False) -> Policy:
    """The SB3 model in ``model_dir`` (``model.zip``, with ``vec_normalize.pkl`` if there) behind
    the scripted-policy interface. The algorithm is ``algo`` or, if None, ``config.json``'s
    (train.py writes it): one of ALGORITHM_CLASSES.

    ``portable=True``: the same deterministic policy evaluated in float64 without torch
    (:class:`agents.portable_policy.PortablePolicy`; from ``portable_policy.npz`` if it was
    exported from the model files there now, else from the model's weights now): the same
    actions, bit for bit, on every CPU. ValueError for an architecture it does not cover."""
    if portable:
        from .portable_policy import PortablePolicy, export_arrays, is_current
        if is_current(model_dir):           # exported from these very model files (else: export now)
            cfg_path = Path(model_dir) / "config.json"
            cfg = json.loads(cfg_path.read_text()) if cfg_path.exists() else {}
            return PortablePolicy.load(model_dir, name=_trained_name(algo or cfg.get("algo", "policy"), cfg))
        sb3 = load_trained(model_dir, algo)
        return PortablePolicy(export_arrays(sb3.model, sb3.obs_rms, sb3.clip_obs, sb3.epsilon), name=sb3.name)
    import importlib
    import pickle

    model_dir = Path(model_dir)
    cfg_path = model_dir / "config.json"
    cfg = json.loads(cfg_path.read_text()) if cfg_path.exists() else {}
    algo = algo or cfg.get("algo")
    if algo is None:
        raise ValueError(f"{model_dir}: no config.json says which algorithm model.zip is; pass algo= "
                         f"(one of {', '.join(ALGORITHM_CLASSES)})")
    if algo not in ALGORITHM_CLASSES:
        raise ValueError(f"{model_dir}: unknown algorithm {algo!r}; known: {', '.join(ALGORITHM_CLASSES)}")
    module, cls_name = ALGORITHM_CLASSES[algo]
    try:
        cls = getattr(importlib.import_module(module), cls_name)
    except ImportError as err:
        raise ImportError(f"{algo} needs the package {module.replace('_', '-')}: pip install "
                          f"{module.replace('_', '-')}") from err
    if not (model_dir / "model.zip").exists():
        raise FileNotFoundError(f"{model_dir / 'model.zip'} not found: point at a directory written by "
                                "train.py (or a shipped policy directory)")
    model = cls.load(model_dir / "model.zip", device="cpu")
    obs_rms = None
    vn = model_dir / "vec_normalize.pkl"
    if vn.exists():
        with vn.open("rb") as fh:
            obs_rms = pickle.load(fh).obs_rms
    return SB3Policy(model, obs_rms, name=_trained_name(algo, cfg))


def _trained_name(algo: str, cfg: dict) -> str:
    steps = cfg.get("selected_timesteps", cfg.get("num_timesteps"))
    detail = "" if steps is None else f", {int(steps):,} steps"
    return f"{algo.upper()} (trained{detail})"


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
    it may change the settled physics state of the envs (``agents.chaos`` nudges it by 1e-15).

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
                speed, radial, clearance = venv.operating_points()
                pol.set_conditions(speed[sl], radial[sl], clearance[sl])
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
                              first_obs=first_obs[sl], vibration_um=vibration_sum[sl] / np.maximum(steps[sl], 1)))
    return out


def constant_sweep(preloads_n, episodes: int, seed: int, episode_steps: int, **kw) -> list[EvalResult]:
    """Every constant preload of ``preloads_n`` on the same scenarios (seeds seed ..
    seed+episodes-1), in one batch (``kw`` as for :func:`run_policies`)."""
    return run_policies([ConstantPreload(float(p)) for p in preloads_n], episodes, seed, episode_steps, **kw)


def sweep_row(sweep: list[EvalResult], preload_n: float) -> EvalResult | None:
    """The sweep's result for the constant ``preload_n`` (None if it was not swept)."""
    name = ConstantPreload(preload_n).name
    return next((r for r in sweep if r.name == name), None)


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


def baselines(table: StabilityTable | None) -> list[Policy]:
    """The scripted controllers besides the constant preloads (those come from the sweep)."""
    pols: list[Policy] = [FeedbackRule()]
    if table is not None:
        pols += [SpeedScheduledPreload(table)]
    pols.append(MapOracle())
    return pols


def stored_choice(tier: str, store_path: str | Path = STORE_PATH, verbose: bool = True) -> ValidationChoice | None:
    """The validation-chosen constant of ``tier`` from the store, or None (with a warning that
    says how to build it) if the store has none."""
    try:
        return load_choice(tier, store_path)
    except LookupError as err:
        if verbose:
            print(f"warning: {err}; the report has no validation-chosen constant row", flush=True)
        return None


def evaluate(model_dir: str | Path | list[str | Path] | None, episodes: int = 20, seed: int = TEST_SEED,
             episode_steps: int = EPISODE_STEPS, out_dir: str | Path | None = None,
             table_path: str | Path | None = None, verbose: bool = True,
             progress_every_s: float = 30.0, tier: str = DEFAULT_TIER,
             store_path: str | Path = STORE_PATH, grid_step_n: float = HINDSIGHT_GRID_STEP_N) -> list[EvalResult]:
    """Every policy (the trained ones in ``model_dir``, the scripted baselines, the constant
    preloads) on the same held-out scenarios; writes the report files to ``out_dir`` (default:
    the first model directory, else ``evaluation/``). With ``verbose``, progress lines (at most
    one per ``progress_every_s`` seconds per phase) and the table are printed.

    The best constant preload is the one stored for ``tier`` in ``store_path`` (chosen on
    validation seeds by ``python -m agents.references``), never chosen on these episodes; the
    hindsight reference is the best constant per scenario of a ``grid_step_n`` grid over the
    actuator's whole range (the stored constant's row is that sweep's run of it)."""
    try:
        table = StabilityTable.load(table_path) if table_path else StabilityTable.load()
    except FileNotFoundError as err:
        print(f"warning: {err}; speed-schedule and oracle baselines skipped")
        table = None
    if model_dir is None:
        model_dirs = []
    elif isinstance(model_dir, (str, Path)):
        model_dirs = [model_dir]
    else:
        model_dirs = list(model_dir)
    policies: list[Policy] = [load_trained(d) for d in model_dirs]
    policies += baselines(table)
    choice = stored_choice(tier, store_path, verbose)
    grid = preload_grid(grid_step_n)
    if choice is not None and choice.preload_n not in grid:     # a store built on another grid
        grid = tuple(sorted(set(grid) | {choice.preload_n}))
    shape = f"{episodes} held-out episodes of {episode_steps} steps, stepped together"
    kw = {"env_kwargs": {"tier": tier}, "progress_every_s": progress_every_s}
    sweep = constant_sweep(grid, episodes, seed, episode_steps, **kw,
                           progress=f"evaluation 1/2: {len(grid)} constant preloads x {shape}" if verbose else None)
    results = run_policies(policies, episodes, seed, episode_steps, **kw,
                           progress=f"evaluation 2/2: {len(policies)} policies x {shape}" if verbose else None)
    hindsight = hindsight_constant(sweep)
    # the stored constant's row is its sweep run (same scenarios, deterministic): no second run
    chosen = []
    if choice is not None:
        chosen = [dataclasses.replace(sweep_row(sweep, choice.preload_n),
                                      name=f"constant {choice.preload_n:.0f} N (validation choice)")]
    results = results[:len(model_dirs)] + chosen + results[len(model_dirs):] + [hindsight]
    out = Path(out_dir or (model_dirs[0] if model_dirs else "evaluation"))
    definition = (" (the registered BearingPreload-v0)" if tier == DEFAULT_TIER and episode_steps == EPISODE_STEPS
                  else " (not the benchmark definition)")
    if choice is None:
        best = f"no validation-chosen constant is stored for tier {tier} (`{rebuild_command(tier)}` builds it)"
    else:
        problems = choice.protocol_problems()
        best = (f"best constant preload chosen on the validation seeds, not on these: {choice.describe()}"
                + (f" (provisional: {'; '.join(problems)})" if problems else ""))
    header = (f"Held-out seeds {seed}..{seed + episodes - 1}, {episodes} episodes of {episode_steps} control "
              f"intervals (20 ms) each, tier {tier}{definition}; {best}. The last row picks, for each scenario, "
              f"the best constant of a {grid_step_n:g} N grid over {grid[0]:.0f}-{grid[-1]:.0f} N "
              f"({len(grid)} preloads) with hindsight.")
    reference = chosen[0].name if chosen else hindsight.name
    write_report(results, out, header, reference=reference, first_seed=seed)
    if verbose:
        print((out / "evaluation.md").read_text())
    return results


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", nargs="+", help="directories written by train.py, evaluated side by side "
                    "(omit to evaluate the baselines only)")
    ap.add_argument("--pretrained", action="store_true",
                    help="add the shipped policies of agents/pretrained/<algo>/ (written to runs/evaluation_pretrained/ "
                         "unless --out or --model says where); their normalised scores against the stored references: "
                         "python -m agents.leaderboard --pretrained --stored-references")
    ap.add_argument("--episodes", type=int, default=20)
    ap.add_argument("--episode-steps", type=int, default=EPISODE_STEPS,
                    help="control intervals per episode (default: the benchmark's horizon)")
    ap.add_argument("--seed", type=int, default=TEST_SEED)
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    ap.add_argument("--out", help="output directory (default: the first model directory; with --pretrained alone "
                                  "runs/evaluation_pretrained/; with neither, evaluation/)")
    return ap


def main(argv: list[str] | None = None) -> None:
    ap = build_parser()
    args = ap.parse_args(argv)
    if args.episodes < 2:
        ap.error("--episodes must be >= 2 (a confidence interval needs two episodes)")
    models: list[str | Path] = list(args.model or [])
    out = args.out
    if args.pretrained:
        models += shipped_dirs()
        if out is None and not args.model:      # never write reports into the shipped policies' directories
            out = ROOT / "runs" / "evaluation_pretrained"
    evaluate(models or None, args.episodes, args.seed, args.episode_steps, out, tier=args.tier)


if __name__ == "__main__":
    main()
