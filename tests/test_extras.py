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


def test_importing_agents_without_the_rl_extra_says_which_extra_to_install():
    code = textwrap.dedent("""
        import importlib.util
        real = importlib.util.find_spec
        importlib.util.find_spec = lambda name, *a: None if name == "torch" else real(name, *a)
        try:
            import agents
        except ImportError as err:
            print(err)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert 'pip install "bearing-gym[rl]"' in out.stdout and "missing: torch" in out.stdout, out.stdout
