"""The protocol's training runs: which runs, with what arguments, and what is kept of each."""

import json
import sys
from pathlib import Path

import pytest

from agents import protocol as P
from agents.training import protocol_runs as T


def test_the_runs_are_every_algorithm_with_its_seeds_headline_first():
    assert T.RUNS[0][0] == P.HEADLINE_ALGORITHM
    for algo in P.ALGORITHMS:
        seeds = [s for a, _, s in T.RUNS if a == algo]
        assert tuple(seeds) == P.training_seeds(algo)
    assert len(T.RUNS) == P.HEADLINE_SEEDS + (len(P.ALGORITHMS) - 1) * P.OTHER_SEEDS


def test_a_run_trains_at_the_budget_on_the_benchmark_and_validates_on_validation_seeds(tmp_path):
    sys_args = T.train_args("sac", 1000, tmp_path / "r")
    sys.path.insert(0, str(Path(__file__).resolve().parents[3]))
    import train  # the arguments parse with train.py's own parser
    a = train.build_parser().parse_args(sys_args)
    assert a.timesteps == P.STEP_BUDGET_PER_RUN and a.algo == "sac" and a.seed == 1000
    assert a.tier == "transient" and a.episode_steps == 150 and a.eval_episodes == 0
    assert P.range_of(a.val_seed) == "validation" and a.val_episodes == P.VALIDATION_EPISODES_IN_TRAINING
    assert P.range_of(a.val_seed + a.val_episodes - 1) == "validation"
    assert a.eval_freq == P.VALIDATION_EVERY_STEPS


def _finished_run(d, algo, seed, steps, best_return):
    (d / "eval").mkdir(parents=True)
    for name in T.COLLECT:
        (d / name).write_bytes(b"x")
    (d / "config.json").write_text(json.dumps({"algo": algo, "seed": seed, "num_timesteps": steps}))
    (d / "eval" / "best.json").write_text(json.dumps({"mean_validation_return": best_return, "num_timesteps": steps}))


def test_collect_keeps_the_small_files_and_ship_takes_the_best_validation_run(tmp_path):
    trained = tmp_path / "trained"
    for seed, ret in ((0, -80.0), (1000, -60.0), (2000, -70.0)):
        src = tmp_path / f"w{seed}"
        _finished_run(src, "ppo", seed, P.STEP_BUDGET_PER_RUN, ret)
        T.collect(src, T.collected_dir("ppo", seed, trained))
        assert T.is_done("ppo", seed, trained)
    assert not T.is_done("ppo", 3000, trained)
    shipped = T.ship(trained, tmp_path / "pretrained")
    assert shipped == {"ppo": T.collected_dir("ppo", 1000, trained)}
    assert json.loads((tmp_path / "pretrained" / "ppo" / "config.json").read_text())["seed"] == 1000


def test_an_unfinished_run_is_not_collected(tmp_path):
    src = tmp_path / "w"
    src.mkdir()
    (src / "model.zip").write_bytes(b"x")
    with pytest.raises(FileNotFoundError, match="not finished"):
        T.collect(src, tmp_path / "dst")


def test_threads_pass_through_to_train_py_and_are_checked(tmp_path):
    sys.path.insert(0, str(Path(__file__).resolve().parents[3]))
    import train
    assert train.build_parser().parse_args(T.train_args("ppo", 0, tmp_path / "r")).threads is None
    assert train.build_parser().parse_args(T.train_args("ppo", 0, tmp_path / "r", threads=1)).threads == 1
    with pytest.raises(SystemExit, match="--threads must be in"):
        train.main(["--threads", "0", "--out", str(tmp_path / "r")])


def test_a_run_held_by_a_live_process_is_skipped_and_a_stale_lock_is_not(tmp_path):
    import os
    import subprocess
    d = tmp_path / "sac_s1000"
    d.mkdir()
    assert not T.is_running("sac", 1000, tmp_path)                  # no lock
    (d / ".running").write_text(str(os.getpid()))
    assert T.is_running("sac", 1000, tmp_path)                      # this process holds it
    with pytest.raises(SystemExit, match="being trained by process"):
        T.train_run("sac", 1000, budget=10, trained_dir=tmp_path / "t", work_dir=tmp_path)
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    (d / ".running").write_text(str(dead.pid))
    assert not T.is_running("sac", 1000, tmp_path)                  # its process has ended


def test_list_summarises_a_done_run_and_nothing_of_one_not_done(tmp_path):
    src = tmp_path / "w"
    _finished_run(src, "sac", 0, P.STEP_BUDGET_PER_RUN, -123.04)
    T.collect(src, T.collected_dir("sac", 0, tmp_path))
    assert T.run_summary("sac", 1000, tmp_path) == ""
    assert "best checkpoint 100,000 steps, validation return -123.0" in T.run_summary("sac", 0, tmp_path)


