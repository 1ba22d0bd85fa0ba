"""An RLlib policy on the board: the adapter docs/scaling.md promised.

    from agents.submit import score
    from agents.submit.rllib import RLlibPolicy
    result = score(RLlibPolicy(algo), tier="transient", name="RLlib PPO")    # algo: a trained Algorithm

:class:`RLlibPolicy` wraps an RLlib Algorithm (its default module) or an RLModule of the new API
stack (Ray 2.60, the ``rllib`` extra): the batch of observations goes through the module's
``forward_inference``, its ``action_dist_inputs`` become the module's inference action
distribution, and the action is that distribution's deterministic one (for PPO's diagonal
Gaussian, its mean), clipped to [-1, 1] as RLlib's env runners do before they unsquash an action
into the Box (``normalize_actions``, the default; the action space is [-1, 1] here, so the
unsquashing is the identity). The env-to-module connectors are not applied: RLlib's default
pipeline passes a Box observation through unchanged; a config that adds a filter (MeanStdFilter)
must apply its statistics first. Imports nothing of Ray or torch until it runs.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from agents.policies.scripted import Policy
from agents.submit.actions import check_action_batch

__all__ = ["RLlibPolicy"]


class RLlibPolicy(Policy):
    """A trained RLlib Algorithm or RLModule as a board policy (module docstring)."""

    def __init__(self, algorithm_or_module: Any, name: str = "RLlib policy"):
        super().__init__()
        module = algorithm_or_module.get_module() if hasattr(algorithm_or_module, "get_module") else algorithm_or_module
        if not hasattr(module, "forward_inference"):
            raise TypeError(f"RLlibPolicy takes an RLlib Algorithm or RLModule (new API stack), got "
                            f"{type(algorithm_or_module).__name__}")
        self.module, self.name = module, name

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        import torch
        from ray.rllib.core.columns import Columns
        o = np.asarray(obs, dtype=np.float32)
        o = o[None, :] if o.ndim == 1 else o
        with torch.no_grad():
            out = self.module.forward_inference({Columns.OBS: torch.as_tensor(o)})
            dist = self.module.get_inference_action_dist_cls().from_logits(out[Columns.ACTION_DIST_INPUTS])
            actions = dist.to_deterministic().sample().cpu().numpy()
        return check_action_batch(np.clip(actions, -1.0, 1.0), len(o), self.name), state
