"""Learned policies evaluated bit-identically on every CPU: the SB3 networks in float64.

torch's CPU kernels (oneDNN, its GEMM, its ``tanh``) pick their code by CPU and differ in the last
bit between machines; the dynamics amplify that bit into another episode, so a board computed
through torch moves from CPU to CPU. This module evaluates the *deterministic action* of a
trained SB3 policy without torch: its weights are exported once
(:func:`agents.evaluation.trained.export`, a ``portable_policy.npz`` beside ``model.zip``), and
:class:`PortablePolicy` computes

* the VecNormalize step: clip((obs - mean) / sqrt(var + eps), +-clip_obs), cast to float32 as
  SB3 does;
* the network in float64 with fixed-order loops (numba, no ``fastmath``) and the portable
  ``tanh``/``exp`` of :mod:`bearing_gym.physics.portable_math`:
  PPO (``MlpPolicy``): policy MLP (tanh) -> ``action_net``, clipped to [-1, 1];
  RecurrentPPO (``MlpLstmPolicy``): the actor LSTM (gates i, f, g, o as torch orders them; state
  reset at an episode start) -> policy MLP (tanh) -> ``action_net``, clipped;
  SAC and TQC: actor MLP (ReLU) -> ``mu`` -> tanh, unscaled to the action space as SB3 does;
  CrossQ: the same, its batch-renormalisation layers (running statistics) folded into the
  linear layers at export;
* the action as float32, as SB3 returns it.

It agrees with torch's float32 action to float32 precision (``tests/agents/policies/test_portable.py``,
on recorded observations) and is the same bits on every CPU. The leaderboard evaluates shipped
and protocol policies this way; a policy loaded through torch (``load_trained(...,
portable=False)``) is statistical across machines (docs/results.md, "How reproducible these
numbers are").
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numba import njit

from bearing_gym.physics.portable_math import exp, tanh

from agents.policies.scripted import Policy


PORTABLE_FILE = "portable_policy.npz"


ACTIVATIONS = {"tanh": 0, "relu": 1}


class NotPortableError(ValueError):
    """The portable path does not cover this model's architecture (gSDE, a CNN extractor, ...):
    ``load_trained(..., portable="auto")`` then loads it through torch."""


@njit(cache=True)
def _dense(w, b, x, activation):
    """activation(W x + b) in float64, summed in index order; activation -1 = none."""
    out = np.empty(w.shape[0])
    for i in range(w.shape[0]):
        acc = b[i]
        for j in range(w.shape[1]):
            acc = acc + w[i, j] * x[j]
        if activation == 0:
            acc = tanh(acc)
        elif activation == 1:
            acc = acc if acc > 0.0 else 0.0
        out[i] = acc
    return out


@njit(cache=True)
def _sigmoid(x):
    return 1.0 / (1.0 + exp(-x))


@njit(cache=True)
def _lstm_step(w_ih, w_hh, b_ih, b_hh, x, h, c):
    """One step of torch's LSTM cell (gates i, f, g, o): returns (h', c')."""
    n = h.shape[0]
    gates = np.empty(4 * n)
    for k in range(4 * n):
        acc = b_ih[k] + b_hh[k]
        for j in range(x.shape[0]):
            acc = acc + w_ih[k, j] * x[j]
        for j in range(n):
            acc = acc + w_hh[k, j] * h[j]
        gates[k] = acc
    h_new = np.empty(n)
    c_new = np.empty(n)
    for k in range(n):
        i = _sigmoid(gates[k])
        f = _sigmoid(gates[n + k])
        g = tanh(gates[2 * n + k])
        o = _sigmoid(gates[3 * n + k])
        c_new[k] = f * c[k] + i * g
        h_new[k] = o * tanh(c_new[k])
    return h_new, c_new


def _renorm_affine(layer) -> tuple[np.ndarray, np.ndarray]:
    """sb3-contrib's BatchRenorm in evaluation mode as x -> a x + d (float64): (x - ra_mean) /
    sqrt(ra_var + eps), times ``scale`` plus ``bias`` if affine."""
    mean = layer.ra_mean.detach().cpu().double().numpy()
    inv = 1.0 / np.sqrt(layer.ra_var.detach().cpu().double().numpy() + float(layer.eps))
    a, d = inv, -mean * inv
    if layer.affine:
        g = layer.scale.detach().cpu().double().numpy()
        a, d = a * g, d * g + layer.bias.detach().cpu().double().numpy()
    return a, d


