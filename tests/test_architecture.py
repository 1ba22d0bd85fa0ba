"""The import graph of bearing_gym points down and has no cycle.

Layers, lowest first (a module may import its own layer and those below):

    validation, units, serialization, task (and the numba cache set-up)
    < params (and the package's __init__)
    < physics < analysis < envs < engineering < reproduction < cli (and ``python -m bearing_gym``)

Nothing in bearing_gym imports ``agents``, ``train`` or ``benchmarks``, which sit above it.

``agents`` (the ``rl`` extra) has layers of its own, lowest first:

    paths, protocol, extras, clock < policies < evaluation < references < leaderboard (and the
    ``agents.evaluate`` alias) < training < regenerate < the package's __init__

and may import any of bearing_gym, never ``train`` or ``benchmarks``.
Every import statement counts, at module level or inside a function (a deferred import is
still a dependency). Read with the standard library's ``ast``: nothing is imported to check.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "bearing_gym"
AGENTS = ROOT / "agents"

LAYERS = (
    ("base", ("bearing_gym._numba_cache", "bearing_gym.validation", "bearing_gym.units",
              "bearing_gym.serialization", "bearing_gym.task")),
    ("params", ("bearing_gym.params", "bearing_gym")),
    ("physics", ("bearing_gym.physics",)),
    ("analysis", ("bearing_gym.analysis",)),
    ("envs", ("bearing_gym.envs",)),
    ("engineering", ("bearing_gym.engineering",)),
    ("reproduction", ("bearing_gym.reproduction",)),
    ("cli", ("bearing_gym.cli", "bearing_gym.__main__")),
)
OUTSIDE = ("agents", "train", "benchmarks")
AGENT_LAYERS = (
    ("base", ("agents.paths", "agents.protocol", "agents.extras", "agents.clock")),
    ("policies", ("agents.policies",)),
    ("evaluation", ("agents.evaluation",)),
    ("references", ("agents.references",)),
    ("leaderboard", ("agents.leaderboard", "agents.evaluate")),
    ("submit", ("agents.submit",)),
    ("training", ("agents.training",)),
    ("regenerate", ("agents.regenerate",)),
    ("api", ("agents",)),
)
#: a package of more modules than this is a flat room that wants subpackages
MAX_MODULES_PER_PACKAGE = 20


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}
AGENT_MODULES = {_module_name(p): p for p in sorted(AGENTS.rglob("*.py"))}


def _layer(module: str, layers=LAYERS) -> int:
    """Index of the layer of ``module``: the longest matching prefix decides."""
    best, rank = -1, None
    for k, (_, prefixes) in enumerate(layers):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > best:
                best, rank = len(prefix), k
    if rank is None:
        raise AssertionError(f"{module} is in no layer; add it to LAYERS")
    return rank


def _resolve(name: str, modules=MODULES) -> str:
    """The module of ``modules`` an imported name lives in (a submodule if one exists)."""
    while name and name not in modules:
        name = name.rpartition(".")[0]
    return name


def _imports(module: str, path: Path) -> set[str]:
    """Every module named by an import statement in ``path``."""
    is_pkg = path.name == "__init__.py"
    package = module if is_pkg else module.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - (node.level - 1)]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module
            out.add(stem)
            out.update(f"{stem}.{a.name}" for a in node.names)
    return out


def _graph() -> dict[str, set[str]]:
    graph = {}
    for module, path in MODULES.items():
        deps = set()
        for name in _imports(module, path):
            if name.split(".")[0] in OUTSIDE:
                deps.add(name)
            elif name == "bearing_gym" or name.startswith("bearing_gym."):
                target = _resolve(name)
                if target and target != module:
                    deps.add(target)
        graph[module] = deps
    return graph


GRAPH = _graph()


def _agent_graph() -> dict[str, set[str]]:
    graph = {}
    for module, path in AGENT_MODULES.items():
        deps = set()
        for name in _imports(module, path):
            top = name.split(".")[0]
            if top in ("train", "benchmarks"):
                deps.add(name)
            elif top == "agents" and name != "agents":     # `from agents import x`: x decides
                target = _resolve(name, AGENT_MODULES)
                if target and target != module:
                    deps.add(target)
        graph[module] = deps
    return graph


AGENT_GRAPH = _agent_graph()


def test_every_module_has_a_layer():
    for module in MODULES:
        _layer(module)


def test_nothing_in_bearing_gym_imports_the_agents_train_or_benchmarks():
    bad = {m: sorted(d for d in deps if d.split(".")[0] in OUTSIDE) for m, deps in GRAPH.items()}
    assert {m: d for m, d in bad.items() if d} == {}


def test_no_import_points_up_a_layer():
    upward = []
    for module, deps in GRAPH.items():
        for dep in deps:
            if dep.split(".")[0] in OUTSIDE:
                continue
            if _layer(dep) > _layer(module):
                upward.append(f"{module} ({LAYERS[_layer(module)][0]}) imports {dep} "
                              f"({LAYERS[_layer(dep)][0]})")
    assert upward == []


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_import_cycle_between_modules():
    assert _cycles(GRAPH) == []


@pytest.mark.parametrize("graph, cycles", [
    ({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}, [["a", "b", "c"]]),
    ({"a": {"b"}, "b": set()}, []),
])
def test_the_cycle_finder_finds_cycles(graph, cycles):
    assert _cycles(graph) == cycles


def test_the_checks_see_a_deferred_upward_import(tmp_path):
    """An import inside a function is found (the params -> physics import this test guards
    against was one)."""
    src = tmp_path / "m.py"
    src.write_text("def f():\n    from bearing_gym.physics.layout import pack_params\n")
    assert "bearing_gym.physics.layout" in _imports("bearing_gym.params", src)
    assert _layer("bearing_gym.physics.layout") > _layer("bearing_gym.params")


def test_every_agents_module_has_a_layer():
    for module in AGENT_MODULES:
        _layer(module, AGENT_LAYERS)


def test_agents_import_neither_train_nor_benchmarks():
    bad = {m: sorted(d for d in deps if d.split(".")[0] in ("train", "benchmarks")) for m, deps in AGENT_GRAPH.items()}
    assert {m: d for m, d in bad.items() if d} == {}


def test_no_import_in_agents_points_up_a_layer():
    upward = [f"{m} ({AGENT_LAYERS[_layer(m, AGENT_LAYERS)][0]}) imports {d} ({AGENT_LAYERS[_layer(d, AGENT_LAYERS)][0]})"
              for m, deps in AGENT_GRAPH.items() for d in deps
              if d.startswith("agents") and _layer(d, AGENT_LAYERS) > _layer(m, AGENT_LAYERS)]
    assert upward == []


def test_no_import_cycle_in_agents():
    assert _cycles(AGENT_GRAPH) == []


def test_the_agents_layering_sees_an_upward_import(tmp_path):
    """A policy importing the leaderboard would be found (the contextual constant once imported
    the evaluation loop to fit itself)."""
    src = tmp_path / "m.py"
    src.write_text("def fit():\n    from agents.leaderboard.scoring import iqm\n")
    assert "agents.leaderboard.scoring" in _imports("agents.policies.contextual", src)
    assert _layer("agents.leaderboard.scoring", AGENT_LAYERS) > _layer("agents.policies.contextual", AGENT_LAYERS)


@pytest.mark.parametrize("root", [PACKAGE, AGENTS])
def test_no_package_is_a_flat_room_of_more_than_twenty_modules(root):
    crowded = {str(d.relative_to(ROOT)): n for d in [root, *root.rglob("*")] if d.is_dir()
               and (n := len([p for p in d.glob("*.py") if p.name not in ("__init__.py", "__main__.py")])) > MAX_MODULES_PER_PACKAGE}
    assert crowded == {}
