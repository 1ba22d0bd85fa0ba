"""The tier-gap study is resumable: a re-run keeps the scenarios stored with the same settings on
the same kernel and drops those of any other; its summary is the paired statistic of the rows."""

import argparse
import json

import numpy as np
import pytest

from agents.references import tier_gap as G


def _row(seed: int, mpc: float, hindsight: float) -> dict:
    return {"seed": seed, "mpc_return": mpc, "hindsight_return": hindsight, "hindsight_preload_n": 1000.0, "wall_s": 2.0}


def test_a_rerun_keeps_only_rows_made_with_the_same_settings_and_kernel(tmp_path):
    a = argparse.Namespace(tier="transient", grid_step=50.0, horizon=10, replan_every=5)
    settings = G.run_settings(a)
    seeds = [200000, 200001, 200002]
    rows = [_row(200000, -10.0, -14.0), _row(200001, -20.0, -21.0)]
    path = tmp_path / "gap.json"
    path.write_text(json.dumps(G.summarise(settings, seeds, rows)))
    assert sorted(G.stored_rows(str(path), settings)) == [200000, 200001]
    assert G.stored_rows(str(tmp_path / "absent.json"), settings) == {}
    for change in ({"kernel_hash": "0" * 16}, {"grid_step_n": 100.0}, {"mpc": {**settings["mpc"], "horizon": 5}}):
        assert G.stored_rows(str(path), {**settings, **change}) == {}
    # an incomplete run says so; a complete one has the paired mean and its Student-t interval
    assert json.loads(path.read_text())["complete"] is False
    full = G.summarise(settings, seeds, rows + [_row(200002, -5.0, -11.0)])
    diff = np.array([4.0, 1.0, 6.0])
    half = 4.302652729911275 * diff.std(ddof=1) / np.sqrt(3)      # t(0.975, 2 dof)
    assert full["complete"] and full["mpc_wins"] == 3 and full["core_s"] == 6.0
    assert full["paired_mpc_minus_hindsight"] == pytest.approx(diff.mean(), abs=1e-12)
    assert full["ci95_low"] == pytest.approx(diff.mean() - half, rel=1e-9)
