"""The example scenes shipped with rustfrac (TOML files installed with the package, so they work
from a wheel as well as from a clone)::

    import rustfrac as rf
    rf.examples.list()                                  # ['double_edge_crack.toml', ...]
    scene = rf.Scene.from_toml(rf.examples.path("paper_ccm_pd.toml"))

On the command line, ``rustfrac examples`` prints the name and path of each.
"""

from __future__ import annotations

import builtins
from pathlib import Path

from ..errors import InvalidParameterError, InvalidTypeError

__all__ = ["DIRECTORY", "list", "path"]

#: the directory holding the example files
DIRECTORY: Path = Path(__file__).resolve().parent


def list() -> builtins.list[str]:
    """The file names of the example scenes, sorted."""
    return sorted(p.name for p in DIRECTORY.glob("*.toml"))


def path(name: str) -> Path:
    """The path of the example scene ``name`` (a file name from :func:`list`; the ``.toml``
    suffix may be left out).

    Raises:
        InvalidParameterError: no example has that name (the message lists the valid ones).
    """
    names = list()
    if not isinstance(name, str):
        raise InvalidTypeError(
            f"invalid name: an example's file name (str), one of {', '.join(names)}; got "
            f"{type(name).__name__}",
            "name",
        )
    file = name if name.endswith(".toml") else name + ".toml"
    if file not in names:
        raise InvalidParameterError(
            f"invalid name: no example scene {name!r}; valid: {', '.join(names)}", "name"
        )
    return DIRECTORY / file
