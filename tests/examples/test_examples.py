"""The worked examples of the open board run as a user runs them, and the CleanRL-style actor holds
the shipped SAC's policy.

Each example is run as a script (``python examples/<name>.py 2``: the first 2 test episodes of
``transient``) in a scratch directory; it must print its row beside the references and write its
submission file for those episodes. Each is under 20 lines (docs/benchmark.md promises it).
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


@pytest.mark.slow          # ~50 s each on 2 cores, most of it the board's 50,000 bootstrap draws (CI runs them)
@pytest.mark.parametrize("script,row", [("numpy_rule.py", "NumPy rule"), ("cleanrl_actor.py", "CleanRL actor")])
def test_the_example_scores_its_policy_and_writes_its_submission(script, row, tmp_path):
    assert len((EXAMPLES / script).read_text().splitlines()) < 20
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    out = subprocess.run([sys.executable, str(EXAMPLES / script), "2"], capture_output=True, text=True, cwd=tmp_path,
                         env=env)
    assert out.returncode == 0, out.stderr[-3000:]
    assert f"| {row} | 1 | 2 |" in out.stdout and "| validation constant (" in out.stdout
    sub = json.loads(next((tmp_path / "runs" / "submissions").glob("*.json")).read_text())
    assert sub["name"] == row and sub["episodes"] == 2 and sub["test_seeds"] == [300_000, 300_001]


def test_the_cleanrl_actor_is_the_shipped_sac():
    """Its weights are the conversion of the shipped SAC (run convert_shipped_sac.py when that
    changes), and on the observations of a test episode its actions are the portable SAC's to
    float32 rounding (1e-5; the portable path clips scaled observations at +-10, the actor does not:
    observations beyond are left out)."""
    torch = pytest.importorskip("torch", reason="the CleanRL example needs torch (the rl extra)")
    sys.path.insert(0, str(EXAMPLES))
    try:
        from convert_shipped_sac import OUT, converted
    finally:
        sys.path.remove(str(EXAMPLES))
    shipped = torch.load(OUT, weights_only=True)
    fresh = converted()
    assert shipped.keys() == fresh.keys() and all(torch.equal(shipped[k], fresh[k]) for k in fresh)

    from agents.evaluation.trained import PRETRAINED_DIR, load_trained
    from bearing_gym.envs import BearingPreloadVectorEnv
    portable = load_trained(PRETRAINED_DIR / "sac", portable=True)
    venv = BearingPreloadVectorEnv(num_envs=4, max_episode_steps=None)
    obs, _ = venv.reset(seed=300_000)
    rows = []
    for _ in range(20):
        rows.append(obs)
        obs, *_ = venv.step(portable.predict(obs)[0])
    obs = np.concatenate(rows)
    p = np.load(PRETRAINED_DIR / "sac" / "portable_policy.npz")
    inside = np.all(np.abs((obs - p["obs_mean"]) / np.sqrt(p["obs_var"] + p["epsilon"])) < 10, axis=1)
    assert inside.mean() > 0.9
    x = torch.as_tensor(obs[inside])
    h = torch.relu(x @ fresh["fc1.weight"].T + fresh["fc1.bias"])
    h = torch.relu(h @ fresh["fc2.weight"].T + fresh["fc2.bias"])
    actor = torch.tanh(h @ fresh["fc_mean.weight"].T + fresh["fc_mean.bias"]).numpy()
    np.testing.assert_allclose(actor, portable.predict(obs[inside])[0], atol=1e-5)
