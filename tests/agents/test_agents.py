"""Scripted policies, the evaluation loop and SB3 training (smoke scale)."""

import csv
import json
import pickle
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from agents.evaluate import run_policies
from agents.policies import ConstantPreload, FeedbackRule, OraclePreload, SpeedScheduledPreload
from agents.stability_table import DEFAULT_PATH, StabilityTable
from bearing_gym.envs import BearingPreloadEnv
from bearing_gym.envs.observation import FEATURE_NAMES

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def table():
    return StabilityTable.load(DEFAULT_PATH)


def all_policies(table):
    return [ConstantPreload(900.0), FeedbackRule(), SpeedScheduledPreload(table), OraclePreload(table)]


def test_scripted_policies_act_within_the_action_space(table):
    env = BearingPreloadEnv()
    rng = np.random.default_rng(0)
    obs = np.array([env.observation_space.sample() for _ in range(16)])
    obs[:, 8] = rng.uniform(0, 1.5, 16)          # quasi-periodicity index
    for pol in all_policies(table):
        if isinstance(pol, OraclePreload):
            pol.set_conditions(rng.uniform(0, 40000, 16), rng.uniform(0, 800, 16), rng.uniform(0, 4e-5, 16))
        act, _ = pol.predict(obs)
        assert act.shape == (16, 1) and act.dtype == np.float32
        assert np.all(act >= -1.0) and np.all(act <= 1.0), pol.name


def test_constant_preload_rejects_out_of_range():
    with pytest.raises(ValueError, match="preload_n"):
        ConstantPreload(5000.0)


def test_feedback_rule_raises_on_quasi_periodic_and_lowers_slowly():
    pol = FeedbackRule(start_n=1000.0, raise_n=200.0, lower_n=10.0, hold_steps=2)
    obs = np.zeros((1, len(FEATURE_NAMES)))
    obs[0, 8] = 0.9
    _, st = pol.predict(obs, episode_start=np.array([True]))
    assert st[0, 0] == 1200.0
    obs[0, 8] = 0.01
    for _ in range(3):
        _, st = pol.predict(obs, state=st)
    assert st[0, 0] == 1190.0


def test_oracle_keeps_the_paper_preset_periodic(table):
    res = run_policies([OraclePreload(table)], episodes=1, seed=0, episode_steps=40,
                       env_kwargs={"scenario": "paper"})[0]
    assert res.trace["qpi"][-10:].max() < 0.1
    crit = table.critical([20000.0], [0.0], [4e-6])[0]
    assert res.trace["preload_n"][-1] == pytest.approx(crit + 100.0, rel=1e-3)


def test_hyperparameter_files_load_for_rl_zoo_and_sb3():
    sys.path.insert(0, str(ROOT))
    import train
    from sb3_contrib import RecurrentPPO
    from stable_baselines3 import PPO, SAC

    from agents.protocol import STEP_BUDGET_PER_RUN
    from bearing_gym.envs import BearingPreloadSB3VecEnv
    for algo, cls, policy in (("ppo", PPO, "MlpPolicy"), ("sac", SAC, "MlpPolicy"),
                              ("ppo_lstm", RecurrentPPO, "MlpLstmPolicy")):
        cfg = yaml.safe_load((ROOT / "agents" / "hyperparams" / f"{algo}.yml").read_text())
        entry = cfg["BearingPreload-v0"]
        # RL Zoo trains the protocol's budget, the same for every algorithm
        assert entry["policy"] == policy and entry["n_timesteps"] == STEP_BUDGET_PER_RUN
        assert isinstance(entry["policy_kwargs"], str)          # RL Zoo evaluates it
        cls(policy, BearingPreloadSB3VecEnv(num_envs=1, scenario="paper"), **train.hyperparams(algo))


