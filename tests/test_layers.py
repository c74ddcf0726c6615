"""The package's import contract: layers in one order, no upward import, no cycle, deferred imports included.

Every ``import`` statement in ``crosscheck/`` is read with ``ast``, wherever it sits: at module level, inside a
function, under ``if TYPE_CHECKING:`` or in a ``try``.  A deferred import hides a cycle from the interpreter; it
does not remove it, so this test counts it like any other.

Layers, lowest first (a module may import its own layer and the ones below):

- ``core``: the modules at the top of the package (``crosscheck/<name>.py``: ``rod``, ``state``, ``checks``,
  ``files``, ``tolerances``, ...), standard library and numpy only.  ``crosscheck/__main__.py`` is the command line
  (``cli``), and the package's ``__init__`` re-exports core and theory, so it sits at ``theory``.
- ``theory``: ``crosscheck/theory/``, the paper.
- ``engines``: ``crosscheck/engines/`` (the registry, ``base``, the classifier, each engine's subpackage), except
  an engine's own ``studies/`` (layer ``studies``) and ``sections/`` (layer ``report``).
- ``sweeps``: ``crosscheck/sweeps/``.
- ``studies``: ``crosscheck/studies/`` and every ``crosscheck/engines/<name>/studies/``.
- ``report``: ``crosscheck/report/`` and every ``crosscheck/engines/<name>/sections/``.
- ``cli``: ``crosscheck/cli/`` and ``crosscheck/__main__.py``.

An edge is the module an import names: ``from crosscheck.engines import base`` is an edge to
``crosscheck.engines.base`` (a submodule), ``from crosscheck.engines import get`` an edge to the package
``crosscheck.engines``.  The parent packages Python runs on the way are not edges of their own: they are the
importer's choice of path, and every ``__init__`` is itself scanned.  A reference by name (``"module:attr"``, as an
``EngineSpec`` names its engine module, its checks, its report sections, its ladder's rungs and its interventions) is
not an import: the layer that resolves it imports it, so an engine declares its own studies and sections without
reaching up to them.

Run ``python tests/test_layers.py`` for the counts and the list of cycles and upward imports.
"""

from __future__ import annotations

import ast
import sys
from collections import defaultdict
from pathlib import Path

PACKAGE = "crosscheck"
ROOT = Path(__file__).resolve().parent.parent / PACKAGE
LAYERS = ("core", "theory", "engines", "sweeps", "studies", "report", "cli")


