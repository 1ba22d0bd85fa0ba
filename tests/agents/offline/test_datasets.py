"""The offline datasets: a small one rebuilt from its recipe to its committed checksum, the
checksum's sensitivity, resumable parts, the mixed join, the expert's replay of stored plans,
and the recipes' promises (training seeds only, the constant is protocol v2's)."""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("minari", reason='the offline datasets need the datasets extra: pip install -e ".[datasets]"')

from agents import protocol as P  # noqa: E402
from agents.offline import build as B  # noqa: E402
from agents.offline import recipes as R  # noqa: E402
from agents.offline.collect import INFO_KEYS, collect_part, part_path  # noqa: E402


@pytest.fixture
def minari_home(tmp_path, monkeypatch):
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "minari"))
    return tmp_path


def test_the_sample_dataset_rebuilds_from_its_recipe_to_the_committed_checksum(minari_home):
    """The acceptance check: built from nothing here (the kernel is the same bits on every CPU),
    the sample's content checksum equals the one committed in agents/data/offline_datasets.json;
    loading it back through Minari gives every step's data and the same info keys every step."""
    import minari
    entry = B.build("transient/sample", work_dir=minari_home / "work", processes=1, log=lambda s: None)
    committed = B.load_catalogue()["datasets"]["bearing_gym/transient/sample-v0"]
    assert entry["checksum"] == committed["checksum"] and entry["steps"] == committed["steps"] == 10 * 150
    assert B.verify("transient/sample") == committed["checksum"]
    ds = minari.load_dataset("bearing_gym/transient/sample-v0")
    for ep in ds.iterate_episodes():
        assert ep.observations.shape == (151, 15) and ep.actions.shape == (150, 1) and ep.rewards.shape == (150,)
        assert sorted(ep.infos) == sorted(INFO_KEYS) and all(len(v) == 151 for v in ep.infos.values())
        assert np.all(np.abs(ep.actions) <= 1.0) and ep.truncations[-1] and not ep.terminations.any()
    assert ds.spec.env_spec.kwargs["tier"] == "transient"     # the env the data came from, its tier included


def test_one_flipped_bit_changes_the_checksum_and_a_mismatch_says_what_differs(minari_home, monkeypatch):
    import minari
    r = R.recipe("transient/sample")
    work = minari_home / "work"
    B.collect(r, work, processes=1, progress=False)
    eps = B.episodes_of(r, work)
    B.write_minari(r, eps)
    base = B.checksum(minari.load_dataset(r.dataset_id))
    eps[3]["rewards"] = eps[3]["rewards"].copy()
    eps[3]["rewards"][7] = np.nextafter(eps[3]["rewards"][7], np.inf)
    B.write_minari(r, eps)
    assert B.checksum(minari.load_dataset(r.dataset_id)) != base
    with pytest.raises(B.DatasetMismatch, match="checksum .* is not the committed"):
        B.verify("transient/sample")
    # a build against a catalogue that records another recipe, or another kernel, says which
    cat = minari_home / "cat.json"
    good = B.load_catalogue()["datasets"][r.dataset_id]
    for key, why in (("recipe_sha", "the recipe changed"), ("kernel_hash", "another kernel made")):
        cat.write_text(json.dumps({"datasets": {r.dataset_id: {**good, key: "0" * 16}}}))
        with pytest.raises(B.DatasetMismatch, match=why):
            B.build("transient/sample", work_dir=work, catalogue=cat, log=lambda s: None)


def test_a_recorded_part_is_kept_and_one_from_another_recipe_is_recorded_again(minari_home):
    r = R.recipe("transient/sample")
    work = minari_home / "work"
    assert B.parts_left(r, work) == r.parts() == [(P.OFFLINE_DATASET_SEED, 10)]
    B.collect(r, work, processes=1, progress=False)
    assert B.parts_left(r, work) == []
    path = part_path(r, *r.parts()[0], work)
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(str(arrays.pop("meta")))
    np.savez(path, meta=np.array(json.dumps({**meta, "recipe_sha": "another"})), **arrays)
    assert B.parts_left(r, work) == r.parts()


def _tiny(monkeypatch) -> dict[str, R.Recipe]:
    """Three small recipes in place of the catalogue: random and constant (3 episodes), mixed (2 of each)."""
    tiny = [R.Recipe("random", "transient", "random", 3, part_episodes=2),
            R.Recipe("constant", "transient", "constant", 3, policy={"preload_n": 2000.0}),
            R.Recipe("mixed", "transient", "mixed", 4, sources=(("random", 2), ("constant", 2)))]
    recipes = {r.dataset_id: r for r in tiny}
    monkeypatch.setattr(R, "RECIPES", recipes)
    return recipes