@pytest.mark.parametrize("algo", ["ppo", "sac"])
def test_smoke_training_saves_reloads_and_evaluates(algo, tmp_path, capsys):
    sys.path.insert(0, str(ROOT))
    import train
    out = tmp_path / algo
    rc = train.main(["--algo", algo, "--timesteps", "128", "--n-envs", "2", "--out", str(out),
                     "--episode-steps", "16", "--eval-episodes", "2", "--eval-freq", "64",
                     "--val-episodes", "2", "--checkpoint-freq", "64", "--no-progress"])
    assert rc == 0
    for name in ("model.zip", "vec_normalize.pkl", "last_model.zip", "last_vec_normalize.pkl",
                 "config.json", "leaderboard.md", "leaderboard.json", "eval/best.json", "eval/validation_returns.npz"):
        assert (out / name).exists(), name
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["num_timesteps"] >= 128
    # it says what it does, in plain lines: kernels, training progress up to the step count the
    # run really reaches (no 36,352/36,000), validations, evaluation progress, where the outputs are
    printed = capsys.readouterr().out
    assert "numba kernels: ready" in printed and "validation at 64 steps" in printed
    n = cfg["num_timesteps"]
    assert f"training: 0 -> {n:,} steps" in printed and f"training: {n:,}/{n:,} steps (100 %)" in printed
    # 16-step episodes are not the stored references' 150: the board computes the hindsight here
    assert "transient 1/3: constant sweep" in printed and "step 16/16 (100 %)" in printed
    announced = printed.split("outputs in")[1].splitlines()[1:]
    for what, name in (("model", "model.zip"), ("leaderboard", "leaderboard.md"),
                       ("tensorboard logs", "tensorboard")):
        line = next(x for x in announced if x.strip().startswith(what))
        assert str(out / name) in line and (out / name).exists(), line
    # model.zip is the best validation checkpoint, with the statistics saved with it
    best = json.loads((out / "eval" / "best.json").read_text())
    assert cfg["selected"] == "best validation checkpoint" and cfg["selected_timesteps"] == best["num_timesteps"]
    assert (out / "model.zip").read_bytes() == (out / "eval" / "best_model.zip").read_bytes()
    assert (out / "vec_normalize.pkl").read_bytes() == (out / "eval" / "best_vec_normalize.pkl").read_bytes()
    text = (out / "leaderboard.md").read_text()
    assert f"{algo.upper()} (this run" in text and "validation constant" in text and "hindsight constant" in text
    assert "contextual constant" in text and "oracle" in text
    board = json.loads((out / "leaderboard.json").read_text())["tiers"]["transient"]
    assert board["episodes"] == 2 and board["episode_steps"] == 16 and not board["protocol"]
    # the per-seed validation returns of the learning curves: one row per validation, env i = seed 50000 + i
    with np.load(out / "eval" / "validation_returns.npz") as log:
        assert list(log["seeds"]) == [50000, 50001] and log["returns"].shape == (len(log["timesteps"]), 2)
        with np.load(out / "eval" / "evaluations.npz") as sb3_log:   # SB3's log holds the same returns
            np.testing.assert_allclose(np.sort(log["returns"], axis=1), np.sort(sb3_log["results"], axis=1), rtol=1e-6)
    # VecNormalize statistics survive save/load
    with (out / "vec_normalize.pkl").open("rb") as fh:
        vn = pickle.load(fh)
    assert vn.obs_rms.count > best["num_timesteps"] and np.all(np.isfinite(vn.obs_rms.mean)) and np.any(vn.obs_rms.var != 1.0)
    with (out / "last_vec_normalize.pkl").open("rb") as fh:
        assert pickle.load(fh).obs_rms.count > 128
    from agents.evaluate import evaluate, load_trained
    pol = load_trained(out)
    np.testing.assert_array_equal(pol.obs_rms.mean, vn.obs_rms.mean)
    assert f"{best['num_timesteps']:,} steps" in pol.name
    # several trained policies side by side, on the same scenarios as the baselines
    res = evaluate([out, out], episodes=2, episode_steps=4, seed=100000, out_dir=tmp_path / "side", verbose=False)
    trained = [r for r in res if "(trained" in r.name]
    assert len(trained) == 2 and np.array_equal(trained[0].returns, trained[1].returns)
    assert (tmp_path / "side" / "evaluation.md").read_text().count("(trained") >= 2
    # every episode's return, per policy, with its scenario seed
    with (tmp_path / "side" / "evaluation_episodes.csv").open() as fh:
        per_episode = list(csv.DictReader(fh))
    assert [int(row["seed"]) for row in per_episode] == [100000, 100001]
    for r in res:
        assert [float(row[r.name]) for row in per_episode] == list(r.returns)
    # resumable; --timesteps is the total: a resumed run continues up to it (SB3 stops at the first
    # rollout boundary at or past it), and one that is already there trains no further
    def resume(total: int) -> int:
        rc = train.main(["--algo", algo, "--timesteps", str(total), "--n-envs", "2", "--out", str(out), "--resume",
                         "--episode-steps", "16", "--eval-episodes", "0", "--eval-freq", "64",
                         "--val-episodes", "2", "--checkpoint-freq", "64", "--no-progress"])
        assert rc == 0
        return json.loads((out / "config.json").read_text())["num_timesteps"]
    done = cfg["num_timesteps"]
    history = np.load(out / "eval" / "evaluations.npz")["timesteps"]
    capsys.readouterr()
    resumed = resume(done + 64)
    # the validation history goes on from the earlier session's
    continued = np.load(out / "eval" / "evaluations.npz")["timesteps"]
    assert len(continued) > len(history) and np.array_equal(continued[:len(history)], history)
    assert resumed >= done + 64
    printed = capsys.readouterr().out
    assert "resuming from" in printed
    # SAC checkpoints its replay buffer, and a resumed run continues with it
    buffers = sorted((out / "checkpoints").glob("model_replay_buffer_*_steps.pkl"))
    assert bool(buffers) == (algo == "sac")
    assert "no replay buffer" not in printed
    # the wall time in config.json covers every session of the run
    assert json.loads((out / "config.json").read_text())["train_wall_s"] > cfg["train_wall_s"]
    assert resume(resumed) == resumed
    if algo == "sac":   # a checkpoint without its buffer (an older run): refill before training
        for b in buffers:
            b.unlink()
        capsys.readouterr()
        assert resume(resumed + 64) >= resumed + 64
        assert "no replay buffer" in capsys.readouterr().out
    # a new run in the same directory starts its validation afresh: with no validation before
    # its end, model.zip is its own final weights, not the earlier run's best checkpoint
    rc = train.main(["--algo", algo, "--timesteps", "16", "--n-envs", "2", "--out", str(out),
                     "--episode-steps", "16", "--eval-episodes", "0", "--eval-freq", "1000000",
                     "--val-episodes", "2", "--checkpoint-freq", "64", "--no-progress"])
    assert rc == 0
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["selected"] == "final weights" and not (out / "eval" / "best.json").exists()
    assert (out / "model.zip").read_bytes() == (out / "last_model.zip").read_bytes()


