"""The leaderboard's smoke run (what CI runs): 2 test episodes of a few intervals, every
reference and a learned algorithm with two training seeds, written to results.json."""

import json
import math

import numpy as np
import pytest

from agents.leaderboard import board as leaderboard

REQUIRED = ("normalised_score_iqm", "ci_low", "ci_high", "n_seeds", "n_episodes")


def _untrained_run(d, seed, tier="transient"):
    """A train.py-like run directory holding an untrained PPO (no training: the weights are the
    seed's initialisation), enough to exercise the learned-policy path."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecNormalize

    from bearing_gym.envs import BearingPreloadSB3VecEnv
    env = VecNormalize(BearingPreloadSB3VecEnv(num_envs=1, tier="transient", episode_steps=3, max_episode_steps=3))
    PPO("MlpPolicy", env, n_steps=8, batch_size=8, seed=seed, device="cpu").save(d / "model.zip")
    env.save(str(d / "vec_normalize.pkl"))
    (d / "config.json").write_text(json.dumps({"algo": "ppo", "seed": seed, "tier": tier, "num_timesteps": 0}))


def untrained_runs(parent, seeds=(0, 1000)):
    """One untrained PPO run directory per seed under ``parent`` (:func:`_untrained_run`)."""
    runs = []
    for seed in seeds:
        d = parent / f"ppo_{seed}"
        d.mkdir()
        _untrained_run(d, seed)
        runs.append(str(d))
    return runs


def test_smoke_leaderboard_writes_every_row_with_its_statistics(tmp_path):
    runs = untrained_runs(tmp_path)
    out = tmp_path / "lb" / "results.json"
    leaderboard.main(["--smoke", "--out", str(out), "--model", *runs])
    data = json.loads(out.read_text())
    from agents import protocol as P
    from agents.leaderboard.results_file import protocol_summary
    assert data["mode"] == "smoke" and data["protocol"] == protocol_summary(P.PROTOCOL_VERSION)
    tier = data["tiers"]["transient"]
    assert not tier["protocol"] and tier["protocol_deviations"][0].startswith("smoke run")
    rows = tier["policies"]
    kinds = {"validation constant": 0, "hindsight constant": 0, "contextual constant": 0, "oracle": 0, "planner": 0,
             "PPO (trained)": 0}
    for name in rows:
        for k in kinds:
            kinds[k] += name.startswith(k)
    assert all(v == 1 for v in kinds.values()), kinds
    for name, r in rows.items():
        assert all(k in r for k in REQUIRED), name
        assert all(math.isfinite(r[k]) for k in ("normalised_score_iqm", "ci_low", "ci_high", "mean_return")), name
        assert r["ci_low"] - 1e-12 <= r["normalised_score_iqm"] <= r["ci_high"] + 1e-12, name
        per_episode = np.array(r["episode_returns"])
        assert per_episode.shape == (r["n_seeds"], r["n_episodes"]), name
        assert per_episode.mean() == pytest.approx(r["mean_return"], rel=1e-12), name
    by = {k: next(r for n, r in rows.items() if n.startswith(k)) for k in kinds}
    # the validation constant is the zero; the hindsight constant (it includes the validation
    # constant among its candidates) is at or above it and at most the upper reference
    assert by["validation constant"]["normalised_score_iqm"] == 0.0
    assert 0.0 <= by["hindsight constant"]["normalised_score_iqm"] <= 1.0 + 1e-12
    # the planner is the upper reference on every episode, never below the hindsight constant
    planner = by["planner"]
    assert planner["n_episodes"] == 2 and planner["n_seeds"] == 1 and tier["planner_episodes"] == 2
    assert np.all(np.array(planner["episode_returns"][0]) >= np.array(by["hindsight constant"]["episode_returns"][0]))
    assert planner["normalised_score_iqm"] <= 1.0 + 1e-12
    ppo = by["PPO (trained)"]
    assert ppo["n_seeds"] == 2 and ppo["n_episodes"] == 2 and ppo["training_seeds"] == [0, 1000]
    assert "seed_ci_low" in ppo and ppo["poi_ci_low"] is not None
    p, lo, hi = ppo["poi_over"]["contextual constant"]          # two seeds: an interval exists
    assert 0.0 <= lo <= p <= hi <= 1.0
    # the smoke run builds its validation constant and contextual fit in its output directory
    assert (out.parent / "reference_constants.json").exists() and (out.parent / "contextual_transient.json").exists()
    table = (out.parent / "results_table.md").read_text()
    assert all(f"| {name} |" in table for name in rows)
    assert "- PPO (trained): seed 0, 0 steps, -; seed 1000, 0 steps, -" in table     # no train_wall_s recorded
    assert (f"| PPO (trained) | {ppo['normalised_score_iqm']:.3f} [{ppo['ci_low']:.3f}, {ppo['ci_high']:.3f}] "
            f"| {ppo['normalised_score_mean']:.3f}") in table                  # the statistics beyond the IQM


def test_pretrained_without_shipped_policies_says_what_to_do(tmp_path):
    with pytest.raises(FileNotFoundError, match="model.zip"):
        leaderboard.learned_groups([], pretrained=True, pretrained_dir=tmp_path)


def test_the_full_mode_needs_the_stored_references_and_names_the_commands(tmp_path):
    from agents.references.store import ValidationChoice, save_choice
    with pytest.raises(LookupError, match="python -m agents.references --tier transient"):
        leaderboard.run_tier("transient", leaderboard.FULL, [], store=tmp_path / "none.json",
                             contextual_dir=tmp_path, out_dir=tmp_path, progress=False)
    store = tmp_path / "store.json"
    save_choice(ValidationChoice("transient", 1150.0, (50_000, 50_001, 50_002), 850.0, (300.0, 1150.0, 2000.0),
                                 (-3.0, -1.0, -2.0), 150), store)
    with pytest.raises(FileNotFoundError, match="python -m agents.references.contextual_fit --tier transient"):
        leaderboard.run_tier("transient", leaderboard.FULL, [], store=store, contextual_dir=tmp_path,
                             out_dir=tmp_path, progress=False)


def test_stored_references_reproduce_the_computed_rows_and_refuse_a_stale_store(tmp_path):
    """A run that stores its references and one that reads them give the same reference rows
    (the stored validation constant is run again and must repeat its returns); a store whose
    returns the env no longer reproduces is refused with the command that rebuilds it."""
    from agents.references.store import load_references
    s = leaderboard.SMOKE
    computed = leaderboard.run_tier("transient", s, [], out_dir=tmp_path, progress=False,
                                    contextual_dir=tmp_path, save_references_to=tmp_path / "refs")
    refs = load_references("transient", tmp_path / "refs")
    assert refs.seeds == (300000, 300001) and len(refs.planner.returns) == 2
    again = leaderboard.run_tier("transient", s, [], out_dir=tmp_path, progress=False,
                                 contextual_dir=tmp_path, stored=refs)
    assert again["references"].startswith("stored") and computed["references"] == "computed in this run"
    for name, row in computed["policies"].items():
        for key in ("normalised_score_iqm", "ci_low", "ci_high", "mean_return", "heat_cost"):
            assert again["policies"][name][key] == pytest.approx(row[key], rel=1e-12, abs=1e-12), (name, key)
    from bearing_gym.envs.provenance import kernel_hash
    assert refs.kernel_hash == kernel_hash()                 # the store says which kernel made it
    refs.validation_constant.returns[1] = np.nextafter(refs.validation_constant.returns[1], 0.0)
    with pytest.raises(RuntimeError, match="stale.*python -m agents.leaderboard --tier transient"):
        leaderboard.run_tier("transient", s, [], out_dir=tmp_path, progress=False, contextual_dir=tmp_path,
                             stored=refs)                     # one ulp off: the kernel is portable
    refs.validation_constant.returns[1] = np.nan             # a NaN return is no match either
    with pytest.raises(RuntimeError, match="stale"):
        leaderboard.run_tier("transient", s, [], out_dir=tmp_path, progress=False, contextual_dir=tmp_path,
                             stored=refs)
    other = load_references("transient", tmp_path / "refs")
    other.kernel_hash = "0123456789abcdef"                   # made by another kernel
    with pytest.raises(RuntimeError, match="made by kernel 0123456789abcdef.*stale.*agents.leaderboard --tier transient"):
        leaderboard.run_tier("transient", s, [], out_dir=tmp_path, progress=False, contextual_dir=tmp_path,
                             stored=other)


def test_a_deterministic_tier_runs_one_episode_and_names_policies_trained_elsewhere(tmp_path):
    """On the paper tier every seed gives the same episode: the board runs one test episode
    (not a deviation), says why, and evaluates a policy trained on transient under a name that
    says so. The validation episode is then the test episode, so the validation-chosen constant
    is the hindsight best of the same grid, and the contextual fit (same grid in the smoke
    settings, fitted on copies of that episode) picks it too: three rows with one return."""
    d = tmp_path / "ppo_0"
    d.mkdir()
    _untrained_run(d, 0)
    out = tmp_path / "lb" / "results.json"
    leaderboard.main(["--smoke", "--tier", "paper", "--out", str(out), "--model", str(d)])
    tier = json.loads(out.read_text())["tiers"]["paper"]
    assert tier["deterministic"] and tier["episodes"] == 1 and tier["planner_episodes"] == 1
    assert "same episode" in tier["deterministic_note"]
    assert not any("test episodes" in x for x in tier["protocol_deviations"]), tier["protocol_deviations"]
    rows = tier["policies"]
    ppo = rows["PPO (trained) - trained on transient"]
    assert ppo["n_episodes"] == 1 and ppo["n_seeds"] == 1
    by = {k: next(r for n, r in rows.items() if n.startswith(k))
          for k in ("validation constant", "hindsight constant", "contextual constant")}
    returns = {k: r["mean_return"] for k, r in by.items()}
    assert len(set(returns.values())) == 1, returns
    assert "Deterministic tier" in (out.parent / "results_table.md").read_text()


def test_the_after_training_board_on_a_deterministic_tier_keeps_the_stored_references(tmp_path):
    """train.py --tier paper --eval-episodes 20: the board runs the one paper episode with the
    committed references (the planner included), not 20 copies with the hindsight recomputed."""
    from agents.training.after_training import evaluate_run
    _untrained_run(tmp_path, 0, tier="paper")
    board = evaluate_run(tmp_path, episodes=20, tier="paper", pretrained_dir=tmp_path / "no_shipped")
    assert board["episodes"] == 1 and board["planner_episodes"] == 1 and board["references"].startswith("stored")
    assert not any("episodes" in x for x in board["protocol_deviations"]), board["protocol_deviations"]
    assert "short demo on 1 of those episodes" in (tmp_path / "leaderboard.md").read_text()


def test_only_a_run_of_trained_models_overwrites_the_committed_leaderboard(tmp_path, monkeypatch):
    """docs/results.json (the checkout's) only for a protocol-sized run of trained models; every
    other board under the current directory's runs/; an installed package (no checkout) is told
    to pass --out instead of writing into site-packages."""
    from agents import paths
    from agents.leaderboard.results_file import default_out
    monkeypatch.chdir(tmp_path)
    assert default_out(smoke=False, models_given=True) == paths.checkout_root() / "docs" / "results.json"
    for smoke, models in ((False, False), (True, True), (True, False)):
        assert default_out(smoke, models).parent.parent == tmp_path / "runs"
    assert default_out(False, True, protocol_size=False).parent.parent == tmp_path / "runs"
    monkeypatch.setattr(paths, "checkout_root", lambda: None)
    with pytest.raises(ValueError, match="--out"):
        default_out(smoke=False, models_given=True)


def test_protocol_sized_is_decided_per_tier_once():
    """A run is protocol-sized on a tier when it runs the protocol's test episodes and planner
    there: on the deterministic paper tier any --episodes is its one episode; on a random tier
    fewer (or more) episodes are not; a smoke run never is."""
    import dataclasses
    from agents import protocol as P
    from agents.leaderboard.settings import FULL, SMOKE
    fewer = dataclasses.replace(FULL, episodes=P.TEST_EPISODES // 2)
    assert all(FULL.protocol_sized(t) for t in ("paper", "transient", "stationary", "field"))
    assert fewer.protocol_sized("paper") and not fewer.protocol_sized("transient")
    more = dataclasses.replace(FULL, episodes=2 * P.TEST_EPISODES)
    assert more.protocol_sized("paper") and not more.protocol_sized("stationary")
    assert not dataclasses.replace(FULL, planner=None).protocol_sized("field")
    assert not dataclasses.replace(FULL, planner=None).protocol_sized("paper")     # the paper tier's planner skipped
    assert not any(SMOKE.protocol_sized(t) for t in ("paper", "transient"))


def test_keep_other_tiers_keeps_only_what_is_not_recomputed_and_only_under_one_protocol():
    from agents.leaderboard.results_file import kept_tiers
    head = {"benchmark": "BearingPreload-v0", "mode": "full", "protocol": {"test": [300000, 309999]},
            "statistics": {"bootstrap_reps": 50000}, "kernel_hash": "55a0b029d9e058f6"}
    previous = {**head, "command": "python -m agents.leaderboard --tier transient paper",
                "tiers": {"transient": {"episodes": 100}, "paper": {"episodes": 1, "command": "older"}}}
    now = {**head, "command": "python -m agents.leaderboard --tier stationary paper", "tiers": {}}
    kept = kept_tiers(previous, now, ["stationary", "paper"])
    assert list(kept) == ["transient"]                  # paper is recomputed, so not kept
    assert kept["transient"] == {"episodes": 100, "command": previous["command"]}
    for key, other in (("protocol", {"test": [100000, 109999]}), ("mode", "smoke"),
                       ("statistics", {"bootstrap_reps": 10}), ("kernel_hash", None)):   # None: before the portable kernel
        with pytest.raises(ValueError, match=key):
            kept_tiers({**previous, key: other}, now, ["stationary"])


def test_stored_industry_fits_and_causal_mpc_runs_become_rows_compared_pairwise(tmp_path, monkeypatch):
    """A fitted speed switch and a tuned feedback rule stored for this kernel are rows of kind
    industry (evaluated like any policy: their returns are those of the same policies run alone);
    stored causal-MPC runs are replayed as a model-based row; every pair of industry rows gets its
    probability of improvement; a fit of another kernel is left out."""
    from agents import protocol as P
    from agents.evaluation.episodes import run_policies
    from agents.policies.causal_mpc import CausalMPCSettings
    from agents.policies.scripted import FeedbackRule
    from agents.policies.speed_schedule import SpeedSchedule
    from agents.references import causal_mpc_runs
    from agents.references.feedback_fit import feedback_path
    from agents.references.speed_schedule_fit import schedule_path
    from bearing_gym.envs.provenance import kernel_hash
    s = leaderboard.SMOKE
    switch = SpeedSchedule((17500.0,), (1400.0, 900.0))
    schedule_path("transient", "2-level", tmp_path).write_text(json.dumps(
        {"schedule": switch.to_json(), "kernel_hash": kernel_hash()}))
    schedule_path("transient", "table", tmp_path).write_text(json.dumps(
        {"schedule": SpeedSchedule((1e4, 2.5e4), (900.0, 1200.0), True).to_json(), "kernel_hash": "0" * 16}))
    rule = {"start_n": 1500.0, "raise_n": 100.0, "lower_n": 5.0, "hold_steps": 5}
    feedback_path("transient", tmp_path).write_text(json.dumps({"rule": rule, "kernel_hash": kernel_hash()}))
    seeds = list(P.held_out_seeds(s.episodes))
    small = CausalMPCSettings(candidates_n=(800.0, 1600.0), horizon=3, replan_every=5)
    causal_mpc_runs.run("transient", seeds, small, s.episode_steps, data_dir=tmp_path)
    import agents.leaderboard.baselines as B
    monkeypatch.setattr(B, "causal_mpc_row", lambda tier, n, steps, data_dir: causal_mpc_runs.replay(
        tier, causal_mpc_runs.load_runs(tier, n, small, steps, data_dir), steps))
    tier = leaderboard.run_tier("transient", s, [], out_dir=tmp_path, progress=False, contextual_dir=tmp_path)
    rows = tier["policies"]
    kinds = {name: row["kind"] for name, row in rows.items()}
    assert kinds["speed switch (2 levels) (fitted on training seeds)"] == "industry"
    assert kinds["feedback rule (tuned on validation seeds)"] == "industry"
    assert kinds[causal_mpc_runs.ROW_NAME] == "model-based"
    assert not any(name.startswith("speed table") for name in rows)          # another kernel's fit
    alone = run_policies([switch, FeedbackRule(**rule)], s.episodes, seeds[0], s.episode_steps,
                         env_kwargs={"tier": "transient"})
    assert rows["speed switch (2 levels) (fitted on training seeds)"]["episode_returns"] == [alone[0].returns.tolist()]
    assert rows["feedback rule (tuned on validation seeds)"]["episode_returns"] == [alone[1].returns.tolist()]
    iqm = {name: rows[name]["normalised_score_iqm"] for name in rows if rows[name]["kind"] == "industry"}
    assert tier["best_industry_row"] == max(iqm, key=iqm.get)
    pair = tier["pairwise_improvement"]["speed switch (2 levels) (fitted on training seeds)"]
    p, lo, hi = pair["feedback rule (tuned on validation seeds)"]
    assert 0.0 <= lo <= p <= hi <= 1.0


def test_learned_rows_are_compared_with_the_learned_rows_of_their_own_budget():
    """Protocol v2's early rows (the best checkpoint up to 100k steps) are compared with each other,
    the selected checkpoints with each other, and both with every industry and model-based row;
    never an early row with another algorithm's selected checkpoint."""
    rng = np.random.default_rng(0)
    r0, r1 = np.full(6, -100.0), np.full(6, -50.0)

    def row(kind, early=None):
        return {"kind": kind, "early_row_steps": early, "episode_returns": rng.normal(-75, 10, (2, 6)).tolist()}

    rows = {"ref": row("reference"), "switch": row("industry"), "MPC": row("model-based"),
            "A": row("learned"), "B": row("learned"), "A 100k": row("learned", 100_000), "B 100k": row("learned", 100_000)}
    from agents.leaderboard.tables import board_pairwise
    out = board_pairwise(rows, r0, r1, poi_reps=50)
    pairs = {frozenset((a, b)) for a, vs in out.items() for b in vs}
    assert pairs == {frozenset(p) for p in [("switch", "MPC"), ("switch", "A"), ("switch", "B"), ("MPC", "A"),
                                            ("MPC", "B"), ("A", "B"), ("switch", "A 100k"), ("switch", "B 100k"),
                                            ("MPC", "A 100k"), ("MPC", "B 100k"), ("A 100k", "B 100k")]}
    from agents.leaderboard.tables import pairwise_improvement
    alone = pairwise_improvement({k: np.asarray(rows[k]["episode_returns"]) for k in ("switch", "MPC", "A", "B")},
                                 r0, r1, poi_reps=50)
    assert out["A"]["B"] == alone["A"]["B"] and out["switch"]["A"] == alone["switch"]["A"]


def test_protocol_v2_names_every_learned_row_no_run_gives():
    from agents import protocol as P
    g = leaderboard.LearnedGroup("SAC (trained)", "sac", "transient", [], [], [])
    from agents.leaderboard.learned import missing_v2_rows
    missing = missing_v2_rows([g])
    assert len(missing) == 2 * len(P.V2_ALGORITHMS) - 1
    assert "SAC: no early row" in missing[0] and not any(m.startswith("SAC: no trained run") for m in missing)


def test_a_stored_fit_that_is_not_the_protocols_is_named_with_its_command(tmp_path):
    """A fit of this kernel is a row, but one whose record is not what the protocol's fit writes
    (here: tuned on 3 episodes, an older record without candidates) is a deviation naming the refit."""
    from agents.leaderboard import baselines
    from agents.references.feedback_fit import feedback_path
    from bearing_gym.envs.provenance import kernel_hash
    rule = {"start_n": 1500.0, "raise_n": 100.0, "lower_n": 5.0, "hold_steps": 5}
    feedback_path("transient", tmp_path).write_text(json.dumps(
        {"rule": rule, "kernel_hash": kernel_hash(), "tier": "transient", "seeds": [50000, 50002]}))
    assert len(baselines.industry_policies("transient", tmp_path)) == 1
    problems = baselines.not_the_protocols("transient", tmp_path)
    assert len(problems) == 1 and problems[0].startswith("feedback rule is not the protocol's fit (seeds: stored")
    assert problems[0].endswith("python -m agents.references.feedback_fit --tier transient")
    assert baselines.not_the_protocols("stationary", tmp_path) == []          # nothing stored: missing(), not this
