"""A resumed run's validation record: what it was at the checkpoint it resumes from (the
validations of the stopped session after that checkpoint are on a discarded trajectory)."""

import json

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from agents.training.callbacks import BEST_INFO, BEST_MODEL, BEST_VECNORMALIZE, restore_selection  # noqa: E402


def _run(tmp_path, best_step, results):
    """An eval dir validated at 32, 64, 96 and 128 steps (``results``: per step the returns of 2
    episodes), its selected checkpoint at ``best_step``, an early-row copy by_64, and checkpoints
    at 32, 64 and 96 (the session stopped before the one at 128)."""
    ev, ck = tmp_path / "eval", tmp_path / "checkpoints"
    ev.mkdir()
    ck.mkdir()
    steps = np.array([32, 64, 96, 128])
    res = np.array(results, dtype=float)
    np.savez(ev / "evaluations.npz", timesteps=steps, results=res, ep_lengths=np.full(res.shape, 16))
    np.savez(ev / "validation_returns.npz", timesteps=steps, seeds=np.array([50000, 50001]), returns=res)
    (ev / BEST_MODEL).write_bytes(f"model {best_step}".encode())
    (ev / BEST_VECNORMALIZE).write_bytes(f"stats {best_step}".encode())
    (ev / BEST_INFO).write_text(json.dumps({"mean_validation_return": float(res[list(steps).index(best_step)].mean()),
                                            "num_timesteps": best_step, "validation_seed": 50000, "episodes": 2}))
    (ev / "by_64").mkdir()
    (ev / "by_64" / BEST_INFO).write_text("{}")
    for t in (32, 64, 96):
        (ck / f"model_{t}_steps.zip").write_bytes(f"checkpoint {t}".encode())
        (ck / f"model_vecnormalize_{t}_steps.pkl").write_bytes(f"checkpoint stats {t}".encode())
    return ev, ck


def test_a_selection_made_after_the_checkpoint_is_restored_to_the_best_validation_kept(tmp_path):
    # means: -10, -5 (best kept), -5 (a tie: the first keeps it), -1 (after the checkpoint: dropped)
    ev, ck = _run(tmp_path, 128, [[-12, -8], [-6, -4], [-5, -5], [0, -2]])
    restore_selection(ev, ck, 96, snapshot_at=64)
    with np.load(ev / "evaluations.npz") as log:
        assert log["timesteps"].tolist() == [32, 64, 96] and log["results"].shape == (3, 2)
    with np.load(ev / "validation_returns.npz") as log:
        assert log["timesteps"].tolist() == [32, 64, 96] and log["seeds"].tolist() == [50000, 50001]
    info = json.loads((ev / BEST_INFO).read_text())
    assert info["num_timesteps"] == 64 and info["mean_validation_return"] == -5.0 and info["episodes"] == 2
    assert (ev / BEST_MODEL).read_bytes() == b"checkpoint 64"
    assert (ev / BEST_VECNORMALIZE).read_bytes() == b"checkpoint stats 64"
    assert (ev / "by_64" / BEST_INFO).exists()                 # made at 64 <= 96: kept


def test_a_selection_before_the_checkpoint_stays_and_a_later_early_row_goes(tmp_path):
    ev, ck = _run(tmp_path, 32, [[-1, -1], [-6, -4], [-5, -5], [0, 2]])
    restore_selection(ev, ck, 32, snapshot_at=64)
    assert json.loads((ev / BEST_INFO).read_text())["num_timesteps"] == 32
    assert (ev / BEST_MODEL).read_bytes() == b"model 32"
    assert not (ev / "by_64").exists()                         # made at 64 > 32: to be made again


def test_a_selection_without_the_checkpoint_to_restore_it_from_is_refused(tmp_path):
    ev, ck = _run(tmp_path, 128, [[-12, -8], [-6, -4], [-5, -5], [0, -2]])
    (ck / "model_64_steps.zip").unlink()
    with pytest.raises(RuntimeError, match="best validation kept \\(64 steps\\) has no checkpoint"):
        restore_selection(ev, ck, 96)
