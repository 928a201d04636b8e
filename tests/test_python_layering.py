"""No circle of Python files in ``python/rustfrac``: the module-level imports (those under
``if TYPE_CHECKING:`` included; imports inside functions are deferred and not counted) of the
package's modules form no cycle. The core's twin is ``src/layering_test.rs``."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "python" / "rustfrac"


def _module(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _top_level(body: list[ast.stmt]) -> list[ast.stmt]:
    """The statements run at import: the body, and the bodies of its ``if`` and ``try`` blocks."""
    out: list[ast.stmt] = []
    for s in body:
        out.append(s)
        if isinstance(s, ast.If):
            out += _top_level(s.body) + _top_level(s.orelse)
        elif isinstance(s, ast.Try):
            out += _top_level(s.body) + _top_level(s.orelse) + _top_level(s.finalbody)
            for h in s.handlers:
                out += _top_level(h.body)
    return out


def imports(source: str, module: str, is_package: bool, known: set[str]) -> set[str]:
    """The modules of ``known`` that ``source`` (the text of ``module``) imports at module level."""
    package = module if is_package else module.rpartition(".")[0]
    out: set[str] = set()
    for s in _top_level(ast.parse(source).body):
        if isinstance(s, ast.ImportFrom):
            base = package
            for _ in range(max(s.level - 1, 0)):
                base = base.rpartition(".")[0]
            target = (f"{base}.{s.module}" if s.module else base) if s.level else s.module or ""
            names = [f"{target}.{a.name}" for a in s.names]
            hits = [n for n in names if n in known]
            out.update(hits or ([target] if target in known else []))
        elif isinstance(s, ast.Import):
            out.update(a.name for a in s.names if a.name in known)
    out.discard(module)
    return out


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every cycle found by a depth-first search, each as the list of its modules."""
    found, state = [], {}

    def visit(n: str, path: list[str]) -> None:
        state[n] = 1
        path.append(n)
        for m in sorted(graph.get(n, ())):
            if state.get(m) == 1:
                found.append([*path[path.index(m) :], m])
            elif m not in state:
                visit(m, path)
        path.pop()
        state[n] = 2

    for n in sorted(graph):
        if n not in state:
            visit(n, [])
    return found


def package_graph() -> dict[str, set[str]]:
    files = sorted(PACKAGE.rglob("*.py"))
    known = {_module(p) for p in files}
    graph = {}
    for p in files:
        m = _module(p)
        if p.name == "__init__.py" and m == PACKAGE.name:
            continue  # the package's front door re-exports its modules; nothing imports it back
        graph[m] = imports(p.read_text(encoding="utf-8"), m, p.name == "__init__.py", known)
        graph[m].discard(PACKAGE.name)
    return graph


def test_no_circle_of_python_files() -> None:
    graph = package_graph()
    # the reader sees the imports it must (it cannot pass by reading nothing)
    assert "rustfrac._vtk" in graph["rustfrac.result"]
    assert "rustfrac.study" in graph["rustfrac.fig7"]
    found = circles(graph)
    assert not found, "circles of Python files:\n" + "\n".join(" -> ".join(c) for c in found)


def test_the_reader_finds_a_planted_circle() -> None:
    known = {"p", "p.a", "p.b"}
    g = {
        "p.a": imports("from .b import x\n", "p.a", False, known),
        "p.b": imports(
            "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from . import a\n",
            "p.b",
            False,
            known,
        ),
    }
    assert g == {"p.a": {"p.b"}, "p.b": {"p.a"}}
    assert circles(g) == [["p.a", "p.b", "p.a"]]
    # an import inside a function is deferred: no edge
    assert imports("def f():\n    from .a import y\n", "p.b", False, known) == set()
