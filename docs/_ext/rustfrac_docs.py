"""Sphinx directives that build parts of the rustfrac documentation from the package itself, so
the pages cannot drift from the code:

- ``rustfrac-scene-keys`` [section]: the table of scene keys (default, valid range, meaning) as the
  core's schema defines them (:func:`rustfrac.scene.keys`); one table per section;
- ``rustfrac-errors``: the exception and warning classes of :mod:`rustfrac.errors` with their
  bases and the first sentence of their docstrings;
- ``rustfrac-gallery``: every example scene of :mod:`rustfrac.examples`: its TOML text, its
  one-line description and, for the cheap ones, a figure of its result computed at build time
  (``docs/_generated/gallery/``; the costly ones name their coarse variant instead).
"""

from __future__ import annotations

import inspect
import os
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any, ClassVar

from docutils import nodes
from docutils.parsers.rst import directives
from sphinx import addnodes
from sphinx.application import Sphinx
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)

#: example scenes not run at build time (seconds each; the build stays well under two minutes),
#: with the cheap scene that shows the same method
COSTLY: dict[str, str] = {
    "paper_ccm_pd.toml": "pd_coarse.toml",
    "paper_ccm_pd_clamped.toml": "pd_coarse.toml",
    "paper_ccm_pd_adaptive.toml": "pd_coarse.toml",
}
#: where the gallery's figures go, relative to the documentation's source directory
GENERATED = Path("_generated") / "gallery"


def _text(s: Any) -> nodes.Node:
    return nodes.Text(str(s))


def _table(header: list[str], rows: list[list[nodes.Node]], widths: list[int]) -> nodes.table:
    """A docutils table of ``rows`` (each cell one inline node)."""
    table = nodes.table(classes=["rustfrac-table"])
    group = nodes.tgroup(cols=len(header))
    table += group
    for w in widths:
        group += nodes.colspec(colwidth=w)
    head = nodes.thead()
    group += head
    body = nodes.tbody()
    group += body
    for target, cells in ((head, [_text(h) for h in header]), *((body, r) for r in rows)):
        row = nodes.row()
        for cell in cells:
            entry = nodes.entry()
            entry += nodes.paragraph("", "", cell)
            row += entry
        target += row
    return table


class SceneKeys(SphinxDirective):
    """The scene keys of one section (argument) or of every section, from the core's schema."""

    optional_arguments = 1

    def run(self) -> list[nodes.Node]:
        from rustfrac import scene

        sections = (
            [self.arguments[0]]
            if self.arguments
            else list(dict.fromkeys(k["section"] for k in scene.keys()))
        )
        out: list[nodes.Node] = []
        for section in sections:
            specs = scene.keys(section)
            if not specs:
                raise self.error(f"rustfrac-scene-keys: no scene section {section!r}")
            rows = [
                [
                    nodes.literal(text=s["key"]),
                    nodes.literal(text=repr(s["default"])),
                    _text(s["kind"] + ": " + s["valid"]),
                    _text(s["doc"] + (f" ({s['required_words']})" if s["required_words"] else "")),
                ]
                for s in specs
            ]
            table = _table(["key", "default", "kind: valid", "meaning"], rows, [12, 12, 30, 46])
            title = nodes.title(text=f"[{section}]")
            table.insert(0, title)
            out.append(table)
        return out


class Errors(SphinxDirective):
    """The classes of rustfrac.errors: name (linked to the API reference), bases, meaning."""

    def run(self) -> list[nodes.Node]:
        from rustfrac import errors

        rows = []
        names = [n for n in errors.__all__ if inspect.isclass(getattr(errors, n))]
        for name in names:
            cls = getattr(errors, name)
            ref = addnodes.pending_xref(
                "",
                nodes.literal(text=name),
                refdomain="py",
                reftype="class",
                reftarget=f"rustfrac.errors.{name}",
                refexplicit=True,
                refwarn=True,
            )
            bases = ", ".join(b.__name__ for b in cls.__bases__)
            doc = inspect.getdoc(cls) or ""
            first = " ".join(doc.split("\n\n")[0].split())
            rows.append([ref, _text(bases), _text(first)])
        return [_table(["class", "bases", "meaning"], rows, [22, 28, 50])]


def _figure(scene: Any, res: Any, units: Any, path: Path) -> None:
    """Draws the result's overview (field or damage, crack path, load path) into ``path``."""
    from matplotlib.figure import Figure

    from rustfrac import plotting

    panels: list[Any] = []
    if res.method in ("pd", "ccm_pd"):
        panels.append(lambda ax: plotting.plot_damage(res, ax=ax, units=units))
    else:
        panels.append(lambda ax: plotting.plot_field(res, ax=ax, units=units))
    if scene.crack.kind != "none":
        panels.append(lambda ax: plotting.plot_crack_path(res, ax=ax, units=units))
    if res.history:
        x = "cmod" if "cmod" in res.history else "u0"
        panels.append(lambda ax: plotting.plot_load_path(res, x=x, ax=ax, units=units))
    fig = Figure(figsize=(4.2 * len(panels), 4.6), constrained_layout=True)  # matplotlib 3.5+
    for k, draw in enumerate(panels):
        draw(fig.add_subplot(1, len(panels), k + 1))
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".png")  # concurrent builds: rename
    os.close(fd)
    fig.savefig(tmp, dpi=80)
    os.replace(tmp, path)


