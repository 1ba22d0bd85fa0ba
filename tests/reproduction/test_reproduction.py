"""The reproduction package: the claim rules, the three-model switch, the figure bookkeeping;
the full quick run is a slow test."""

import json
import math

import numpy as np
import pytest

import bearing_gym
from bearing_gym.physics import Simulator
from bearing_gym.reproduction import main as reproduction
from bearing_gym.reproduction.claims import combination_share, verdict
from bearing_gym.reproduction.experiments import simulator_variant
from bearing_gym.reproduction.figures import FIGURE_NAMES, remove_stale_figures
from bearing_gym.reproduction.summary import floquet_axial_pair


def test_combination_share_and_verdict_rule():
    assert combination_share([333.3, 113.0, 220.3, 446.3, 55.0], 333.3, 113.0, 1.0) == 0.8
    ok, bad = dict(passed=True), dict(passed=False)
    assert verdict([ok, ok]) == "matched"
    assert verdict([ok, bad]) == "partly"
    assert verdict([bad, bad]) == "not matched"


def test_axial_pair_of_a_summary_is_the_least_stable_pair_with_an_axial_share():
    pairs = [dict(modulus=0.99, axial_share=0.05), dict(modulus=0.8, axial_share=0.3),
             dict(modulus=0.85, axial_share=0.2), dict(modulus=0.7, axial_share=0.9)]
    assert floquet_axial_pair(dict(pairs=pairs)) is pairs[2]
    # none with 20 %: the most axial one
    low = [dict(modulus=0.99, axial_share=0.05), dict(modulus=0.5, axial_share=0.1)]
    assert floquet_axial_pair(dict(pairs=low)) is low[1]
    assert floquet_axial_pair(None) is None and floquet_axial_pair(dict(pairs=[])) is None


def test_model_variant_switches_the_terms_and_keeps_the_full_models_damping():
    p = bearing_gym.default_params(shaft_speed_rpm=2000.0)
    full = simulator_variant(p, True, True)
    none = simulator_variant(p, False, False)
    assert full.params == p
    assert not none.params.include_centrifugal and not none.params.include_gyroscopic
    np.testing.assert_array_equal(none.damping_coefficients, full.damping_coefficients)
    # started at the equilibrium of the variant: collinear contacts (alpha_i = alpha_o)
    np.testing.assert_allclose(none.equilibrium.alpha_i, none.equilibrium.alpha_o, atol=1e-9)
    np.testing.assert_array_equal(none.state.X, none.equilibrium.U)
    # a variant built from its own equilibrium would be damped differently
    own = Simulator(p.replace(include_centrifugal=False, include_gyroscopic=False))
    assert not np.array_equal(own.damping_coefficients, full.damping_coefficients)


def test_only_the_reproductions_own_stale_figures_are_removed(tmp_path):
    own = sorted(FIGURE_NAMES)
    for name in own[:3] + ["my_plot.png", "notes.txt"]:
        (tmp_path / name).write_bytes(b"x")
    removed = remove_stale_figures(tmp_path, written=[own[0]])
    assert removed == own[1:3]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([own[0], "my_plot.png", "notes.txt"])


@pytest.mark.slow
def test_quick_reproduction_writes_figures_summary_and_report(tmp_path):
    out = tmp_path / "reproduction"
    out.mkdir()
    (out / "someone_elses.png").write_bytes(b"kept")
    assert reproduction.main(["--quick", "--out", str(out), "--no-progress"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    for key in ("critical_preload_n", "critical_preload_n_radial_200", "critical_preload_n_radial_500",
                "floquet_modulus_800n", "floquet_modulus_600n", "critical_preload_n_by_clearance",
                "cage_speed_ratio_by_rpm", "claims"):
        assert key in summary
    assert set(summary["claims"]) == {str(k) for k in range(1, 8)}
    assert set(summary["figures"]) <= FIGURE_NAMES
    for name in summary["figures"]:
        assert (out / name).stat().st_size > 10_000
    assert (out / "someone_elses.png").read_bytes() == b"kept"
    # the Floquet multipliers of the summary are [re, im] pairs
    mu = summary["floquet_800n"]["multipliers"][0]
    assert len(mu) == 2 and all(isinstance(v, float) for v in mu)
    assert math.isfinite(summary["critical_preload_n"])
    report = (tmp_path / "reproduction.md").read_text()
    assert all(f"## Claim {k}" in report for k in range(1, 8))
