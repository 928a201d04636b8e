"""The result schema the core owns (``_core.result_schema()``): every result key Python reads
by name is an entry of it, ``rf.run`` returns exactly its entries, and statuses are exported.

The core checks every record its runs emit against the same table
(``crates/rustfrac-core/src/output/tests.rs``); here the Python side: a key renamed in the core
fails :func:`test_every_result_key_python_reads_is_in_the_schema`."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from rustfrac.result import result_entry

PACKAGE = Path(rf.__file__).parent
GROUPS = ("fields", "history", "scalars", "meta")


def _group_of(node: ast.AST, aliases: dict[str, str]) -> str | None:
    """The result group an expression is (``res.fields``, ``self.meta``, or a name assigned
    one of them), else None."""
    if isinstance(node, ast.Attribute) and node.attr in GROUPS:
        return node.attr
    if isinstance(node, ast.Name):
        return aliases.get(node.id)
    return None


def _key(node: ast.AST) -> str | None:
    return node.value if isinstance(node, ast.Constant) and isinstance(node.value, str) else None


def _reads(tree: ast.AST, aliases: dict[str, str]) -> list[tuple[str, str, int]]:
    """(group, key, line) of every result key read by a string literal in ``tree``:
    ``g["k"]``, ``g.get("k")``, ``"k" in g`` and a nested table's ``g["t"]["k"]`` /
    ``g.get("t", {}).get("k")``."""
    out: list[tuple[str, str, int]] = []

    def base(node: ast.AST) -> tuple[str, str] | None:
        """(group, key) when ``node`` reads a literal key of a group (to nest one more key)."""
        if isinstance(node, ast.Subscript):
            g, k = _group_of(node.value, aliases), _key(node.slice)
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            if node.func.attr not in ("get", "setdefault", "pop") or not node.args:
                return None
            g, k = _group_of(node.func.value, aliases), _key(node.args[0])
        else:
            return None
        if g is None or k is None:
            inner = base(node.value if isinstance(node, ast.Subscript) else node.func.value)  # type: ignore[attr-defined]
            if inner is None:
                return None
            k2 = _key(node.slice) if isinstance(node, ast.Subscript) else _key(node.args[0])  # type: ignore[attr-defined]
            return None if k2 is None else (inner[0], f"{inner[1]}.{k2}")
        return g, k

    for node in ast.walk(tree):
        if isinstance(node, (ast.Subscript, ast.Call)):
            gk = base(node)
            if gk is not None:
                out.append((*gk, node.lineno))
        elif isinstance(node, ast.Compare) and isinstance(node.ops[0], (ast.In, ast.NotIn)):
            g, k = _group_of(node.comparators[0], aliases), _key(node.left)
            if g is not None and k is not None:
                out.append((g, k, node.lineno))
    return out


def _aliases(tree: ast.AST) -> dict[str, str]:
    """Names assigned a result group in ``tree`` (``f = res.fields``)."""
    out: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and len(node.targets) == 1:
            t, g = node.targets[0], _group_of(node.value, {})
            if isinstance(t, ast.Name) and g is not None:
                out[t.id] = g
    return out


def _literal_reads() -> list[tuple[str, str, str, int]]:
    """(module, group, key, line) of every literal result key the package's modules read."""
    out = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        scopes = [tree, *(n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef))]
        seen = set()
        for scope in scopes:
            for g, k, line in _reads(scope, _aliases(scope)):
                if (g, k, line) not in seen:
                    seen.add((g, k, line))
                    out.append((path.relative_to(PACKAGE).as_posix(), g, k, line))
    return out


def _known(group: str, key: str) -> bool:
    """Whether the schema has the key; inside a table without entries of its own (the scene
    echo) any key is the scene's, not a result name."""
    if result_entry(group, key) is not None:
        return True
    parent = key.rsplit(".", 1)[0] if "." in key else None
    if parent is None:
        return False
    e = result_entry(group, parent)
    return e is not None and not any(
        x["name"].startswith(parent + ".") for x in rf.result_schema() if x["group"] == group
    )