def export_arrays(model, obs_rms=None, clip_obs: float = 10.0, epsilon: float = 1e-8) -> dict[str, np.ndarray]:
    """The arrays of a loaded SB3 model (PPO, SAC, sb3-contrib's RecurrentPPO, TQC and CrossQ,
    MLP policies) and its VecNormalize statistics, as :class:`PortablePolicy` reads them. TQC's
    actor is SAC's; CrossQ's batch-renormalisation layers (evaluation mode: the running
    statistics) are folded into the linear layer after each: W diag(a), b + W d."""
    import torch.nn as nn

    from stable_baselines3.common.torch_layers import FlattenExtractor

    pol = model.policy
    name = type(pol).__name__
    arrays: dict[str, np.ndarray] = {}
    extractor = getattr(getattr(pol, "actor", pol), "features_extractor", None)
    if extractor is not None and not isinstance(extractor, FlattenExtractor):
        raise NotPortableError(f"no portable path for a {type(extractor).__name__} features extractor (Flatten only)")
    if getattr(model, "use_sde", False):
        raise NotPortableError("no portable path for a policy trained with gSDE (use_sde=True)")
    if name in ("SACPolicy", "TQCPolicy", "CrossQPolicy"):
        seq, out, kind = pol.actor.latent_pi, pol.actor.mu, "sac"
    elif name in ("ActorCriticPolicy", "RecurrentActorCriticPolicy"):
        seq, out = pol.mlp_extractor.policy_net, pol.action_net
        kind = "lstm" if name == "RecurrentActorCriticPolicy" else "ppo"
        if kind == "lstm":
            lstm = pol.lstm_actor
            if lstm.num_layers != 1:
                raise NotPortableError(f"only a one-layer LSTM is supported, this one has {lstm.num_layers}")
            for key in ("weight_ih_l0", "weight_hh_l0", "bias_ih_l0", "bias_hh_l0"):
                arrays[f"lstm_{key}"] = getattr(lstm, key).detach().cpu().double().numpy()
    else:
        raise NotPortableError(f"no portable path for {name}: PPO, SAC, RecurrentPPO, TQC and CrossQ with MLP "
                               "policies are supported")
    BatchRenorm = type(None)                   # noqa: N806 - a class no layer is, unless CrossQ's is loaded
    if name == "CrossQPolicy":
        from sb3_contrib.common.torch_layers import BatchRenorm

    layers = list(seq)
    k = 0
    pending = None                       # a batch-renormalisation to fold into the next linear layer

    def linear(layer) -> tuple[np.ndarray, np.ndarray]:
        w, b = layer.weight.detach().cpu().double().numpy(), layer.bias.detach().cpu().double().numpy()
        if pending is None:
            return w, b
        a, d = pending
        return w * a[None, :], b + w @ d

    for i, layer in enumerate(layers):
        if isinstance(layer, BatchRenorm):
            if pending is not None:
                raise NotPortableError(f"two batch-renormalisation layers in a row at layer {i}")
            pending = _renorm_affine(layer)
            continue
        if not isinstance(layer, nn.Linear):
            continue
        act = layers[i + 1] if i + 1 < len(layers) else None
        act_name = {nn.Tanh: "tanh", nn.ReLU: "relu"}.get(type(act))
        if act_name is None:
            raise NotPortableError(f"unsupported activation after layer {i}: {type(act).__name__}")
        arrays[f"hidden_{k}_w"], arrays[f"hidden_{k}_b"] = linear(layer)
        pending = None
        arrays[f"hidden_{k}_activation"] = np.array(ACTIVATIONS[act_name])
        k += 1
    if not isinstance(out, nn.Linear):
        raise NotPortableError(f"no portable path for an action head of type {type(out).__name__}")
    arrays["out_w"], arrays["out_b"] = linear(out)
    arrays["kind"] = np.array(kind)
    arrays["action_low"] = np.asarray(model.action_space.low, dtype=np.float64)
    arrays["action_high"] = np.asarray(model.action_space.high, dtype=np.float64)
    if obs_rms is not None:
        arrays["obs_mean"] = np.asarray(obs_rms.mean, dtype=np.float64)
        arrays["obs_var"] = np.asarray(obs_rms.var, dtype=np.float64)
    arrays["clip_obs"] = np.array(float(clip_obs))
    arrays["epsilon"] = np.array(float(epsilon))
    return arrays


def source_digest(model_dir: str | Path) -> str:
    """SHA-256 of ``model.zip`` and ``vec_normalize.pkl``: what an export was made from."""
    import hashlib
    h = hashlib.sha256()
    for name in ("model.zip", "vec_normalize.pkl"):
        path = Path(model_dir) / name
        if path.exists():
            h.update(name.encode())
            h.update(path.read_bytes())
    return h.hexdigest()


