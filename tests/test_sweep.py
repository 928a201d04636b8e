"""The speed-accuracy sweep (``rustfrac sweep``): local pool against a local dask cluster, errors,
Richardson extrapolation, presets and the files of the CLI."""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path
from typing import Any

import pytest

from rustfrac.cli import main
from rustfrac.sweep import NUMERIC_KEYS, QUANTITIES, define_points, richardson, sweep

FILES = ("sweep.csv", "sweep.json", "sweep.md", "sweep_xfem.png", "sweep_ccm_pd.png")


@pytest.fixture(scope="module")
def tiny(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    """The tiny preset through the CLI (local process pool, 2 workers)."""
    out = tmp_path_factory.mktemp("sweep")
    assert main(["sweep", "--out", str(out), "--preset", "tiny", "--workers", "2", "-q"]) == 0
    return out, json.loads((out / "sweep.json").read_text())


def test_cli_writes_every_file(tiny: tuple[Path, dict[str, Any]]) -> None:
    out, doc = tiny
    for name in FILES:
        assert (out / name).stat().st_size > 0, name
    assert not list(out.glob(".*.tmp"))  # atomic writes leave no temporaries
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert len(rows) == len(doc["points"]) == len(define_points("tiny"))
    assert {r["method"] for r in rows} == {"xfem", "ccm_pd"}
    md = (out / "sweep.md").read_text()
    assert "## References" in md and "## Presets" in md
    for method in ("xfem", "ccm_pd"):
        assert set(doc["presets"][method]) == {"fast", "balanced", "accurate"}
        for p in doc["presets"][method].values():
            assert p["scene"]["method"] == method
    for r in doc["points"]:
        assert r["wall_time_s"] > 0 and r["peak_rss_mb"] > 0 and r["n_dofs"] > 0
        assert r["peak_sigma22"] is not None  # growth / SLA runs: the load path's peak
        if r["method"] == "ccm_pd":
            assert r["n_bonds"] > 0 and r["K_I"] is None
        else:
            assert r["K_I"] > 0


def test_dask_cluster_gives_identical_numbers(tiny: tuple[Path, dict[str, Any]]) -> None:
    distributed = pytest.importorskip("distributed")
    _, doc = tiny
    points = define_points("tiny")
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:  # fmt: skip
        remote = sweep(points, scheduler=client)
        # a scheduler address (as `rustfrac sweep --scheduler tcp://...` passes it)
        by_address = sweep(points[:2], scheduler=cluster.scheduler_address)
    assert len(remote) == len(doc["points"])
    for a, b in zip(remote, by_address):
        assert all(a[k] == b[k] for k in NUMERIC_KEYS)
    for a, b in zip(doc["points"], remote):
        assert a["name"] == b["name"]
        for k in NUMERIC_KEYS:
            assert a[k] == b[k], (a["name"], k)  # bit for bit (JSON round-trips floats exactly)


def test_finest_level_error_is_zero(tiny: tuple[Path, dict[str, Any]]) -> None:
    _, doc = tiny
    for method, study in (("xfem", "mesh"), ("ccm_pd", "dx")):
        levels = [r for r in doc["points"] if r["method"] == method and r["study"] == study]
        finest = min(levels, key=lambda r: r["h"])
        for q in QUANTITIES:
            if finest[q] is not None:
                assert finest[f"err_finest_{q}"] == 0.0
                ref = doc["references"][method][q]
                if ref["kind"] == "finest":
                    assert finest[f"err_{q}"] == 0.0
                else:
                    assert ref["rate"] is not None and 0.5 <= ref["rate"] <= 6


def test_xfem_errors_decrease_with_refinement(tiny: tuple[Path, dict[str, Any]]) -> None:
    _, doc = tiny
    levels = sorted(
        (r for r in doc["points"] if r["method"] == "xfem" and r["study"] == "mesh"),
        key=lambda r: -r["h"],
    )
    assert len(levels) == 3
    for q in ("K_I", "cmod"):
        errs = [r[f"err_finest_{q}"] for r in levels]
        assert errs[0] > errs[1] > errs[2] == 0.0, (q, errs)


def test_richardson_recovers_a_known_rate() -> None:
    hs = (0.4, 0.2, 0.1)
    ext, p = richardson(hs, [3.0 + 0.7 * h**2 for h in hs])
    assert ext == pytest.approx(3.0, rel=1e-9) and p == pytest.approx(2.0, rel=1e-6)
    ext, p = richardson((0.3, 0.2, 0.1), [1.0 - 0.5 * h**1.5 for h in (0.3, 0.2, 0.1)])
    assert ext == pytest.approx(1.0, rel=1e-9) and p == pytest.approx(1.5, rel=1e-6)
    assert richardson(hs, [1.0, 2.0, 1.5]) is None  # oscillating: no consistent rate


def test_missing_dask_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(ImportError, match=r"rustfrac\[dask\]"):
        sweep(define_points("tiny")[:1], scheduler="tcp://127.0.0.1:1")


def test_ctrl_c_keeps_finished_points(tmp_path: Path) -> None:
    from rustfrac.sweep import SweepInterrupted, write_outputs

    points = [p for p in define_points("tiny") if p["method"] == "xfem"][:3]

    def stop(done: int, total: int, message: str) -> None:
        raise KeyboardInterrupt  # as Ctrl-C arriving after the first finished point

    with pytest.raises(SweepInterrupted) as exc:
        sweep(points, workers=1, progress=stop)
    done = exc.value.records
    # the first point, and the one running when the interrupt came (one worker, queue cancelled)
    assert 1 <= len(done) <= 2 and all(r["K_I"] > 0 for r in done)
    doc = write_outputs(tmp_path, points, done, extra={"interrupted": True})
    assert doc["interrupted"] and len(doc["points"]) == len(done)
    assert (tmp_path / "sweep.csv").exists() and (tmp_path / "sweep.md").exists()


# -- partial outputs marked --------------------------------------------------------------------


def test_ctrl_c_while_plotting_marks_the_sweep_incomplete(
    tiny: tuple[Path, dict[str, Any]], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from rustfrac import sweep as sweep_mod
    from rustfrac.sweep import SweepInterrupted, write_outputs

    _, full = tiny
    assert full["complete"] is True and full["missing_points"] == full["missing_files"] == []
    real = sweep_mod.plot

    def plot(records: Any, method: str, path: Path) -> None:
        if method == "xfem":
            path.write_bytes(b"half a png")
            raise KeyboardInterrupt
        real(records, method, path)

    monkeypatch.setattr(sweep_mod, "plot", plot)
    with pytest.raises(SweepInterrupted) as e:
        write_outputs(tmp_path, define_points("tiny"), full["points"])
    doc = json.loads((tmp_path / "sweep.json").read_text())
    assert doc == e.value.doc
    assert doc["interrupted"] is True and doc["complete"] is False
    assert doc["missing_files"] == ["sweep_xfem.png"] and doc["missing_points"] == []
    assert not (tmp_path / "sweep_xfem.png").exists() and (tmp_path / "sweep_ccm_pd.png").exists()
    assert not list(tmp_path.glob(".*.tmp"))


def test_missing_points_are_listed(tiny: tuple[Path, dict[str, Any]], tmp_path: Path) -> None:
    from rustfrac.sweep import write_outputs

    _, full = tiny
    points = define_points("tiny")
    doc = write_outputs(tmp_path, points, full["points"][:-2])
    assert doc["complete"] is False
    assert doc["missing_points"] == [p["scene"]["name"] for p in points[-2:]]


def test_out_naming_a_file_fails_before_the_sweep(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from rustfrac import sweep as sweep_mod

    calls: list[object] = []
    monkeypatch.setattr(sweep_mod, "sweep", lambda *a, **k: calls.append(a))
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["sweep", "--out", str(f), "--preset", "tiny", "-q"]) == 2
    assert "it is a file, not a folder" in capsys.readouterr().err
    assert calls == []


# -- presets not picked by timer noise ---------------------------------------------------------


def test_presets_are_not_picked_by_timer_noise(tiny: tuple[Path, dict[str, Any]]) -> None:
    from rustfrac.sweep import choose_presets, pareto

    _, doc = tiny
    xfem = [r for r in doc["points"] if r["method"] == "xfem"]
    assert all(r["repeats"] == 3 and len(r["wall_times_s"]) == 3 for r in xfem)
    assert all(r["wall_time_s"] == min(r["wall_times_s"]) for r in xfem)
    # nsub 4 is the base mesh itself and r_I changes no compared quantity: the same choice as
    # the base mesh of the refinement study, whatever the timer says
    assert doc["presets"]["xfem"]["fast"]["point"] == "xfem mesh 44x83"
    base = next(r for r in xfem if r["name"] == "xfem mesh 44x83")
    for t in (0.5, 2.0):  # the twins faster or slower than the base mesh
        recs = [dict(r, wall_time_s=r["wall_time_s"] * t) if r["n_dofs"] == base["n_dofs"]
                and r["name"] != base["name"] else r for r in xfem]  # fmt: skip
        assert choose_presets(recs)["xfem"]["fast"]["point"] == "xfem mesh 44x83"
        assert sum(r["n_dofs"] == base["n_dofs"] for r in pareto(recs)) <= 2  # nsub 1 differs
