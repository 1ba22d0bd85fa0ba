"""What a training run is made of, shared by train.py and protocol v2's search
(:mod:`agents.training.tuning`): the hyperparameters of an RL Zoo file, the start bank a run draws
from, and the training env (the native batched env behind SB3's VecEnv interface)."""

from __future__ import annotations

from pathlib import Path

from agents.paths import HYPERPARAMS_DIR

__all__ = ["hyperparams", "load_start_bank", "make_env"]


def hyperparams(algo: str, protocol: int = 1) -> dict:
    """The SB3 keyword arguments of ``algo``'s RL Zoo file (agents/hyperparams/<algo>.yml; protocol
    2's tuned ones in agents/hyperparams/v2/): its settings without RL Zoo's own keys,
    ``policy_kwargs`` evaluated from its string."""
    import yaml
    path = HYPERPARAMS_DIR / ("" if protocol == 1 else f"v{protocol}") / f"{algo}.yml"
    if not path.exists():
        raise SystemExit(f"no hyperparameters for {algo} under protocol {protocol}: {path} is missing (protocol 2's "
                         f"come from its search: python -m agents.training.tuning --algo {algo} --until HH:MM)")
    cfg = yaml.safe_load(path.read_text())["BearingPreload-v0"]
    out = {k: v for k, v in cfg.items() if k not in ("n_timesteps", "policy", "normalize", "n_envs", "policy_kwargs", "env_kwargs")}
    if "policy_kwargs" in cfg:
        out["policy_kwargs"] = eval(cfg["policy_kwargs"], {"dict": dict})  # RL Zoo stores it as a string
    return out


def load_start_bank(path: str | Path, tier: str, episode_steps: int):
    """The start bank at ``path`` if it fits a run on ``tier`` with ``episode_steps``-step
    episodes and the env's default physics and timing; ValueError saying why not
    (:func:`bearing_gym.envs.start_bank.check_fits`)."""
    from bearing_gym.envs import BearingPreloadVectorEnv
    from bearing_gym.envs import start_bank as banks
    try:
        bank = banks.load(path)
    except OSError as err:
        raise ValueError(str(err)) from None
    probe = BearingPreloadVectorEnv(num_envs=1, tier=tier, episode_steps=episode_steps, max_episode_steps=None)
    try:
        return banks.check_fits(bank, tier, episode_steps, probe.batch)
    finally:
        probe.close()


def make_env(n_envs: int, seed: int, episode_steps: int, tier: str, threads: int | None = None,
             start_bank=None, bank_draws_done: int = 0):
    """``n_envs`` environments stepped by one numba kernel on ``threads`` threads (default: one
    per env, at most numba's thread count - the cores, or ``NUMBA_NUM_THREADS`` if set); with
    ``start_bank`` (a loaded bank, or the path of a .npz of :mod:`bearing_gym.envs.start_bank`:
    SystemExit if it does not fit the run) they draw its scenarios, skipping the first
    ``bank_draws_done`` of the order (a resumed run: those its earlier sessions drew), and copy
    its settled starts."""
    import numba
    from stable_baselines3.common.vec_env import VecMonitor

    from bearing_gym.envs import BearingPreloadSB3VecEnv
    extra = {}
    if start_bank is not None:
        from bearing_gym.envs import start_bank as banks
        if isinstance(start_bank, (str, Path)):
            try:
                start_bank = load_start_bank(start_bank, tier, episode_steps)
            except ValueError as err:
                raise SystemExit(f"train.py: --start-bank: {err}") from None
        extra["scenario"] = banks.BankScenarios(start_bank.install(), skip=bank_draws_done)
    venv = BearingPreloadSB3VecEnv(num_envs=n_envs, tier=tier, episode_steps=episode_steps,
                                   max_episode_steps=episode_steps,
                                   num_threads=threads or min(n_envs, numba.config.NUMBA_NUM_THREADS), **extra)
    venv.seed(seed)
    return VecMonitor(venv)