class Gallery(SphinxDirective):
    """One section per example scene: the file, its description, a figure (cheap scenes)."""

    option_spec: ClassVar[dict[str, Any]] = {"no-figures": directives.flag}

    def run(self) -> list[nodes.Node]:
        import rustfrac as rf

        out: list[nodes.Node] = []
        for name in rf.examples.list():
            out.append(self._example(rf, name))
        return out

    def _example(self, rf: Any, name: str) -> nodes.section:
        stem = name.removesuffix(".toml")
        path = rf.examples.path(name)
        text = path.read_text(encoding="utf-8")
        sec = nodes.section(ids=[nodes.make_id(f"example-{stem}")], names=[stem])
        sec += nodes.title(text=name)
        try:
            scene = rf.Scene.from_toml(path)
        except rf.InvalidParameterError as e:
            # a scene this build's core refuses (holes and notches until the fictitious-domain
            # integration lands): shown with the core's message, not run
            sec += nodes.literal_block(text, text, language="toml")
            sec += nodes.paragraph("", "", _text(f"Not runnable with this build: {e}"))
            return sec
        sec += nodes.paragraph("", "", nodes.emphasis(text=scene.describe()))
        run = nodes.paragraph()
        run += _text("Run it: ")
        run += nodes.literal(text=f"rustfrac run $(rustfrac examples {stem}) --out out/")
        run += _text(" or ")
        run += nodes.literal(text=f'rf.run(rf.examples.path("{name}"))')
        sec += run
        block = nodes.literal_block(text, text, language="toml")
        sec += block
        if name in COSTLY:
            sec += nodes.paragraph(
                "",
                "",
                _text(
                    "Not run when the documentation is built (seconds, not a fraction of one); "
                    f"the figure of {COSTLY[name]} shows the same method on a coarse grid."
                ),
            )
            return sec
        if "no-figures" in self.options:
            return sec
        units = rf.plotting.PAPER_UNITS if "N, mm, MPa" in text else rf.plotting.DEFAULT_UNITS
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # accuracy warnings are listed below instead
            res = rf.run(scene)
        rel = GENERATED / f"{stem}.png"
        _figure(scene, res, units, Path(self.env.srcdir) / rel)
        logger.info("gallery: %s in %.2f s", name, time.perf_counter() - t0)
        sec += nodes.paragraph("", "", nodes.literal(text=res.summary()))
        for w in res.warnings:
            sec += nodes.paragraph("", "", _text(f"Warning: {w}"))
        img = nodes.image(uri="/" + rel.as_posix(), alt=f"result of {name}")
        sec += img
        return sec


def _reexported(app: Sphinx, env: Any, node: Any, contnode: nodes.Node) -> nodes.Node | None:
    """Resolves ``rustfrac.Scene``, ``rustfrac.Result``, ... (the package's re-exports, as the
    docstrings write them) to the object's documented name (``rustfrac.scene.Scene``)."""
    target = node.get("reftarget", "")
    if node.get("refdomain") != "py" or not target.startswith("rustfrac."):
        return None
    import importlib

    parts = target.split(".")
    for k in range(len(parts) - 1, 0, -1):  # longest importable module prefix, then attributes
        try:
            obj: Any = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        try:
            for attr in parts[k:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None
        break
    else:
        return None
    if not (inspect.isclass(obj) or inspect.isroutine(obj)):
        return None
    module = getattr(obj, "__module__", None)
    qualname = getattr(obj, "__qualname__", None)
    if not module or not qualname or f"{module}.{qualname}" == target:
        return None
    new = f"{module}.{qualname}"
    domain = env.get_domain("py")
    return domain.resolve_xref(
        env, node["refdoc"], app.builder, node["reftype"], new, node, contnode
    )


def _public_bases(app: Sphinx, name: str, obj: Any, options: Any, bases: list[Any]) -> None:
    """The scene section classes derive from the private ``_Section``: not shown."""
    bases[:] = [b for b in bases if not b.__name__.startswith("_")] or [object]


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("autodoc-process-bases", _public_bases)
    app.connect("missing-reference", _reexported)
    app.add_directive("rustfrac-scene-keys", SceneKeys)
    app.add_directive("rustfrac-errors", Errors)
    app.add_directive("rustfrac-gallery", Gallery)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
