"""Every Python block of the README and of the user guide runs as written: the pages' code is
executed, block after block in one namespace per page (a page reads like a session), in a fresh
working folder. The README's blocks must also run without a warning: a newcomer's first run is
clean."""

from __future__ import annotations

import os
import re
import warnings
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def _blocks(page: Path) -> list[str]:
    return BLOCK.findall(page.read_text(encoding="utf-8"))


def test_the_pages_have_python_blocks() -> None:
    counts = {p.name: len(_blocks(p)) for p in PAGES}
    assert counts["README.md"] >= 1 and sum(counts.values()) >= 6, counts


@pytest.mark.parametrize("page", [p for p in PAGES if _blocks(p)], ids=lambda p: p.name)
def test_every_python_block_runs(page: Path, tmp_path: Path) -> None:
    import matplotlib.pyplot as plt

    namespace: dict[str, object] = {"__name__": "__doc_block__"}
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for i, code in enumerate(_blocks(page)):
            with warnings.catch_warnings():
                if page.name == "README.md":
                    warnings.simplefilter("error")
                exec(compile(code, f"{page.name}, python block {i}", "exec"), namespace)
    finally:
        os.chdir(cwd)
        plt.close("all")
