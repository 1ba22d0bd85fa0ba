"""docs/scaling.md's RLlib snippet ("Training past one machine") runs as written on a local Ray.

The snippet is read from docs/scaling.md and executed with only its sizes made small (``SMALL``: 2
env runners, a 400-step batch, one epoch), so the test and the page make the same calls; its loop
of ``algo.train()`` is run here for ``ITERATIONS`` iterations. The slow test needs the ``rllib``
extra (``pip install -e ".[rllib]"``: Ray's RLlib, pinned, with the gymnasium it pins) and
BEARING_GYM_SLOW=1; 1.5-2 min on a loaded 2-core machine. The fast test checks, without
RLlib, that the snippet still has the shape the slow test relies on.

Asserted: every iteration samples exactly the configured batch; the env runners step
``BearingPreloadEnv`` of the transient tier under the registered time limit (``EPISODE_STEPS``),
and the sampled episodes end there; each episode's return is finite and in
[-worst step cost x EPISODE_STEPS, 0); the learner's losses are finite. Nothing about speed or
learning.
"""

import ast
import math
from pathlib import Path

import gymnasium
import numpy as np
import pytest

import bearing_gym  # noqa: F401 - registers BearingPreload-v0
from bearing_gym.task import EPISODE_STEPS
from bearing_gym.envs.reward import VibrationFirstReward

from tests.agents.helpers import first_python_block

PAGE = Path(__file__).resolve().parents[2] / "docs" / "scaling.md"
SECTION = "## Training past one machine"
ENV_ID = "BearingPreload-v0"

# The snippet's sizes for a test (keyword -> value); its other arguments are run as written.
SMALL = {"num_env_runners": 2, "train_batch_size_per_learner": 400, "minibatch_size": 100,
         "num_epochs": 1}
ITERATIONS = 3
LOOP = "for _ in range(100):\n    result = algo.train()"


def page_snippet() -> str:
    """The first ``python`` code block of docs/scaling.md's section on training past one machine."""
    return first_python_block(PAGE, SECTION)


def small_setup(snippet: str) -> ast.Module:
    """The snippet's statements before its training loop, with the sizes of ``SMALL``."""
    tree = ast.parse(snippet)
    *setup, loop = tree.body
    assert ast.unparse(loop) == LOOP, f"the snippet should end with its training loop:\n{LOOP}"
    module = ast.Module(body=setup, type_ignores=[])
    replaced = []
    for node in ast.walk(module):
        if isinstance(node, ast.keyword) and node.arg in SMALL:
            node.value = ast.copy_location(ast.Constant(SMALL[node.arg]), node.value)
            replaced.append(node.arg)
    assert sorted(replaced) == sorted(SMALL), f"the snippet should set each of {sorted(SMALL)} once"
    return ast.fix_missing_locations(module)


