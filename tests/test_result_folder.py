"""Result folders are written as one unit and read back checked: a full disk, a killed
writer or several concurrent writers never leave a folder that loads as a mix of two runs, and
``rf.load`` refuses what it cannot trust with an error naming the file and the field."""

from __future__ import annotations

import errno
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import result as result_mod

N = 20_000  # nodes: a few hundred kB of incompressible data, so that a save takes a while


def make(k: int, n: int = N) -> rf.Result:
    """Result number k: every array and the meta say k (``noise`` is seeded with k)."""
    return rf.Result(
        method="fem",
        sigma22=float(k),
        cmod=0.0,
        n_dofs=2 * n,
        wall_time_s=0.0,
        fields={
            "coords": np.full((n, 2), float(k)),
            "elements": np.array([[0, 1, 2, 3]]),
            "u": np.full(2 * n, float(k)),
            "noise": np.random.default_rng(k).random(n),
        },
        history={"sigma22": np.full(5, float(k)), "cmod": np.arange(5.0)},
        meta={"writer": k},
    )


def coherent(res: rf.Result) -> int:
    """The writer of a loaded result, asserting that every part of it is that writer's."""
    k = res.meta["writer"]
    assert res.sigma22 == k
    assert (res.fields["coords"] == k).all() and (res.fields["u"] == k).all()
    assert (res.history["sigma22"] == k).all()
    np.testing.assert_array_equal(res.fields["noise"], np.random.default_rng(k).random(N))
    return int(k)


def temporaries(d: Path) -> list[str]:
    return sorted(p.name for p in d.iterdir() if p.name.endswith(".tmp"))


# -- a full disk --------------------------------------------------------------------------------


