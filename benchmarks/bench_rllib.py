"""RLlib PPO throughput on the env: env steps per second with 1 and 2 env runners.

    python benchmarks/bench_rllib.py            # table, ~3 min on a 2-core machine
    python benchmarks/bench_rllib.py --json     # one JSON object instead
    python benchmarks/bench_rllib.py --quick    # same keys, a 100-step batch, one round

Needs the ``rllib`` extra (``pip install -e ".[rllib]"``). One local Ray session holds both
configurations: docs/scaling.md's PPO config ("Training past one machine": transient tier, 2 envs
per env runner) with 1 and with 2 env runners, each with a ``--batch``-step train batch (64-step
minibatches, one epoch, so that sampling dominates). After one untimed ``algo.train()`` each
(the workers load the numba kernels), every round times, for each configuration in turn:

* ``train``: one ``algo.train()`` (sampling, PPO update, weight sync): env steps sampled / wall
  time, what a user's training loop gets;
* ``sample``: every env runner samples ``batch / runners`` env steps at once (the policy acting,
  no update): env steps / wall time.

The table gives the median over the rounds (each round's figure is in the JSON). For
reference, ``single_env_steps_per_s`` is a plain ``gymnasium.make`` loop in this process
(random actions, no Ray). The 1-minute load average is printed at the start and the end: the
figures are comparable only at a similar load. One env step is one 20 ms control interval.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

import gymnasium
import numpy as np

import bearing_gym  # noqa: F401 - registers BearingPreload-v0

ENV_ID = "BearingPreload-v0"
ENV_CONFIG = {"tier": "transient"}
ENVS_PER_RUNNER = 2
RUNNERS = (1, 2)                 # env runners of the configurations compared


def single_env_rate(steps: int) -> float:
    env = gymnasium.make(ENV_ID, **ENV_CONFIG)
    env.reset(seed=0)
    env.action_space.seed(0)
    env.step(env.action_space.sample())
    t0 = time.perf_counter()
    for _ in range(steps):
        _, _, term, trunc, _ = env.step(env.action_space.sample())
        if term or trunc:
            env.reset()
    return steps / (time.perf_counter() - t0)


def make_env(cfg):
    import bearing_gym  # noqa: F401,F811 - registers BearingPreload-v0 in the worker process
    return gymnasium.make(ENV_ID, **cfg)


def build(runners: int, batch: int):
    """docs/scaling.md's PPO config with ``runners`` env runners and a small batch."""
    from ray.rllib.algorithms.ppo import PPOConfig

    config = (PPOConfig()
              .environment(ENV_ID, env_config=ENV_CONFIG)
              .env_runners(num_env_runners=runners, num_envs_per_env_runner=ENVS_PER_RUNNER)
              .training(train_batch_size_per_learner=batch, minibatch_size=min(64, batch),
                        num_epochs=1))
    return config.build_algo()


def timed_train(algo) -> tuple[int, float]:
    t0 = time.perf_counter()
    steps = int(algo.train()["env_runners"]["num_env_steps_sampled"])
    return steps, time.perf_counter() - t0


def timed_sample(algo, batch: int) -> tuple[int, float]:
    per_runner = batch // algo.config.num_env_runners
    t0 = time.perf_counter()
    counts = algo.env_runner_group.foreach_env_runner(
        lambda r: sum(len(e) for e in r.sample(num_timesteps=per_runner)), local_env_runner=False)
    return int(sum(counts)), time.perf_counter() - t0


def rllib_rates(runner_counts: tuple[int, ...], batch: int, rounds: int) -> list[dict]:
    """Both configurations live in one Ray session and are timed in alternation, so that a
    change of the machine's load hits them alike."""
    import ray
    from ray.tune.registry import register_env

    # Logical CPUs: one per env runner of all the configurations (each idles while another is
    # timed), whatever the machine has.
    ray.init(num_cpus=sum(runner_counts), include_dashboard=False, log_to_driver=False)
    algos = []
    try:
        register_env(ENV_ID, make_env)
        algos = [build(n, batch) for n in runner_counts]
        for algo in algos:
            algo.train()                                   # warm-up: kernels loaded in the workers
        rates = [{"train": [], "sample": []} for _ in algos]
        for _ in range(rounds):
            for algo, rate in zip(algos, rates):
                steps, s = timed_train(algo)
                rate["train"].append(steps / s)
                steps, s = timed_sample(algo, batch)
                rate["sample"].append(steps / s)
    finally:
        for algo in algos:
            algo.stop()
        ray.shutdown()
    return [{"env_runners": n, "envs": n * ENVS_PER_RUNNER,
             "train_env_steps_per_s": float(np.median(r["train"])),
             "sample_env_steps_per_s": float(np.median(r["sample"])),
             "train_env_steps_per_s_each_round": r["train"],
             "sample_env_steps_per_s_each_round": r["sample"]}
            for n, r in zip(runner_counts, rates)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a 100-step batch, one round (same keys)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--batch", type=int, default=None, help="train batch in env steps (default 200)")
    ap.add_argument("--rounds", type=int, default=None, help="timed rounds (default 3)")
    args = ap.parse_args()
    batch = args.batch or (100 if args.quick else 200)
    rounds = args.rounds or (1 if args.quick else 3)

    import ray
    res = {"machine": platform.processor() or platform.machine(), "cores": os.cpu_count(),
           "ray": ray.__version__, "gymnasium": gymnasium.__version__, "tier": ENV_CONFIG["tier"],
           "envs_per_env_runner": ENVS_PER_RUNNER, "batch": batch, "rounds": rounds,
           "load_1min_start": os.getloadavg()[0]}
    res["single_env_steps_per_s"] = single_env_rate(30 if args.quick else 60)
    res["runs"] = rllib_rates(RUNNERS, batch, rounds)
    res["load_1min_end"] = os.getloadavg()[0]
    if args.json:
        print(json.dumps(res))
        return
    print(f"{res['machine']}, {res['cores']} cores; Ray {res['ray']}, gymnasium {res['gymnasium']}; "
          f"tier {res['tier']}; batch {batch}; median of {rounds} rounds")
    print(f"1-min load average: {res['load_1min_start']:.2f} at the start, "
          f"{res['load_1min_end']:.2f} at the end")
    print(f"single env, no Ray: {res['single_env_steps_per_s']:.1f} env steps/s")
    print(f"{'env runners':>11s} {'envs':>5s} {'train env steps/s':>18s} {'sample env steps/s':>19s}")
    for r in res["runs"]:
        print(f"{r['env_runners']:>11d} {r['envs']:>5d} {r['train_env_steps_per_s']:>18.1f} "
              f"{r['sample_env_steps_per_s']:>19.1f}")
    a, b = res["runs"]
    print(f"{b['env_runners']} vs {a['env_runners']} env runners: "
          f"train {b['train_env_steps_per_s'] / a['train_env_steps_per_s']:.2f}x, "
          f"sample {b['sample_env_steps_per_s'] / a['sample_env_steps_per_s']:.2f}x")


if __name__ == "__main__":
    main()
