"""Regenerate tests/data/paper_golden.npz (the "paper" preset under a fixed action sequence).

Run only when the physics deliberately changes:  PYTHONPATH=. python tests/data/make_golden.py
(``--out FILE`` writes elsewhere: ``python -m agents.regenerate`` builds it so in a scratch tree).
"""

import argparse
from pathlib import Path

import numpy as np

from bearing_gym.envs import BearingPreloadEnv
from tests.envs.test_env import golden_actions, run

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=str(Path(__file__).with_name("paper_golden.npz")), help="the .npz to write")
    out = Path(ap.parse_args().out)
    actions = golden_actions(30)
    obs, rew, _ = run(BearingPreloadEnv(scenario="paper"), actions, seed=0)
    out.parent.mkdir(parents=True, exist_ok=True)
    np.savez(out, actions=actions, observations=obs, rewards=rew)
    print(f"wrote {out}: {len(rew)} steps, final preload obs {obs[-1, 9]:.4f}, return {rew.sum():.4f}")
