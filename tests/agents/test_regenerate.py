"""python -m agents.regenerate: what is fresh and why, what a change rebuilds, --until, failures
(on a small graph of fake products: no simulation), then the real products on the tiny profile
from nothing in a scratch directory."""

from __future__ import annotations

import dataclasses
import json
import shutil
from datetime import datetime, timedelta
from functools import partial
from pathlib import Path

import pytest

from bearing_gym.analysis.sweeps import SerialExecutor

from agents.regenerate import TINY, main, plan, regenerate
from agents.regenerate.manifest import FRESH, MISSING, PARTIAL, STALE, Manifest
from agents.regenerate.product import Layout, Part, Product
from agents.regenerate.scheduler import build, make_executor, select, simulate


# -- a graph of fake products: a (2 parts) -> b -> d <- c (c kernel-free) --------------------------
def _touch(path: str, text: str, log: str) -> str:
    Path(path).write_text(text)
    with open(log, "a") as fh:
        fh.write(Path(path).stem + "\n")
    return text


def _fail(path: str, text: str, log: str) -> str:
    raise RuntimeError(f"{text} failed")


def _commit(root: Path, result: str) -> None:
    (root / "b.commit").write_text(result)


def _join(root: Path) -> None:
    (root / "d.sum").write_text((root / "b.out").read_text() + (root / "c.out").read_text())


def _graph(root: Path, b_setting: int = 1, a2_cost: float = 1.0, b_fn=_touch) -> list[Product]:
    log = str(root / "runs.log")

    def part(name: str, cost: float = 1.0, fn=_touch, commit=None) -> Part:
        return Part(name, fn, (str(root / f"{name}.out"), f"{name}:{b_setting if name == 'b' else ''}", log), cost, commit)
    return [Product("a", "first", (root / "a1.out", root / "a2.out"), (part("a1"), part("a2", a2_cost))),
            Product("b", "from a", (root / "b.out", root / "b.commit"), (part("b", fn=b_fn, commit=partial(_commit, root)),),
                    upstream=("a",), settings={"n": b_setting}),
            Product("c", "alone", (root / "c.out",), (part("c"),), kernel=False),
            Product("d", "from b and c", (root / "d.out", root / "d.sum"), (part("d"),), upstream=("b", "c"),
                    finish=partial(_join, root))]


def _run(root: Path, products: list[Product], kernel: str = "kernel-1", executor=None, **kw):
    layout = Layout(root)
    manifest = Manifest(layout.manifest, "test")
    sel = select(products, layout, manifest, kernel, kw.get("only"), kw.get("force", ()))
    out = build(sel, layout, manifest, executor or SerialExecutor(), kw.get("workers", 1), kw.get("threads", 1),
                kw.get("deadline"), log=lambda line: None)
    return sel, out


def _ran(root: Path) -> list[str]:
    """The parts run since the last call (in order)."""
    log = root / "runs.log"
    lines = log.read_text().split() if log.exists() else []
    log.unlink(missing_ok=True)
    return lines


@pytest.fixture
def built(tmp_path):
    sel, out = _run(tmp_path, _graph(tmp_path))
    assert sel.to_build == ["a", "b", "c", "d"] and all(s.state == MISSING for s in sel.states.values())
    assert sorted(out.built) == ["a", "b", "c", "d"] and not out.failed and not out.left
    assert sorted(_ran(tmp_path)) == ["a1", "a2", "b", "c", "d"]
    return tmp_path


def test_from_nothing_everything_is_built_in_order_then_nothing(built):
    assert (built / "b.commit").read_text() == "b:1"                      # the commit ran in the driver
    assert (built / "d.sum").read_text() == "b:1c:"                        # finish after its part, upstream done
    sel, out = _run(built, _graph(built))
    assert sel.to_build == [] and out.built == [] and _ran(built) == []
    assert {n: s.state for n, s in sel.states.items()} == dict.fromkeys("abcd", FRESH)


def test_a_changed_setting_rebuilds_that_product_and_its_dependants_only(built):
    sel, out = _run(built, _graph(built, b_setting=2))
    assert sel.to_build == ["b", "d"]
    assert sel.states["b"].reasons == ["setting n: 1 -> 2"]
    assert sel.states["d"].reasons == ["upstream b changed"]
    assert _ran(built) == ["b", "d"] and (built / "d.sum").read_text() == "b:2c:"


def test_a_new_kernel_spares_what_the_kernel_does_not_make(built):
    sel, _ = _run(built, _graph(built), kernel="kernel-2")
    assert sel.to_build == ["a", "b", "d"] and sel.states["c"].state == FRESH
    assert sel.states["a"].reasons == ["kernel kernel-1 -> kernel-2"]
    assert sorted(_ran(built)) == ["a1", "a2", "b", "d"]


