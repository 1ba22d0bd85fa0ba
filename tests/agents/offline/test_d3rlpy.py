"""The offline baselines' pipeline on the sample dataset: d3rlpy trains on the Minari data, the
portable export gives d3rlpy's deterministic actions (float32 precision), and the runs are
scored through the scoring API into a submission the board takes."""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("minari", reason='needs the datasets extra: pip install -e ".[datasets]"')
pytest.importorskip("d3rlpy", reason='needs d3rlpy: pip install -e ".[offline]" && pip install --no-deps d3rlpy==2.8.1')

from agents.offline import build as B  # noqa: E402
from agents.offline import d3rlpy_baselines as D  # noqa: E402


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    import os
    home = tmp_path_factory.mktemp("offline")
    old = os.environ.get("MINARI_DATASETS_PATH")
    os.environ["MINARI_DATASETS_PATH"] = str(home / "minari")
    B.build("transient/sample", work_dir=home / "work", processes=1, log=lambda s: None)
    yield home
    if old is None:
        os.environ.pop("MINARI_DATASETS_PATH", None)
    else:
        os.environ["MINARI_DATASETS_PATH"] = old


def test_the_minari_data_become_d3rlpys_transitions_episode_by_episode(sample):
    import minari
    mdp = D.to_mdp(minari.load_dataset("bearing_gym/transient/sample-v0"))
    # d3rlpy keeps no observation after an episode's last action: a truncated episode of T steps
    # gives T - 1 transitions (the D4RL convention)
    assert mdp.transition_count == 10 * 149 and len(mdp.episodes) == 10
    assert all(ep.observations.shape == (150, 15) for ep in mdp.episodes)


@pytest.mark.parametrize("algo", D.ALGOS)
def test_a_trained_run_exports_its_deterministic_actor_and_is_scored_through_the_api(sample, algo):
    import d3rlpy
    import minari
    from agents.policies.portable import PortablePolicy
    from agents.submit.submission import check_schema, load_submission
    root = sample / "runs"
    out = D.train(algo, "transient/sample", 0, steps=50, root=root)
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["gradient_steps"] == 50 and cfg["library_version"] == d3rlpy.__version__
    model = d3rlpy.load_learnable(str(out / "model.d3"))
    obs = np.concatenate([e.observations for e in minari.load_dataset("bearing_gym/transient/sample-v0")
                          .iterate_episodes()])
    want = model.predict(obs)
    got, _ = PortablePolicy.load(out).predict(obs)
    # torch's float32 network against the float64 export with the scaler folded in: float32 precision
    assert np.max(np.abs(got - want)) < 1e-5 and np.ptp(want) > 0
    sub = sample / f"{algo}.json"
    scored = D.score_runs(algo, "transient/sample", root=root, out=sub, seeds=(0,), episodes=2)
    row = load_submission(sub)
    check_schema(row)
    assert row["library"] == "d3rlpy" and row["training_steps"] == 0 and row["episodes"] == 2
    assert row["runs"][0]["returns"] == [float(x) for x in scored.results[0].returns]