def test_mixed_joins_its_sources_first_episodes_in_order(minari_home, monkeypatch):
    import minari
    _tiny(monkeypatch)
    work = minari_home / "work"
    cat = minari_home / "cat.json"
    # built first, mixed records only the source parts that hold the episodes it takes
    B.build("transient/mixed", work_dir=work, processes=1, record=True, catalogue=cat, log=lambda s: None)
    assert sorted(p.name for p in (work / "transient" / "random").iterdir()) == ["part_45000_2.npz"]
    assert B.parts_left(R.recipe("transient/random"), work) == [(45_002, 1)]
    for name in ("transient/random", "transient/constant"):
        B.build(name, work_dir=work, processes=1, record=True, catalogue=cat, log=lambda s: None)
    assert B.parts_left(R.recipe("transient/random"), work) == []
    mixed = list(minari.load_dataset("bearing_gym/transient/mixed-v0").iterate_episodes())
    random = B.episodes_of(R.recipe("transient/random"), work)
    constant = B.episodes_of(R.recipe("transient/constant"), work)
    assert [e["seed"] for e in random[:2] + constant[:2]] == [45_000, 45_001] * 2
    for got, want in zip(mixed, random[:2] + constant[:2]):
        assert np.array_equal(got.rewards, want["rewards"]) and np.array_equal(got.observations, want["observations"])
    # the constant's actions are the actuator's top, every step
    assert np.all(constant[0]["actions"] == np.float32(1.0))
    # mixed's recipe digest follows its sources' (a source's new recipe is a new mixed dataset)
    before = R.recipe("transient/mixed").digest()
    R.RECIPES["bearing_gym/transient/constant-v0"] = R.Recipe("constant", "transient", "constant", 3,
                                                              policy={"preload_n": 1900.0})
    assert R.recipe("transient/mixed").digest() != before


def test_the_expert_replays_its_stored_plans_and_refuses_a_stale_one(minari_home, monkeypatch):
    """A plan file in agents.references.planner_runs' format (here: 2000 N every interval, whose
    return the constant recipe gives): the expert's part replays it to that return bit for bit;
    a stored return one ulp off is refused."""
    from bearing_gym.envs.provenance import kernel_hash
    from agents.policies.planner import PlannerSettings
    recipes = _tiny(monkeypatch)
    expert = R.Recipe("expert", "transient", "planner", 1, policy={"planner": PlannerSettings().as_dict()})
    recipes[expert.dataset_id] = expert
    work, plans = minari_home / "work", minari_home / "plans"
    with np.load(collect_part("transient/constant", P.OFFLINE_DATASET_SEED, 1, str(work))) as z:
        want = sum(float(x) for x in z["rewards"])          # 2000 N held: the plan below, as a constant
    seed = P.OFFLINE_DATASET_SEED
    path = plans / "planner_transient" / f"seed_{seed}.json"
    path.parent.mkdir(parents=True)

    def write(ret: float) -> None:
        path.write_text(json.dumps({
            "tier": "transient", "kernel_hash": kernel_hash(), "episode_steps": 150, "seed": seed, "return": ret,
            "hindsight_preload_n": 2000.0, "hindsight_return": ret, "decisions": 0, "accepted": 0, "env_steps": 0,
            "wall_s": 0.0, "terminated": False, "settings": PlannerSettings().as_dict(), "plan_n": [2000.0] * 15}))
    write(want)
    out = collect_part(expert.dataset_id, seed, 1, str(work), str(plans))
    with np.load(out) as z:
        assert sum(float(x) for x in z["rewards"]) == want
    assert B.parts_left(expert, work, plans) == []
    d = json.loads(path.read_text())                   # re-made plans: the part replayed from the old ones is stale
    path.write_text(json.dumps({**d, "wall_s": 1.0}))
    assert B.parts_left(expert, work, plans) == [(seed, 1)]
    write(float(np.nextafter(want, -np.inf)))
    with pytest.raises(RuntimeError, match="the plan file is stale"):
        collect_part(expert.dataset_id, seed, 1, str(work), str(plans))
    path.unlink()
    with pytest.raises(FileNotFoundError, match="plan the expert's episodes first"):
        collect_part(expert.dataset_id, seed, 1, str(work), str(plans))


def test_the_recipes_use_training_seeds_only_and_protocol_v2s_validation_constant():
    from agents.references.store import load_choice
    digests = {r.dataset_id: r.digest() for r in R.RECIPES.values()}   # every file a recipe names is there
    assert len(set(digests.values())) == len(digests)
    for r in R.RECIPES.values():
        assert r.first_seed == P.OFFLINE_DATASET_SEED and P.range_of(r.first_seed) == "train"
        if r.kind != "mixed":
            last = r.parts()[-1]
            assert sum(n for _, n in r.parts()) == r.episodes and P.range_of(last[0] + last[1] - 1) == "train"
    for tier, preload_n in R.VALIDATION_CONSTANT_N.items():
        assert load_choice(tier).preload_for_rule(P.V2_VALIDATION_RULE) == preload_n
    with pytest.raises(ValueError, match="must lie in the offline datasets' training block"):
        R.Recipe("x", "transient", "random", 10, first_seed=P.TEST.start)
    with pytest.raises(KeyError, match="no dataset 'transient/nothing'"):
        R.recipe("transient/nothing")


def test_the_expert_is_planned_on_spawned_worker_processes(tmp_path):
    """``plan --processes N`` hands plan_chunk to spawned workers: it must be importable there
    (not defined in a package's __main__); chunks with nothing left to plan return 0."""
    from bearing_gym.analysis.sweeps import run_tasks
    from agents.offline.collect import plan_chunk
    assert run_tasks(plan_chunk, [("transient/expert", [], str(tmp_path), None)] * 2, max_workers=2,
                     progress=False) == [0, 0]
