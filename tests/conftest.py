from __future__ import annotations

import os
from pathlib import Path

import pytest

import rustfrac as rf

ROOT = Path(__file__).resolve().parents[1]


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
