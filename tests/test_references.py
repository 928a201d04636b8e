"""References a reader of the repository can follow: no source or documentation file cites the
design notes or the tracker that only the developers had (a "DESIGN" file's section, an issue
number), and every section of ``docs/design.md`` the files cite by its quoted title is a heading of
it."""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SUFFIXES = {".rs", ".py", ".pyi", ".md", ".toml", ".txt", ".ipynb", ".yml", ".yaml", ".cfg"}
SKIP_DIRS = {"target", ".venv", "venv", ".git", "_build", "node_modules", "__pycache__"}

# a private file's section, a tracker's number (with or without an item, capitalised, plural,
# with "#"), a conversation's turn; \b keeps "return 0" (the examples below are written in two
# parts so that this file does not cite them itself)
UNFOLLOWABLE = re.compile(r"DESIGN\.md|\b[Ii]ssues? #?[0-9]+|\b[Tt]urn [0-9]+")
# a citation of a design section: the path, a comma, the quoted title (which may wrap onto the next
# comment line, whose prefix is dropped)
CITATION = re.compile(r'docs/design\.md,\s*(?:(?://[/!]?|#)\s*)?"([^"]+)"')


def _files() -> list[Path]:
    """The repository's text files: tracked ones in a git checkout, else a walk of the tree."""
    try:
        out = subprocess.run(
            ["git", "-C", str(ROOT), "ls-files", "-z"],
            capture_output=True,
            check=True,
            timeout=60,
        ).stdout.decode()
        paths = [ROOT / n for n in out.split("\0") if n]
    except (OSError, subprocess.SubprocessError):
        paths = []
        for d, dirs, names in os.walk(ROOT):
            dirs[:] = [x for x in dirs if x not in SKIP_DIRS]
            paths += [Path(d) / n for n in names]
    return sorted(p for p in paths if p.suffix in SUFFIXES and p.is_file())


def _text(p: Path) -> str:
    try:
        return p.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        return ""


def _headings() -> set[str]:
    text = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")
    return {m.group(1).strip() for m in re.finditer(r"^#{1,6}\s+(.+)$", text, re.MULTILINE)}


@pytest.mark.parametrize(
    ("line", "flagged"),
    [
        ("//! Detached nodes and debris (DESIGN" + ".md section 4).", True),
        ('"""Iss' + "ue 17, item 3: Ctrl-C (SIGINT) stops a long run", True),
        ('(`pd.region = "adaptive"`, iss' + "ue 13 item 2)", True),
        ("## The two targets not reached (iss" + "ues 13 and 15)", True),
        ("see iss" + "ue #7", True),
        ("as asked in tu" + "rn 3", True),
        ("        return 0.0;", False),
        ("A and B run alternately 5 times each", False),
        ('(docs/design.md, "The splice coupling")', False),
    ],
)
def test_the_pattern_flags_what_a_reader_cannot_follow(line: str, flagged: bool) -> None:
    assert bool(UNFOLLOWABLE.search(line)) is flagged


def test_no_file_cites_the_private_design_notes_or_issue_numbers() -> None:
    files = _files()
    assert any(p.name == "design.md" for p in files), "docs/design.md is part of the repository"
    hits = [
        f"{p.relative_to(ROOT)}:{i}: {line.strip()[:100]}"
        for p in files
        for i, line in enumerate(_text(p).splitlines(), 1)
        if UNFOLLOWABLE.search(line)
    ]
    where = "\n".join(hits)
    assert not hits, f"cite a docs/design.md section, a module or a test instead:\n{where}"


def test_every_cited_design_section_exists() -> None:
    headings = _headings()
    # the sections every part of the code cites
    for title in (
        "Units and the paper's conventions",
        "The XFEM model",
        "The bond-based PD model and gamma",
        "The splice coupling",
        "Matrix symmetry and solver strategy",
        "The SLA engines",
        "The adaptive region",
        "The energy audit",
        "Checkpoints",
    ):
        assert title in headings, title
    cited = {
        (p.relative_to(ROOT), " ".join(m.group(1).split()))
        for p in _files()
        for m in CITATION.finditer(_text(p))
    }
    assert cited, "the code cites docs/design.md"
    missing = sorted(f"{p}: {t!r}" for p, t in cited if t not in headings)
    assert not missing, "no such heading in docs/design.md:\n" + "\n".join(missing)
