"""A plain NumPy rule on the board: raise the preload while the motion is quasi-periodic, else ease it.
Run: python examples/numpy_rule.py [EPISODES]  (default: the 100 test episodes of transient)."""
import sys

import numpy as np

from agents.submit import score

QPI, SETPOINT = 8, 10          # observation features (bearing_gym.envs.FEATURE_NAMES)


def rule(obs: np.ndarray) -> np.ndarray:
    return np.clip(obs[:, SETPOINT] + np.where(obs[:, QPI] > 0.1, 0.2, -0.02), -1.0, 1.0)


result = score(rule, tier="transient", name="NumPy rule", episodes=int(sys.argv[1]) if sys.argv[1:] else None)
result.save("runs/submissions/numpy_rule.json", algorithm="hand rule", training_steps=0, library="numpy")
print(result.markdown())
