"""The package's layout (docs/layout.md): no import circle between its modules, few modules loose
at the top, short modules and short functions. The imports are read from the source (an AST
walk), each import statement wherever it stands: a lazy import inside a function is an edge, and
so is one under `if TYPE_CHECKING:` (a type named across two modules ties them as much as a call)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "upliftcli"


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules() -> dict[str, Path]:
    return {module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}


def _targets(node: ast.AST, name: str, is_package: bool, known: dict[str, Path]) -> list[str]:
    """The modules of the package that one import statement of module `name` loads by name."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names if alias.name in known]
    if node.level:
        base = name.split(".")
        base = base[:len(base) - node.level + (1 if is_package else 0)]
        source = ".".join(base + ([node.module] if node.module else []))
    else:
        source = node.module or ""
    found = [f"{source}.{alias.name}" for alias in node.names if f"{source}.{alias.name}" in known]
    if len(found) < len(node.names) and source in known:
        found.append(source)
    return found


def import_graph() -> dict[str, set[str]]:
    """module -> the modules of the package it imports."""
    known = modules()
    graph: dict[str, set[str]] = {}
    for name, path in known.items():
        tree = ast.parse(path.read_text(), str(path))
        edges = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Import | ast.ImportFrom):
                edges.update(_targets(node, name, path.name == "__init__.py", known))
        graph[name] = edges - {name}
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for other in sorted(graph[node]):
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def test_the_circle_finder_finds_a_circle_and_passes_a_tree():
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert circles({"a": {"b", "c"}, "b": {"c"}, "c": set()}) == []


def test_the_import_graph_sees_relative_lazy_and_module_imports():
    graph = import_graph()
    assert "upliftcli.errors" in graph["upliftcli.deck.load"]  # from ..errors import InputError
    assert "upliftcli.deck.schema" in graph["upliftcli.deck.load"]  # from . import schema
    assert len(graph) > 100


def test_no_import_circle():
    found = circles(import_graph())
    assert not found, "import circles: " + "; ".join(" <-> ".join(c) for c in found)


#: the layers of docs/layout.md: a module imports only from its own layer and the layers before it
LAYERS = {"errors": 1, "units": 1, "display": 1, "runtime": 1, "deck.fields": 1, "deck.choices": 1,
          "provenance.values": 1, "model": 2, "motion": 2, "engines": 3, "deck": 4, "analysis": 5,
          "provenance": 5, "output": 5, "histories": 5, "figures": 6, "report": 6, "sweep": 6, "api": 7, "cli": 7,
          "__main__": 7, "": 7}


def layer(module: str) -> int:
    """The layer of a module of the package: of its own entry (deck.fields), else of its folder."""
    parts = module.split(".")[1:]
    return LAYERS.get(".".join(parts[:2]), LAYERS[parts[0] if parts else ""])


def test_each_module_imports_only_from_its_layer_and_those_before():
    upward = sorted(f"{a} -> {b}" for a, targets in import_graph().items() for b in targets if layer(b) > layer(a))
    assert not upward, upward


def test_few_modules_loose_at_the_top():
    loose = [path.name for path in PACKAGE.glob("*.py") if path.name not in ("__init__.py", "__main__.py")]
    assert len(loose) <= 12, loose


def test_no_long_module():
    """No Python module over 400 lines (docs/layout.md)."""
    long = {name: n for name, path in modules().items() if (n := len(path.read_text().splitlines())) > 400}
    assert not long, long


def test_short_functions():
    """Mean cyclomatic complexity (radon, over functions, methods and classes) at most 3.0, and no
    function above 20."""
    radon = pytest.importorskip("radon.complexity")
    blocks = []
    for path in modules().values():
        blocks += radon.cc_visit(path.read_text())
    # cc_visit lists every function, class and method once, as `radon cc -a` averages them
    mean = sum(block.complexity for block in blocks) / len(blocks)
    worst = sorted(((block.complexity, block.name) for block in blocks), reverse=True)[:5]
    assert mean <= 3.0, f"mean cyclomatic complexity {mean:.3f}; the most complex: {worst}"
    assert worst[0][0] <= 20, worst
