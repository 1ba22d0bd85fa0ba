"""The stored test references built in parts equal the one-go computation, episode by episode."""

import json

import pytest

from agents import protocol as P
from agents.leaderboard import reference_parts as RP
from agents.evaluation.episodes import sweep_row
from agents.leaderboard.settings import FULL, SMOKE
from agents.references.store import load_choice
from agents.references.validation import hindsight_reference, run_mpc
from agents.references.store import load_references, result_to_json


def test_the_parts_cover_the_test_episodes_and_the_mpc_subset_once(tmp_path):
    parts = RP.plan(FULL)
    sweep = [s for k, f, n in parts if k == "sweep" for s in range(f, f + n)]
    mpc = [s for k, f, n in parts if k == "mpc" for s in range(f, f + n)]
    assert sweep == list(P.held_out_seeds(P.TEST_EPISODES))
    assert mpc == list(P.held_out_seeds(P.TEST_EPISODES))[:P.MPC_EPISODES]
    # the deterministic paper tier: one episode of each kind, also where no settings are given
    one = [("sweep", P.TEST.start, 1), ("mpc", P.TEST.start, 1)]
    assert RP.plan(FULL.for_tier("paper")) == one
    assert RP.missing("paper", data_dir=tmp_path) == one and len(RP.missing("transient", data_dir=tmp_path)) == len(parts)


def test_parts_merge_to_the_one_go_references_and_a_missing_or_foreign_part_is_refused(tmp_path, monkeypatch):
    tier = "transient"
    monkeypatch.setattr(RP, "SWEEP_PART_EPISODES", 1)         # two sweep parts of one episode each
    plan = RP.plan(SMOKE)
    assert [p[0] for p in plan] == ["sweep", "sweep", "mpc"]
    for part in plan[:2]:
        RP.compute_part(tier, *part, s=SMOKE, data_dir=tmp_path, processes=1)
    with pytest.raises(FileNotFoundError, match="1 parts of tier transient are missing"):
        RP.merge(tier, SMOKE, tmp_path)
    RP.compute_part(tier, *plan[2], s=SMOKE, data_dir=tmp_path, processes=1)
    RP.merge(tier, SMOKE, tmp_path)
    refs = load_references(tier, tmp_path)

    choice = load_choice(tier)
    seeds = P.held_out_seeds(SMOKE.episodes)
    hindsight, sweep = hindsight_reference(tier, SMOKE.episodes, seeds.start, SMOKE.episode_steps,
                                           SMOKE.hindsight_grid_step_n, extra_n=(choice.preload_n,))
    mpc, _ = run_mpc(tier, seeds[:SMOKE.mpc_episodes], SMOKE.episode_steps, SMOKE.mpc)
    constant = sweep_row(sweep, choice.preload_n)
    assert refs.seeds == tuple(seeds) and refs.validation_preload_n == choice.preload_n
    for got, want in ((refs.validation_constant, constant), (refs.hindsight, hindsight), (refs.mpc, mpc)):
        assert result_to_json(got) == result_to_json(want)      # every stored metric, bit for bit
    assert refs.mpc_wall_s_per_episode > 0

    part = tmp_path / "test_references_transient_parts" / f"sweep_{seeds.start}_1.json"
    good = json.loads(part.read_text())
    for change, problem in ((lambda d: d.update(hindsight_grid_step_n=100.0), "hindsight_grid_step_n = 100.0"),
                            (lambda d: d["rows"]["hindsight"].update(returns=[]), "hindsight row has 0 episodes"),
                            (lambda d: d.update(first_seed=seeds.start + 1), "its file holds sweep from seed")):
        d = json.loads(json.dumps(good))
        change(d)
        part.write_text(json.dumps(d))
        with pytest.raises(ValueError, match=problem):
            RP.merge(tier, SMOKE, tmp_path)


def test_a_part_made_by_another_kernel_counts_as_missing(tmp_path):
    import json

    from agents.leaderboard import reference_parts as rp
    from agents.leaderboard.settings import SMOKE
    todo = rp.missing("transient", SMOKE, tmp_path)
    kind, first, n = todo[0]
    path = rp._path("transient", kind, first, n, tmp_path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"kernel_hash": "0123456789abcdef"}))
    assert (kind, first, n) in rp.missing("transient", SMOKE, tmp_path)
    from bearing_gym.envs.provenance import kernel_hash
    path.write_text(json.dumps({"kernel_hash": kernel_hash()}))
    assert (kind, first, n) not in rp.missing("transient", SMOKE, tmp_path)
