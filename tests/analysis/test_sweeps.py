"""Sweep runners on tiny durations, the readers on synthetic rows."""

import math

import numpy as np
import pytest

import bearing_gym
from bearing_gym.analysis.sweeps import (COLUMNS, SerialExecutor, SweepSettings, axial_index,
                                         continuation_chain, critical_preload, load_csv, save_csv,
                                         save_npz, stability_map, stable_windows)
from bearing_gym.analysis.sweeps.io import truthy

TINY = SweepSettings(settle_s=0.005, measure_s=0.01, cold_settle_s=0.005, floquet=False)


def test_continuation_chain_runs_and_returns_the_columns():
    rows = continuation_chain(bearing_gym.default_params(), [800.0, 700.0], TINY, label="t")
    assert len(rows) == 2
    for r in rows:
        assert set(COLUMNS) <= set(r)
        assert r["status"] == "ok" and r["mode"] == "continuation"
        assert 0 <= r["qpi"] < 2 and r["ptp_x_m"] > 0 and r["cage_mean_rad_s"] > 0
    assert [r["axial_preload_n"] for r in rows] == [800.0, 700.0]
    assert [r["order"] for r in rows] == [0, 1]
    assert rows[0]["damping_ratio"] == 0.02


def test_stability_map_cold_with_the_default_process_pool(tmp_path):
    rows = stability_map(bearing_gym.default_params(), [800.0, 700.0], mode="cold",
                         settings=TINY, max_workers=2, progress=False)
    assert [r["axial_preload_n"] for r in rows] == [800.0, 700.0]
    assert all(set(COLUMNS) <= set(r) and r["mode"] == "cold" for r in rows)
    save_csv(rows, tmp_path / "s.csv")
    back = load_csv(tmp_path / "s.csv")
    assert [r["axial_preload_n"] for r in back] == [800.0, 700.0]
    assert back[0]["qpi"] == pytest.approx(rows[0]["qpi"], rel=1e-9)
    save_npz(rows, tmp_path / "s.npz")
    with np.load(tmp_path / "s.npz") as z:
        assert set(COLUMNS) <= set(z.files)
        np.testing.assert_array_equal(z["axial_preload_n"], [800.0, 700.0])
        np.testing.assert_array_equal(z["qpi"], [r["qpi"] for r in rows])      # exactly
        assert z["periodic"].dtype == bool and list(z["periodic"]) == [r["periodic"] for r in rows]
        assert list(z["mode"]) == ["cold", "cold"] and z["mode"].dtype.kind == "U"


def test_stability_map_with_a_pluggable_executor_and_floquet():
    settings = SweepSettings(settle_s=0.005, measure_s=0.01, cold_settle_s=0.02, floquet=True)
    with SerialExecutor() as ex:
        rows = stability_map(bearing_gym.default_params(), [800.0], radial_loads_n=[0.0, 200.0],
                             mode="continuation", settings=settings, executor=ex, progress=False)
    assert [r["label"] for r in rows] == ["Pr0N", "Pr200N"]
    assert rows[1]["radial_load_x_n"] == 200.0 and rows[1]["radial_load_y_n"] == 200.0
    for r in rows:
        assert r["periodic"] == (r["qpi"] < settings.qpi_threshold and r["floquet_max_modulus"] < 1)


def _rows(pairs):
    return [dict(axial_preload_n=p, periodic=ok, status="ok") for p, ok in pairs]


def test_critical_preload_and_windows_on_synthetic_rows():
    rows = _rows([(1000, True), (900, True), (800, False), (750, True), (700, False)])
    c = critical_preload(rows)
    assert c["critical_n"] == 850 and c["bracket_n"] == (800, 900)
    assert stable_windows(rows) == [(900, 1000), (750, 750)]
    assert math.isnan(critical_preload(_rows([(1000, True), (900, True)]))["critical_n"])
    assert "above" in critical_preload(_rows([(1000, False)]))["note"]


def test_settings_are_validated():
    with pytest.raises(ValueError, match="measure_s"):
        SweepSettings(measure_s=0.0)


def test_axial_index_picks_the_least_stable_mode_with_an_axial_share():
    assert axial_index([0.99, 0.8, 0.85, 0.7], [0.05, 0.3, 0.2, 0.9]) == 2
    assert axial_index([0.99, 0.5], [0.05, 0.1]) == 1          # none axial: the most axial one
    with pytest.raises(ValueError, match="one length"):
        axial_index([0.9, 0.8], [0.5])


def test_truthy_reads_csv_cells_and_values():
    assert [truthy(v) for v in ("True", " yes", "1", "False", "0", "", True, 0)] == \
        [True, True, True, False, False, False, True, False]


_AFTER_THREADS_SCRIPT = '''
import numpy as np

def first_reward(seed):
    from bearing_gym.envs.vector import BearingPreloadVectorEnv
    env = BearingPreloadVectorEnv(num_envs=2, num_threads=2)
    env.reset(seed=seed)
    return float(env.step(np.zeros((2, 1), dtype=np.float32))[1][0])

if __name__ == "__main__":
    from bearing_gym.analysis.sweeps import run_tasks
    here = first_reward(0)          # this process's numba OpenMP pool is now in use
    there = run_tasks(first_reward, [(0,), (0,)], max_workers=2, progress=False)
    import json
    print(json.dumps([here] + there))
'''


def test_the_default_pool_runs_threaded_kernels_after_this_process_used_its_openmp_pool(tmp_path):
    """A forked worker whose parent has used numba's OpenMP threading layer is terminated when it
    runs a parallel kernel ("fork() called from a process already using GNU OpenMP"): the default
    pool spawns its workers, and they give the parent's numbers bit for bit."""
    import subprocess
    import sys

    script = tmp_path / "after_threads.py"
    script.write_text(_AFTER_THREADS_SCRIPT)
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    import json

    here, *there = json.loads(done.stdout.strip().splitlines()[-1])
    assert there == [here, here]
