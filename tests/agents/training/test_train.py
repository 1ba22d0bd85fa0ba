"""train.py at smoke scale: the RL Zoo hyperparameter files, training, saving, reloading,
validation during training, RecurrentPPO's memory."""

import csv
import json
import pickle
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml


ROOT = Path(__file__).resolve().parents[3]


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


# PPO rolls out its n_steps (256 per env, 512 steps here) whatever --timesteps says: ~50 s on 2 cores (CI runs it)
@pytest.mark.parametrize("algo", [pytest.param("ppo", marks=pytest.mark.slow), "sac"])
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
    # each validation's result in train.py's voice, SB3's own evaluation lines folded in
    assert "validation at 64 steps: mean return" in printed and "Eval num_timesteps" not in printed
    n = cfg["num_timesteps"]
    assert f"training: 0 -> {n:,} steps" in printed and f"training: {n:,}/{n:,} steps (100 %)" in printed
    # 16-step episodes are not the stored references' 150: the board computes the hindsight here
    # (no planner: two stages, counted up in order)
    assert "transient stage 1/2: constant sweep" in printed and "step 16/16 (100 %)" in printed
    assert printed.index("stage 1/2") < printed.index("stage 2/2")
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
    from agents.leaderboard.compare import evaluate
    from agents.evaluation.trained import load_trained
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
    # SAC checkpoints its replay buffer (the newest only: each holds the whole buffer), and a resumed
    # run continues with it; every model checkpoint is kept (a validated one may have to be restored)
    buffers = sorted((out / "checkpoints").glob("model_replay_buffer_*_steps.pkl"))
    models = sorted((out / "checkpoints").glob("model_*_steps.zip"))
    assert len(buffers) == (algo == "sac") and len(models) >= 2
    if buffers:
        assert buffers[0].name == f"model_replay_buffer_{max(int(m.stem.split('_')[-2]) for m in models)}_steps.pkl"
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
    from agents.training.callbacks import ValidationCallback
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
    # each evaluation is announced, says how far it is (here at every step: 2 envs x 6 steps),
    # then its result in one line
    printed = capsys.readouterr().out
    assert printed.count("steps: mean return") == 2 and "Eval num_timesteps" not in printed
    blocks = [b for b in printed.split("validation at ")[1:] if "mean return" not in b.splitlines()[0]]
    assert len(blocks) == 2
    for block in blocks:
        done = [int(line.split()[1].split("/")[0]) for line in block.splitlines() if line.startswith("validation: ")]
        assert len(done) >= 6 and done == sorted(done) and done[0] == 0 and done[-1] >= 1
    assert (tmp_path / "fixed" / "best_vec_normalize.pkl").exists()
    drawn = two_evaluations(EvalCallback, tmp_path / "drawn")
    assert not np.array_equal(np.sort(drawn[0]), np.sort(drawn[1]))


@pytest.mark.slow          # ~55 s on 2 cores: a training run end to end (CI runs it)
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

    from agents.evaluation.trained import load_trained
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


def test_a_start_bank_gives_training_its_scenarios_without_a_settle(tmp_path, monkeypatch):
    """train.py --start-bank: the training envs draw the bank's scenarios (each once before any
    repeats) and copy its settled starts - no settle is simulated; a bank of another tier is refused."""
    from collections import OrderedDict

    sys.path.insert(0, str(ROOT))
    import train
    from bearing_gym.envs import core
    from bearing_gym.envs import start_bank as banks
    monkeypatch.setattr(core, "_SETTLED", OrderedDict())
    monkeypatch.setattr(core, "_BANKED", {})
    path = banks.build("transient", (11, 12, 13, 14), episode_steps=6).save(tmp_path / "bank.npz")
    other = banks.build("transient", (11,), episode_steps=6, control_dt_s=0.04).save(tmp_path / "other.npz")
    monkeypatch.setattr(core, "_SETTLED", OrderedDict())          # only the bank knows them now

    def no_settle(self, todo):
        raise AssertionError("a settle ran although the bank holds the start")
    monkeypatch.setattr(core.PreloadBatch, "_run_settle", no_settle)
    env = train.make_env(2, 0, 6, "transient", start_bank=path)
    env.reset()
    seen = list(env.venv.venv.batch.scenarios)
    for _ in range(6):                                              # both envs end and reset once
        env.step(np.zeros((2, 1), dtype=np.float32))
    seen += list(env.venv.venv.batch.scenarios)
    bank = banks.load(path)
    assert sorted(bank.scenarios.index(sc) for sc in seen) == [0, 1, 2, 3]    # all four, none twice
    with pytest.raises(SystemExit, match="holds tier 'transient' starts, this env is of tier 'stationary'"):
        train.make_env(2, 0, 6, "stationary", start_bank=path)
    with pytest.raises(SystemExit, match="scenarios of 6-step episodes, this env's have 150"):
        train.make_env(2, 0, 150, "transient", start_bank=path)
    with pytest.raises(SystemExit, match="built for other env settings"):      # another control interval
        train.make_env(2, 0, 6, "transient", start_bank=other)


