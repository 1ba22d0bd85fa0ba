"""The side-by-side comparison (python -m agents.evaluate): paired differences, the report,
the trace figure, the shipped policies."""

import csv
from pathlib import Path

import numpy as np
from tests.agents.helpers import diverging, eval_result
import pytest

from agents.evaluation.episodes import run_policies
from agents.policies.scripted import ConstantPreload
from agents.protocol import V2_ALGORITHMS


ROOT = Path(__file__).resolve().parents[3]


def test_paired_difference_matches_a_hand_computed_t_interval():
    from agents.leaderboard.compare_report import paired_difference
    a = eval_result("a", [-10.0, -20.0, -33.0, -41.0])
    b = eval_result("b", [-12.0, -25.0, -34.0, -45.0])
    m, lo, hi = paired_difference(a, b)
    d = np.array([2.0, 5.0, 1.0, 4.0])
    half = 3.182446305284263 * d.std(ddof=1) / 2.0      # t(0.975, 3) from tables
    assert m == pytest.approx(3.0) and lo == pytest.approx(3.0 - half) and hi == pytest.approx(3.0 + half)


def test_evaluation_reports_episodes_that_all_terminate_in_the_same_step(tmp_path):
    from agents.leaderboard.compare_report import write_report
    from bearing_gym.envs.reward import VibrationFirstReward
    # every env of the batch ends in the same step: the next venv.step would only autoreset them
    res = run_policies([ConstantPreload(300.0)], episodes=2, seed=0, episode_steps=25,
                       env_kwargs=diverging(2e-5))[0]
    assert res.terminated.all() and res.terminated_count == 2
    assert np.all(np.isfinite(res.returns))
    worst = VibrationFirstReward().worst_step_cost(20000 * np.pi / 30, 0.0)
    assert np.all(res.returns <= -worst)   # the termination penalty is in the return
    # the trace stops where the episode ended, it does not run on into the autoreset episode
    assert 1 <= len(res.trace["t"]) < 25 and np.all(np.diff(res.trace["t"]) > 0)
    write_report([res], tmp_path, first_seed=0)
    with (tmp_path / "evaluation.csv").open() as fh:
        assert int(next(csv.DictReader(fh))["terminated_episodes"]) == 2
    text = (tmp_path / "evaluation.md").read_text()
    row = next(line for line in text.splitlines() if line.startswith(f"| {res.name} |"))
    assert "terminated early" in text and row.endswith("| 2 |")
    assert (tmp_path / "evaluation_traces.png").stat().st_size > 0


def test_trace_figure_names_its_scenario_shows_the_hindsight_reference_and_labels_every_axis():
    from agents.leaderboard.compare_report import plot_traces
    from agents.evaluation.episodes import hindsight_constant
    sweep = run_policies([ConstantPreload(800.0), ConstantPreload(1400.0)], episodes=2, seed=100000, episode_steps=4)
    h = hindsight_constant(sweep)
    chosen = sweep[int(np.argmax([r.returns[0] for r in sweep]))]
    # the hindsight trace is the first scenario's chosen constant
    assert h.trace is chosen.trace and chosen.name in h.trace_label
    fig = plot_traces([sweep[0], h], None, first_seed=100000)
    try:
        title = fig.get_suptitle()                  # the figure's title, wrapped inside its width
        assert "seed 100000" in title and "rpm" in title and "radial load" in title and "clearance" in title
        assert max(len(line) for line in title.splitlines()) <= 110
        # the legend stands right of the top panel, over no trace
        legend = fig.axes[0].get_legend()
        assert legend is not None and legend.get_bbox_to_anchor().transformed(
            fig.axes[0].transAxes.inverted()).x0 >= 1.0
        assert any(line.get_label() == h.trace_label for line in fig.axes[0].get_lines())
        for ax in fig.axes:
            assert ax.get_ylabel().endswith(")"), ax.get_ylabel()       # every axis has its unit
        assert fig.axes[2].get_xlabel() == "time in episode (s)"
    finally:
        import matplotlib.pyplot as plt
        plt.close(fig)


def test_evaluate_pretrained_runs_every_shipped_policy_and_writes_outside_them(tmp_path, monkeypatch):
    """`python -m agents.evaluate --pretrained` puts each shipped policy (agents/pretrained/<algo>/)
    beside the baselines; without --out or --model the reports go to runs/, never into the
    shipped directories; with no shipped policy it says what to do."""
    from agents.leaderboard import compare as ev
    shipped = ev.shipped_dirs()
    assert {d.name for d in shipped} == set(V2_ALGORITHMS)      # a portable export alone counts (--ship)
    calls = {}
    monkeypatch.setattr(ev, "evaluate", lambda models, episodes, seed, steps, out, **k: calls.update(models=models, out=out))
    ev.main(["--pretrained", "--episodes", "2"])
    assert calls["models"] == shipped and Path(calls["out"]).parts[-2:] == ("runs", "evaluation_pretrained")
    ev.main(["--pretrained", "--model", str(tmp_path), "--episodes", "2"])
    assert calls["models"] == [str(tmp_path), *shipped] and calls["out"] is None   # the first model directory
    monkeypatch.undo()
    ev.main(["--pretrained", "--episodes", "2", "--episode-steps", "2", "--out", str(tmp_path / "out")])
    with (tmp_path / "out" / "evaluation.csv").open() as fh:
        algos = [r["policy"].split(" (")[0].lower() for r in csv.DictReader(fh) if "(trained" in r["policy"]]
    assert sorted(algos) == sorted(d.name for d in shipped)
    with pytest.raises(FileNotFoundError, match="no shipped policy"):
        ev.shipped_dirs(tmp_path / "nothing")
    assert ev.shipped_dirs(tmp_path / "nothing", required=False) == []