def test_the_lock_names_the_train_py_process_while_it_runs(tmp_path, monkeypatch):
    """train_run starts train.py as a process of its own; while it runs, the run's .running file
    names that process (so killing the launcher leaves the run marked as running), and a failing
    train.py is reported with its exit code."""
    root = tmp_path / "root"
    root.mkdir()
    (root / "train.py").write_text(
        "import os, sys, time, pathlib\n"
        "out = pathlib.Path(sys.argv[sys.argv.index('--out') + 1])\n"
        "for _ in range(500):\n"
        "    if (out / '.running').read_text() == str(os.getpid()):\n"
        "        (out / 'lock_named_me').write_text('yes')\n"
        "        break\n"
        "    time.sleep(0.01)\n"
        "sys.exit(3)\n")
    monkeypatch.setattr(T, "ROOT", root)
    with pytest.raises(SystemExit, match=r"train.py failed \(3\)"):
        T.train_run("sac", 1000, budget=10, trained_dir=tmp_path / "t", work_dir=tmp_path / "w")
    run = tmp_path / "w" / "sac_s1000"
    assert (run / "lock_named_me").read_text() == "yes"
    assert not (run / ".running").exists()         # released when train.py ended


def test_protocol_v2_runs_are_its_algorithms_and_seeds_at_its_budget_on_the_bank(tmp_path, monkeypatch):
    """Every V2 algorithm x V2 seed; train.py reads protocol 2's settings (its tuned yml, the
    budget, 50 validation episodes) and the shipped start bank, and refuses a bank smaller than
    the protocol's."""
    assert sorted(T.RUNS_V2) == sorted((a, k, s) for a in P.V2_ALGORITHMS for k, s in enumerate(P.v2_training_seeds()))
    sys.path.insert(0, str(Path(__file__).resolve().parents[3]))
    import train
    a = train.protocol_defaults(train.build_parser().parse_args(
        T.train_args("tqc", 2000, tmp_path / "r", P.V2_STEP_BUDGET_PER_RUN, protocol=2)))
    assert a.protocol == 2 and a.timesteps == P.V2_STEP_BUDGET_PER_RUN and a.val_episodes == 50
    assert a.snapshot_at == P.V2_EARLY_ROW_STEPS and a.start_bank.endswith("start_bank_transient.npz")
    assert T.TRAINED_DIR_V2 != T.TRAINED_DIR and T.WORK_DIR_V2 != T.WORK_DIR
    from bearing_gym.envs import start_bank as banks
    n = len(banks.load(banks.shipped_path("transient"), check_kernel=False))
    monkeypatch.setattr(P, "V2_START_BANK_STARTS", n + 1)
    with pytest.raises(SystemExit, match=f"start bank of {n + 1} starts; .* holds {n}"):
        T.check_v2_bank()


def test_ship_v2_takes_the_best_validation_run_and_leaves_no_other_runs_sb3_files(tmp_path):
    """Protocol v2: the shipped directory gets the best run's portable export and config, its SB3
    files from the work directory where they are, and none of an earlier policy's (else the
    portable export would not be current for the model files beside it)."""
    trained, work, pretrained = tmp_path / "trained_v2", tmp_path / "work", tmp_path / "pretrained"
    for algo, seed, ret in (("sac", 0, -80.0), ("sac", 1000, -60.0), ("tqc", 0, -50.0)):
        d = T.collected_dir(algo, seed, trained)
        (d / "eval").mkdir(parents=True)
        (d / "portable_policy.npz").write_bytes(f"{algo}{seed}".encode())
        (d / "config.json").write_text(json.dumps({"algo": algo, "seed": seed}))
        (d / "eval" / "best.json").write_text(json.dumps({"mean_validation_return": ret, "num_timesteps": 10}))
    (work / "sac_s1000").mkdir(parents=True)
    for name in ("model.zip", "vec_normalize.pkl"):
        (work / "sac_s1000" / name).write_bytes(b"sac1000 " + name.encode())
    (pretrained / "tqc").mkdir(parents=True)
    (pretrained / "tqc" / "model.zip").write_bytes(b"an earlier tqc")       # a stale SB3 file
    shipped = T.ship_v2(trained, work, pretrained)
    assert shipped == {"sac": T.collected_dir("sac", 1000, trained), "tqc": T.collected_dir("tqc", 0, trained)}
    assert (pretrained / "sac" / "portable_policy.npz").read_bytes() == b"sac1000"
    assert (pretrained / "sac" / "model.zip").read_bytes() == b"sac1000 model.zip"
    assert (pretrained / "tqc" / "portable_policy.npz").read_bytes() == b"tqc0"
    assert not (pretrained / "tqc" / "model.zip").exists() and not (pretrained / "tqc" / "vec_normalize.pkl").exists()