def test_train_uses_the_shipped_start_bank_only_where_it_fits(tmp_path, monkeypatch, capsys):
    """--start-bank auto: the tier's shipped bank when it exists and fits the run; otherwise it
    says why and settles every start (no error, also for an unreadable file); none never uses one;
    a named bank that does not fit is an error."""
    sys.path.insert(0, str(ROOT))
    import train
    from bearing_gym.envs import start_bank as banks
    shipped = tmp_path / "start_bank_transient.npz"
    monkeypatch.setattr(train, "start_bank_path", lambda tier: tmp_path / f"start_bank_{tier}.npz")
    assert train.choose_start_bank("auto", "transient", 6) is None
    assert "none shipped for tier transient" in capsys.readouterr().out
    shipped.write_bytes(b"not a zip file")
    assert train.choose_start_bank(None, "transient", 6) is None
    assert "not a readable start bank" in capsys.readouterr().out
    banks.build("transient", (21, 22), episode_steps=6).save(shipped)
    bank = train.choose_start_bank("auto", "transient", 6)
    assert bank is not None and bank.seeds == (21, 22)
    assert "2 settled starts of tier transient" in capsys.readouterr().out
    assert train.choose_start_bank("none", "transient", 6) is None
    # a bank for other episodes is passed over with the reason, not used and not fatal
    assert train.choose_start_bank("auto", "transient", 150) is None
    assert "not used" in capsys.readouterr().out
    with pytest.raises(SystemExit, match="scenarios of 6-step episodes, this env's have 150"):
        train.choose_start_bank(str(shipped), "transient", 150)


def test_a_resumed_run_keeps_its_start_bank_and_draws_no_scenario_twice(tmp_path, monkeypatch, capsys):
    """train.py with a bank records it (config.json, start_bank.json); --resume keeps it, refuses
    another, and continues the bank's order after the draws its checkpoint had made: over two
    sessions of 64 steps (2 envs, 16-step episodes: 6 draws each) the 12 scenarios of the bank are
    each drawn once."""
    sys.path.insert(0, str(ROOT))
    import train
    from bearing_gym.envs import start_bank as banks
    path = banks.build("transient", tuple(range(31, 43)), episode_steps=16).save(tmp_path / "start_bank_transient.npz")
    monkeypatch.setattr(train, "start_bank_path", lambda tier: path)
    drawn: list = []
    sample = banks.BankScenarios.sample
    monkeypatch.setattr(banks.BankScenarios, "sample",
                        lambda self, *a, **k: drawn.append(sample(self, *a, **k)) or drawn[-1])
    out = tmp_path / "run"
    common = ["--algo", "sac", "--n-envs", "2", "--episode-steps", "16", "--eval-episodes", "0", "--val-episodes", "2",
              "--eval-freq", "64", "--checkpoint-freq", "32", "--out", str(out), "--no-progress"]
    assert train.main(common + ["--timesteps", "64"]) == 0
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["start_bank"] == str(path.resolve()) and cfg["num_timesteps"] == 64
    assert json.loads((out / "start_bank.json").read_text())["starts"] == 12
    first = list(drawn)
    assert len(first) == train.bank_draws_made(64, 2, 16) == 6
    with pytest.raises(SystemExit, match="trained with --start-bank .*start_bank_transient.npz, not none"):
        train.main(common + ["--timesteps", "128", "--resume", "--start-bank", "none"])
    drawn.clear()
    capsys.readouterr()
    assert train.main(common + ["--timesteps", "128", "--resume"]) == 0
    assert "resuming after 6 of its 12 scenarios" in capsys.readouterr().out
    bank = banks.load(path)
    assert sorted(bank.scenarios.index(sc) for sc in first + drawn[:6]) == list(range(12))
    with pytest.raises(SystemExit, match="validation seeds 31..32 include 2 of the start bank's"):
        train.main(common + ["--timesteps", "64", "--out", str(tmp_path / "other"), "--val-seed", "31"])


def test_protocol_runs_train_without_a_start_bank():
    """The frozen protocol draws every training start afresh."""
    from agents.training.protocol_runs import train_args
    args = train_args("sac", 0, Path("out"))
    assert args[args.index("--start-bank") + 1] == "none"


