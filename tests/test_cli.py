"""The command line ``rustfrac run``."""

from __future__ import annotations

import errno
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

import rustfrac as rf
from rustfrac.cli import main

E, NU, U0, L = 10000.0, 0.25, 0.01, 21.0


def test_run_uncracked(root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(
        ["run", str(rf.examples.path("paper_fem_uncracked.toml")), "--out", str(tmp_path / "out")]
    )
    assert code == 0
    log = capsys.readouterr().out
    assert "method fem" in log and "7560 unknowns" in log and "bc free" in log
    doc = json.loads((tmp_path / "out" / "result.json").read_text())
    assert doc["sigma22"] == pytest.approx(E / (1 - NU**2) * 2 * U0 / L, rel=1e-10)
    assert (tmp_path / "out" / "fields.npz").exists()
    assert (tmp_path / "out" / "result.vtu").exists()


def test_run_seam_quiet_plot(
    root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(
        [
            "run",
            str(rf.examples.path("paper_fem_seam.toml")),
            "--out",
            str(tmp_path),
            "--quiet",
            "--plot",
        ]
    )
    assert code == 0
    assert capsys.readouterr().out == ""
    res = rf.load(tmp_path)
    assert res.cmod > 0
    assert res.meta["seam_y"] == pytest.approx(10.5, abs=1e-12)  # ny = 84: exact grid line
    assert (tmp_path / "s22.png").exists()


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ('method = "fem"\n[material]\nnu = 0.5\n', "material.nu"),
        ('method = "fem"\n[mesh]\nnx = 0\n', "mesh.nx"),
        ('method = "fem"\n[mesh]\nnz = 3\n', "mesh.nz"),
        ("[mesh]\nnx = 3\n", "method"),
        ('method = "pd"\n[material]\nnu = 0.3\n', "material.nu"),
        ('method = "xfem"\n[xfem]\nnsub = 0\n', "xfem.nsub"),
    ],
)
def test_bad_scene_exit_code_2(
    text: str, needle: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    f = tmp_path / "bad.toml"
    f.write_text(text)
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert needle in err
    assert not (tmp_path / "o").exists()


def test_missing_file_exit_code_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(tmp_path / "nope.toml"), "--out", str(tmp_path)]) == 2
    assert "cannot read scene" in capsys.readouterr().err