def test_a_deleted_or_edited_file_rebuilds_its_product_alone(built):
    (built / "c.out").unlink()
    (built / "b.out").write_text("edited by hand")
    sel, _ = _run(built, _graph(built))
    assert sel.states["c"].state == MISSING and sel.states["b"].state == STALE
    assert sel.states["b"].reasons == ["its files changed since it was built (by hand?)"]
    assert sel.to_build == ["b", "c"] and sorted(_ran(built)) == ["b", "c"]    # d was made from the same inputs
    assert (built / "b.out").read_text() == "b:1"


def test_force_counts_as_a_change_and_its_dependants_follow(built):
    sel, _ = _run(built, _graph(built), force=["a"])
    assert sel.to_build == ["a", "b", "d"] and sel.states["a"].reasons[0].startswith("forced")
    _ran(built)
    assert _run(built, _graph(built))[0].to_build == []                   # the force is recorded, not repeated


def test_a_force_outlives_a_run_stopped_before_any_part_ends(built):
    """--force NAME then a stop (a deadline already past) before a part of NAME finished: the next
    run without --force still rebuilds NAME and its dependants."""
    past = datetime.now() - timedelta(seconds=1)
    sel, out = _run(built, _graph(built), force=["b"], deadline=past)
    assert out.stopped_for_deadline and _ran(built) == []
    sel, _ = _run(built, _graph(built))
    assert sel.to_build == ["b", "d"] and sel.states["b"].state != FRESH


def test_adopt_records_a_verified_product_fresh_without_building_it_and_refuses_otherwise(built):
    """A definition change (b's settings gain a key) makes b and d stale though their files could
    not change: --adopt runs b's check of its files and records b fresh, builds nothing, and d
    (no check) is refused; a check that finds a difference, or an upstream not fresh, is refused."""
    from agents.regenerate.adopt import AdoptError, adopt

    def graph(problems: list[str]) -> list[Product]:
        g = _graph(built)
        g[1] = dataclasses.replace(g[1], settings={"n": 1, "rule": "new"}, verify=lambda: list(problems))
        return g
    layout, manifest = Layout(built), Manifest(Layout(built).manifest, "test")
    sel = select(graph([]), layout, manifest, "kernel-1")
    assert sel.to_build == ["b", "d"] and sel.states["b"].reasons == ['setting rule: null -> "new"']
    with pytest.raises(AdoptError, match="d has no check of its files"):
        adopt(sel, ["d"], layout, manifest, log=lambda line: None)
    with pytest.raises(AdoptError, match="b: its files are not what today's inputs build: b.out differs"):
        adopt(select(graph(["b.out differs"]), layout, manifest, "kernel-1"), ["b"], layout, manifest,
              log=lambda line: None)
    assert adopt(sel, ["b"], layout, manifest, log=lambda line: None) == ["b"]
    assert manifest.entry("b")["built"].startswith("adopted")
    sel, out = _run(built, graph([]))
    assert sel.states["b"].state == FRESH and sel.to_build == ["d"] and _ran(built) == ["d"]
    # what a check of records cannot see is refused: files edited by hand since their build, a --force
    (built / "b.out").write_text("edited by hand")
    with pytest.raises(AdoptError, match="b: its inputs are today's; it is not fresh because its files changed"):
        adopt(select(graph([]), layout, manifest, "kernel-1"), ["b"], layout, manifest, log=lambda line: None)
    g = graph([])
    g[1] = dataclasses.replace(g[1], settings={"n": 1, "rule": "newest"})
    with pytest.raises(AdoptError, match="files changed since its last build"):
        adopt(select(g, layout, manifest, "kernel-1"), ["b"], layout, manifest, log=lambda line: None)
    (built / "b.out").write_text("b:1")
    # a check that cannot run proves nothing
    bad = dataclasses.replace(g[1], settings={"n": 1, "rule": "other"}, verify=lambda: 1 / 0)
    with pytest.raises(AdoptError, match="its check failed: ZeroDivisionError"):
        adopt(select([g[0], bad, *g[2:]], layout, manifest, "kernel-1"), ["b"], layout, manifest, log=lambda line: None)
    # an upstream that is not fresh: adopt it (or build it) first
    g = graph([])
    g[0] = dataclasses.replace(g[0], settings={"m": 1})
    g[1] = dataclasses.replace(g[1], settings={"n": 1, "rule": "newer"})
    with pytest.raises(AdoptError, match="b: its upstream a is not fresh"):
        adopt(select(g, layout, manifest, "kernel-1"), ["b"], layout, manifest, log=lambda line: None)
    # a --force (a change the hashes do not see) stays until the product is built
    with pytest.raises(AdoptError, match="b is forced"):
        adopt(select(graph([]), layout, manifest, "kernel-1", force=["b"]), ["b"], layout, manifest, log=lambda line: None)


