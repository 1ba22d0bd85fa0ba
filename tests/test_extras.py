"""The env installs without the RL stack: ``pip install bearing-gym`` is the env, physics,
analysis and CLI; the learners and the leaderboard are the ``rl`` extra (pyproject.toml)."""

import subprocess
import sys
import textwrap
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: what the rl extra brings and the env must not need (import names)
RL_STACK = ("torch", "stable_baselines3", "sb3_contrib", "rliable", "tensorboard", "arch", "pandas", "rich")
RL_DISTRIBUTIONS = ("torch", "stable-baselines3", "sb3-contrib", "rliable", "tensorboard", "arch", "pandas")


def _names(requirements: list[str]) -> set[str]:
    return {r.split(";")[0].split("[")[0].split("<")[0].split(">")[0].split("=")[0].split("!")[0].strip().lower()
            for r in requirements}


def test_the_core_dependencies_hold_no_rl_package_and_the_rl_extra_all():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    core, rl = _names(project["dependencies"]), _names(project["optional-dependencies"]["rl"])
    assert core.isdisjoint(RL_DISTRIBUTIONS), core & set(RL_DISTRIBUTIONS)
    assert set(RL_DISTRIBUTIONS) <= rl


def test_the_env_the_cli_and_the_analysis_import_nothing_of_the_rl_stack():
    """gymnasium.make, a reset and a step, the CLI, the analysis and the reproduction, in a fresh
    interpreter: none of the rl extra's modules gets imported."""
    code = textwrap.dedent(f"""
        import sys
        import gymnasium as gym
        import bearing_gym, bearing_gym.cli.main, bearing_gym.analysis, bearing_gym.reproduction
        env = gym.make("BearingPreload-v0")
        env.reset(seed=0)
        env.step(env.action_space.sample())
        print(sorted(m for m in {RL_STACK!r} if m in sys.modules))
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip().splitlines()[-1] == "[]", out.stdout


#: run before a snippet: torch, SB3 and sb3-contrib cannot be found or imported (as in a venv without them)
NO_TORCH = textwrap.dedent("""
    import importlib.abc, importlib.util, sys
    BLOCKED = ("torch", "stable_baselines3", "sb3_contrib")
    real = importlib.util.find_spec
    importlib.util.find_spec = lambda name, *a: None if name.split(".")[0] in BLOCKED else real(name, *a)
    class Block(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path, target=None):
            if name.split(".")[0] in BLOCKED:
                raise ImportError(f"{name} is blocked: this snippet runs as if torch were not installed")
    sys.meta_path.insert(0, Block())
""")


def test_the_score_extra_holds_the_statistics_and_no_torch():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    score, rl = _names(extras["score"]), _names(extras["rl"])
    assert {"rliable", "arch", "pandas"} <= score and score <= rl
    assert score.isdisjoint({"torch", "stable-baselines3", "sb3-contrib", "tensorboard"})


def test_training_without_the_rl_extra_says_which_extra_to_install():
    code = NO_TORCH + textwrap.dedent("""
        import agents                                  # the package itself imports without torch
        try:
            import agents.training
        except ImportError as err:
            print(err)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert 'pip install "bearing-gym[rl]"' in out.stdout and "missing: stable-baselines3" in out.stdout, out.stdout


def test_a_numpy_policy_is_scored_where_torch_cannot_be_imported():
    """agents.submit.score with torch, SB3 and sb3-contrib blocked: it scores a NumPy rule and the
    shipped SAC through its exported portable weights, and none of the blocked modules is loaded.
    (.ci/run repeats the API's tests in a fresh venv with only the score extra.)"""
    code = NO_TORCH + textwrap.dedent("""
        import numpy as np
        from agents.submit import score
        rule = score(lambda o: np.clip(o[:, 10] + 0.1, -1, 1), tier="paper", progress=False,
                     bootstrap_reps=200, poi_reps=50)
        sac = score("agents/pretrained/sac", tier="paper", progress=False, bootstrap_reps=200, poi_reps=50)
        print(len(rule.row["episode_returns"][0]), np.isfinite(sac.row["mean_return"]))
        print(sorted(m for m in sys.modules if m.split(".")[0] in BLOCKED))
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0, out.stderr[-3000:]
    assert out.stdout.strip().splitlines()[-2:] == ["1 True", "[]"], out.stdout
