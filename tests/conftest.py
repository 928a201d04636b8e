from __future__ import annotations

from pathlib import Path

import pytest

import rustfrac as rf

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def uncracked() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate(method="fem", crack="none"))


@pytest.fixture(scope="session")
def seam() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate(method="fem", crack="seam"))
