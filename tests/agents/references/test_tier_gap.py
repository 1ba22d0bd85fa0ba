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


def test_the_balance_override_draws_only_the_unbalance_anew():
    """--eccentricity-um 0.2 2.5: each seed's scenario is the tier's with the unbalance drawn in
    that range (the same draws in the same order, so everything else is equal); a stored run
    with the override is not one without it; a deterministic tier and a bad range are refused."""
    import dataclasses

    from bearing_gym.envs import BearingPreloadEnv
    for seed in (200000, 200007, 200013):
        plain, low = BearingPreloadEnv(tier="transient"), BearingPreloadEnv(**G.scenario_kwargs("transient", (0.2, 2.5)))
        plain.reset(seed=seed)
        low.reset(seed=seed)
        assert 0.2e-6 <= low.scenario.eccentricity_m <= 2.5e-6
        assert dataclasses.replace(low.scenario, eccentricity_m=plain.scenario.eccentricity_m) == plain.scenario
    a = argparse.Namespace(tier="transient", grid_step=50.0, horizon=10, replan_every=5, eccentricity_um=[0.2, 2.5])
    b = argparse.Namespace(tier="transient", grid_step=50.0, horizon=10, replan_every=5, eccentricity_um=None)
    assert G.run_settings(a) != G.run_settings(b)
    with pytest.raises(ValueError, match="needs a tier that draws"):
        G.scenario_kwargs("paper", (0.2, 2.5))
    with pytest.raises(ValueError, match="0 < LO <= HI"):
        G.scenario_kwargs("transient", (2.5, 0.2))
