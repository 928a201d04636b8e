"""Ctrl-C (SIGINT) stops a long run promptly with or without a progress
callback, ends in a clean KeyboardInterrupt (never a PanicException) and keeps what finished:
``rf.run`` attaches it as ``e.result``, ``rustfrac run`` writes it to ``--out`` and exits 130."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

# a CCM-PD run of many cheap steps (coarse grid) and an XFEM growth of many states: each runs
# far longer than the time before the signal


def _sigint_default() -> None:
    """The child starts with SIGINT at its default, as in a terminal: a runner that starts the
    suite in the background (SIGINT ignored, inherited through exec) must not hide the handling
    under test (Python installs its KeyboardInterrupt handler only if SIGINT is not ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


SCENES = {
    "ccm_pd": 'method = "ccm_pd"\n[pd]\nsize = [5.0, 2.0]\ncenter = [2.8, 10.5]\nsla_steps = 200000\n',
    "xfem": 'method = "xfem"\n[mesh]\nnx = 88\nny = 166\n[xfem]\ngrowth_steps = 400\nda = 0.005\n',
}


def _interrupt(
    cmd: list[str], after: float, cwd: Path, env: dict[str, str]
) -> tuple[int, str, float]:
    p = subprocess.Popen(
        cmd,
        cwd=cwd,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=_sigint_default,
    )
    time.sleep(after)
    assert p.poll() is None, "the run ended before the signal"
    t0 = time.perf_counter()
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    return p.returncode, err, time.perf_counter() - t0


@pytest.mark.parametrize("method", ["ccm_pd", "xfem"])
def test_cli_ctrl_c_keeps_the_finished_part(
    tmp_path: Path, method: str, child_env: dict[str, str]
) -> None:
    scene = tmp_path / "s.toml"
    scene.write_text(SCENES[method])
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "rustfrac.cli", "run", str(scene), "--out", str(out), "-q"]
    code, err, waited = _interrupt(cmd, 4.0, tmp_path, child_env)
    print(f"{method}: exit {code} {waited:.2f} s after SIGINT; stderr: {err.strip()[-300:]}")
    assert code == 130, err
    assert "PanicException" not in err and "Traceback" not in err, err
    # a liveness bound, not a timing claim: the run (200 000 steps, or 400 growth steps) must
    # stop at the next step; a dense condensation in progress cannot be interrupted (about 5 s
    # here on a quiet machine, several times that on a loaded one)
    assert waited < 40.0
    meta = json.loads((out / "result.json").read_text())["meta"]
    assert meta["status"] == "cancelled"
    assert "finished part" in err


def test_rf_run_without_callback_is_interrupted(child_env: dict[str, str]) -> None:
    script = textwrap.dedent(
        """
        import rustfrac as rf
        try:
            rf.run(rf.Scene.from_dict({"method": "ccm_pd", "pd": {"size": [5.0, 2.0],
                   "center": [2.8, 10.5], "sla_steps": 200000}}))
            print("finished")
        except KeyboardInterrupt as e:
            r = e.result
            print("interrupted", r.meta["status"], r.meta["sla_steps_done"],
                  len(r.history["sigma22"]))
        """
    )
    p = subprocess.Popen(
        [sys.executable, "-c", script],
        env=child_env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=_sigint_default,
    )
    time.sleep(4.0)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    print(out, err[-300:])
    assert p.returncode == 0, err
    words = out.split()
    assert words[:2] == ["interrupted", "cancelled"], out
    steps, rows = int(words[2]), int(words[3])
    assert steps > 0 and rows == steps + 1  # the origin row and every finished step