def test_train_env_defaults_to_at_most_numbas_threads(monkeypatch):
    """With NUMBA_NUM_THREADS below the env count (a user limiting threads), train.py's default
    thread count follows numba's, not the cores: it builds the envs instead of refusing."""
    import numba
    sys.path.insert(0, str(ROOT))
    import train
    monkeypatch.setattr(numba.config, "NUMBA_NUM_THREADS", 1)
    env = train.make_env(2, seed=0, episode_steps=4, tier="transient")
    try:
        assert env.num_envs == 2 and env.venv.venv.num_threads == 1
    finally:
        env.close()


def test_validation_scores_every_checkpoint_on_the_same_scenarios(tmp_path, capsys):
    """The same policy evaluated twice by ValidationCallback gets the same returns (fixed
    validation scenarios); SB3's plain EvalCallback draws new scenarios each time."""
    sys.path.insert(0, str(ROOT))
    import train
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import EvalCallback
    from stable_baselines3.common.logger import configure as configure_logger
    from stable_baselines3.common.vec_env import VecNormalize
    from agents.callbacks import ValidationCallback
    env = VecNormalize(train.make_env(2, 0, 6, "transient"))
    model = PPO("MlpPolicy", env, n_steps=8, batch_size=8, seed=0, device="cpu")
    model.set_logger(configure_logger(None, []))

    def two_evaluations(cls, path, **kw):
        val = VecNormalize(train.make_env(2, 50000, 6, "transient"), training=False, norm_reward=False)
        cb = cls(val, n_eval_episodes=2, eval_freq=1, log_path=str(path), best_model_save_path=str(path), **kw)
        cb.init_callback(model)
        cb.on_step()
        cb.on_step()
        return np.array(cb.evaluations_results)
    fixed = two_evaluations(ValidationCallback, tmp_path / "fixed", validation_seed=50000, progress_every_s=0.0)
    np.testing.assert_array_equal(fixed[0], fixed[1])
    # each evaluation is announced, then says how far it is (here at every step: 2 envs x 6 steps)
    blocks = capsys.readouterr().out.split("validation at ")[1:]
    assert len(blocks) == 2
    for block in blocks:
        done = [int(line.split()[1].split("/")[0]) for line in block.splitlines() if line.startswith("validation: ")]
        assert len(done) >= 6 and done == sorted(done) and done[0] == 0 and done[-1] >= 1
    assert (tmp_path / "fixed" / "best_vec_normalize.pkl").exists()
    drawn = two_evaluations(EvalCallback, tmp_path / "drawn")
    assert not np.array_equal(np.sort(drawn[0]), np.sort(drawn[1]))


