"""``benchmarks/bench_training.py --quick --json`` runs and reports every key.

A slow test (three fresh interpreters that import torch and train a few hundred steps; well
over a minute on a loaded 2-core machine): skipped unless BEARING_GYM_SLOW=1. Only the shape of
the output is checked (every key present, finite numbers, shares between 0 and 1): speed
depends on the machine and its load and is never asserted here.
"""

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = ROOT / "benchmarks" / "bench_training.py"

RATES = ("ppo_steps_per_s", "sac_steps_per_s", "eval_episodes_per_s", "eval_wall_s_per_100_episodes")
PARTS = ("physics_step", "physics_settle", "features", "reset_load", "bearing_gym_python", "torch", "sb3", "other")
SHARES = tuple(f"share_{a}_{p}" for a in ("ppo", "sac") for p in PARTS) + tuple(
    f"share_eval_{p}" for p in ("physics_step", "physics_settle", "reset_load"))


@pytest.mark.slow
def test_bench_training_quick_json_has_every_key_with_finite_values():
    r = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--json"], cwd=ROOT,
                       capture_output=True, text=True, timeout=1800,
                       env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout)             # exactly one JSON object on stdout
    assert out["mode"] == "quick"
    for key in RATES + SHARES:
        assert key in out, key
        v = out[key]
        assert isinstance(v, (int, float)) and not isinstance(v, bool), (key, v)
        assert math.isfinite(v), (key, v)
    for key in RATES:
        assert out[key] > 0, key
    for key in SHARES:                     # a fraction of the timed wall time (timer jitter aside)
        assert -0.01 <= out[key] <= 1.01, (key, out[key])
    for algo in ("ppo", "sac"):            # the parts cover the timed run
        assert abs(sum(out[f"share_{algo}_{p}"] for p in PARTS) - 1.0) < 0.01, algo
    assert not any(k.endswith(("_baseline", "_ratio")) for k in out)     # no baseline asked for
    kinds = [run["kind"] for run in out["runs"]]
    assert sorted(kinds) == ["eval", "ppo", "sac"]
    for run in out["runs"]:
        assert run["tree"] == str(ROOT.resolve())
        assert math.isfinite(run["load_1min_start"]) and math.isfinite(run["load_1min_end"])
    assert out["trees"]["current"]["path"] == str(ROOT.resolve())
    acc = out["accuracy"]                  # --quick: checks 1 and 2 beside the speed, no maps
    assert acc["map_classification"] is None
    assert math.isfinite(acc["critical_preload"]["difference_n"])
    assert isinstance(acc["amplitudes"]["ok"], bool) and len(acc["amplitudes"]["points"]) >= 1