def is_current(model_dir: str | Path) -> bool:
    """True if ``portable_policy.npz`` exists and was exported from the model files there now, or
    no ``model.zip`` is there (a collected protocol-v2 run keeps its export only)."""
    path = Path(model_dir) / PORTABLE_FILE
    if not path.exists():
        return False
    if not (Path(model_dir) / "model.zip").exists():
        return True
    with np.load(path) as data:
        return "source_sha256" in data.files and str(data["source_sha256"]) == source_digest(model_dir)


class PortablePolicy(Policy):
    """A trained SB3 policy's deterministic action in float64, the same bits on every CPU
    (module docstring). ``predict`` has SB3's signature; the recurrent state is ``(h, c)``, each
    (n_envs, hidden), reset where ``episode_start``."""

    def __init__(self, arrays: dict[str, Any], name: str = "trained"):
        super().__init__()
        self.name = name
        self.kind = str(arrays["kind"])
        self.layers = []
        k = 0
        while f"hidden_{k}_w" in arrays:
            self.layers.append((np.ascontiguousarray(arrays[f"hidden_{k}_w"], dtype=np.float64),
                                np.ascontiguousarray(arrays[f"hidden_{k}_b"], dtype=np.float64),
                                int(arrays[f"hidden_{k}_activation"])))
            k += 1
        self.out_w = np.ascontiguousarray(arrays["out_w"], dtype=np.float64)
        self.out_b = np.ascontiguousarray(arrays["out_b"], dtype=np.float64)
        self.low = np.asarray(arrays["action_low"], dtype=np.float64)
        self.high = np.asarray(arrays["action_high"], dtype=np.float64)
        self.obs_mean = arrays.get("obs_mean")
        self.obs_var = arrays.get("obs_var")
        self.clip_obs = float(arrays["clip_obs"])
        self.epsilon = float(arrays["epsilon"])
        if self.kind == "lstm":
            self.lstm = tuple(np.ascontiguousarray(arrays[f"lstm_{k}"], dtype=np.float64)
                              for k in ("weight_ih_l0", "weight_hh_l0", "bias_ih_l0", "bias_hh_l0"))
            self.hidden = self.lstm[1].shape[1]
        elif self.kind not in ("ppo", "sac"):
            raise ValueError(f"unknown portable policy kind {self.kind!r}")

    @classmethod
    def load(cls, model_dir: str | Path, name: str = "trained") -> "PortablePolicy":
        """From ``model_dir/portable_policy.npz`` (written by :func:`agents.evaluation.trained.export`)."""
        path = Path(model_dir) / PORTABLE_FILE
        if not path.exists():
            raise FileNotFoundError(f"{path} not found: export it once with "
                                    f"`python -m agents.evaluation.trained {model_dir}` (needs torch)")
        with np.load(path) as data:
            return cls({k: data[k] for k in data.files}, name=name)

    def normalise(self, obs: np.ndarray) -> np.ndarray:
        """SB3's VecNormalize step on float32 observations (basic operations only)."""
        o = np.asarray(obs, dtype=np.float32)
        if self.obs_mean is None:
            return o
        return np.clip((o - self.obs_mean) / np.sqrt(self.obs_var + self.epsilon),
                       -self.clip_obs, self.clip_obs).astype(np.float32)

    def _mlp(self, x: np.ndarray) -> np.ndarray:
        for w, b, act in self.layers:
            x = _dense(w, b, x, act)
        return _dense(self.out_w, self.out_b, x, -1)

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        o = self.normalise(self._batch(np.asarray(obs, dtype=np.float32))).astype(np.float64)
        n = o.shape[0]
        actions = np.empty((n, self.out_w.shape[0]))
        if self.kind == "lstm":
            h, c = (np.zeros((n, self.hidden)), np.zeros((n, self.hidden))) if state is None else \
                (np.array(state[0], dtype=np.float64), np.array(state[1], dtype=np.float64))
            if episode_start is not None:
                start = np.asarray(episode_start, dtype=bool).reshape(n)
                h[start] = 0.0
                c[start] = 0.0
            for e in range(n):
                h[e], c[e] = _lstm_step(*self.lstm, o[e], h[e], c[e])
                actions[e] = self._mlp(h[e])
            state = (h, c)
        else:
            for e in range(n):
                actions[e] = self._mlp(o[e])
        if self.kind == "sac":                   # squashed Gaussian: tanh, then SB3's unscale_action
            squashed = np.array([[tanh(v) for v in row] for row in actions])
            actions = self.low + (0.5 * (squashed + 1.0) * (self.high - self.low))
        actions = np.clip(np.clip(actions, self.low, self.high), -1.0, 1.0)
        return actions.astype(np.float32), state
