from __future__ import annotations

import os
from pathlib import Path

import pytest

import rustfrac as rf

ROOT = Path(__file__).resolve().parents[1]

# The optional families, by file, and the slowest tests, by file and name (all parameters): the
# markers registered in pyproject.toml, so that `pytest -m "not slow and not docs"` is the quick
# loop. CI runs everything.
FAMILIES = {
    "test_docs.py": "docs",
    "test_notebook.py": "notebook",
    "test_packaging.py": "packaging",
}
SLOW = {
    "test_docs.py": {"*"},
    "test_notebook.py": {"test_example_notebook_reproduces_fig7"},
}


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for file, names in SLOW.items():  # an entry that names no test is an error, not a no-op
        text = (ROOT / "tests" / file).read_text(encoding="utf-8")
        missing = [n for n in names if n != "*" and f"def {n}(" not in text]
        assert not missing, f"tests/conftest.py SLOW names tests not in {file}: {missing}"
    for item in items:
        file = item.path.name
        if file in FAMILIES:
            item.add_marker(FAMILIES[file])
        names = SLOW.get(file, ())
        if "*" in names or getattr(item, "originalname", item.name) in names:
            item.add_marker("slow")


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def child_env() -> dict[str, str]:
    """The environment of a child Python process that must import the rustfrac this suite
    imports, whatever its working directory (a relative PYTHONPATH, as in ``PYTHONPATH=python
    pytest``, would not reach it from another directory)."""
    return {**os.environ, "PYTHONPATH": str(Path(rf.__file__).resolve().parents[1])}


@pytest.fixture(scope="session")
def uncracked() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate(method="fem", crack="none"))


@pytest.fixture(scope="session")
def seam() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate(method="fem", crack="seam"))
