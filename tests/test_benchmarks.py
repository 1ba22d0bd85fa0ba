"""``benchmarks/run_all.py --quick --json`` runs and reports every performance target.

A slow test (a benchmark run, about a minute): skipped unless BEARING_GYM_SLOW=1. Only the
shape of the output is checked (every key present, finite numbers, a bool per target): speed
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
SCRIPT = ROOT / "benchmarks" / "run_all.py"

KEYS = ("speedup_vs_numpy", "real_time_factor", "dt_convergence_rel_err", "env_steps_per_s",
        "vector_env_speedup_2_cores", "rss_growth_mb", "import_s", "first_reset_s")


@pytest.mark.slow
def test_run_all_quick_json_has_every_key_with_finite_values():
    r = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--json"], cwd=ROOT,
                       capture_output=True, text=True, timeout=900, env=dict(os.environ))
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout)             # exactly one JSON object on stdout
    assert out["mode"] == "quick"
    for key in KEYS:
        assert key in out, key
        assert isinstance(out[key], (int, float)) and not isinstance(out[key], bool), key
        assert math.isfinite(out[key]), (key, out[key])
    assert set(out["targets_met"]) == set(KEYS)
    assert all(isinstance(v, bool) for v in out["targets_met"].values())
    assert set(out["targets"]) == set(KEYS)
    # the amplitudes behind the dt check are there for both step sizes
    runs = out["details"]["dt_convergence"]["runs"]
    assert set(runs) == {"dt", "dt/4"}
    for run in runs.values():
        assert all(math.isfinite(v) and v > 0 for v in run["peak_to_peak"].values())
    rss = out["details"]["rss"]
    assert rss["rss_start_mb"] > 0 and rss["rss_end_mb"] > 0


@pytest.mark.slow
def test_bench_reset_quick_json_reports_both_resets_in_env_steps():
    """``benchmarks/bench_reset.py --quick --json``: every key, finite and positive; every banked
    reset came from the bank (its settle key is the bank's); no speed is asserted."""
    r = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "bench_reset.py"), "--quick", "--json"], cwd=ROOT,
                       capture_output=True, text=True, timeout=900, env=dict(os.environ))
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout)
    for kind in ("settled", "banked"):
        seconds, steps = out[f"reset_{kind}_s"], out[f"reset_{kind}_env_steps"]
        assert math.isfinite(seconds) and seconds > 0 and math.isfinite(steps)
        assert steps == pytest.approx(seconds / out["step_s"], rel=1e-12)
    assert out["tier"] == "transient" and out["resets"] == 3 and out["machine"]["logical_cpus"] >= 1
    assert out["banked_resets_from_the_bank"] == 3          # the banked figure is the bank's copy, not a settle