def _result(name, returns, qp=None):
    from agents.eval_result import EvalResult
    from bearing_gym.envs.reward import REWARD_TERMS
    r = np.asarray(returns, dtype=float)
    terms = {k: r / len(REWARD_TERMS) for k in REWARD_TERMS}
    q = np.zeros_like(r) if qp is None else np.asarray(qp, dtype=float)
    return EvalResult(name, r, terms, q, np.full_like(r, 1000.0))


def test_hindsight_constant_takes_the_best_candidate_of_each_scenario():
    from agents.evaluate import hindsight_constant
    a = _result("constant 800 N", [-10.0, -50.0, -30.0], qp=[0.0, 0.9, 0.1])
    b = _result("constant 1400 N", [-20.0, -25.0, -40.0], qp=[0.0, 0.0, 0.0])
    h = hindsight_constant([a, b])
    np.testing.assert_array_equal(h.returns, [-10.0, -25.0, -30.0])
    np.testing.assert_array_equal(h.qp_fraction, [0.0, 0.0, 0.1])
    # the terms come from the chosen candidate and still add up to its return
    np.testing.assert_allclose(sum(h.terms.values()), h.returns)


def test_paired_difference_matches_a_hand_computed_t_interval():
    from agents.eval_report import paired_difference
    a = _result("a", [-10.0, -20.0, -33.0, -41.0])
    b = _result("b", [-12.0, -25.0, -34.0, -45.0])
    m, lo, hi = paired_difference(a, b)
    d = np.array([2.0, 5.0, 1.0, 4.0])
    half = 3.182446305284263 * d.std(ddof=1) / 2.0      # t(0.975, 3) from tables
    assert m == pytest.approx(3.0) and lo == pytest.approx(3.0 - half) and hi == pytest.approx(3.0 + half)


def test_episode_results_do_not_depend_on_the_batch_they_run_in():
    # evaluate() reuses the best constant's sweep row instead of running it again next to the
    # other policies; that is only sound if an episode's outcome is independent of its batch
    alone = run_policies([ConstantPreload(1000.0)], episodes=2, seed=100000, episode_steps=3)[0]
    mixed = run_policies([ConstantPreload(600.0), FeedbackRule(), ConstantPreload(1000.0)],
                         episodes=2, seed=100000, episode_steps=3)[2]
    np.testing.assert_array_equal(alone.returns, mixed.returns)
    np.testing.assert_array_equal(alone.trace["qpi"], mixed.trace["qpi"])


def _diverging(limit_m):
    # a tight divergence limit makes the integrator "diverge" (terminate the episode) on purpose
    from bearing_gym.envs import env_params
    return {"scenario": "paper", "params": env_params(divergence_limit_m=limit_m)}


def test_evaluation_reports_episodes_that_all_terminate_in_the_same_step(tmp_path):
    from agents.eval_report import write_report
    from bearing_gym.envs.reward import VibrationFirstReward
    # every env of the batch ends in the same step: the next venv.step would only autoreset them
    res = run_policies([ConstantPreload(300.0)], episodes=2, seed=0, episode_steps=25,
                       env_kwargs=_diverging(2e-5))[0]
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


def test_terminated_episodes_do_not_disturb_the_others_in_the_batch():
    # at this limit the low preload diverges within a few steps, the high one does not
    kw = _diverging(1e-4)
    low, high = run_policies([ConstantPreload(300.0), ConstantPreload(2000.0)], episodes=2, seed=0,
                             episode_steps=30, env_kwargs=kw)
    alone = run_policies([ConstantPreload(2000.0)], episodes=2, seed=0, episode_steps=30, env_kwargs=kw)[0]
    assert low.terminated.all() and not high.terminated.any()
    assert len(low.trace["t"]) < 30 and len(high.trace["t"]) == 30
    np.testing.assert_array_equal(high.returns, alone.returns)
    np.testing.assert_array_equal(high.trace["qpi"], alone.trace["qpi"])
    assert low.row()["terminated_episodes"] == 2 and high.row()["terminated_episodes"] == 0


def test_trace_figure_names_its_scenario_shows_the_hindsight_reference_and_labels_every_axis():
    from agents.eval_report import plot_traces
    from agents.evaluate import hindsight_constant
    sweep = run_policies([ConstantPreload(800.0), ConstantPreload(1400.0)], episodes=2, seed=100000, episode_steps=4)
    h = hindsight_constant(sweep)
    chosen = sweep[int(np.argmax([r.returns[0] for r in sweep]))]
    # the hindsight trace is the first scenario's chosen constant
    assert h.trace is chosen.trace and chosen.name in h.trace_label
    fig = plot_traces([sweep[0], h], None, first_seed=100000)
    try:
        title = fig.axes[0].get_title()
        assert "seed 100000" in title and "rpm" in title and "radial load" in title and "clearance" in title
        assert any(line.get_label() == h.trace_label for line in fig.axes[0].get_lines())
        for ax in fig.axes:
            assert ax.get_ylabel().endswith(")"), ax.get_ylabel()       # every axis has its unit
        assert fig.axes[2].get_xlabel() == "time in episode (s)"
    finally:
        import matplotlib.pyplot as plt
        plt.close(fig)


