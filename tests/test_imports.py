"""Imports point one way: no module imports itself back, and the packages keep the
layering of DESIGN.md (models <- formations, skills <- agent <- server/optimization).

The graph is read from the source with `ast`, so nothing is imported: every
``import`` and ``from ... import`` counts, at module level, inside functions and
under ``if TYPE_CHECKING:`` alike (an import inside a function that closes a cycle
is still a cycle, only a later one). Edges go to the module named: ``from a.b
import c`` is an edge to ``a.b.c`` when that is a module, else to ``a.b``; a
package's ``__init__`` is not counted as imported by its submodules' importers.
"""

from __future__ import annotations

import ast
from collections.abc import Mapping
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("models", "formations", "skills", "agent", "server", "optimization", "replay", "cli")

# package -> the other project packages it may import (DESIGN.md, "The packages"); None: any.
ALLOWED: dict[str, frozenset[str] | None] = {
    "models": frozenset(),
    "formations": frozenset(),
    "skills": frozenset({"models"}),
    "agent": frozenset({"models", "skills", "formations"}),
    "server": frozenset({"models"}),
    "optimization": frozenset({"server", "agent", "skills", "models", "formations"}),
    "replay": None,
    "cli": None,
}


def module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def project_modules(root: Path = ROOT) -> dict[str, Path]:
    """Every module of the project's packages by dotted name."""
    out = {}
    for pkg in PACKAGES:
        for path in sorted((root / pkg).rglob("*.py")):
            out[module_name(path, root)] = path
    return out


def _resolve(name: str, modules: Mapping[str, Path]) -> str | None:
    """The project module `name` denotes: itself, or its longest prefix that is one."""
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        candidate = ".".join(parts[:k])
        if candidate in modules:
            return candidate
    return None


def imports_of(module: str, source: str, modules: Mapping[str, Path]) -> dict[str, int]:
    """The project modules `module` imports (anywhere in its source), with a line of each."""
    is_package = modules[module].name == "__init__.py"
    out: dict[str, int] = {}
    for node in ast.walk(ast.parse(source)):
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:  # relative: from the module's own package
                pkg = module.split(".") if is_package else module.split(".")[:-1]
                pkg = pkg[:len(pkg) - (node.level - 1)]
                base = ".".join([*pkg, base] if base else pkg)
            targets = [f"{base}.{a.name}" if base else a.name for a in node.names]
        for t in targets:
            m = _resolve(t, modules)
            if m is not None and m != module:
                out.setdefault(m, node.lineno)
    return out


def import_graph(root: Path = ROOT) -> dict[str, dict[str, int]]:
    """module -> {imported project module: line}."""
    modules = project_modules(root)
    return {m: imports_of(m, p.read_text(encoding="utf-8"), modules) for m, p in modules.items()}


def find_cycles(graph: Mapping[str, Mapping[str, int]]) -> list[list[str]]:
    """One cycle (``[a, b, ..., a]``) per strongly connected component that has one
    (Tarjan's algorithm, iterative); `components` gives the components themselves."""
    return [_cycle_in(graph, set(c)) for c in components(graph)]


def components(graph: Mapping[str, Mapping[str, int]]) -> list[list[str]]:
    """The strongly connected components of more than one module, each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    counter = 0
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            v, it = work[-1]
            for w in it:
                if w not in graph:
                    continue
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    if len(comp) > 1:
                        found.append(sorted(comp))
    return found


def _cycle_in(graph: Mapping[str, Mapping[str, int]], comp: set[str]) -> list[str]:
    """A shortest cycle through the component's first module (breadth-first)."""
    start = min(comp)
    parent: dict[str, str] = {}
    frontier = [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(graph[v]):
                if w not in comp:
                    continue
                if w == start:
                    path = [v]
                    while path[-1] != start:
                        path.append(parent[path[-1]])
                    return [start, *reversed(path[:-1]), start] if v != start else [start, start]
                if w not in parent:
                    parent[w] = v
                    nxt.append(w)
        frontier = nxt
    raise AssertionError(f"no cycle in component {sorted(comp)}")


def describe(cycle: list[str], graph: Mapping[str, Mapping[str, int]]) -> str:
    return " -> ".join(f"{a} (line {graph[a][b]})" for a, b in zip(cycle, cycle[1:])) + f" -> {cycle[-1]}"


def layering_violations(graph: Mapping[str, Mapping[str, int]]) -> list[str]:
    out = []
    for m, targets in sorted(graph.items()):
        pkg = m.split(".")[0]
        allowed = ALLOWED[pkg]
        if allowed is None:
            continue
        for t, line in sorted(targets.items()):
            other = t.split(".")[0]
            if other != pkg and other not in allowed:
                out.append(f"{m} (line {line}) imports {t}: {pkg} may import "
                           f"{', '.join(sorted(allowed)) or 'no other project package'}")
    return out


def test_no_import_cycles():
    graph = import_graph()
    found = components(graph)
    assert not found, "import cycles:\n" + "\n".join(
        f"{describe(_cycle_in(graph, set(c)), graph)}\n  (modules on cycles together: {', '.join(c)})"
        for c in found)


def test_package_layering():
    violations = layering_violations(import_graph())
    assert not violations, "imports against DESIGN.md's layering:\n" + "\n".join(violations)


def test_the_graph_sees_every_kind_of_import(tmp_path):
    """A cycle closed by an import inside a function, a relative one and one under
    TYPE_CHECKING are all found, and named."""
    pkg = tmp_path / "skills"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("import skills.b\n")
    (pkg / "b.py").write_text("def f():\n    from skills.c import g\n")
    (pkg / "c.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from . import a\n")
    (pkg / "d.py").write_text("from skills import a\n")
    modules = {module_name(p, tmp_path): p for p in sorted(pkg.rglob("*.py"))}
    graph = {m: imports_of(m, p.read_text(), modules) for m, p in modules.items()}
    assert graph["skills.d"] == {"skills.a": 1}
    cycles = find_cycles(graph)
    assert cycles == [["skills.a", "skills.b", "skills.c", "skills.a"]]
    assert describe(cycles[0], graph) == ("skills.a (line 1) -> skills.b (line 2) -> "
                                          "skills.c (line 3) -> skills.a")


def test_layering_names_the_import():
    graph = {"skills.x": {"agent.kicker": 7}, "agent.kicker": {}, "cli.main": {"skills.x": 1}}
    assert layering_violations(graph) == [
        "skills.x (line 7) imports agent.kicker: skills may import models"]