def modules(root: Path = ROOT) -> dict[str, Path]:
    """Dotted module name -> source file, for every ``.py`` under ``root`` (a package's name for its ``__init__``)."""
    found = {}
    for path in sorted(root.rglob("*.py")):
        parts = (PACKAGE, *path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


def layer(module: str) -> str:
    """The layer ``module`` belongs to (see the module docstring)."""
    parts = module.split(".")[1:]
    if not parts:
        return "theory"
    if len(parts) == 1 and parts[0] != "__main__" and parts[0] not in LAYERS + ("theory",):
        return "core"
    head = parts[0]
    if head == "__main__":
        return "cli"
    if head == "engines":
        # crosscheck.engines.<name>.studies / .sections sit with the studies and the report
        if len(parts) >= 3 and parts[2] == "studies":
            return "studies"
        if len(parts) >= 3 and parts[2] == "sections":
            return "report"
        return "engines"
    if head in LAYERS:
        return head
    raise ValueError(f"module {module} is in no layer; add its package to tests/test_layers.py")


def _is_package(path: Path) -> bool:
    return path.name == "__init__.py"


def imports(module: str, path: Path, known: dict[str, Path]) -> list[tuple[str, int]]:
    """``(imported module, line)`` for every import of a crosscheck module in ``path``, at any depth."""
    tree = ast.parse(path.read_text(), filename=str(path))
    package = module if _is_package(path) else module.rpartition(".")[0]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == PACKAGE:
                    found.append((_known_prefix(alias.name, known), node.lineno))
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != PACKAGE:
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                found.append((sub if sub in known else _known_prefix(target, known), node.lineno))
    return found


def _known_prefix(name: str, known: dict[str, Path]) -> str:
    while name not in known and "." in name:
        name = name.rpartition(".")[0]
    return name


def graph(root: Path = ROOT) -> dict[str, dict[str, int]]:
    """Importer -> {imported: first line}, self-imports dropped."""
    known = modules(root)
    edges: dict[str, dict[str, int]] = defaultdict(dict)
    for module, path in known.items():
        edges[module]
        for target, line in imports(module, path, known):
            if target != module:
                edges[module].setdefault(target, line)
    return dict(edges)


def upward(edges: dict[str, dict[str, int]]) -> list[str]:
    """One line per import that goes up a layer: ``importer:line -> imported (layer -> layer)``."""
    rank = {name: i for i, name in enumerate(LAYERS)}
    out = []
    for module, targets in sorted(edges.items()):
        for target, line in sorted(targets.items()):
            if rank[layer(target)] > rank[layer(module)]:
                out.append(f"{module}:{line} -> {target} ({layer(module)} -> {layer(target)})")
    return out


def cycles(edges: dict[str, dict[str, int]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan), each sorted; every import cycle lies
    inside one of them."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in edges.get(v, {}):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 10_000))
    try:
        for v in sorted(edges):
            if v not in index:
                visit(v)
    finally:
        sys.setrecursionlimit(limit)
    return sorted(found)


def cycle_through(component: list[str], edges: dict[str, dict[str, int]]) -> list[str]:
    """One shortest cycle inside ``component`` (for the message), as ``a:line -> b:line -> ... -> a``."""
    members = set(component)
    start = component[0]
    # breadth-first search from start back to start, inside the component
    paths = {start: [start]}
    frontier = [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(edges.get(v, {})):
                if w not in members:
                    continue
                if w == start:
                    path = paths[v] + [start]
                    return [f"{a}:{edges[a][b]}" for a, b in zip(path, path[1:])] + [start]
                if w not in paths:
                    paths[w] = paths[v] + [w]
                    nxt.append(w)
        frontier = nxt
    return component


def test_every_module_has_a_layer():
    for module in modules():
        assert layer(module) in LAYERS


def test_the_scanner_sees_deferred_imports(tmp_path):
    """A cycle made only of an import inside a function, and an upward import under ``if TYPE_CHECKING``, are found."""
    pkg = tmp_path / PACKAGE
    (pkg / "theory").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "theory" / "__init__.py").write_text("")
    (pkg / "rod.py").write_text("def f():\n    from crosscheck.files import g\n")
    (pkg / "files.py").write_text("from crosscheck import rod\nif TYPE_CHECKING:\n    from .theory import paper\n")
    (pkg / "checks.py").write_text("")
    (pkg / "theory" / "paper.py").write_text("from .. import checks\n")
    edges = graph(pkg)
    assert edges["crosscheck.rod"] == {"crosscheck.files": 2}
    assert edges["crosscheck.files"] == {"crosscheck.rod": 1, "crosscheck.theory.paper": 3}
    assert edges["crosscheck.theory.paper"] == {"crosscheck.checks": 1}
    assert cycles(edges) == [["crosscheck.files", "crosscheck.rod"]]
    assert upward(edges) == ["crosscheck.files:3 -> crosscheck.theory.paper (core -> theory)"]


def test_no_upward_import():
    found = upward(graph())
    assert not found, "imports that go up a layer:\n" + "\n".join(found)


def test_no_import_cycle():
    edges = graph()
    found = cycles(edges)
    assert not found, "import cycles (deferred imports included):\n" + "\n".join(
        " -> ".join(cycle_through(c, edges)) for c in found
    )


if __name__ == "__main__":
    edges = graph()
    found = cycles(edges)
    ups = upward(edges)
    n_edges = sum(len(t) for t in edges.values())
    print(f"{len(edges)} modules, {n_edges} import edges")
    print(f"{len(found)} import cycles (strongly connected components):")
    for c in found:
        print(f"  [{len(c)} modules] " + " -> ".join(cycle_through(c, edges)))
    print(f"{len(ups)} upward imports:")
    for line in ups:
        print("  " + line)
