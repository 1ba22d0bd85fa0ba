"""Trained SB3 models (train.py's directories and the shipped ones in ``agents/pretrained/``)
behind the scripted-policy interface: :func:`load_trained` through torch, with ``portable=True``
in float64 without torch (:class:`agents.policies.portable.PortablePolicy`: the same bits on every
CPU), or with ``portable="auto"`` as the board loads a model (portable where it covers the
architecture, torch elsewhere); :func:`is_model_dir` says whether a directory holds a model;
:func:`export` writes the portable weights beside ``model.zip``.

    python -m agents.evaluation.trained DIR [DIR ...]     # writes DIR/portable_policy.npz
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import Literal

import numpy as np

from agents.paths import PRETRAINED_DIR
from agents.policies.scripted import Policy
from agents.policies.portable import PORTABLE_FILE, export_arrays, source_digest


#: The algorithms load_trained knows: train.py's --algo -> (module, class).
ALGORITHM_CLASSES = {"ppo": ("stable_baselines3", "PPO"), "sac": ("stable_baselines3", "SAC"),
                     "ppo_lstm": ("sb3_contrib", "RecurrentPPO"), "tqc": ("sb3_contrib", "TQC"),
                     "crossq": ("sb3_contrib", "CrossQ")}



def is_model_dir(model_dir: str | Path) -> bool:
    """Whether ``model_dir`` holds a model :func:`load_trained` can load: train.py's ``model.zip``,
    or a shipped or collected run's portable export alone (``portable_policy.npz``)."""
    d = Path(model_dir)
    return (d / "model.zip").is_file() or (d / PORTABLE_FILE).is_file()


def shipped_dirs(pretrained_dir: Path = PRETRAINED_DIR, required: bool = True) -> list[Path]:
    """The shipped policies' directories (``pretrained_dir/<algo>/`` holding a model.zip or a
    portable export: protocol 2 ships a run's export alone when the machine that shipped it no
    longer had the run's SB3 files), sorted; if there is none: FileNotFoundError saying what to
    do, or [] when not ``required``."""
    found = sorted(p for p in pretrained_dir.glob("*") if is_model_dir(p)) if pretrained_dir.exists() else []
    if not found and required:
        raise FileNotFoundError(f"--pretrained: no shipped policy in {pretrained_dir}/<algo>/ (each needs model.zip "
                                f"and vec_normalize.pkl, as train.py writes them, or {PORTABLE_FILE}); "
                                "`python -m agents.training.protocol_runs --ship` copies the best run of each "
                                "algorithm there; or leave out --pretrained")
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


def load_trained(model_dir: str | Path, algo: str | None = None,
                 portable: bool | Literal["auto"] = False) -> Policy:
    """The SB3 model in ``model_dir`` (``model.zip``, with ``vec_normalize.pkl`` if there) behind
    the scripted-policy interface. The algorithm is ``algo`` or, if None, ``config.json``'s
    (train.py writes it): one of ALGORITHM_CLASSES.

    ``portable=True``: the same deterministic policy evaluated in float64 without torch
    (:class:`agents.policies.portable.PortablePolicy`; from ``portable_policy.npz`` if it was
    exported from the model files there now, else from the model's weights now): the same
    actions, bit for bit, on every CPU. NotPortableError (a ValueError) for an architecture it
    does not cover.

    ``portable="auto"``: as the board loads every model: the portable path, and through torch
    (with a warning: its actions are then statistical across CPUs) where that path does not
    cover the architecture (:class:`agents.policies.portable.NotPortableError`); any other error
    (a broken export, an unknown algorithm) is raised as it is."""
    if portable == "auto":
        from agents.policies.portable import NotPortableError
        try:
            return load_trained(model_dir, algo, portable=True)
        except NotPortableError as err:    # an architecture the portable path does not cover (other errors: raised)
            warnings.warn(f"{model_dir}: {err}; evaluated through torch (statistical across CPUs)", stacklevel=2)
            return load_trained(model_dir, algo, portable=False)
    if portable:
        from agents.policies.portable import PortablePolicy, export_arrays, is_current
        if is_current(model_dir):           # exported from these very model files (else: export now)
            cfg_path = Path(model_dir) / "config.json"
            cfg = json.loads(cfg_path.read_text()) if cfg_path.exists() else {}
            return PortablePolicy.load(model_dir, name=_trained_name(algo or cfg.get("algo", "policy"), cfg))
        sb3 = load_trained(model_dir, algo)
        return PortablePolicy(export_arrays(sb3.model, sb3.obs_rms, sb3.clip_obs, sb3.epsilon), name=sb3.name)
    import importlib
    import pickle

    from agents.extras import require_extra
    require_extra("loading an SB3 model through torch (portable=False, or an architecture the portable path does not cover)")
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


def export(model_dir: str | Path) -> Path:
    """Write ``portable_policy.npz`` beside ``model.zip`` (train.py's layout), with the digest of
    the files it was made from; returns its path."""
    model_dir = Path(model_dir)
    sb3 = load_trained(model_dir, portable=False)
    path = model_dir / PORTABLE_FILE
    np.savez(path, **export_arrays(sb3.model, sb3.obs_rms, sb3.clip_obs, sb3.epsilon),
             source_sha256=np.array(source_digest(model_dir)))
    return path


def main(argv: list[str] | None = None) -> int:
    import argparse
    ap = argparse.ArgumentParser(description="Export trained SB3 policies for the portable float64 path "
                                             "(writes portable_policy.npz beside each model.zip).")
    ap.add_argument("model_dirs", nargs="+", help="directories written by train.py (model.zip, vec_normalize.pkl)")
    args = ap.parse_args(argv)
    for d in args.model_dirs:
        print(f"wrote {export(d)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
