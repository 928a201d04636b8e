"""The command line's logs and exit codes: a batch log gets at most one progress line every few
seconds, ``-v`` / ``--log-level`` show the package's log, inputs that do not exist (a result
folder, a checkpoint) are bad input (exit 2), and derived numbers in messages print short."""

from __future__ import annotations

import io
import logging
from pathlib import Path

import pytest

import rustfrac as rf
from rustfrac._log import logger
from rustfrac.cli import main
from rustfrac.progress import LOG_INTERVAL_S, ProgressBar


class _Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_progress_in_a_log_file_is_one_line_every_few_seconds() -> None:
    clock, out = _Clock(), io.StringIO()  # StringIO is not a terminal
    bar = ProgressBar(stream=out, delay=0.0, clock=clock)
    for i in range(201):  # 20 s of reports every 0.1 s, as the native side sends them
        clock.t = 0.1 * i
        bar(i, 200, f"step {i}")
    lines = out.getvalue().splitlines()
    assert len(lines) <= 20 / LOG_INTERVAL_S + 2, len(lines)
    assert lines[0].endswith("step 0") and "100.0%" in lines[-1]  # first and last are there


def test_progress_on_a_terminal_keeps_redrawing() -> None:
    class Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    clock, out = _Clock(), Tty()
    bar = ProgressBar(stream=out, delay=0.0, clock=clock)
    for i in range(50):
        clock.t = 0.1 * i
        bar(i, 100, "x")
    assert out.getvalue().count("\r") == 50


def test_verbose_and_log_level_show_the_package_log(capsys: pytest.CaptureFixture[str]) -> None:
    def emit(args: list[str]) -> str:
        # `examples` runs nothing; log from inside the command through a patched command table
        import rustfrac.cli as cli

        orig = cli.cmd_examples

        def cmd(a: object) -> int:
            logger.info("info line")
            logger.debug("debug line")
            logger.warning("warning line")
            return 0

        cli.cmd_examples = cmd  # type: ignore[assignment]
        try:
            assert main([*args, "examples"]) == 0
        finally:
            cli.cmd_examples = orig  # type: ignore[assignment]
        return capsys.readouterr().err

    err = emit([])
    assert "warning line" in err and "info line" not in err
    err = emit(["-v"])
    assert "rustfrac: INFO: info line" in err and "debug line" not in err
    assert "debug line" in emit(["-vv"])
    err = emit(["--log-level", "error"])
    assert "warning line" not in err
    with pytest.raises(SystemExit) as e:
        main(["--log-level", "loud", "examples"])
    assert e.value.code == 2
    logger.setLevel(logging.NOTSET)


def test_missing_inputs_are_bad_input(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["plot", "load-path", str(tmp_path / "none"), "--x", "cmod", "--y", "sigma22"]
    assert main([*argv, "-o", str(tmp_path / "p.png")]) == 2
    assert "no result folder" in capsys.readouterr().err
    scene = rf.examples.path("pd_coarse.toml")
    out, ckpt = tmp_path / "o", tmp_path / "missing.ckpt"
    assert main(["run", str(scene), "--out", str(out), "--resume", str(ckpt)]) == 2
    err = capsys.readouterr().err
    assert "--resume" in err and "missing" in err and not out.exists()  # refused before running
    assert main(["run", str(scene), "--out", str(out), "--resume", str(tmp_path)]) == 2
    assert "not a regular file" in capsys.readouterr().err


def test_growth_progress_prints_derived_lengths_short() -> None:
    seen: list[str] = []
    # to a_stop = 0.7 x 11 (~1 s: the native side reports at most every 0.1 s)
    scene = rf.scenes.edge_crack_plate(method="xfem", growth_steps=1000)
    rf.run(scene, progress=lambda d, t, m: seen.append(m))
    msgs = [m for m in seen if "a_stop" in m]
    assert msgs and all("a_stop 7.7)" in m for m in msgs), msgs[:2]
