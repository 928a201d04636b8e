"""The command line ``rustfrac run``."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

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
