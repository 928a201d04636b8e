"""Shared by the tests of general scenes: whether this build's core runs holes and notches.

The fictitious-domain integration of holes lands separately; until then the core refuses every
``[[hole]]`` / ``[[notch]]`` (naming ``hole[0]``). Tests that need holes are marked
``needs_holes`` and start running by themselves once a build accepts the tiny scene below.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

import rustfrac as rf

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def _holes_refused() -> str | None:
    """None when the core accepts a small hole in the paper's plate, else its message."""
    try:
        rf.Scene.from_dict({"method": "fem", "hole": [{"center": [5.5, 3.0], "radius": 0.5}]})
    except rf.InvalidParameterError as e:
        if e.param is not None and str(e.param).startswith(("hole", "notch")):
            return str(e)
        raise
    return None


#: the core's refusal of holes (None once holes are supported); checked once, at import
HOLES_REFUSED: str | None = _holes_refused()
needs_holes = pytest.mark.skipif(
    HOLES_REFUSED is not None,
    reason=f"this build's core refuses holes and notches (fictitious domain pending): "
    f"{HOLES_REFUSED}",
)


def has_holes(path: Path) -> bool:
    """Whether the scene file has [[hole]] or [[notch]] tables."""
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    return bool(data.get("hole") or data.get("notch"))
