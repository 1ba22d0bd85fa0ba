"""The stored test references built in parts (sweep parts + the planner's episodes) equal the
one-go computation, episode by episode."""

import json

import numpy as np
import pytest

from agents import protocol as P
from agents.leaderboard import reference_parts as RP
from agents.evaluation.episodes import sweep_row
from agents.leaderboard.settings import FULL, SMOKE
from agents.policies.planner import plan_episode
from agents.references import planner_runs
from agents.references.store import (ValidationChoice, load_choice, load_references, result_to_json, save_choice,
                                     stored_hindsight)
from agents.references.validation import hindsight_reference


def test_the_parts_cover_the_test_episodes_once(tmp_path):
    parts = RP.plan(FULL)
    sweep = [s for k, f, n in parts if k == "sweep" for s in range(f, f + n)]
    assert sweep == list(P.held_out_seeds(P.TEST_EPISODES)) and {k for k, _, _ in parts} == {"sweep"}
    # the deterministic paper tier: one episode, also where no settings are given
    one = [("sweep", P.TEST.start, 1)]
    assert RP.plan(FULL.for_tier("paper")) == one
    assert RP.missing("paper", data_dir=tmp_path) == one and len(RP.missing("transient", data_dir=tmp_path)) == len(parts)


def test_parts_and_plans_merge_to_the_one_go_references_and_a_missing_or_foreign_part_is_refused(tmp_path, monkeypatch):
    tier = "transient"
    monkeypatch.setattr(RP, "SWEEP_PART_EPISODES", 1)         # two sweep parts of one episode each
    store = tmp_path / "constants.json"                       # a validation constant on the smoke grid
    save_choice(ValidationChoice(tier, 1150.0, (50_000, 50_001, 50_002), 850.0, (300.0, 1150.0, 2000.0),
                                 (-3.0, -1.0, -2.0), SMOKE.episode_steps), store)
    plan = RP.plan(SMOKE)
    assert plan == [("sweep", P.TEST.start, 1), ("sweep", P.TEST.start + 1, 1)]
    RP.compute_part(tier, *plan[0], s=SMOKE, data_dir=tmp_path)
    with pytest.raises(FileNotFoundError, match="1 parts of tier transient are missing"):
        RP.merge(tier, SMOKE, tmp_path, store)
    RP.compute_part(tier, *plan[1], s=SMOKE, data_dir=tmp_path)
    with pytest.raises(ValueError, match="validation constant's row.*no validation row.*--validation-row"):
        RP.merge(tier, SMOKE, tmp_path, store)
    RP.compute_validation_row(tier, SMOKE, store, tmp_path)
    with pytest.raises(ValueError, match="2 test episode.*not planned.*planner_runs --tier transient"):
        RP.merge(tier, SMOKE, tmp_path, store)                      # the planner's episodes are missing
    seeds = P.held_out_seeds(SMOKE.episodes)
    written = planner_runs.run(tier, list(seeds), SMOKE.planner, SMOKE.episode_steps, data_dir=tmp_path)
    assert len(written) == 2
    RP.merge(tier, SMOKE, tmp_path, store)
    refs = load_references(tier, tmp_path)

    choice = load_choice(tier, store)
    hindsight, sweep = hindsight_reference(tier, SMOKE.episodes, seeds.start, SMOKE.episode_steps,
                                           SMOKE.hindsight_grid_step_n)       # the grid alone: it holds 1150 N
    constant = sweep_row(sweep, choice.preload_n)
    assert refs.seeds == tuple(seeds) and refs.validation_preload_n == choice.preload_n
    for got, want in ((refs.validation_constant, constant), (refs.hindsight, hindsight)):
        assert result_to_json(got) == result_to_json(want)      # every stored metric, bit for bit
    # the planner started from the stored sweep, and planning from scratch gives the same bits
    for k, seed in enumerate(seeds):
        stored = json.loads(planner_runs.episode_path(tier, seed, tmp_path).read_text())
        assert stored["hindsight_from"] == "stored"
        assert stored_hindsight(tier, seed, SMOKE.hindsight_grid_step_n, SMOKE.episode_steps, tmp_path) == (
            stored["hindsight_preload_n"], hindsight.returns[k])
        fresh = plan_episode(tier, seed, SMOKE.episode_steps, SMOKE.planner)
        assert fresh.hindsight_from == "sweep" and fresh.return_ == refs.planner.returns[k]
        assert np.array_equal(fresh.plan_n, stored["plan_n"])
    assert np.all(refs.planner.returns >= refs.hindsight.returns) and refs.planner_wall_s_per_episode > 0

    part = tmp_path / "test_references_transient_parts" / f"sweep_{seeds.start}_1.json"
    good = json.loads(part.read_text())
    # the regeneration's adoption check: the planned episodes are what planning now would write ...
    check = (tier, SMOKE.episodes, SMOKE.planner, SMOKE.episode_steps, SMOKE.hindsight_grid_step_n, tmp_path)
    assert planner_runs.problems(*check) == []
    other = json.loads(part.read_text())                # ... until the sweep holds another start
    other["hindsight_preload_n"] = [2000.0 if good["hindsight_preload_n"][0] != 2000.0 else 300.0]
    part.write_text(json.dumps(other))
    assert [p.split(":")[0] for p in planner_runs.problems(*check)] == [f"seed {seeds.start}"]
    part.write_text(json.dumps(good))
    for change, problem in ((lambda d: d.update(hindsight_grid_step_n=100.0), "hindsight_grid_step_n = 100.0"),
                            (lambda d: d["rows"]["hindsight"].update(returns=[]), "hindsight row has 0 episodes"),
                            (lambda d: d.update(first_seed=seeds.start + 1), "its file holds sweep from seed")):
        d = json.loads(json.dumps(good))
        change(d)
        part.write_text(json.dumps(d))
        with pytest.raises(ValueError, match=problem):
            RP.merge(tier, SMOKE, tmp_path, store)
    part.write_text(json.dumps(good))
    # a plan whose stored return the replay does not repeat is refused
    path = planner_runs.episode_path(tier, seeds.start, tmp_path)
    d = json.loads(path.read_text())
    d["return"] = float(np.nextafter(d["return"], np.inf))
    path.write_text(json.dumps(d))
    with pytest.raises(RuntimeError, match=f"seed {seeds.start}: its plan replayed returns"):
        RP.merge(tier, SMOKE, tmp_path, store)
    # without the planner: the board's hindsight-only store
    RP.merge(tier, SMOKE, tmp_path, store, with_planner=False)
    assert load_references(tier, tmp_path).planner is None
    # another validation constant in the store (a new rule): its row is stale, the sweep is not;
    # one off the hindsight grid is refused (the hindsight would not bound it)
    before = 1150.0
    for preload_n, grid_n, means in ((2000.0, (300.0, 1150.0, 2000.0), (-3.0, -2.0, -1.0)),
                                     (1175.0, (300.0, 1175.0, 2000.0), (-3.0, -1.0, -2.0))):
        save_choice(ValidationChoice(tier, preload_n, (50_000, 50_001, 50_002), 25.0, grid_n, means,
                                     SMOKE.episode_steps), store)
        with pytest.raises(ValueError, match=f"preload_n = {before}, today's is {preload_n}"):
            RP.merge(tier, SMOKE, tmp_path, store, with_planner=False)
        RP.compute_validation_row(tier, SMOKE, store, tmp_path)
        if preload_n == 2000.0:
            RP.merge(tier, SMOKE, tmp_path, store, with_planner=False)
            got = load_references(tier, tmp_path)
            assert got.validation_preload_n == 2000.0 and result_to_json(got.hindsight) == result_to_json(hindsight)
            assert result_to_json(got.validation_constant) == result_to_json(sweep_row(sweep, 2000.0))
        else:
            with pytest.raises(ValueError, match="1175 N is not on the hindsight grid"):
                RP.merge(tier, SMOKE, tmp_path, store, with_planner=False)
        before = preload_n


def test_a_part_made_by_another_kernel_or_the_old_definition_counts_as_missing(tmp_path):
    from agents.leaderboard import reference_parts as rp
    todo = rp.missing("transient", SMOKE, tmp_path)
    kind, first, n = todo[0]
    path = rp._path("transient", kind, first, n, tmp_path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"kernel_hash": "0123456789abcdef"}))
    assert (kind, first, n) in rp.missing("transient", SMOKE, tmp_path)
    from bearing_gym.envs.provenance import kernel_hash
    path.write_text(json.dumps({"kernel_hash": kernel_hash()}))
    assert (kind, first, n) not in rp.missing("transient", SMOKE, tmp_path)
    # a part of the definition before the sweep was decoupled (it swept the validation constant too) is missing
    path.write_text(json.dumps({"kernel_hash": kernel_hash(), "validation_preload_n": 1850.0}))
    assert (kind, first, n) in rp.missing("transient", SMOKE, tmp_path)
