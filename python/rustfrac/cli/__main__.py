"""``python -m rustfrac.cli``: the ``rustfrac`` command line (:func:`rustfrac.cli.console`)."""

from __future__ import annotations

import sys

from . import console

if __name__ == "__main__":
    sys.exit(console())
