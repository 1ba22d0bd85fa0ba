"""Helpers of the reproduction script; the full quick run is a slow test."""

import json
import math
import os

import numpy as np
import pytest

import bearing_gym
from bearing_gym import reproduce
from bearing_gym.physics import static_equilibrium


def test_without_high_speed_terms_the_contact_angles_are_equal():
    # with no centrifugal force and no gyroscopic moment a ball is held by its two contact
    # forces only, so they are collinear: alpha_i = alpha_o (and the cage runs at the
    # epicyclic speed of that angle, w/2 (1 - gamma cos a))
    p = bearing_gym.default_params(shaft_speed_rpm=2000.0)
    eq = static_equilibrium(reproduce._ParamsWithoutHighSpeedTerms(p, False, False))
    np.testing.assert_allclose(eq.alpha_i, eq.alpha_o, atol=1e-9)
    gamma = p.geometry.diameter_ratio
    assert eq.cage_speed_ratio == pytest.approx(0.5 * (1 - gamma * math.cos(eq.alpha_i[0])), rel=1e-9)
    # and the full model is different: the centrifugal force opens the angles apart
    full = static_equilibrium(p)
    assert full.alpha_i[0] - full.alpha_o[0] > math.radians(1)


def test_combination_share_and_verdict_rule():
    assert reproduce._combination_share([333.3, 113.0, 220.3, 446.3, 55.0], 333.3, 113.0, 1.0) == 0.8
    ok, bad = dict(passed=True), dict(passed=False)
    assert reproduce._verdict([ok, ok]) == "matched"
    assert reproduce._verdict([ok, bad]) == "partly"
    assert reproduce._verdict([bad, bad]) == "not matched"


@pytest.mark.slow
@pytest.mark.skipif(not os.environ.get("BEARING_GYM_SLOW"),
                    reason="about 2 minutes on 2 cores; set BEARING_GYM_SLOW=1 to run")
def test_quick_reproduction_writes_figures_summary_and_report(tmp_path):
    out = tmp_path / "reproduction"
    assert reproduce.main(["--quick", "--out", str(out), "--no-progress"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    for key in ("critical_preload_n", "critical_preload_n_radial_200", "critical_preload_n_radial_500",
                "floquet_modulus_800n", "floquet_modulus_600n", "critical_preload_n_by_clearance",
                "cage_speed_ratio_by_rpm", "claims"):
        assert key in summary
    assert set(summary["claims"]) == {str(k) for k in range(1, 8)}
    for name in summary["figures"]:
        assert (out / name).stat().st_size > 10_000
    report = (tmp_path / "reproduction.md").read_text()
    assert all(f"## Claim {k}" in report for k in range(1, 8))