def test_only_builds_a_product_and_what_it_needs(tmp_path):
    sel, out = _run(tmp_path, _graph(tmp_path), only=["b"])
    assert sel.to_build == ["a", "b"] and sorted(out.built) == ["a", "b"]
    with pytest.raises(ValueError, match="no product named 'e'"):
        _run(tmp_path, _graph(tmp_path), only=["e"])


def test_until_starts_no_part_that_cannot_finish_and_a_rerun_keeps_the_parts_done(tmp_path):
    slow = _graph(tmp_path, a2_cost=1e9)         # a2's estimate, even at a1's pace: far past the deadline
    sel, out = _run(tmp_path, slow, deadline=datetime.now() + timedelta(seconds=10))
    assert out.stopped_for_deadline and sorted(_ran(tmp_path)) == ["a1", "c"]
    assert out.built == ["c"] and out.left == ["a", "b", "d"] and not out.failed
    sel, out = _run(tmp_path, slow)
    assert sel.states["a"].state == PARTIAL and sel.states["a"].parts_done == {"a1"}
    assert _ran(tmp_path) == ["a2", "b", "d"] and sorted(out.built) == ["a", "b", "d"]


def test_a_failed_part_stops_its_dependants_and_nothing_else(tmp_path):
    sel, out = _run(tmp_path, _graph(tmp_path, b_fn=_fail))
    assert out.failed == {"b": "RuntimeError: b:1 failed"} and sorted(out.built) == ["a", "c"]
    assert out.left == ["b", "d"]
    _ran(tmp_path)
    sel, out = _run(tmp_path, _graph(tmp_path))
    assert sel.to_build == ["b", "d"] and _ran(tmp_path) == ["b", "d"]


def test_parts_run_in_worker_processes(tmp_path):
    """The same graph on two spawned worker processes (module-level functions, pickled)."""
    executor = make_executor(2, None)
    try:
        sel, out = _run(tmp_path, _graph(tmp_path), executor=executor, workers=2)
    finally:
        executor.shutdown()
    assert sorted(out.built) == ["a", "b", "c", "d"] and (tmp_path / "d.sum").read_text() == "b:1c:"


def test_the_schedule_estimate_shrinks_with_workers_down_to_the_longest_chain(tmp_path):
    layout = Layout(tmp_path)
    sel = select(_graph(tmp_path, a2_cost=10.0), layout, Manifest(layout.manifest, "test"), "k")
    one, two = simulate(sel, 1, 1), simulate(sel, 2, 1)
    assert one == pytest.approx(sel.cost_left())
    assert two < one and two >= 10.0 + 1.0 + 1.0            # a2, then b, then d


# -- the real products ------------------------------------------------------------------------------
def test_the_full_profile_names_the_files_the_checkout_ships_and_the_docs_list_them():
    from agents.paths import checkout_root
    from agents.regenerate import FULL
    from agents.regenerate.product import missing_files
    root = checkout_root()
    if root is None:
        pytest.skip("not a source checkout")
    sel = plan(FULL, root, kernel="0" * 16)[0]
    assert {n: missing_files(p.outputs) for n, p in sel.products.items() if missing_files(p.outputs)} == {}
    doc = (root / "docs" / "regeneration.md").read_text()
    assert [n for n in sel.products if f"| `{n}` |" not in doc] == []
    for name in ("sweep:transient", "planner:field", "board", "chaos:transient"):
        assert len(sel.products[name].parts) > 1                  # spread over workers


# -- the tiny profile, from nothing ---------------------------------------------------------------
def _dependants(sel, name: str) -> set[str]:
    out, grew = {name}, True
    while grew:
        new = {n for n, p in sel.products.items() if set(p.upstream) & out} - out
        out |= new
        grew = bool(new)
    return out


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    root = tmp_path_factory.mktemp("regen")
    lines: list[str] = []
    stopped = regenerate(TINY, root, until=datetime.now() + timedelta(seconds=1), log=lines.append)
    first = regenerate(TINY, root, log=lines.append)
    return root, stopped, first, lines


def test_tiny_until_now_builds_nothing_then_from_nothing_builds_every_product(tiny):
    root, stopped, first, lines = tiny
    sel = plan(TINY, root)[0]
    assert stopped.stopped_for_deadline and stopped.built == [] and stopped.parts_run == 0
    assert sorted(stopped.left) == sorted(sel.products)
    assert not first.failed and sorted(first.built) == sorted(sel.products)
    assert first.parts_run == sum(len(p.parts) for p in sel.products.values())
    for p in sel.products.values():
        assert all(f.exists() for f in p.outputs), p.name
    results = json.loads((root / "docs" / "results.json").read_text())
    assert results["mode"] == "tiny" and "planner (true simulator, the episode's future)" in results["tiers"]["transient"]["policies"]
    assert any("part seed_300001" in line and "done" in line for line in lines)     # progress lines


