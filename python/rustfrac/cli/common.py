"""What the commands share: a scene file read, or why it cannot be read."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InvalidParameterError

if TYPE_CHECKING:
    from ..scene import Scene as _Scene


def read_scene(path: Path) -> _Scene | None:
    """The scene in the TOML file ``path``, or None after saying why it cannot be read (the
    commands then exit with 2)."""
    from ..scene import Scene

    try:
        return Scene.from_toml(path)
    except OSError as e:
        print(f"rustfrac: error: cannot read scene {path}: {e.strerror or e}", file=sys.stderr)
    except InvalidParameterError as e:
        print(f"rustfrac: error: invalid scene {path}: {e}", file=sys.stderr)
    return None
