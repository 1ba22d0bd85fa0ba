"""The validation-chosen constant: chosen on validation seeds only, stored, and read (not
re-chosen) by the evaluation; the hindsight sweep covers the actuator's whole range."""

import json

import numpy as np
import pytest

from agents.references import validation as references
from agents.evaluation.result import EvalResult
from agents.leaderboard.compare import evaluate
from agents.protocol import TEST, TRAIN, VALIDATION, preload_grid
from agents.references.store import STORE_PATH, ValidationChoice, load_choice, save_choice
from bearing_gym.envs.reward import REWARD_TERMS

GRID = (300.0, 1150.0, 2000.0)


def _choice(preload, seeds=(50_000, 50_001), means=(-3.0, -2.0, -1.0)):
    return ValidationChoice("transient", preload, tuple(seeds), 850.0, GRID, means, 2)


def test_a_choice_on_test_or_training_seeds_is_refused():
    for bad in (TEST.start, TRAIN.start + 5):
        with pytest.raises(ValueError, match="validation seeds"):
            _choice(2000.0, seeds=(50_000, bad))
    with pytest.raises(ValueError, match="rule 'best_mean' picks"):
        _choice(300.0)                                  # not the argmax of its own mean returns


def test_the_one_se_rule_takes_the_largest_preload_within_one_standard_error_of_the_best():
    """Worked by hand: the best (1150 N) has returns -1, -3 (mean -2, sample std sqrt(2), SE 1), so
    means down to -3 are ties: 2000 N at -2.9 is picked, not at -3.1; a single episode has no
    spread (the rule is the best mean)."""
    from agents.references.store import rule_choice
    two = ((-5.0, -5.0), (-1.0, -3.0), (-2.8, -3.0))
    assert rule_choice("one_se_largest", GRID, (-5.0, -2.0, -2.9), two) == 2
    assert rule_choice("one_se_largest", GRID, (-5.0, -2.0, -3.1), two) == 1
    assert rule_choice("one_se_largest", (2000.0, 300.0, 1150.0), (-2.9, -5.0, -2.0), (two[2], two[0], two[1])) == 0
    assert rule_choice("one_se_largest", GRID, (-5.0, -2.0, -2.1), ((-5.0,), (-2.0,), (-2.1,))) == 1
    assert rule_choice("best_mean", GRID, (-5.0, -2.0, -2.9)) == 1
    with pytest.raises(LookupError, match="per-episode"):
        rule_choice("one_se_largest", GRID, (-5.0, -2.0, -2.9))
    with pytest.raises(ValueError, match="one_se_largest"):
        rule_choice("median", GRID, (-5.0, -2.0, -2.9))
    c = ValidationChoice("transient", 2000.0, (50_000, 50_001), 850.0, GRID, (-5.0, -2.0, -2.9), 150,
                         episode_returns=two, rule="one_se_largest")
    assert c.preload_for_rule("best_mean") == 1150.0
    r0, r1 = c.validation_references([50_001], preload_n=1150.0)
    assert r0.tolist() == [-3.0] and r1.tolist() == [-3.0]


def test_a_store_holding_a_test_seed_does_not_load(tmp_path):
    path = tmp_path / "store.json"
    save_choice(_choice(2000.0), path)
    data = json.loads(path.read_text())
    data["tiers"]["transient"]["seeds"][1] = TEST.start
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="test range"):
        load_choice("transient", path)
    with pytest.raises(LookupError, match="python -m agents.references --tier paper"):
        load_choice("paper", path)


def test_the_committed_store_holds_only_validation_seeds():
    tiers = json.loads(STORE_PATH.read_text())["tiers"]
    for tier in tiers:
        assert all(s in VALIDATION for s in load_choice(tier).seeds), tier


def _fake_sweep(calls):
    """A stand-in for constant_sweep that records its seeds: the best mean return at 1150 N."""
    def sweep(preloads, episodes, seed, episode_steps, **kw):
        calls.append((seed, episodes))
        out = []
        for p in preloads:
            r = np.full(episodes, -abs(p - 1150.0) / 100.0)
            out.append(EvalResult(f"constant {p:.0f} N", r, {k: r / len(REWARD_TERMS) for k in REWARD_TERMS},
                                  np.zeros(episodes), np.full(episodes, p)))
        return out
    return sweep