def test_tiny_second_call_builds_nothing(tiny):
    root = tiny[0]
    before = (root / "agents" / "data" / "regeneration.json").read_bytes()
    sel = plan(TINY, root)[0]
    assert sel.to_build == [] and {s.state for s in sel.states.values()} == {FRESH}
    assert regenerate(TINY, root, log=lambda line: None).built == []
    assert (root / "agents" / "data" / "regeneration.json").read_bytes() == before


def test_tiny_a_new_kernel_makes_everything_stale_and_says_why(tiny):
    sel = plan(TINY, tiny[0], kernel="0" * 16)[0]
    assert sorted(sel.to_build) == sorted(sel.products)
    assert sel.states["reward_map"].reasons[0].startswith("kernel ") and sel.states["reward_map"].reasons[0].endswith(" -> " + "0" * 16)
    assert sel.states["oracle_table"].reasons == ["upstream reward_map changed"]      # made from the map, not the kernel


def test_tiny_a_changed_setting_rebuilds_exactly_what_depends_on_it(tiny, tmp_path):
    root = tmp_path / "copy"
    shutil.copytree(tiny[0], root)
    changed = dataclasses.replace(TINY, stability_table={**TINY.stability_table, "preloads": (800.0, 700.0)})
    sel = plan(changed, root)[0]
    want = _dependants(sel, "stability_table")
    assert 1 < len(want) < len(sel.products)
    assert set(sel.to_build) == want
    assert sel.states["stability_table"].reasons == ["setting grid.preloads: [800.0, 600.0] -> [800.0, 700.0]"]
    before = json.loads((root / "agents" / "data" / "regeneration.json").read_text())["products"]
    out = regenerate(changed, root, log=lambda line: None)
    assert set(out.built) == want and not out.failed
    after = json.loads((root / "agents" / "data" / "regeneration.json").read_text())["products"]
    assert {n for n in after if after[n] != before[n]} == want
    assert plan(changed, root)[0].to_build == []


def test_tiny_status_from_the_command_line(tiny, capsys):
    assert main(["--profile", "tiny", "--root", str(tiny[0]), "--status"]) == 0
    out = capsys.readouterr().out
    assert "board" in out and f"{len(plan(TINY, tiny[0])[0].products)} fresh" in out
    with pytest.raises(SystemExit):
        main(["--profile", "tiny", "--status"])                # tiny would overwrite the committed data


@pytest.mark.slow
def test_tiny_on_worker_processes_gives_the_same_numbers(tiny, tmp_path):
    out = regenerate(TINY, tmp_path, processes=2, log=lambda line: None)
    assert not out.failed and not out.left
    for name in ("agents/data/test_references_transient.json", "docs/reward_map.csv", "agents/data/oracle_table.csv"):
        a, b = (r / name for r in (tiny[0], tmp_path))
        if a.suffix == ".json":
            a, b = json.loads(a.read_text()), json.loads(b.read_text())
            a.pop("planner_wall_s_per_episode"), b.pop("planner_wall_s_per_episode")
            assert a == b
        else:
            assert a.read_bytes() == b.read_bytes()


@pytest.mark.slow
def test_tiny_on_ray(tmp_path):
    pytest.importorskip("ray")
    out = regenerate(TINY, tmp_path, only=["oracle_table", "start_bank"], processes=2, ray="local",
                     log=lambda line: None)
    assert sorted(out.built) == ["oracle_table", "reward_map", "start_bank"] and not out.failed


def test_protocol_2s_board_reads_the_v2_runs_and_their_early_rows(tmp_path, monkeypatch):
    """trained_runs(2): every agents/trained_v2/<algo>/seed_<s> and, where collected, its
    by_<V2_EARLY_ROW_STEPS> early row; protocol 1 keeps agents/trained/."""
    from agents import protocol as P
    from agents.regenerate import profiles
    root = tmp_path / "agents"
    early = f"by_{P.V2_EARLY_ROW_STEPS}"
    for d in (f"trained_v2/sac/seed_0/{early}", "trained_v2/sac/seed_1000", "trained/ppo/seed_0"):
        (root / d).mkdir(parents=True)
    monkeypatch.setattr(profiles, "PACKAGE_DIR", root)
    monkeypatch.setattr(profiles, "TRAINED_DIR", root / "trained")
    monkeypatch.setattr(profiles, "TRAINED_V2_DIR", root / "trained_v2")
    assert profiles.trained_runs(2) == ("agents/trained_v2/sac/seed_0", f"agents/trained_v2/sac/seed_0/{early}",
                                        "agents/trained_v2/sac/seed_1000")
    assert profiles.trained_runs(1) == ("agents/trained/ppo/seed_0",)