def test_full_disk_midway_keeps_the_previous_result(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    make(1).save(tmp_path)

    def full(f: object, res: rf.Result) -> None:  # fields.npz is written, result.vtu is not
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(result_mod, "write_vtu", full)
    with pytest.raises(rf.OutputError, match="No space left") as e:
        make(2).save(tmp_path)
    assert isinstance(e.value, OSError) and isinstance(e.value, rf.RustfracError)
    assert str(tmp_path) in str(e.value)
    assert coherent(rf.load(tmp_path)) == 1  # the previous result, whole
    assert temporaries(tmp_path) == []


def test_stale_files_of_an_earlier_save_are_removed(tmp_path: Path) -> None:
    make(1).save(tmp_path)
    (tmp_path / "s22.png").write_bytes(b"plot of run 1")
    make(2).save(tmp_path, vtu=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fields.npz", "result.json"]
    assert coherent(rf.load(tmp_path)) == 2


def test_other_files_in_the_folder_are_kept(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("mine")
    make(1).save(tmp_path)
    make(2).save(tmp_path)
    assert (tmp_path / "notes.txt").read_text() == "mine"


# -- a killed writer ----------------------------------------------------------------------------

KILLED = """
import os, signal, sys, time
from pathlib import Path
sys.path.insert(0, {tests!r})
import rustfrac.result as rm
import rustfrac._folder as fm
from test_result_folder import make
out, when = Path({out!r}), {when!r}
if when == "while staging":
    def slow(f, res):
        Path({marker!r}).write_text("staging")
        time.sleep(60)
    rm.write_vtu = slow
else:  # between the renames of the commit: after fields.npz, before result.json
    real = os.replace
    def replace(src, dst):
        real(src, dst)
        if str(dst).endswith("fields.npz"):
            os.kill(os.getpid(), signal.SIGKILL)
    fm.os.replace = replace
make(2).save(out)
"""


def _killed_writer(tmp_path: Path, when: str) -> Path:
    out = tmp_path / "res"
    make(1).save(out)
    marker = tmp_path / "marker"
    code = KILLED.format(
        tests=str(Path(__file__).parent), out=str(out), when=when, marker=str(marker)
    )
    p = subprocess.Popen([sys.executable, "-c", textwrap.dedent(code)])
    if when == "while staging":
        t0 = time.monotonic()
        while not marker.exists():
            assert p.poll() is None, "the writer ended early"
            assert time.monotonic() - t0 < 60
            time.sleep(0.02)
        p.send_signal(signal.SIGKILL)
    assert p.wait(timeout=60) == -signal.SIGKILL
    return out


def test_writer_killed_while_staging_leaves_the_previous_result(tmp_path: Path) -> None:
    out = _killed_writer(tmp_path, "while staging")
    assert coherent(rf.load(out)) == 1
    make(3).save(out)  # the folder stays usable
    assert coherent(rf.load(out)) == 3


def test_writer_killed_between_renames_is_refused_not_mixed(tmp_path: Path) -> None:
    out = _killed_writer(tmp_path, "between renames")
    with pytest.raises(rf.InvalidResultError, match="two saves") as e:
        rf.load(out)
    assert e.value.path == out / "fields.npz"
    make(3).save(out)  # the next save repairs it
    assert coherent(rf.load(out)) == 3


# -- concurrent writers -------------------------------------------------------------------------

WRITER = """
import sys
sys.path.insert(0, {tests!r})
from test_result_folder import make
for r in range({rounds}):
    make({k}).save({out!r})
"""

READER = """
import sys, time
sys.path.insert(0, {tests!r})
import rustfrac as rf
from test_result_folder import coherent
seen, bad = set(), 0
t0 = time.monotonic()
while time.monotonic() - t0 < {seconds}:
    try:
        seen.add(coherent(rf.load({out!r})))
    except rf.ResultNotFoundError:
        pass  # before the first save
    except Exception as e:
        bad += 1
        print(type(e).__name__, e, file=sys.stderr)
print(len(seen), bad)
"""


def test_concurrent_writers_never_mix(tmp_path: Path) -> None:
    out, tests = str(tmp_path / "res"), str(Path(__file__).parent)
    writers, rounds = 6, 5
    reader = subprocess.Popen(
        [sys.executable, "-c", READER.format(tests=tests, out=out, seconds=8)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", WRITER.format(tests=tests, out=out, k=k, rounds=rounds)],
            stderr=subprocess.PIPE,
            text=True,
        )
        for k in range(1, writers + 1)
    ]
    for p in procs:
        _, err = p.communicate(timeout=300)
        assert p.returncode == 0, err  # every writer wins in turn: none fails
    final = coherent(rf.load(out))
    assert 1 <= final <= writers
    stdout, stderr = reader.communicate(timeout=300)
    _n_seen, n_bad = map(int, stdout.split())
    assert n_bad == 0, stderr  # every load while they wrote gave one whole run
    assert temporaries(Path(out)) == []


# -- what rf.load refuses -------------------------------------------------------------------------


def _edit(d: Path, change: dict) -> None:
    doc = json.loads((d / "result.json").read_text())
    doc.update(change)
    (d / "result.json").write_text(json.dumps(doc))


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"format_version": 99}, "format_version"),
        ({"format_version": True}, "format_version"),
        ({"format": "other"}, "format"),
        ({"method": "magic"}, "method"),
        ({"n_dofs": -1}, "n_dofs"),
        ({"n_dofs": 2.5}, "n_dofs"),
        ({"wall_time_s": None}, "wall_time_s"),
        ({"sigma22": "big"}, "sigma22"),
        ({"scalars": [1]}, "scalars"),
        ({"fields": ["coords", "u"]}, "fields"),
        ({"shapes": {"coords": [3, 2]}}, "coords"),
    ],
)
def test_load_refuses_invalid_values_naming_the_field(
    tmp_path: Path, change: dict, field: str
) -> None:
    make(1, n=10).save(tmp_path)
    _edit(tmp_path, change)
    with pytest.raises(rf.InvalidResultError) as e:
        rf.load(tmp_path)
    assert e.value.field == field or field in str(e.value), str(e.value)
    assert str(tmp_path) in str(e.value)
    assert isinstance(e.value, ValueError) and isinstance(e.value, rf.RustfracError)


@pytest.mark.parametrize("token", ["NaN", "Infinity", "-Infinity", "1e999"])
def test_load_refuses_non_finite_numbers(tmp_path: Path, token: str) -> None:
    make(1, n=10).save(tmp_path)
    text = (tmp_path / "result.json").read_text()
    (tmp_path / "result.json").write_text(text.replace('"cmod": 0.0', f'"cmod": {token}'))
    with pytest.raises(rf.InvalidResultError, match=r"finite|not allowed") as e:
        rf.load(tmp_path)
    assert "result.json" in str(e.value)


