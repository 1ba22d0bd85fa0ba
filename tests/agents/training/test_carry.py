"""A run paused by train.py --until, carried through an archive to another directory (another
machine), and continued there: the pause point, what the carry holds, and the continued run."""

import io
import json
import sys
import tarfile
from datetime import datetime
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from agents.training import carry
from agents.training import protocol_runs as T
from agents.training.callbacks import StopBefore


ROOT = Path(__file__).resolve().parents[3]


def _stepper(cb: StopBefore, clock: list[float], monkeypatch):
    """Drive ``cb`` as SB3 does, with ``time.time`` reading ``clock[0]``."""
    monkeypatch.setattr("agents.training.callbacks.time.time", lambda: clock[0])
    cb.init_callback(SimpleNamespace(num_timesteps=0, get_env=lambda: None, logger=None))
    cb.on_training_start({}, {})

    def step(seconds: float) -> bool:
        clock[0] += seconds
        cb.model.num_timesteps += 2
        return cb.on_step()
    return step


def test_stop_before_pauses_at_the_last_resume_point_the_deadline_allows(monkeypatch):
    """Resume points every 3 calls, each interval 10 s: with the deadline at 65 s and margin 1.25
    the point at 30 s goes on (30 + 12.5 <= 65), the one at 60 s pauses (60 + 12.5 > 65); calls between
    points never stop."""
    clock = [0.0]
    cb = StopBefore(deadline=65.0, every=3, margin=1.25)
    step = _stepper(cb, clock, monkeypatch)
    results = [step(10 / 3) for _ in range(9)]
    assert results[:5] == [True] * 5 and not cb.paused   # points at calls 3 (10 s) and 6 (20 s)
    assert results[5] is True                            # the point at call 6: 20 + 12.5 <= 65
    assert results[8] is True                            # call 9 at 30 s: 30 + 12.5 <= 65
    results = [step(10 / 3) for _ in range(9)]
    assert results[-1] is False and cb.paused            # call 18 at 60 s: 60 + 12.5 > 65
    assert all(results[:-1])
    assert cb.num_timesteps == 36


def test_stop_before_checks_its_arguments():
    with pytest.raises(ValueError, match="every must be >= 1"):
        StopBefore(0.0, every=0)
    with pytest.raises(ValueError, match="margin must be >= 1"):
        StopBefore(0.0, every=1, margin=0.5)


def _paused_run(tmp_path: Path, monkeypatch) -> tuple[Path, Path, list]:
    """A SAC run on a 12-start bank (16-step episodes, 2 envs), paused by --until at its first
    resume point (32 steps: the deadline is now)."""
    sys.path.insert(0, str(ROOT))
    import train
    from bearing_gym.envs import start_bank as banks
    path = banks.build("transient", tuple(range(31, 43)), episode_steps=16).save(tmp_path / "a" / "start_bank_transient.npz")
    monkeypatch.setattr(train, "start_bank_path", lambda tier: path)
    monkeypatch.setattr("agents.clock.deadline", lambda text: datetime.now())
    drawn: list = []
    sample = banks.BankScenarios.sample
    monkeypatch.setattr(banks.BankScenarios, "sample",
                        lambda self, *a, **k: drawn.append(sample(self, *a, **k)) or drawn[-1])
    out = tmp_path / "a" / "run"
    assert train.main(["--algo", "sac", "--n-envs", "2", "--episode-steps", "16", "--eval-episodes", "0",
                       "--val-episodes", "2", "--eval-freq", "32", "--out", str(out), "--no-progress",
                       "--timesteps", "128", "--until", "23:59"]) == 0
    return out, path, drawn