def test_the_shipped_start_bank_is_this_kernels_settles(monkeypatch):
    """bearing_gym/data/start_bank_transient.npz (train.py's default): made by this kernel for the
    default env (a kernel change without a rebuild fails here, naming the command), its first and
    last starts equal a fresh settle bit for bit, and it holds more starts than a run of the
    budget has episodes (none is met twice)."""
    from collections import OrderedDict

    from agents.paths import start_bank_path
    from agents.protocol import STEP_BUDGET_PER_RUN, V2_START_BANK_STARTS
    from bearing_gym.envs import BearingPreloadVectorEnv, core
    from bearing_gym.envs import start_bank as banks
    from bearing_gym.task import EPISODE_STEPS
    sys.path.insert(0, str(ROOT))
    import train
    path = start_bank_path("transient")
    bank = train.load_start_bank(path, "transient", EPISODE_STEPS)     # kernel, tier, horizon, env settings
    assert len(bank) > STEP_BUDGET_PER_RUN / EPISODE_STEPS and len(bank) >= V2_START_BANK_STARTS
    assert len(set(bank.digests)) == len(bank)
    monkeypatch.setattr(core, "_SETTLED", OrderedDict())
    monkeypatch.setattr(core, "_BANKED", {})
    venv = BearingPreloadVectorEnv(num_envs=2, tier="transient", max_episode_steps=None)
    venv.reset(seed=[bank.seeds[0], bank.seeds[-1]])
    for b, i in ((0, 0), (1, len(bank) - 1)):
        digest, state = venv.batch.settled_state(b)
        assert digest == bank.digests[i] and venv.batch.scenarios[b] == bank.scenarios[i]
        for fresh, stored in zip(state, bank.states[digest]):
            np.testing.assert_array_equal(fresh, stored)
    assert banks.rebuild_command(bank.tier, bank.seeds, path).endswith(f"--seeds 0 {V2_START_BANK_STARTS} --out {path}")


def test_the_early_row_keeps_the_best_checkpoint_up_to_its_step_and_exports_portably(tmp_path, monkeypatch):
    """Protocol v2's early row: the ValidationCallback copies the best checkpoint so far when the
    run reaches ``snapshot_at`` and never again (a later, better checkpoint replaces the run's
    selection, not the copy); a finished run's portable exports are collected without model.zip
    and load as the same policy as its SB3 files."""
    sys.path.insert(0, str(ROOT))
    import json

    import train
    from agents.evaluation.trained import load_trained
    from agents.training import protocol_runs as T
    from agents.training.callbacks import BEST_INFO

    out = tmp_path / "run"
    monkeypatch.setattr(train, "protocol_defaults", lambda a: (setattr(a, "snapshot_at", 32), a)[1]
                        if a.timesteps is not None and a.val_episodes is not None else a)
    rc = train.main(["--algo", "ppo", "--timesteps", "96", "--n-envs", "2", "--out", str(out), "--eval-episodes", "0",
                     "--eval-freq", "16", "--val-episodes", "2", "--episode-steps", "8", "--no-progress",
                     "--start-bank", "none"])
    assert rc == 0
    snap = json.loads((out / "eval" / "by_32" / BEST_INFO).read_text())
    best = json.loads((out / "eval" / BEST_INFO).read_text())
    with np.load(out / "eval" / "evaluations.npz") as log:
        steps, means = log["timesteps"], log["results"].mean(axis=1)
    upto = steps <= 32
    assert snap["num_timesteps"] == int(steps[upto][np.argmax(means[upto])])     # the first best among those
    assert best["num_timesteps"] == int(steps[np.argmax(means)])
    # collect as protocol 2 does (its early row under by_<V2_EARLY_ROW_STEPS>)
    monkeypatch.setattr(T, "EARLY", "by_32")
    T.export_v2(out)
    files = tuple(f.replace(f"by_{T.P.V2_EARLY_ROW_STEPS}", "by_32") for f in T.COLLECT_V2)
    dst = tmp_path / "collected"
    T.collect(out, dst, files)
    assert not (dst / "model.zip").exists() and (dst / "by_32" / "portable_policy.npz").exists()
    obs = np.random.default_rng(0).normal(size=(5, 15)).astype(np.float32)
    a_collected, _ = load_trained(dst, portable=True).predict(obs)
    a_run, _ = load_trained(out, portable=True).predict(obs)
    np.testing.assert_array_equal(a_collected, a_run)
    from agents.leaderboard.board import learned_groups
    groups = {g.name: g.early_row_steps for g in learned_groups([dst, dst / "by_32"], pretrained=False)}
    assert groups == {"PPO (trained)": None,
                      f"PPO (trained, best up to {T.P.V2_EARLY_ROW_STEPS // 1000}k steps)": T.P.V2_EARLY_ROW_STEPS}