def test_load_refuses_arrays_that_do_not_match(tmp_path: Path) -> None:
    r = make(1, n=10)
    r.fields["elements"] = np.array([[0, 1, 2, 99]])  # node 99 of 10
    r.save(tmp_path)
    with pytest.raises(rf.InvalidResultError, match=r"elements must be indices in \[0, 10\)"):
        rf.load(tmp_path)
    r.fields["elements"] = np.array([[0, 1, 2, 3]])
    r.fields["u"] = np.zeros(7)
    r.save(tmp_path)
    with pytest.raises(rf.InvalidResultError, match=r"array u must be \(20,\) floats") as e:
        rf.load(tmp_path)
    assert e.value.field == "u"


@pytest.mark.parametrize(
    ("name", "content", "needle"),
    [
        ("result.json", b"{not json", "not valid JSON"),
        ("result.json", b"[1, 2]", "expected a JSON object"),
        ("result.json", b"\xff\xfe", "not UTF-8"),
        ("result.json", b"[" * 100_000 + b"]" * 100_000, "nested too deeply|not valid JSON"),
        ("fields.npz", b"PK\x03\x04 truncated", "two saves"),
    ],
)
def test_load_errors_are_rustfrac_errors(
    tmp_path: Path, name: str, content: bytes, needle: str
) -> None:
    make(1, n=10).save(tmp_path)
    (tmp_path / name).write_bytes(content)
    with pytest.raises(rf.InvalidResultError, match=needle) as e:
        rf.load(tmp_path)
    assert name in str(e.value)


def test_load_of_a_damaged_old_format_npz(tmp_path: Path) -> None:
    make(1, n=10).save(tmp_path)
    _edit(tmp_path, {"format_version": 1})  # no checksums in version 1: the archive is read
    (tmp_path / "fields.npz").write_bytes(b"PK\x03\x04 truncated")
    with pytest.raises(rf.InvalidResultError, match=r"not a readable NumPy \.npz archive"):
        rf.load(tmp_path)


def test_load_of_a_missing_folder_or_file(tmp_path: Path) -> None:
    with pytest.raises(rf.ResultNotFoundError, match="no result folder"):
        rf.load(tmp_path / "nope")
    make(1, n=10).save(tmp_path)
    os.unlink(tmp_path / "fields.npz")
    with pytest.raises(FileNotFoundError, match=r"fields\.npz"):  # a ResultNotFoundError
        rf.load(tmp_path)


def test_version_1_results_still_load(tmp_path: Path) -> None:
    make(1, n=10).save(tmp_path)
    doc = json.loads((tmp_path / "result.json").read_text())
    for k in ("save_id", "shapes", "files"):
        del doc[k]
    doc["format_version"] = 1
    (tmp_path / "result.json").write_text(json.dumps(doc))
    assert rf.load(tmp_path).meta["writer"] == 1


def test_long_lists_are_written_compactly(tmp_path: Path) -> None:
    steps = list(range(1, 100_001))
    r = make(1, n=10)
    r.meta["scene"] = {"method": "pd", "pd": {"damage_at_steps": steps}}
    r.save(tmp_path)
    size = (tmp_path / "result.json").stat().st_size
    assert size < 1.1 * len(json.dumps(steps)) + 10_000  # not an indented line per item
    assert rf.load(tmp_path).meta["scene"]["pd"]["damage_at_steps"] == steps


def test_stage_each_stops_at_a_ctrl_c_and_discards_the_file_it_interrupted(
    tmp_path: Path,
) -> None:
    """The jobs' figures (run --plot, fig7, compare, sweep) are staged by
    ``FolderWriter.stage_each``: a Ctrl-C in one file's writer discards that file, writes none
    after it and commits those before it."""
    from rustfrac._folder import writing

    def text(s: str):  # type: ignore[no-untyped-def]
        return lambda p: Path(p).write_text(s)

    def interrupted(p: Path) -> None:
        Path(p).write_text("half")
        raise KeyboardInterrupt

    files = [("a.txt", text("a")), ("b.txt", interrupted), ("c.txt", text("c"))]
    with writing(tmp_path, owned=["a.txt", "b.txt", "c.txt", "last"], last="last") as w:
        done, stopped = w.stage_each(files)
        w.stage("last").write_text("x")
    assert done == ["a.txt"] and stopped
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "last"]
    with writing(tmp_path, owned=["a.txt", "c.txt", "last"], last="last") as w:
        assert w.stage_each(files[::2]) == (["a.txt", "c.txt"], False)
