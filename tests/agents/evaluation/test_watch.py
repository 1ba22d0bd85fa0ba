"""``python -m agents.evaluation.watch`` (console script bearing-gym-watch): play a scripted or trained
policy in the env with render_mode="human", headless here (frames as PNG files)."""

import json
import re
import subprocess
import sys

import pytest

from agents.evaluation import watch


def _error(capsys):
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0, err
    assert err.startswith("bearing-gym-watch: error:"), err
    return err


@pytest.mark.parametrize("argv, names", [
    ([], ["--model/--policy"]),
    (["--policy", "feedback", "--model", "runs/x"], ["--model/--policy", "exactly one"]),
    (["--policy", "constant:5000"], ["--policy", "[300, 2000] N", "5000"]),
    (["--policy", "constant:lots"], ["--policy", "not a number"]),
    (["--policy", "dance"], ["--policy", "unknown policy 'dance'"]),
    (["--model", "/no/such/dir"], ["--model", "no such directory"]),
    (["--policy", "feedback", "--steps", "0"], ["--steps", "[1, 100000]"]),
    (["--policy", "feedback", "--tier", "moon"], ["--tier", "transient"]),
])
def test_bad_options_exit_2_with_one_line_naming_the_option(argv, names, capsys):
    assert watch.main(argv) == 2
    err = _error(capsys)
    for name in names:
        assert name in err


_STEP_LINE = re.compile(r"^\s*(\d+)\s+(\d+)" + r"\s+(-?[\d.]+)" * 5 + r"\s*$")


def _steps(text):
    """The per-step lines of bearing-gym-watch: (episode, step, t, preload, set-point, qpi,
    reward)."""
    return [tuple(float(v) for v in m.groups()) for m in map(_STEP_LINE.match, text.splitlines())
            if m]


def test_watch_scripted_policy_headless_writes_frames_and_step_lines(tmp_path, capsys):
    frames = tmp_path / "frames"
    assert watch.main(["--policy", "constant:1200", "--tier", "paper", "--steps", "3",
                       "--frames", str(frames)]) == 0
    text = capsys.readouterr().out
    steps = _steps(text)
    assert [s[:3] for s in steps] == [(0, 1, 0.02), (0, 2, 0.04), (0, 3, 0.06)]
    assert all(s[4] == 1200.0 and 1000.0 <= s[3] <= 1200.0 and 0 <= s[5] < 2 and s[6] < 0
               for s in steps)
    assert "constant 1200 N" in text and "episode 0: return" in text
    assert sorted(p.name for p in frames.iterdir()) == [f"frame_{k:05d}.png" for k in range(4)]
    assert (frames / "frame_00003.png").read_bytes()[:4] == b"\x89PNG"
    # two episodes, quiet: no output, the frames still come
    assert watch.main(["--policy", "feedback", "--episodes", "2", "--steps", "1", "-q",
                       "--frames", str(tmp_path / "q")]) == 0
    assert capsys.readouterr().out == ""
    assert len(list((tmp_path / "q").iterdir())) == 4


def test_watch_a_model_directory_of_train_py(tmp_path, capsys, monkeypatch):
    """An (untrained) PPO model saved the way train.py saves one: model.zip, config.json and
    the VecNormalize statistics; without --frames the latest frame goes to the temp dir."""
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "tmp"))
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    from bearing_gym.envs import BearingPreloadEnv

    venv = VecNormalize(DummyVecEnv([lambda: BearingPreloadEnv(scenario="paper")]))
    venv.obs_rms.mean[:] = 0.5
    PPO("MlpPolicy", venv, n_steps=8, batch_size=8, seed=0, device="cpu").save(tmp_path / "model.zip")
    venv.save(tmp_path / "vec_normalize.pkl")
    (tmp_path / "config.json").write_text(json.dumps({"algo": "ppo"}))
    assert watch.main(["--model", str(tmp_path), "--steps", "2", "--seed", "7"]) == 0
    text = capsys.readouterr().out
    assert "PPO (trained)" in text and "(seed 7)" in text
    latest = tmp_path / "tmp" / "bearing_gym_frames" / "latest.png"
    assert f"latest frame goes to {latest}" in text and latest.is_file()
    assert [s[:2] for s in _steps(text)] == [(0, 1), (0, 2)]
    # a shipped directory holding the portable export alone (protocol 2's --ship without the run's
    # SB3 files) plays the same policy: the same lines, step by step (both plays go through the
    # portable float64 path, as the board loads a model: the same printed values)
    from agents.evaluation.trained import export
    export(tmp_path)
    (tmp_path / "model.zip").unlink()
    (tmp_path / "vec_normalize.pkl").unlink()
    assert watch.main(["--model", str(tmp_path), "--steps", "2", "--seed", "7"]) == 0
    played = _steps(capsys.readouterr().out)
    assert len(played) == 2 and played == _steps(text)
    (tmp_path / "config.json").unlink()
    assert watch.main(["--model", str(tmp_path)]) == 2
    assert "config.json" in _error(capsys)


def test_python_m_agents_watch_in_a_subprocess(tmp_path):
    run = subprocess.run([sys.executable, "-m", "agents.evaluation.watch", "--policy", "constant:900",
                          "--tier", "paper", "--steps", "1", "-q", "--frames",
                          str(tmp_path / "f")], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout == ""
    assert sorted(p.name for p in (tmp_path / "f").iterdir()) == ["frame_00000.png", "frame_00001.png"]
