"""Sphinx configuration of the rustfrac documentation.

Build (warnings are errors, as in CI: ``tests/test_docs.py``)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

The pages are Markdown (MyST); the README's sections and ``benches/RESULTS.md`` are included,
not copied (``docs/design.md`` and ``docs/architecture.md`` are pages of their own). The scene-key
table, the error hierarchy and the gallery (each example scene, run at build time for a figure)
come from the package itself (``docs/_ext/rustfrac_docs.py``). rustfrac is imported from the
installed package, or from ``python/`` of this checkout when it holds a built native module.
"""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))
if any((ROOT / "python" / "rustfrac").glob("_core*.so")) or any(
    (ROOT / "python" / "rustfrac").glob("_core*.pyd")
):
    sys.path.insert(0, str(ROOT / "python"))

import rustfrac  # noqa: E402

project = "rustfrac"
author = "the rustfrac authors"
copyright = "the rustfrac authors; MIT OR Apache-2.0"
release = rustfrac.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "rustfrac_docs",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "_generated/**/*.md", "Thumbs.db", ".DS_Store"]
root_doc = "index"
smartquotes = False  # the texts quote values ('free', "seam"): keep them as typed

# MyST: ``{include}``, tables, ``$...$`` not used; headings get anchors for in-page links
myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 3

# autodoc: the docstrings are Google style (napoleon); single backticks in the native module's
# docstrings (written in Markdown style) are inline code
default_role = "code"
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_class_signature = "separated"
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_rtype = False
napoleon_use_ivar = True  # "Attributes:" as fields: dataclass fields are not documented twice


def _foreign_member(app, what, name, obj, skip, options):
    """Skips members a rustfrac class inherits from another package (matplotlib's generated
    ``Figure.set`` on :class:`rustfrac.plotting.NotebookFigure`)."""
    module = getattr(obj, "__module__", None)
    if what == "class" and callable(obj) and module and not module.startswith("rustfrac"):
        return True
    return None


def _escape_schema_text(app, what, name, obj, options, lines):
    """The section classes' key lists quote the core's range texts, which write absolute values
    as ``|x|``: literal bars, not reST substitutions."""
    from rustfrac.scene import _Section

    if what == "class" and isinstance(obj, type) and issubclass(obj, _Section):
        lines[:] = [ln.replace("|", r"\|") if ln.startswith("- ``") else ln for ln in lines]


def setup(app):
    app.connect("autodoc-skip-member", _foreign_member)
    app.connect("autodoc-process-docstring", _escape_schema_text)


# every reference to a rustfrac object must resolve (the others, numpy, matplotlib, the standard
# library, are plain text: the documentation links nothing outside the repository)
nitpicky = True
nitpick_ignore_regex = [(r"py:.*", r"(?!rustfrac\b).*")]

html_theme = "alabaster"
html_title = f"rustfrac {release}"
html_static_path: list[str] = []
html_show_sourcelink = False
html_show_sphinx = False  # the footer's links would leave the repository's documentation
html_theme_options = {"show_powered_by": False}