def _calls(module: ast.Module) -> dict[str, ast.Call]:
    """The snippet's calls by the name called (function or method)."""
    out = {}
    for node in ast.walk(module):
        if isinstance(node, ast.Call):
            f = node.func
            out[f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")] = node
    return out


def test_rllib_snippet_has_the_shape_the_slow_test_runs():
    """Without RLlib: the snippet registers and configures the registered env id on the
    transient tier, and has every size that the slow test makes small."""
    calls = _calls(small_setup(page_snippet()))
    for name in ("register_env", "PPOConfig", "environment", "env_runners", "training", "build_algo"):
        assert name in calls, name
    assert ast.literal_eval(calls["register_env"].args[0]) == ENV_ID
    env = calls["environment"]
    assert ast.literal_eval(env.args[0]) == ENV_ID
    assert {k.arg: ast.literal_eval(k.value) for k in env.keywords} == {"env_config": {"tier": "transient"}}
    assert ast.literal_eval(calls["make"].args[0]) == ENV_ID            # gymnasium.make in make_env
    spec = gymnasium.spec(ENV_ID)
    assert spec.entry_point == "bearing_gym.envs.bearing_preload:BearingPreloadEnv"
    assert spec.max_episode_steps == EPISODE_STEPS


SCORE_EPISODES = 2


def _score_through_the_adapter(algo):
    """The trained module scored on the first test episodes through docs/scaling.md's adapter,
    and its actions and the module's own Gaussian means on a few observations."""
    import torch
    from ray.rllib.core.columns import Columns

    from agents.submit import score
    from agents.submit.rllib import RLlibPolicy
    policy = RLlibPolicy(algo)
    obs = np.stack([gymnasium.make(ENV_ID).reset(seed=s)[0] for s in range(3)])
    with torch.no_grad():
        inputs = policy.module.forward_inference({Columns.OBS: torch.as_tensor(obs)})[Columns.ACTION_DIST_INPUTS]
    scored = score(policy, tier="transient", episodes=SCORE_EPISODES, name="RLlib PPO", progress=False,
                   bootstrap_reps=500, poi_reps=100)
    return scored, policy.predict(obs)[0], inputs[:, 0].numpy()


@pytest.mark.slow
def test_rllib_snippet_trains_ppo_on_two_env_runners():
    pytest.importorskip("ray.rllib", reason='RLlib is not installed: pip install -e ".[rllib]"')
    import ray

    def sub_envs(runner):              # runs on each env runner (nested: pickled by value)
        """(class, tier, time limit) of each of the runner's gymnasium envs."""
        out = []
        for env in runner.env.unwrapped.envs:
            limit, e = None, env
            while hasattr(e, "env"):                   # through the wrappers, outermost first
                limit = limit or getattr(e, "_max_episode_steps", None)
                e = e.env
            out.append((type(e).__name__, e.tier, limit))
        return out

    code = compile(small_setup(page_snippet()), f"docs/{PAGE.name} ({SECTION[3:]})", "exec")
    # compile the kernels here, once: the env runners (which inherit NUMBA_CACHE_DIR) then load
    # them from the cache in seconds. A runner that compiles them inside its first sample() can
    # overrun RLlib's 60 s sample timeout on a loaded 2-core machine, and an iteration whose
    # sampling timed out reports no samples at all (no "env_runners" in its result).
    env = gymnasium.make(ENV_ID, tier="transient")
    env.reset(seed=0)
    env.step(env.action_space.sample())
    env.close()
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        ns: dict = {}
        exec(code, ns)                                 # the page's statements, small sizes
        algo = ns["algo"]
        try:
            results = [algo.train() for _ in range(ITERATIONS)]
            envs = algo.env_runner_group.foreach_env_runner(sub_envs, local_env_runner=False)
            scored, actions, means = _score_through_the_adapter(algo)
        finally:
            algo.stop()
    finally:
        ray.shutdown()

    assert algo.config.env == ENV_ID
    assert algo.config.num_env_runners == SMALL["num_env_runners"]
    n_envs = SMALL["num_env_runners"] * algo.config.num_envs_per_env_runner
    assert [e for runner in envs for e in runner] == [("BearingPreloadEnv", "transient", EPISODE_STEPS)] * n_envs

    batch = SMALL["train_batch_size_per_learner"]
    assert all("env_runners" in r for r in results), \
        "an iteration sampled nothing (RLlib's sample timeout, 60 s, ran out: a machine too loaded?)"
    sampled = [r["env_runners"]["num_env_steps_sampled"] for r in results]
    assert sampled == [batch] * ITERATIONS
    assert results[-1]["env_runners"]["num_env_steps_sampled_lifetime"] == ITERATIONS * batch

    # Each env stepped ITERATIONS * batch / n_envs times, so it finished at least that many //
    # EPISODE_STEPS episodes (more only if the integrator failed and the episode ended early).
    finished = results[-1]["env_runners"]["num_episodes_lifetime"]
    assert finished >= n_envs * (ITERATIONS * batch // n_envs // EPISODE_STEPS) >= n_envs

    # Per interval the reward is in [-worst, 0]; a failed interval earns -worst for itself and
    # for every interval left, so an episode's return is in [-worst * EPISODE_STEPS, 0]. worst:
    # the costliest interval of the task's envelope (the transient tier's speeds and radial
    # loads stay inside it): quasi-periodic at the amplitude cap, P_max, n_max, F_r,max, and the
    # whole preload range moved.
    worst = float(VibrationFirstReward().worst_step_cost(0.0, 0.0))
    assert worst == pytest.approx(1 + 100 / 10 + 0.5 + 0.5 + 0.1)
    with_episodes = [r["env_runners"] for r in results if r["env_runners"].get("num_episodes", 0) > 0]
    assert with_episodes
    for er in with_episodes:
        lo, mean, hi = er["episode_return_min"], er["episode_return_mean"], er["episode_return_max"]
        assert all(math.isfinite(v) for v in (lo, mean, hi)), er
        assert -worst * EPISODE_STEPS <= lo <= mean <= hi < 0.0, (lo, mean, hi)
        assert 1 <= er["episode_len_min"] <= er["episode_len_max"] == EPISODE_STEPS

    # the board's adapter (agents.submit.rllib, docs/scaling.md): its actions are the module's
    # Gaussian means clipped to the action space, and the scoring API scores them
    np.testing.assert_array_equal(actions[:, 0], np.clip(means, -1.0, 1.0).astype(np.float32))
    assert scored.row["n_episodes"] == SCORE_EPISODES and math.isfinite(scored.row["normalised_score_iqm"])
    assert all(-worst * EPISODE_STEPS <= r < 0.0 for r in scored.row["episode_returns"][0])

    learner = results[-1]["learners"]["default_policy"]
    for key in ("policy_loss", "vf_loss", "total_loss"):
        assert math.isfinite(learner[key]), (key, learner[key])