def test_the_choice_runs_on_validation_seeds_and_refuses_test_seeds_before_running(monkeypatch, tmp_path):
    calls = []
    monkeypatch.setattr(references, "constant_sweep", _fake_sweep(calls))
    choice = references.choose_validation_constant("transient", episodes=4, episode_steps=2, grid_step_n=850.0)
    assert calls == [(VALIDATION.start, 4)]
    assert choice.seeds == tuple(range(VALIDATION.start, VALIDATION.start + 4)) and choice.preload_n == 1150.0
    save_choice(choice, tmp_path / "s.json")
    assert load_choice("transient", tmp_path / "s.json") == choice
    with pytest.raises(ValueError, match="validation"):
        references.choose_validation_constant("transient", episodes=2, seed=TEST.start)
    with pytest.raises(ValueError, match="validation"):
        references.choose_validation_constant("transient", episodes=3, seed=VALIDATION.stop - 2)
    assert len(calls) == 1                              # nothing ran for the refused seeds


def test_the_hindsight_grid_covers_the_whole_action_range_every_50_n():
    grid = preload_grid(50.0)
    assert grid[0] == 300.0 and grid[-1] == 2000.0 and len(grid) == 35
    assert np.allclose(np.diff(grid), 50.0)
    assert preload_grid(850.0) == GRID and preload_grid(800.0) == (300.0, 1100.0, 1900.0, 2000.0)


@pytest.mark.parametrize("stored", [300.0, 2000.0])
def test_evaluation_reads_the_stored_constant_instead_of_choosing_on_its_episodes(tmp_path, stored):
    # a stored choice at either end of the range: at most one of them can be the test-best
    means = (-1.0, -2.0, -3.0) if stored == 300.0 else (-3.0, -2.0, -1.0)
    store = tmp_path / "store.json"
    save_choice(_choice(stored, means=means), store)
    res = evaluate(None, episodes=2, seed=TEST.start, episode_steps=2, out_dir=tmp_path / "ev", verbose=False,
                   tier="transient", store_path=store, grid_step_n=850.0)
    names = [r.name for r in res]
    row = next(r for r in res if r.name == f"constant {stored:.0f} N (validation choice)")
    assert sum("validation choice" in n for n in names) == 1
    hindsight = next(r for r in res if "hindsight" in r.name)
    assert np.all(hindsight.returns >= row.returns)     # the stored constant is a hindsight candidate
    assert "chosen on the validation seeds, not on these" in (tmp_path / "ev" / "evaluation.md").read_text()
    # without a stored choice there is no such row (and nothing is chosen on the test episodes)
    res = evaluate(None, episodes=2, seed=TEST.start, episode_steps=2, out_dir=tmp_path / "none", verbose=False,
                   tier="transient", store_path=tmp_path / "empty.json", grid_step_n=850.0)
    assert not any("validation choice" in r.name for r in res)


def test_one_validation_episode_is_the_protocol_only_on_a_deterministic_tier():
    grid = preload_grid(50.0)
    means = tuple(-float(k) for k in range(len(grid)))
    one = {tier: ValidationChoice(tier, grid[0], (VALIDATION.start,), 50.0, grid, means, 150,
                                  episode_returns=tuple((m,) for m in means))
           for tier in ("paper", "transient")}
    assert one["paper"].protocol_problems() == []
    assert one["transient"].protocol_problems() == ["1 validation episodes (the protocol: 50)"]
    # the learning curves score every validation episode of a paper run against the one stored
    seeds = range(VALIDATION.start, VALIDATION.start + 3)
    r0, r1 = one["paper"].validation_references(seeds)
    assert r0.shape == r1.shape == (3,) and len(set(r0)) == 1 and np.all(r1 >= r0)
    with pytest.raises(ValueError, match="not one of the stored validation episodes"):
        one["transient"].validation_references(seeds)


