"""The package's logger: ``logging.getLogger("rustfrac")`` (library code logs, never prints; the
CLI prints its own output). A ``NullHandler`` keeps it quiet until the application configures
logging, e.g. ``logging.basicConfig(level=logging.INFO)``."""

from __future__ import annotations

import logging

logger = logging.getLogger("rustfrac")
logger.addHandler(logging.NullHandler())
