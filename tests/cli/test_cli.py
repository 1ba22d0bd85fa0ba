"""The ``bearing-gym`` command line, end to end on tiny inputs (in-process through
``bearing_gym.cli.main`` and once in a subprocess). Nothing here needs the optional ray extra."""

import csv
import functools
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from bearing_gym import cli
from bearing_gym.analysis import sweeps
from bearing_gym.analysis.sweeps import runner

_REAL_CHAIN = sweeps.continuation_chain
TINY_SWEEP = ["--settle-s", "0.005", "--cold-settle-s", "0.005", "--measure-s", "0.02",
              "--no-floquet", "--workers", "1"]


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_simulate_writes_summary_plots_and_record(tmp_path, capsys):
    out = tmp_path / "sim"
    assert cli.main(["simulate", "--duration", "0.02", "--rpm", "20000", "--preload", "800",
                     "--clearance-um", "4", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    for phrase in ("peak-to-peak: x", "principal frequencies (Hz)", "motion:"):
        assert phrase in text
    rec = np.load(out / "record.npz")
    assert rec["x"].shape == (2000,) and rec["bearing_force"].shape == (2000, 5)
    assert str(rec["status"]) == "ok" and rec["t"][-1] == pytest.approx(0.02)
    assert json.loads(str(rec["params_json"]))["loads"]["axial_preload_n"] == 800.0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["ptp_x_um"] > 0 and summary["cage_speed_mean_rad_s"] > 0
    assert summary["principal_frequency_hz"]["x"] == pytest.approx(333.3, rel=0.2)
    for png in ("timeseries.png", "orbit.png", "spectrum.png", "poincare.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_equilibrium_table_and_json_with_config_files(tmp_path, capsys):
    assert cli.main(["equilibrium", "--json", str(tmp_path / "eq.json")]) == 0
    text = capsys.readouterr().out
    assert "alpha_i" in text and "stiffness matrix" in text
    eq = json.loads((tmp_path / "eq.json").read_text())
    assert eq["balls"]["alpha_i_deg"][0] == pytest.approx(33.88, abs=0.01)   # docs/simulator.md reference
    assert eq["balls"]["q_o_n"][0] == pytest.approx(2099, rel=1e-3)
    assert np.array(eq["stiffness"]["matrix"]).shape == (5, 5)

    # config values apply, a subcommand table wins over top-level keys, the command line wins
    (tmp_path / "c.toml").write_text('rpm = 10000\npreload = 900\n[equilibrium]\nclearance_um = 6\n')
    (tmp_path / "c.yaml").write_text("rpm: 10000\npreload: 900\nequilibrium:\n  clearance_um: 6\n")
    for name in ("c.toml", "c.yaml"):
        assert cli.main(["equilibrium", "--config", str(tmp_path / name), "--preload", "1000",
                         "-q", "--json", str(tmp_path / "c.json")]) == 0
        assert capsys.readouterr().out == ""
        p = json.loads((tmp_path / "c.json").read_text())["params"]
        assert p["shaft_speed_rpm"] == 10000 and p["loads"]["axial_preload_n"] == 1000
        assert p["geometry"]["clearance_inner_m"] == pytest.approx(6e-6)


def test_floquet_quiet_json(tmp_path, capsys):
    assert cli.main(["floquet", "--settle-s", "0.05", "--measure-s", "0.01", "-q",
                     "--json", str(tmp_path / "f.json")]) == 0
    assert capsys.readouterr().out == ""
    res = json.loads((tmp_path / "f.json").read_text())
    assert len(res["multipliers"]) == 10
    assert res["leading_modulus"] == pytest.approx(max(m["modulus"] for m in res["multipliers"]))
    assert res["product"] == pytest.approx(res["liouville_det"], rel=0.05)


def _counting(monkeypatch, fail_label=None):
    """Replace sweeps.continuation_chain by a wrapper that records (and optionally fails) labels."""
    calls = []
    real = _REAL_CHAIN

    @functools.wraps(real)
    def chain(base, preloads, settings, label, *a, **k):
        calls.append(label)
        if label == fail_label:
            raise RuntimeError("simulated crash")
        return real(base, preloads, settings, label, *a, **k)

    monkeypatch.setattr(runner, "continuation_chain", chain)      # where stability_map looks it up
    return calls


def test_sweep_writes_csv_and_resumes(tmp_path, capsys, monkeypatch):
    out = tmp_path / "map.csv"
    argv = ["sweep", "--preloads", "800", "700", "--rpms", "20000", "10000", *TINY_SWEEP,
            "--out", str(out), "-q"]
    # a run that dies on its second chain keeps the first one in the file
    _counting(monkeypatch, fail_label="10000rpm")
    assert cli.main(argv) == 1
    err = capsys.readouterr().err
    assert "rerun" in err and err.count("\n") == 1
    first = _rows(out)
    assert [(r["label"], r["axial_preload_n"]) for r in first] == [("20000rpm", "800"),
                                                                   ("20000rpm", "700")]
    # the rerun computes only the missing chain and keeps the finished rows as they were
    calls = _counting(monkeypatch)
    assert cli.main(argv) == 0
    assert calls == ["10000rpm"]
    rows = _rows(out)
    assert [r["label"] for r in rows] == ["20000rpm"] * 2 + ["10000rpm"] * 2
    assert [r["wall_s"] for r in rows[:2]] == [r["wall_s"] for r in first]
    assert all(r["status"] == "ok" and math.isfinite(float(r["qpi"])) for r in rows)
    # nothing left to do
    calls = _counting(monkeypatch)
    assert cli.main(argv) == 0 and calls == []
    assert _rows(out) == rows
    # cold starts resume point by point; the continuation rows stay in the file
    argv_cold = ["sweep", "--mode", "cold", "--preloads", "800", *TINY_SWEEP, "--out", str(out)]
    assert cli.main(argv_cold) == 0
    assert "1 task(s) computed, 0 reused" in capsys.readouterr().out
    argv_cold[4:5] = ["800", "700"]        # and on a process pool
    assert cli.main(argv_cold + ["--workers", "2", "--plot", str(tmp_path / "map.png")]) == 0
    assert "1 task(s) computed, 1 reused" in capsys.readouterr().out
    cold = [r for r in _rows(out) if r["mode"] == "cold"]
    assert [(r["label"], r["axial_preload_n"]) for r in cold] == [("base", "800"), ("base", "700")]
    assert len(_rows(out)) == 6 and (tmp_path / "map.png").exists()


def test_sweep_refuses_to_resume_with_other_settings(tmp_path, capsys):
    out = tmp_path / "map.csv"
    argv = ["sweep", "--preloads", "800", *TINY_SWEEP, "--out", str(out), "-q"]
    assert cli.main(argv) == 0
    first = _rows(out)
    assert first[0]["settle_s"] == "0.005" and first[0]["dt_s"] == "1e-05"
    assert first[0]["floquet"] == "False" and first[0]["refine_step_n"] == "none"
    for extra, names in ((["--settle-s", "0.01"], ["--settle-s 0.005", "--settle-s 0.01"]),
                         (["--dt-us", "5"], ["--dt-us 10", "--dt-us 5"]),
                         (["--race-control", "inner"], ["--race-control outer"])):
        assert cli.main(argv + extra) == 2
        err = _error(capsys)
        assert err.startswith(f"bearing-gym: error: {extra[0]}: ") and str(out) in err
        for name in names:
            assert name in err
    no_floquet = [a for a in argv if a != "--no-floquet"]
    assert cli.main(no_floquet) == 2
    assert "--no-floquet:" in _error(capsys)
    assert _rows(out) == first                      # a refused run leaves the file alone
    # rows written before the settings were recorded (no such columns) are still reused
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(sweeps.COLUMNS), extrasaction="ignore")
        w.writeheader()
        w.writerows(first)
    assert cli.main(argv[:-1] + ["--settle-s", "0.01"]) == 0
    assert "0 task(s) computed, 1 reused" in capsys.readouterr().out
    assert _rows(out)[0]["settle_s"] == "" and _rows(out)[0]["wall_s"] == first[0]["wall_s"]


def _error(capsys):
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0, err
    assert err.startswith("bearing-gym: error:"), err
    return err


@pytest.mark.parametrize("argv, names", [
    (["simulate", "--preload", "-5"], ["--preload", "[0, 1e+06]", "-5"]),
    (["simulate", "--rpm", "nan"], ["--rpm", "[0, 200000]"]),
    (["equilibrium", "--clearance-um", "500"], ["--clearance-um", "[0, 381)"]),
    (["simulate", "--dt-us", "0"], ["--dt-us", "(0, 1000] us"]),
    (["simulate", "--duration", "-1"], ["--duration", "(0, 10000] s"]),
    (["equilibrium", "--race-control", "sideways"], ["--race-control", "outer"]),
    (["simulate", "--rpm", "fast"], ["--rpm", "not a number"]),
    (["simulate", "--no-such-option", "1"], ["--no-such-option"]),
    (["floquet", "--fd-step-um", "0"], ["--fd-step-um", "(0, 10] um"]),
    (["sweep", "--preloads", "800", "--rpms", "20000", "-100"], ["--rpms", "[0, 200000]"]),
    (["sweep", "--preloads", "800", "--measure-s", "0"], ["--measure-s"]),
    (["sweep", "--rpm", "20000"], ["--preloads"]),
    (["sweep", "--preloads", "800", "--address", "auto"], ["--address", "--backend ray"]),
    (["sweep", "--preloads", "800", "--backend", "dask"], ["--backend", "'local', 'ray'"]),
    (["sweep", "--preloads", "800", "--backend", "ray", "--address", " "], ["--address", "empty"]),
])
def test_bad_options_exit_nonzero_with_one_line_naming_the_option(argv, names, tmp_path, capsys):
    assert cli.main(argv + (["--out", str(tmp_path / "x")] if argv[0] == "simulate" else [])) == 2
    err = _error(capsys)
    for name in names:
        assert name in err


@pytest.mark.parametrize("text, suffix, names", [
    ("rpm = 10000\nspeed = 3\n", ".toml", ["--config", "'speed'"]),
    ("[equilibrium]\nduration = 0.1\n", ".toml", ["--config", "'duration'", "[equilibrium]"]),
    ("preload: -5\n", ".yaml", ["--preload", "[0, 1e+06]"]),
    ("rpm: fast\n", ".yml", ["--rpm", "must be a number"]),
    ("rpm = \n", ".toml", ["--config", "invalid TOML"]),
    ("rpm: 1\n", ".ini", ["--config", "use .toml, .yaml or .yml"]),
])
def test_bad_config_files(text, suffix, names, tmp_path, capsys):
    path = tmp_path / f"c{suffix}"
    path.write_text(text)
    assert cli.main(["equilibrium", "--config", str(path)]) == 2
    err = _error(capsys)
    for name in names:
        assert name in err


def _without_ray(monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a, **k: None if name == "ray" else real(name, *a, **k))


def test_address_is_checked_before_the_ray_install(monkeypatch, capsys):
    """An empty --address is named as such whether or not ray is installed."""
    _without_ray(monkeypatch)
    assert cli.main(["sweep", "--preloads", "800", "--backend", "ray", "--address", " "]) == 2
    err = _error(capsys)
    assert err.startswith("bearing-gym: error: --address: must not be empty")


def test_sweep_backend_ray_without_ray_says_how_to_install(monkeypatch, capsys):
    _without_ray(monkeypatch)
    assert cli.main(["sweep", "--preloads", "800", "--backend", "ray"]) == 2
    err = _error(capsys)
    assert "--backend" in err and "pip install 'bearing-gym[ray]'" in err


def test_help_lists_units(capsys):
    assert cli.main(["simulate", "--help"]) == 0
    text = capsys.readouterr().out
    for unit in ("(rpm", "(N", "(um", "(us", "(s,"):
        assert unit in text


def test_the_watch_command_moved_to_the_agents(capsys):
    assert cli.main(["watch", "--policy", "feedback"]) == 2
    assert "invalid choice: 'watch'" in _error(capsys)


def test_reproduce_passes_its_options_through(tmp_path, capsys, monkeypatch):
    from bearing_gym.reproduction import main as reproduction

    seen = []

    def fake_main(argv=None):
        seen.append(list(argv))
        print("reproduction output")
        return 0

    monkeypatch.setattr(reproduction, "main", fake_main)
    cfg = tmp_path / "r.toml"
    cfg.write_text('[reproduce]\nquick = true\nworkers = 1\nredo = ["waviness_", "detail_"]\n')
    assert cli.main(["reproduce", "--config", str(cfg), "--out", "X", "-q"]) == 0
    assert seen[-1] == ["--quick", "--workers", "1", "--redo", "waviness_", "detail_",
                        "--out", "X", "--no-progress"]
    assert capsys.readouterr().out == ""           # --quiet
    monkeypatch.undo()
    assert cli.main(["reproduce", "--help"]) == 0  # the real parser of the reproduction
    assert "--report-only" in capsys.readouterr().out


def test_python_m_bearing_gym_cli_in_a_subprocess(tmp_path):
    env = dict(os.environ)
    ok = subprocess.run([sys.executable, "-m", "bearing_gym.cli", "equilibrium", "--rpm", "10000",
                         "--quiet", "--json", "-"], capture_output=True, text=True, env=env,
                        timeout=300)
    assert ok.returncode == 0, ok.stderr
    assert json.loads(ok.stdout)["params"]["shaft_speed_rpm"] == 10000
    bad = subprocess.run([sys.executable, "-m", "bearing_gym.cli", "simulate", "--preload", "-5",
                          "--out", str(tmp_path / "s")], capture_output=True, text=True, env=env,
                         timeout=300)
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.strip() == ("bearing-gym: error: --preload: axial_preload_n must be in "
                                  "[0, 1e+06], got -5")