def test_every_result_key_python_reads_is_in_the_schema() -> None:
    reads = _literal_reads()
    # the scan finds the reads it is meant to find (it cannot pass by finding nothing)
    found = {(m, g, k) for m, g, k, _ in reads}
    for probe in (
        ("energy.py", "meta", "work_conjugate"),
        ("_vtk.py", "fields", "node_xy"),
        ("runner.py", "meta", "timings"),
        ("cli/run.py", "meta", "enrichment"),
    ):
        assert probe in found, probe
    unknown = [f"{m}:{line}: {g}[{k!r}]" for m, g, k, line in reads if not _known(g, k)]
    assert not unknown, "result keys read by name that the schema does not have:\n" + "\n".join(
        unknown
    )


def test_status_literals_are_statuses() -> None:
    """A status the package compares ``meta["status"]`` with is one of a method's statuses."""
    names = {n for st in rf.STATUSES.values() for n in st}
    bad, checked = [], 0
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Compare):
                continue
            sides = [node.left, *node.comparators]
            reads_status = any(
                isinstance(s, (ast.Subscript, ast.Call))
                and "meta" in ast.unparse(s)
                and "'status'" in ast.unparse(s)
                for s in sides
            )
            for s in sides:
                k = _key(s)
                checked += reads_status and k is not None
                if reads_status and k is not None and k not in names:
                    bad.append(f"{path.name}:{node.lineno}: {k!r}")
    assert checked, "the scan finds the status comparisons (energy.py compares 'separated')"
    assert not bad, bad


def test_schema_lists_every_method_and_the_statuses() -> None:
    rows = rf.result_schema()
    assert {m for e in rows for m in e["methods"]} == set(rf.METHODS)
    for e in rows:
        assert e["group"] in ("headline", *GROUPS) and e["doc"], e
        assert (e["shape"] is None) == (
            e["kind"] not in ("float array", "int array", "bool array", "float list")
        ), e
    assert "separated" in rf.STATUSES["pd"] and "a_stop_reached" in rf.STATUSES["xfem"]
    assert rf.STATUSES["fem"] == {}
    by = {(e["group"], e["name"]): e for e in rf.result_schema("fem")}
    assert by[("fields", "coords")]["shape"] == "(n_nodes, 2)"
    assert by[("headline", "sigma22")]["unit"] == "stress"


_KINDS = {
    "float": float,
    "int": int,
    "bool": bool,
    "str": str,
    "str list": list,
    "float list": list,
    "table": dict,
    "table list": list,
}
_DTYPES = {"float array": "f", "int array": "i", "bool array": "b"}


@pytest.mark.parametrize(
    "scene",
    [
        rf.scenes.edge_crack_plate("fem", mesh=(11, 21)),
        rf.scenes.edge_crack_plate("xfem", mesh=(22, 42), growth_steps=2),
        rf.scenes.edge_crack_plate("ccm_pd", dx=0.2, sla_steps=5),
    ],
    ids=["fem", "xfem", "ccm_pd"],
)
def test_a_run_returns_exactly_schema_entries(scene: rf.Scene) -> None:
    """Every key of ``rf.run``'s result is an entry of its method, of the entry's kind and
    dtype; the entries present always are there; the units label the Result."""
    res = rf.run(scene)
    groups = {
        "headline": {
            k: getattr(res, k) for k in ("method", "sigma22", "cmod", "n_dofs", "wall_time_s")
        }
    }
    groups.update({g: getattr(res, g) for g in GROUPS})
    for g, d in groups.items():
        for k, v in d.items():
            e = result_entry(g, k, res.method)
            assert e is not None, f"{g}[{k!r}] is not in the schema of {res.method}"
            if v is None:
                assert e["nullable"], (g, k)
            elif e["kind"] in _DTYPES:
                assert isinstance(v, np.ndarray) and v.dtype.kind == _DTYPES[e["kind"]], (g, k)
                assert v.ndim == e["shape"].count(",") + (0 if e["shape"].endswith(",)") else 1), (
                    g,
                    k,
                )
            else:
                assert isinstance(v, _KINDS[e["kind"]]), (g, k, type(v))
    for e in rf.result_schema(res.method):
        if e["presence"] == "always" and "." not in e["name"]:
            assert e["name"] in groups[e["group"]], e
    assert res.unit("sigma22", "headline") == "stress" and res.unit("nonsense") is None
    if res.history:
        assert res.unit("cmod") == "length"
    if res.method != "fem":
        assert res.meta["status"] in res.statuses