def test_a_paused_run_is_carried_to_another_directory_and_finishes_there(tmp_path, monkeypatch, capsys):
    out, bank_a, drawn = _paused_run(tmp_path, monkeypatch)
    printed = capsys.readouterr().out
    cfg = json.loads((out / "config.json").read_text())
    # paused at the first resume point, with nothing written as if the run were done
    assert cfg["paused"] is True and cfg["num_timesteps"] == 32 and cfg["train_wall_s"] > 0
    assert "paused at 32 of 128 steps" in printed
    assert not (out / "model.zip").exists() and not (out / "last_model.zip").exists()
    first = list(drawn)
    assert len(first) == 4                                   # 2 envs, each on its 2nd episode at 32 steps

    archive = carry.pack(out, tmp_path / "carry" / "sac_s0.tar.xz")
    with tarfile.open(archive, "r:xz") as tar:
        names = set(tar.getnames())
    assert {"config.json", "start_bank.json", "eval/best.json", "eval/evaluations.npz", "checkpoints/model_32_steps.zip",
            "checkpoints/model_vecnormalize_32_steps.pkl", "checkpoints/model_replay_buffer_32_steps.pkl"} <= names
    assert not any(n.startswith("tensorboard") or n.endswith(".running") for n in names)
    assert carry.carry_steps(archive) == 32
    assert "paused at 32 of 128 steps" in carry.describe(archive)

    # another machine: another checkout path holds the same bank
    bank_b = tmp_path / "b" / "start_bank_transient.npz"
    bank_b.parent.mkdir()
    bank_b.write_bytes(bank_a.read_bytes())
    other = tmp_path / "b" / "run"
    assert carry.unpack(archive, other, bank_b) == 32
    assert json.loads((other / "start_bank.json").read_text())["path"] == str(bank_b.resolve())
    with pytest.raises(carry.CarryError, match="not older than the carry's"):
        carry.unpack(archive, other, bank_b)

    import shutil
    shutil.rmtree(out)                                       # the first machine is gone
    import train
    monkeypatch.setattr(train, "start_bank_path", lambda tier: bank_b)
    drawn.clear()
    capsys.readouterr()
    assert train.main(["--algo", "sac", "--n-envs", "2", "--episode-steps", "16", "--eval-episodes", "0",
                       "--val-episodes", "2", "--eval-freq", "32", "--out", str(other), "--no-progress",
                       "--timesteps", "128", "--resume"]) == 0
    printed = capsys.readouterr().out
    assert "resuming from" in printed and "resuming after 4 of its 12 scenarios" in printed
    assert "no replay buffer" not in printed                 # the carried buffer was loaded
    done = json.loads((other / "config.json").read_text())
    assert not done.get("paused") and done["num_timesteps"] == 128 and (other / "model.zip").exists()
    assert done["train_wall_s"] > cfg["train_wall_s"]        # the first machine's time counts
    # the resumed model logs to this machine's run directory, not to the first machine's
    assert not out.exists()
    with np.load(other / "eval" / "evaluations.npz") as log:
        assert list(log["timesteps"]) == [32, 64, 96, 128]   # the carried validation history goes on
    from bearing_gym.envs import start_bank as banks
    bank = banks.load(bank_b)
    # over both machines no scenario of the bank is drawn twice before all are drawn
    assert sorted(bank.scenarios.index(sc) for sc in first + drawn[:8]) == list(range(12))


def test_only_a_paused_run_is_carried_and_a_foreign_bank_is_refused(tmp_path, monkeypatch):
    out, bank_a, _ = _paused_run(tmp_path, monkeypatch)
    archive = carry.pack(out, tmp_path / "c.tar.xz")
    from bearing_gym.envs import start_bank as banks
    other_bank = banks.build("transient", tuple(range(31, 41)), episode_steps=16).save(tmp_path / "b" / "bank.npz")
    with pytest.raises(carry.CarryError, match="start bank of 12 starts .* holds 10"):
        carry.unpack(archive, tmp_path / "b" / "run", other_bank)
    cfg = json.loads((out / "config.json").read_text())
    (out / "config.json").write_text(json.dumps(dict(cfg, paused=False)))
    with pytest.raises(carry.CarryError, match="only a run paused by train.py --until"):
        carry.pack(out, tmp_path / "d.tar.xz")
    assert not (tmp_path / "b" / "run").exists()            # nothing is unpacked from a refused carry
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "config.json").write_text(json.dumps(dict(cfg, paused=True)))
    with pytest.raises(carry.CarryError, match="no checkpoint"):
        carry.pack(empty, tmp_path / "e.tar.xz")


def test_a_pause_due_at_the_budgets_end_is_the_runs_end(tmp_path, monkeypatch):
    """The deadline is now, and the first resume point is the budget's last step: the run ends
    there as a finished run (model.zip, no pause), not as a pause with nothing left to train."""
    sys.path.insert(0, str(ROOT))
    import train
    monkeypatch.setattr("agents.clock.deadline", lambda text: datetime.now())
    out = tmp_path / "run"
    assert train.main(["--algo", "sac", "--n-envs", "2", "--episode-steps", "16", "--eval-episodes", "0",
                       "--val-episodes", "2", "--eval-freq", "32", "--out", str(out), "--no-progress",
                       "--timesteps", "32", "--until", "23:59", "--start-bank", "none"]) == 0
    cfg = json.loads((out / "config.json").read_text())
    assert not cfg.get("paused") and cfg["num_timesteps"] == 32 and (out / "model.zip").exists()