def test_singular_exit_code_1(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    f = tmp_path / "s.toml"
    f.write_text('method = "fem"\n[crack]\nkind = "none"\n')

    def singular(*_a: object, **_k: object) -> None:
        raise rf.SingularSystemError("singular stiffness (a rigid mode)")

    monkeypatch.setattr("rustfrac.runner.run", singular)
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 1
    assert "SingularSystemError" in capsys.readouterr().err


def test_one_point_gauss_is_invalid_input_exit_code_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    f = tmp_path / "s.toml"
    f.write_text('method = "fem"\n[crack]\nkind = "none"\n[mesh]\ngauss = 1\n')
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 2
    assert "mesh.gauss" in capsys.readouterr().err


def test_console_script(root: Path, tmp_path: Path) -> None:
    exe = shutil.which("rustfrac", path=str(Path(sys.executable).parent))
    cmd = [exe] if exe else [sys.executable, "-m", "rustfrac.cli"]
    p = subprocess.run(
        [*cmd, "run", str(rf.examples.path("paper_fem_uncracked.toml")), "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert p.returncode == 0, p.stderr
    assert "unknowns" in p.stdout


# -- output problems are found before computing, or the result is kept -----------------------------

UNCRACKED = "paper_fem_uncracked.toml"


@pytest.fixture
def no_run(monkeypatch: pytest.MonkeyPatch) -> list[object]:
    """Records calls of rf.run instead of running (a bad --out must be refused before)."""
    import rustfrac.runner

    calls: list[object] = []
    monkeypatch.setattr(rustfrac.runner, "run", lambda *a, **k: calls.append(a))
    return calls


def test_out_naming_a_file_is_refused_before_the_run(
    root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], no_run: list[object]
) -> None:
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["run", str(rf.examples.path(UNCRACKED)), "--out", str(f)]) == 2
    err = capsys.readouterr().err
    assert f"{f}: it is a file, not a folder" in err and "Traceback" not in err
    assert no_run == []
    assert main(["run", str(rf.examples.path(UNCRACKED)), "--out", str(f / "sub")]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_read_only_out_is_refused_before_the_run(
    root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], no_run: list[object]
) -> None:
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        assert main(["run", str(rf.examples.path(UNCRACKED)), "--out", str(ro / "o")]) == 2
    finally:
        ro.chmod(0o755)
    assert "Permission denied" in capsys.readouterr().err
    assert no_run == []


@pytest.mark.parametrize("problem", ["read-only", "full"])
def test_unwritable_or_full_out_is_refused_before_the_run(
    root: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    no_run: list[object],
    problem: str,
) -> None:
    import rustfrac._folder as folder

    if problem == "read-only":
        real_open = os.open

        def ro_open(path: object, flags: int, *a: object, **k: object) -> int:
            if flags & os.O_CREAT:
                raise OSError(errno.EROFS, "Read-only file system", str(path))
            return real_open(path, flags, *a, **k)

        monkeypatch.setattr(folder.os, "open", ro_open)
    else:
        real = os.statvfs
        monkeypatch.setattr(
            folder.os,
            "statvfs",
            lambda p: (
                type("S", (), {"f_bavail": 3, "f_frsize": 4096})
                if str(p) == str(tmp_path)
                else real(p)
            ),
        )
    assert main(["run", str(rf.examples.path(UNCRACKED)), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert str(tmp_path / "o") in err
    assert ("Read-only file system" if problem == "read-only" else "12288 bytes free") in err
    assert no_run == []


def test_save_failing_at_the_end_keeps_the_result_in_a_fallback(
    root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from rustfrac.result import Result

    out = tmp_path / "o"
    real = Result._stage

    def full_disk(self: Result, w: Any, **kw: Any) -> str:
        if w.path == out:
            raise OSError(errno.ENOSPC, "No space left on device", str(out / "fields.npz"))
        return real(self, w, **kw)

    monkeypatch.setattr(Result, "_stage", full_disk)
    assert main(["run", str(rf.examples.path(UNCRACKED)), "--out", str(out), "-q"]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert f"cannot write output folder {out}: No space left on device" in err
    fallback = Path(err.split("saved to ")[1].split(" instead")[0])
    assert fallback != out and rf.load(fallback).method == "fem"
    shutil.rmtree(fallback)


def test_ctrl_c_while_plotting_keeps_the_result(
    root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import rustfrac.plotting

    def interrupted(*a: object, **k: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(rustfrac.plotting, "plot_field", interrupted)
    code = main(
        ["run", str(rf.examples.path("paper_fem_seam.toml")), "--out", str(tmp_path), "--plot"]
    )
    assert code == 130
    assert "without s22.png" in capsys.readouterr().err
    assert rf.load(tmp_path).cmod > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fields.npz", "result.json", "result.vtu"]


def test_console_runs_main_then_freezes_the_heap(monkeypatch: pytest.MonkeyPatch) -> None:
    """The command's entry point: main's exit code, then gc.freeze() (a cheap shutdown)."""
    import gc

    from rustfrac import cli

    calls: list[str] = []
    monkeypatch.setattr(cli, "main", lambda: calls.append("main") or 7)
    monkeypatch.setattr(gc, "freeze", lambda: calls.append("freeze"))
    assert cli.console() == 7
    assert calls == ["main", "freeze"]


class _Terminal:
    """A text stream that says it is a terminal (the bar then ends its drawings with CR)."""

    def __init__(self) -> None:
        self.parts: list[str] = []

    def write(self, s: str) -> int:
        self.parts.append(s)
        return len(s)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return True


def test_job_console_lines_stay_whole_beside_a_bar_and_another_thread(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """fig7 and compare log from two threads (CCM-PD beside the XFEM runs) while a bar draws on
    the terminal: a log line is one write, and a bar's line is ended first, so neither
    overwrites the other (one line of each once seen: "...m=4run xfem: ..." and a result line
    over the bar's last drawing)."""
    import io
    import threading

    from rustfrac import cli
    from rustfrac.progress import ProgressBar

    term = _Terminal()
    out = io.StringIO()
    writes: list[str] = []

    class Recorded(io.StringIO):
        def write(self, s: str) -> int:  # every write, as the terminal gets them
            writes.append(s)
            return out.write(s)

    monkeypatch.setattr(sys, "stdout", Recorded())
    bars: list[ProgressBar] = []
    log, progress = cli.job_console(bars, quiet=False)
    assert log is not None
    bar = progress("ccm_pd")
    assert bar is not None
    bar.stream, bar.delay = term, 0.0
    bar(1, 10, "sla: step 1/10")
    assert bar.mid_line
    log("        result of ccm_pd")  # after the bar's drawing: its line ended first
    assert term.parts[-1] == "\n" and not bar.mid_line

    def many(name: str) -> None:
        for i in range(200):
            log(f"run     {name} {i}")

    threads = [threading.Thread(target=many, args=(n,)) for n in ("ccm_pd", "xfem")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    lines = out.getvalue().splitlines()
    assert len(lines) == 401 and all(w.endswith("\n") for w in writes)
    for name in ("ccm_pd", "xfem"):
        assert [ln for ln in lines if ln.startswith(f"run     {name} ")] == [
            f"run     {name} {i}" for i in range(200)
        ]
    quiet_log, quiet_progress = cli.job_console([], quiet=True)
    assert quiet_log is None and quiet_progress("x") is None