def test_recurrent_ppo_trains_saves_and_keeps_its_memory_in_evaluation(tmp_path):
    """train.py --algo ppo_lstm (sb3-contrib's RecurrentPPO, RL Zoo's name) trains, saves and
    loads; evaluation carries the LSTM state through an episode: the policy's action on the
    same observation differs with what it has seen before."""
    sys.path.insert(0, str(ROOT))
    import train
    out = tmp_path / "lstm"
    rc = train.main(["--algo", "ppo_lstm", "--timesteps", "64", "--n-envs", "2", "--out", str(out),
                     "--episode-steps", "8", "--eval-episodes", "0", "--eval-freq", "32", "--val-episodes", "2",
                     "--checkpoint-freq", "32", "--no-progress"])
    assert rc == 0
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["algo"] == "ppo_lstm" and cfg["num_timesteps"] >= 64
    from sb3_contrib import RecurrentPPO

    from agents.evaluate import load_trained
    pol = load_trained(out)
    assert isinstance(pol.model, RecurrentPPO)
    rng = np.random.default_rng(0)
    obs = rng.uniform(-1, 1, (1, 15)).astype(np.float32)
    a0, state = pol.predict(obs, state=None, episode_start=np.array([True]))
    for _ in range(5):
        _, state = pol.predict(rng.uniform(-1, 1, (1, 15)).astype(np.float32), state=state,
                               episode_start=np.array([False]))
    a1, _ = pol.predict(obs, state=state, episode_start=np.array([False]))
    assert not np.array_equal(a0, a1)


def test_eval_result_first_cuts_every_per_episode_array():
    from agents.eval_result import EvalResult
    from bearing_gym.envs.reward import REWARD_TERMS
    n = 5
    r = EvalResult("p", np.arange(n, dtype=float), {k: np.arange(n) + i for i, k in enumerate(REWARD_TERMS)},
                   np.linspace(0, 1, n), np.full(n, 900.0), terminated=np.array([0, 1, 0, 0, 1], bool),
                   first_obs=np.zeros((n, 14)), vibration_um=np.arange(n) * 0.5)
    c = r.first(2)
    assert c.episodes == 2 and c.terminated_count == 1 and c.first_obs.shape == (2, 14)
    np.testing.assert_array_equal(c.vibration_um, [0.0, 0.5])
    assert all(len(v) == 2 for v in c.terms.values()) and len(r.returns) == n     # the original untouched
    with pytest.raises(ValueError, match="6 episodes asked of a result on 5"):
        r.first(6)


def test_eval_result_concat_joins_in_order_and_drops_an_array_one_part_lacks():
    from agents.eval_result import EvalResult
    from bearing_gym.envs.reward import REWARD_TERMS

    def part(lo, n, vib):
        return EvalResult("p", np.arange(lo, lo + n, dtype=float), {k: np.arange(lo, lo + n) for k in REWARD_TERMS},
                          np.zeros(n), np.full(n, 900.0), terminated=None if lo == 0 else np.ones(n, bool),
                          vibration_um=np.ones(n) if vib else None)
    c = EvalResult.concat([part(0, 2, True), part(2, 3, False)])
    np.testing.assert_array_equal(c.returns, [0, 1, 2, 3, 4])
    np.testing.assert_array_equal(c.terminated, [False, False, True, True, True])   # None = none ended early
    assert c.vibration_um is None                                                   # not known for every episode
    assert EvalResult.concat([part(0, 2, True), part(0, 1, True)]).terminated is None
    with pytest.raises(ValueError, match="different policies"):
        EvalResult.concat([part(0, 2, True), EvalResult("q", np.zeros(1), {}, np.zeros(1), np.zeros(1))])


def test_evaluate_pretrained_runs_every_shipped_policy_and_writes_outside_them(tmp_path, monkeypatch):
    """`python -m agents.evaluate --pretrained` puts each shipped policy (agents/pretrained/<algo>/)
    beside the baselines; without --out or --model the reports go to runs/, never into the
    shipped directories; with no shipped policy it says what to do."""
    from agents import evaluate as ev
    shipped = ev.shipped_dirs()
    assert {d.name for d in shipped} >= {"ppo", "sac"}
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
