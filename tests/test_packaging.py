"""Package conventions: ``python -m rustfrac``, the examples shipped as package data, the license
files and metadata, a README that stays inside the repository, and the native module's stub."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

import rustfrac as rf
from general_support import HOLES_REFUSED, has_holes

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def _python(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, *args], capture_output=True, text=True, check=False, cwd=ROOT
    )


def test_python_m_rustfrac_is_the_cli(tmp_path: Path) -> None:
    p = _python("-m", "rustfrac", "--version")
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == f"rustfrac {rf.__version__}"
    p = _python("-m", "rustfrac", "examples")
    assert p.returncode == 0, p.stderr
    assert "pd_coarse.toml" in p.stdout and str(rf.examples.path("pd_coarse.toml")) in p.stdout
    p = _python(
        "-m",
        "rustfrac",
        "run",
        str(rf.examples.path("paper_fem_uncracked")),
        "--out",
        str(tmp_path),
        "-q",
    )
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "result.json").is_file()


def test_examples_accessor() -> None:
    names = rf.examples.list()
    assert "paper_ccm_pd.toml" in names and "pd_coarse.toml" in names and len(names) >= 10
    for name in names:
        p = rf.examples.path(name)
        assert p.is_file()
        if HOLES_REFUSED is not None and has_holes(p):
            continue  # the core refuses holes for now (tests/test_general_scenes.py checks them)
        assert rf.Scene.from_toml(p).method in rf.METHODS
    assert rf.examples.path("paper_ccm_pd") == rf.examples.path("paper_ccm_pd.toml")
    with pytest.raises(rf.InvalidParameterError, match=r"valid: double_edge_crack\.toml") as e:
        rf.examples.path("paper_ccm.toml")
    assert e.value.param == "name"
    with pytest.raises(rf.InvalidTypeError):
        rf.examples.path(3)  # type: ignore[arg-type]


def test_examples_are_package_data_in_one_copy() -> None:
    pkg = Path(rf.__file__).resolve().parent
    assert rf.examples.DIRECTORY == pkg / "examples"  # inside the package: in every wheel
    if (ROOT / "examples").is_dir():  # a checkout: no second copy of a scene beside the notebook
        assert not list((ROOT / "examples").glob("*.toml"))
    assert "include" not in PYPROJECT["tool"]["maturin"]  # package data needs no include list


def test_license_files_and_metadata() -> None:
    assert PYPROJECT["project"]["license"] == "MIT OR Apache-2.0"  # an SPDX expression
    assert PYPROJECT["project"]["license-files"] == ["LICENSE-MIT", "LICENSE-APACHE"]
    assert "MIT License" in (ROOT / "LICENSE-MIT").read_text(encoding="utf-8")
    assert "Apache License" in (ROOT / "LICENSE-APACHE").read_text(encoding="utf-8")
    proj = PYPROJECT["project"]
    assert proj["readme"] == "README.md"
    cls = proj["classifiers"]
    assert "Typing :: Typed" in cls
    lo = int(proj["requires-python"].removeprefix(">=3."))
    for minor in range(lo, 14):
        assert f"Programming Language :: Python :: 3.{minor}" in cls
    assert not any(c.startswith("License ::") for c in cls)  # the expression says it (PEP 639)
    assert (
        "Operating System :: POSIX :: Linux" in cls
        and "Operating System :: OS Independent" not in cls
    )
    assert "urls" not in proj  # no public address yet: no placeholders
    for name in ("CITATION.cff", "CHANGELOG.md"):
        assert (ROOT / name).is_file(), name
    test = " ".join(proj["optional-dependencies"]["test"])
    for dep in ("tqdm", "pandas", "nbclient", "nbformat", "ipykernel", "mypy"):
        assert dep in test, dep
    assert (Path(rf.__file__).parent / "py.typed").is_file()


def test_readme_stays_inside_the_repository() -> None:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "../" not in text
    for name in re.findall(r'rf\.examples\.path\("([^"]+)"\)', text):
        rf.examples.path(name)  # every example the README names exists
    for rel in re.findall(r"`((?:docs|benches|examples|tests|crates)/[\w./-]+\.\w+)`", text):
        assert (ROOT / rel).exists(), rel


def test_core_stub_matches_the_native_module(tmp_path: Path, child_env: dict[str, str]) -> None:
    pytest.importorskip("mypy.stubtest")
    # no allowlist: the stub holds in builds with and without the test hooks (private
    # attributes outside __all__)
    p = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "rustfrac._core"],
        capture_output=True,
        text=True,
        check=False,
        cwd=tmp_path,
        env=child_env,
    )
    assert p.returncode == 0, p.stdout + p.stderr