def test_the_adoption_check_names_what_differs_from_today_and_passes_a_choice_made_today(tmp_path, monkeypatch):
    """validation_problems (the regeneration's check before adopting a stored choice): nothing for
    an entry made by this kernel on the given episodes and grid under the protocol's rule; the
    differing field by name otherwise."""
    from bearing_gym.envs.provenance import kernel_hash
    from agents import protocol as P
    from agents.references.store import validation_problems
    monkeypatch.setattr(P, "VALIDATION_RULE", "best_mean")
    store = tmp_path / "c.json"
    grid = preload_grid(850.0)
    means = tuple(-abs(p - 1150.0) for p in grid)
    save_choice(ValidationChoice("transient", 1150.0, (50_000, 50_001), 850.0, grid, means, 2,
                                 kernel_hash=kernel_hash()), store)
    assert [p.split(":")[0] for p in validation_problems("transient", store, 2, 2, 850.0)] == ["episode_returns"]
    save_choice(ValidationChoice("transient", 1150.0, (50_000, 50_001), 850.0, grid, means, 2,
                                 episode_returns=tuple((m, m) for m in means), kernel_hash=kernel_hash()), store)
    assert validation_problems("transient", store, 2, 2, 850.0) == []
    assert [p.split(":")[0] for p in validation_problems("transient", store, 3, 4, 850.0)] == ["seeds", "episode_steps"]
    monkeypatch.setattr(P, "VALIDATION_RULE", "one_se_largest")
    assert [p.split(":")[0] for p in validation_problems("transient", store, 2, 2, 850.0)] == ["rule"]
    assert validation_problems("stationary", store, 2, 2, 850.0)[0].startswith("no validation-chosen constant")


def test_rechoose_picks_again_by_another_rule_from_the_stored_returns_and_runs_nothing(tmp_path, monkeypatch):
    """Protocol v2's rule on protocol 1's validation sweep: the entry's preload and rule change,
    its returns do not, and no episode runs."""
    store = tmp_path / "c.json"
    two = ((-1.0, -3.0), (-2.9, -2.9), (-3.1, -3.1))   # 300 N best (mean -2, SE 1): 1150 N within, 2000 N not
    save_choice(ValidationChoice("transient", 300.0, (50_000, 50_001), 850.0, GRID, (-2.0, -2.9, -3.1), 2,
                                 episode_returns=two), store)
    monkeypatch.setattr(references, "constant_sweep", lambda *a, **k: pytest.fail("rechoose ran an episode"))
    new = references.rechoose("transient", store, "one_se_largest")
    assert (new.preload_n, new.rule) == (1150.0, "one_se_largest")
    stored = load_choice("transient", store)
    assert stored == new and stored.episode_returns == two and stored.mean_returns == (-2.0, -2.9, -3.1)


def test_the_regeneration_picks_a_stored_sweep_again_when_only_the_rule_changed(tmp_path, monkeypatch):
    """A new protocol's rule on today's sweep (agents.regenerate's validation product): the builder
    picks the stored returns again by today's rule and runs nothing, and the adoption check
    reads the result as today's; with another difference too (more episodes) it runs the sweep."""
    from bearing_gym.envs.provenance import kernel_hash
    from agents import protocol as P
    from agents.references.store import only_the_rule_differs, validation_problems
    from agents.regenerate import builders as B
    store = tmp_path / "c.json"
    two = ((-1.0, -3.0), (-2.9, -2.9), (-3.1, -3.1))   # 300 N best (mean -2, SE 1): 1150 N within, 2000 N not
    save_choice(ValidationChoice("transient", 300.0, (50_000, 50_001), 850.0, GRID, (-2.0, -2.9, -3.1), 2,
                                 episode_returns=two, kernel_hash=kernel_hash(), rule="best_mean"), store)
    monkeypatch.setattr(P, "VALIDATION_RULE", "one_se_largest")
    assert only_the_rule_differs("transient", store, 2, 2, 850.0)
    monkeypatch.setattr(references, "constant_sweep", lambda *a, **k: pytest.fail("the builder ran an episode"))
    got = B.validation_constant("transient", 2, 2, 850.0, store)
    assert (got.preload_n, got.rule, got.episode_returns) == (1150.0, "one_se_largest", two)
    assert load_choice("transient", store).preload_n == 300.0      # stored by the driver's commit, not the builder
    B.commit_validation(store, got)
    assert validation_problems("transient", store, 2, 2, 850.0) == []

    class Ran(Exception):
        pass

    def sweep(*a, **k):
        raise Ran
    monkeypatch.setattr(references, "constant_sweep", sweep)
    assert not only_the_rule_differs("transient", store, 3, 2, 850.0)
    with pytest.raises(Ran):
        B.validation_constant("transient", 3, 2, 850.0, store)
