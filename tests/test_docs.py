"""The documentation site (``docs/``, Sphinx + MyST) builds with warnings as errors, from the
package itself: every scene key, every example scene and every error class appears, and no page
links outside the repository. Skipped without Sphinx and MyST-Parser (the ``test`` extra has
them)."""

from __future__ import annotations

import html
import re
import subprocess
import sys
from pathlib import Path

import pytest

import rustfrac as rf

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_parser")
    tmp = tmp_path_factory.mktemp("docs")
    out = tmp / "html"
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "sphinx",
            "-W",
            "--keep-going",
            "-q",
            "-b",
            "html",
            "-d",
            str(tmp / "doctrees"),
            str(ROOT / "docs"),
            str(out),
        ],
        capture_output=True,
        text=True,
        check=False,
        cwd=ROOT,
        timeout=600,
    )
    assert p.returncode == 0, p.stdout[-4000:] + p.stderr[-8000:]
    return out


def _text(page: Path) -> str:
    return html.unescape(re.sub(r"<[^>]+>", "", page.read_text(encoding="utf-8")))


def test_docs_build_with_warnings_as_errors(site: Path) -> None:
    for page in (
        "index",
        "guide/scenes",
        "guide/errors",
        "api/rustfrac",
        "api/core",
        "gallery",
        "validation",
        "design",
        "architecture",
    ):
        assert (site / f"{page}.html").is_file(), page


def test_docs_scene_keys_come_from_the_schema(site: Path) -> None:
    text = _text(site / "guide" / "scenes.html")
    for k in rf.scene.keys():
        assert f"[{k['section']}]" in text
        assert k["key"] in text and k["doc"] in text, k


def test_docs_gallery_shows_every_example(site: Path) -> None:
    page = (site / "gallery.html").read_text(encoding="utf-8")
    for name in rf.examples.list():
        assert f"example-{name.removesuffix('.toml').replace('_', '-')}" in page, name
    images = sorted(p.name for p in (site / "_images").glob("*.png"))
    assert "pd_coarse.png" in images and "paper_xfem_free.png" in images, images


def test_docs_list_every_error_class(site: Path) -> None:
    text = _text(site / "guide" / "errors.html")
    for name in rf.errors.__all__:
        if isinstance(getattr(rf.errors, name), type):
            assert name in text, name


def test_docs_stay_inside_the_repository(site: Path) -> None:
    for page in site.rglob("*.html"):
        body = page.read_text(encoding="utf-8")
        outside = re.findall(r'(?:href|src)="([a-z][a-z0-9+.-]*:[^"]*|//[^"]*)"', body)
        assert not outside, (page.relative_to(site), outside)


def test_api_reference_documents_every_public_name(site: Path) -> None:
    """Every name in ``__all__`` of the package and of its public modules is an object of the
    API reference (Sphinx's inventory), and every public module is reachable as ``rf.NAME``."""
    import importlib
    import zlib

    raw = (site / "objects.inv").read_bytes()
    body = raw.split(b"\n", 4)[4]  # four header lines, then zlib-compressed "name domain:role ..."
    documented = {line.split(" ", 1)[0] for line in zlib.decompress(body).decode().splitlines()}
    missing = []
    modules = ["rustfrac", *(f"rustfrac.{m}" for m in rf.LAZY_SUBMODULES)]
    modules += [f"rustfrac.{m}" for m in ("scene", "scenes", "specimens", "result", "errors")]
    modules += ["rustfrac.examples"]
    loaded = {m: importlib.import_module(m) for m in [*modules, "rustfrac._core"]}
    for mod_name in modules:
        mod = loaded[mod_name]
        if mod_name != "rustfrac":
            assert getattr(rf, mod_name.removeprefix("rustfrac.")) is mod, mod_name
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name)
            # documented where it is defined or where it is re-exported from
            homes = {
                m
                for m, other in list(sys.modules.items())
                if m.startswith("rustfrac") and getattr(other, name, None) is obj
            }
            home = getattr(obj, "__module__", None)
            if isinstance(home, str) and home.startswith("rustfrac"):
                homes.add(home)
            if not {f"{h}.{name}" for h in homes} & documented:
                missing.append(f"{mod_name}.{name}")
    assert not missing, f"{len(missing)} public names missing from the API reference: {missing}"
