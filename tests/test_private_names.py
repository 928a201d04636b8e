"""No module of ``python/rustfrac`` takes a private name (a leading underscore) of another one: a
name two modules share is public in its home module (``from .x import _y`` and ``x._y`` are
refused), and so is an attribute or method: ``obj._y`` where only another module defines ``_y``
(a method or attribute of its classes) is refused too. Private modules (``_core``, ``_folder``,
...) are the package's own and may be imported; their public names too."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "python" / "rustfrac"


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _is_module(name: str) -> bool:
    """Whether the dotted ``name`` (``rustfrac.x.y``) is a module or package of the package
    (the extension ``_core`` included, by its stub)."""
    parts = name.split(".")
    if parts[0] != PACKAGE.name:
        return False
    base = PACKAGE.parent.joinpath(*parts)
    return (
        base.with_suffix(".py").is_file()
        or base.with_suffix(".pyi").is_file()
        or (base / "__init__.py").is_file()
        or any(base.parent.glob(f"{base.name}.*.so"))
    )


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def private_uses(source: str, module: str, is_package: bool = False) -> list[str]:
    """The private names of other modules of the package that ``source`` (the text of
    ``module``) imports or reads as a module's attribute, as "line: module.name"."""
    tree = ast.parse(source)
    package = module if is_package else module.rpartition(".")[0]
    found: list[str] = []
    bound: dict[str, str] = {}  # local name -> the package module it is bound to
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                src = ".".join(base + ([node.module] if node.module else []))
            else:
                src = node.module or ""
            if src.split(".")[0] != PACKAGE.name:
                continue
            for a in node.names:
                full = f"{src}.{a.name}"
                if _is_module(full):
                    bound[a.asname or a.name] = full
                elif _private(a.name) and src != module:
                    found.append(f"{node.lineno}: {src}.{a.name}")
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == PACKAGE.name and a.asname:
                    bound[a.asname] = a.name
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in bound
            and _private(node.attr)
            and not _is_module(f"{bound[node.value.id]}.{node.attr}")
        ):
            found.append(f"{node.lineno}: {bound[node.value.id]}.{node.attr}")
    return found


def private_attributes(source: str) -> set[str]:
    """The private attribute names ``source`` defines: its classes' methods and class-level
    names, and every ``x._y`` it assigns (``self._y = ...`` in a method)."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    found.add(item.name)
                elif isinstance(item, (ast.Assign, ast.AnnAssign)):
                    targets = item.targets if isinstance(item, ast.Assign) else [item.target]
                    found.update(t.id for t in targets if isinstance(t, ast.Name))
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            found.add(node.attr)
    return {n for n in found if _private(n)}


def private_attribute_uses(sources: dict[str, str]) -> list[str]:
    """The private attributes or methods (``obj._y``) that a module of ``sources`` (module ->
    text) reads while another module defines them, as "module:line: ._y (defined in other)":
    ``self._y`` / ``cls._y`` only when the module does not define ``_y`` itself (a class's own
    names), any other ``obj._y`` even when it does (``res._stage`` in a module with a
    ``_stage`` of its own is still another module's)."""
    defined = {m: private_attributes(src) for m, src in sources.items()}
    found: list[tuple[str, int, str]] = []
    for m, src in sources.items():
        for node in ast.walk(ast.parse(src)):
            if not (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Load)):
                continue
            name = node.attr
            own = isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")
            if not _private(name) or (own and name in defined[m]):
                continue
            homes = sorted(o for o, names in defined.items() if o != m and name in names)
            if homes:
                found.append((m, node.lineno, f".{name} (defined in {', '.join(homes)})"))
    return [f"{m}:{line}: {what}" for m, line, what in sorted(found)]


def test_the_checker_finds_a_private_name_taken_from_another_module() -> None:
    src = (
        "from . import fig7, _core\n"
        "from .fig7 import _json_default, run\n"
        "from .scene import Scene as _Scene\n"
        "def f():\n"
        "    from .specimens import _pd_layout\n"
        "    return fig7._machine(), _core.scene_constants(), fig7.__name__\n"
    )
    assert private_uses(src, "rustfrac.compare") == [
        "2: rustfrac.fig7._json_default",
        "5: rustfrac.specimens._pd_layout",
        "6: rustfrac.fig7._machine",
    ]
    # a subpackage's relative imports are resolved from it
    assert private_uses("from .. import scene\nscene._CONST\n", "rustfrac.cli.run") == [
        "2: rustfrac.scene._CONST"
    ]


def test_no_module_takes_a_private_name_of_another() -> None:
    files = sorted(PACKAGE.rglob("*.py"))
    assert len(files) > 20
    offenders = [
        f"{f.relative_to(PACKAGE)}:{use}"
        for f in files
        for use in private_uses(
            f.read_text(encoding="utf-8"), _module_name(f), f.name == "__init__.py"
        )
    ]
    assert not offenders, offenders


def test_the_checker_finds_a_private_method_called_from_another_module() -> None:
    home = (
        "class Writer:\n"
        "    def __init__(self):\n"
        "        self._staged = {}\n"
        "    def _commit(self):\n"
        "        return self._staged\n"
    )
    user = (
        "class Job:\n"
        "    def _own(self):\n"
        "        return 1\n"
        "    def _commit(self, w):\n"
        "        return self._own(), self._commit, w._commit()\n"
        "def f(w, j):\n"
        "    w._commit()\n"
        "    return j._own(), w.__class__, w._staged\n"
    )
    assert private_attribute_uses({"rustfrac.a": home, "rustfrac.b": user}) == [
        "rustfrac.b:5: ._commit (defined in rustfrac.a)",
        "rustfrac.b:7: ._commit (defined in rustfrac.a)",
        "rustfrac.b:8: ._staged (defined in rustfrac.a)",
    ]


def test_no_module_calls_a_private_method_of_another() -> None:
    sources = {
        _module_name(f): f.read_text(encoding="utf-8") for f in sorted(PACKAGE.rglob("*.py"))
    }
    offenders = private_attribute_uses(sources)
    assert not offenders, offenders
