"""Sweeps on Ray give the same rows as on the local backend (tiny durations, 2 x 2 grids)."""

import csv
import math
import os
import subprocess
import sys

import pytest

ray = pytest.importorskip("ray")

import bearing_gym  # noqa: E402
from bearing_gym import cli  # noqa: E402
from bearing_gym.analysis.sweeps import store  # noqa: E402
from bearing_gym.cli import sweep as cli_sweep  # noqa: E402
from bearing_gym.analysis.ray_backend import RayExecutor  # noqa: E402
from bearing_gym.analysis.sweeps import SerialExecutor, SweepSettings, stability_map  # noqa: E402

TINY = SweepSettings(settle_s=0.005, measure_s=0.01, cold_settle_s=0.005, floquet=False)
GRID = dict(preloads=[800.0, 700.0], shaft_speeds_rpm=[20000.0, 15000.0])
CLI_TINY = ["--settle-s", "0.005", "--cold-settle-s", "0.005", "--measure-s", "0.012",
            "--no-floquet", "-q"]
CLI_GRID = ["--preloads", "800", "700", "--rpms", "20000", "15000", *CLI_TINY]


@pytest.fixture(scope="module")
def ray_session():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


def _exact(rows):
    """Rows without the wall-clock column, NaN made comparable."""
    return [{k: ("nan" if isinstance(v, float) and math.isnan(v) else v)
             for k, v in r.items() if k != "wall_s"} for r in rows]


def _csv(path):
    with open(path, newline="") as fh:
        return [{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(fh)]


@pytest.mark.parametrize("mode", [pytest.param("continuation", marks=pytest.mark.slow), "cold"])   # ~15 s each; cold stays in the default run
def test_ray_executor_gives_the_rows_of_the_local_run(ray_session, mode):
    base = bearing_gym.default_params()
    with SerialExecutor() as ex:
        local = stability_map(base, mode=mode, settings=TINY, executor=ex, progress=False, **GRID)
    with RayExecutor(address="ignored: the session is open") as ex:
        remote = stability_map(base, mode=mode, settings=TINY, executor=ex, progress=False, **GRID)
    assert len(local) == 4
    assert [list(r) for r in remote] == [list(r) for r in local]      # same keys, same order
    assert _exact(remote) == _exact(local)                            # same values, exactly
    assert ray.is_initialized()       # the executor did not close the session it did not open


def test_cli_sweep_backend_ray_matches_local(ray_session, tmp_path):
    assert cli.main(["sweep", *CLI_GRID, "--backend", "local", "--workers", "2",
                     "--out", str(tmp_path / "local.csv")]) == 0
    assert cli.main(["sweep", *CLI_GRID, "--backend", "ray", "--out", str(tmp_path / "ray.csv")]) == 0
    local, remote = _csv(tmp_path / "local.csv"), _csv(tmp_path / "ray.csv")
    assert [(r["label"], r["axial_preload_n"]) for r in remote] == [
        ("20000rpm", "800"), ("20000rpm", "700"), ("15000rpm", "800"), ("15000rpm", "700")]
    assert remote == local
    assert ray.is_initialized()
    # resuming a local file on Ray: nothing left to compute
    assert cli.main(["sweep", *CLI_GRID, "--backend", "ray", "--out", str(tmp_path / "local.csv")]) == 0
    assert _csv(tmp_path / "local.csv") == local


@pytest.mark.slow          # ~25 s on 2 cores: a Ray instance started and stopped by the CLI (CI runs it)
def test_console_script_starts_and_stops_its_own_ray_instance(tmp_path):
    out = tmp_path / "own.csv"
    env = dict(os.environ)
    env.pop("RAY_ADDRESS", None)
    run = subprocess.run([sys.executable, "-m", "bearing_gym.cli", "sweep", "--preloads", "800",
                          "700", *CLI_TINY, "--mode", "cold", "--backend", "ray", "--workers", "1",
                          "--out", str(out)], capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout == ""
    rows = _csv(out)
    assert [r["axial_preload_n"] for r in rows] == ["800", "700"]
    assert all(r["status"] == "ok" for r in rows)


def test_sweep_waits_for_late_appends_before_the_final_write(tmp_path, monkeypatch):
    """A future's result reaches the main thread before its done-callback (the CSV append) has
    run in the thread that set it; a slow append must still land before the final rewrite, else
    its rows appear twice (seen with Ray, whose shutdown does not join those threads). A pool of
    plain threads that is not joined on shutdown stands in for Ray here."""
    import concurrent.futures as cf
    import threading
    import time

    class UnjoinedThreads:
        def submit(self, fn, *args):
            fut = cf.Future()
            threading.Thread(target=lambda: fut.set_result(fn(*args)), daemon=True).start()
            return fut

        def shutdown(self, wait=True):
            pass

    slow = store.ResumingExecutor._write_rows

    def late(self, fut):
        time.sleep(0.5)
        slow(self, fut)

    monkeypatch.setattr(store.ResumingExecutor, "_write_rows", late)
    monkeypatch.setattr(cli_sweep, "sweep_pool", lambda *a: UnjoinedThreads)
    out = tmp_path / "late.csv"
    assert cli.main(["sweep", *CLI_GRID, "--workers", "2", "--out", str(out)]) == 0
    time.sleep(1.0)                       # a late append would have landed by now
    keys = [(r["label"], r["axial_preload_n"]) for r in _csv(out)]
    assert sorted(keys) == sorted({("20000rpm", "800"), ("20000rpm", "700"),
                                   ("15000rpm", "800"), ("15000rpm", "700")})


def test_the_preload_map_on_ray_gives_the_local_rows(ray_session):
    """bearing-gym preload-map's cells as Ray tasks: the same rows as in this process."""
    from bearing_gym.engineering.preload_map import preload_map
    kw = dict(speeds_rpm=[20000.0, 25000.0], radial_loads_n=[500.0], preloads_n=(900.0, 1200.0, 1500.0),
              measure_intervals=5, progress=False)
    local, _ = preload_map(workers=1, **kw)
    with RayExecutor(address="ignored: the session is open") as ex:
        remote, _ = preload_map(executor=ex, **kw)
    assert len(local) == 2 and [repr(r) for r in remote] == [repr(r) for r in local]