def test_a_carry_replaces_the_state_of_another_trajectory_and_is_not_overwritten_by_a_shorter_one(tmp_path, monkeypatch):
    out, bank_a, _ = _paused_run(tmp_path, monkeypatch)
    archive = carry.pack(out, tmp_path / "c.tar.xz")
    # a work directory left by another attempt, older than the carry: its checkpoints and
    # validation record go, the carry's come
    other = tmp_path / "other"
    (other / "checkpoints").mkdir(parents=True)
    (other / "checkpoints" / "model_16_steps.zip").write_text("another trajectory")
    (other / "eval").mkdir()
    (other / "eval" / "best.json").write_text("{}")
    assert carry.unpack(archive, other, bank_a) == 32
    assert sorted(f.name for f in (other / "checkpoints").iterdir()) == [
        "model_32_steps.zip", "model_replay_buffer_32_steps.pkl", "model_vecnormalize_32_steps.pkl"]
    assert json.loads((other / "eval" / "best.json").read_text())["num_timesteps"] == 32
    assert not (tmp_path / "other.unpacking").exists()
    # a carry further than the run being packed is kept
    cfg = json.loads((out / "config.json").read_text())
    for name in ("model_32_steps.zip", "model_vecnormalize_32_steps.pkl"):
        (out / "checkpoints" / name).rename(out / "checkpoints" / name.replace("32", "16"))
    (out / "config.json").write_text(json.dumps(dict(cfg, num_timesteps=16)))
    with pytest.raises(carry.CarryError, match="paused at 32 steps, further than the 16"):
        carry.pack(out, archive)
    assert carry.carry_steps(archive) == 32
    with pytest.raises(carry.CarryError, match="cannot be read as a carry"):
        carry.carry_steps(tmp_path / "missing.tar.xz")


def test_a_carry_with_a_path_outside_the_run_is_refused(tmp_path):
    evil = tmp_path / "evil.tar.xz"
    with tarfile.open(evil, "w:xz") as tar:
        data = json.dumps({"num_timesteps": 1}).encode()
        for name in ("config.json", "../outside.txt"):
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    with pytest.raises(carry.CarryError, match="not a plain relative file"):
        carry.unpack(evil, tmp_path / "run")
    assert not (tmp_path / "outside.txt").exists()


def test_protocol_runs_pack_a_paused_v2_run_and_continue_it_from_the_carry(tmp_path, monkeypatch):
    """train_run passes --until to train.py; a run train.py paused is packed into its carry and not
    collected; on a machine without the work directory the carry is unpacked and train.py resumes."""
    root = tmp_path / "root"
    root.mkdir()
    (root / "train.py").write_text(
        "import json, sys, pathlib\n"
        "argv = sys.argv[1:]\n"
        "out = pathlib.Path(argv[argv.index('--out') + 1])\n"
        "(out / 'argv.json').write_text(json.dumps(argv))\n"
        "(out / 'checkpoints').mkdir(exist_ok=True)\n"
        "(out / 'eval').mkdir(exist_ok=True)\n"
        "steps = 20000 if '--resume' in argv else 10000\n"
        "for name in (f'model_{steps}_steps.zip', f'model_vecnormalize_{steps}_steps.pkl', f'model_replay_buffer_{steps}_steps.pkl'):\n"
        "    (out / 'checkpoints' / name).write_text(name)\n"
        "(out / 'eval' / 'best.json').write_text('{}')\n"
        "(out / 'start_bank.json').write_text(json.dumps({'path': None}))\n"
        "(out / 'config.json').write_text(json.dumps({'paused': True, 'num_timesteps': steps, 'timesteps': 300000, 'train_wall_s': 60.0}))\n")
    monkeypatch.setattr(T, "ROOT", root)
    carry_dir = tmp_path / "carry"
    kw = dict(budget=300000, trained_dir=tmp_path / "t", threads=1, protocol=2, until="23:59", carry_dir=carry_dir)
    assert T.train_run("tqc", 2000, work_dir=tmp_path / "w1", **kw) is None
    archive = T.carry_path("tqc", 2000, carry_dir)
    assert carry.carry_steps(archive) == 10000
    argv = json.loads((tmp_path / "w1" / "tqc_s2000" / "argv.json").read_text())
    assert argv[argv.index("--until") + 1] == "23:59" and "--resume" not in argv
    assert not (tmp_path / "t" / "tqc").exists()          # a paused run is not collected
    # the next machine: an empty work directory; the carry is unpacked and the run resumed
    assert T.train_run("tqc", 2000, work_dir=tmp_path / "w2", **kw) is None
    argv = json.loads((tmp_path / "w2" / "tqc_s2000" / "argv.json").read_text())
    assert "--resume" in argv
    assert (tmp_path / "w2" / "tqc_s2000" / "checkpoints" / "model_replay_buffer_10000_steps.pkl").read_text() == \
        "model_replay_buffer_10000_steps.pkl"
    assert carry.carry_steps(archive) == 20000            # the carry now holds the later pause
    # a carry that cannot be used stops the run instead of starting it afresh over the carried progress
    archive.write_bytes(b"not an archive")
    with pytest.raises(SystemExit, match="has a carry that cannot be used"):
        T.train_run("tqc", 2000, work_dir=tmp_path / "w3", **kw)
    assert not (tmp_path / "w3" / "tqc_s2000" / "argv.json").exists()
