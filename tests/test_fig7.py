"""The main job (``rustfrac fig7``) in its fast preset: every file, reloadable results, the two
methods' agreement, and a clean interruption."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import agreement
from rustfrac.cli import main
from rustfrac.fig7 import fig7

FILES = ["fig7.png", "fig7.csv", "fig8a.png", "fig8b.png", "fig6.png", "summary.md", "summary.json"]

#: Agreement of XFEM (LEFM) and CCM-PD on the fast preset. The paper-preset run gives a peak
#: sigma22 difference of a few per cent (benches/RESULTS.md, "Fig. 7"); the coarse PD grid of the
#: fast preset (dx = 0.2, horizon 0.8) adds its own discretisation error, so the tolerances
#: are wider but still fail on any real disagreement (a wrong s0, c or load scaling moves the peak
#: by tens of per cent).
PEAK_TOL = 0.15
INITIAL_CMOD_TOL = 0.15


@pytest.fixture(scope="module")
def fast_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("fig7")
    summary = fig7(out, preset="fast", log=None)
    return out, summary


def test_s0_calibration_rescales_the_ccm_pd_curve(
    fast_run: tuple[Path, dict], tmp_path: Path
) -> None:
    """``fig7(..., s0_calibration="sla")`` (``rustfrac fig7 --s0-calibration sla``): the CCM-PD
    run's s0 is rescaled by the calibration's factor, so its peak is the default run's times the
    factor (the same bonds break; the XFEM runs are untouched)."""
    _, base = fast_run
    summary = fig7(tmp_path, preset="fast", s0_calibration="sla", log=None)
    cal = rf.load(tmp_path / "ccm_pd").meta["s0_calibration"]
    assert cal["rule"] == "sla" and 0.8 < cal["factor"] < 0.99
    ours, ref = summary["ours"], base["ours"]
    assert ours["peak_sigma22_ccm_pd"] == pytest.approx(
        cal["factor"] * ref["peak_sigma22_ccm_pd"], rel=1e-9
    )
    assert ours["peak_sigma22_xfem"] == ref["peak_sigma22_xfem"]
    with pytest.raises(SystemExit) as e:  # argparse: the choices come from the core's schema
        main(["fig7", "--out", str(tmp_path / "x"), "--s0-calibration", "exact"])
    assert e.value.code == 2


def test_every_file_is_written(fast_run: tuple[Path, dict]) -> None:
    out, summary = fast_run
    for f in FILES:
        assert (out / f).is_file() and (out / f).stat().st_size > 0, f
    assert not list(out.glob(".*.tmp")), "temporary files left behind"
    assert json.loads((out / "summary.json").read_text())["files"] == summary["files"]


def test_curves_start_at_the_origin_and_agree(fast_run: tuple[Path, dict]) -> None:
    out, summary = fast_run
    rows = list(csv.DictReader((out / "fig7.csv").open()))
    for method in ("xfem", "ccm_pd", "handbook"):
        pts = [r for r in rows if r["method"] == method]
        assert len(pts) > 5, method
        assert float(pts[0]["sigma22"]) == 0.0 and float(pts[0]["cmod"]) == 0.0
    ag = summary["agreement"]
    print(json.dumps(ag, indent=1))
    assert abs(ag["peak_sigma22_rel_diff"]) < PEAK_TOL
    assert abs(ag["initial_cmod_rel_diff"]) < INITIAL_CMOD_TOL
    ours = summary["ours"]
    assert ours["ccm_pd_status"] in ("completed", "crack_length_reached")
    assert ours["xfem_growth_status"] == "a_stop_reached"


def test_saved_results_reload_to_the_same_numbers(fast_run: tuple[Path, dict]) -> None:
    out, summary = fast_run
    x = rf.load(out / "xfem")
    p = rf.load(out / "ccm_pd")
    assert float(np.max(x.history["sigma22"])) == summary["ours"]["peak_sigma22_xfem"]
    assert float(np.max(p.history["sigma22"])) == summary["ours"]["peak_sigma22_ccm_pd"]
    assert p.gamma == pytest.approx(summary["ours"]["gamma"], rel=0, abs=0)


def test_interruption_keeps_what_finished(tmp_path: Path) -> None:
    def progress(name: str):
        if name != "ccm_pd":
            return None

        def cb(done: int, total: int, message: str) -> None:
            raise KeyboardInterrupt

        return cb

    with pytest.raises(KeyboardInterrupt):
        fig7(tmp_path, preset="fast", log=None, progress=progress)
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["interrupted"] is True
    assert "peak_sigma22_xfem" in s["ours"] and "peak_sigma22_ccm_pd" not in s["ours"]
    x = rf.load(tmp_path / "xfem")
    assert len(x.history["sigma22"]) > 5
    assert (tmp_path / "fig7.png").is_file()


# -- CCM-PD beside the XFEM runs, Fig. 8b drawn meanwhile -----------------------------------


def test_ctrl_c_in_an_xfem_run_cancels_the_ccm_pd_run_beside_it(tmp_path: Path) -> None:
    """CCM-PD runs in a worker thread beside the XFEM runs. A Ctrl-C meets the XFEM run of the
    calling thread; the CCM-PD run is then cancelled at its next progress report (not left to
    finish, and not called on after). Its first report waits here until the interrupt, so the
    race is decided."""
    import threading

    interrupt = threading.Event()
    after: list[int] = []

    def progress(name: str):
        if name == "xfem_growth":

            def stop(done: int, total: int, message: str) -> None:
                interrupt.set()
                raise KeyboardInterrupt

            return stop
        if name == "ccm_pd":

            def wait(done: int, total: int, message: str) -> None:
                if interrupt.is_set():
                    after.append(done)
                assert interrupt.wait(60.0)

            return wait
        return None

    with pytest.raises(KeyboardInterrupt) as e:
        fig7(tmp_path, preset="fast", log=None, progress=progress)
    s = e.value.summary
    assert s["interrupted"] is True and "run ccm_pd" in s["missing"]
    assert "run xfem" not in s["missing"] and "run xfem_growth" in s["missing"]
    assert after == []  # the cancel stops the run before the job's own callback
    assert not (tmp_path / "ccm_pd").exists()


def test_an_error_of_the_ccm_pd_run_beside_reaches_the_caller(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from rustfrac import study

    real = study.run
    failed = threading.Event()
    xfem_runs: list[str] = []

    def failing(scene, **k):  # type: ignore[no-untyped-def]
        if scene.method == "ccm_pd":
            failed.set()
            raise rf.InvalidParameterError("invalid pd.dx: injected", "pd.dx")
        assert failed.wait(30)  # the first XFEM run ends after the failure
        xfem_runs.append(scene.name)
        return real(scene, **k)

    monkeypatch.setattr(study, "run", failing)
    with pytest.raises(rf.InvalidParameterError, match="injected"):
        fig7(tmp_path, preset="fast", log=None)
    assert len(xfem_runs) <= 1  # no XFEM run started after the failure
    # nothing written: xfem/, staged beside the failed run, was removed with its temporaries
    assert list(tmp_path.iterdir()) == []


def test_fig8b_drawn_beside_the_runs_is_the_figure_drawn_after(
    fast_run: tuple[Path, dict], tmp_path: Path
) -> None:
    """Fig. 8b is drawn while CCM-PD computes (``figures_beside_runs``); the file is the one the
    same figure gives when drawn and saved afterwards, pixel for pixel."""
    from matplotlib.image import imread

    from rustfrac import figures
    from rustfrac.fig7 import PRESETS, _fig8b

    out, summary = fast_run
    assert summary["time_split_s"]["figures_beside_runs"] > 0.0
    fig = _fig8b({"xfem_growth": rf.load(out / "xfem")}, PRESETS["fast"])
    assert fig is not None
    figures.save_figure(fig, tmp_path / "late.png")
    ahead, late = imread(out / "fig8b.png"), imread(tmp_path / "late.png")
    assert ahead.shape == late.shape and np.array_equal(ahead, late)


def test_figures_drawn_in_the_child_are_the_figures_drawn_here(
    fast_run: tuple[Path, dict], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """fig8a and fig6 are drawn in a forked child (``rustfrac._forked``) beside fig7.png; the
    files are those the same job gives with every figure drawn in this process, pixel for
    pixel."""
    from matplotlib.image import imread

    from rustfrac import fig7 as fig7_mod

    out, summary = fast_run
    assert set(fig7_mod.BESIDE) <= set(summary["files"])
    monkeypatch.setattr(fig7_mod, "BESIDE", ())
    here = fig7(tmp_path, preset="fast", log=None)
    assert here["files"] == summary["files"]
    for name in ("fig7.png", "fig8a.png", "fig6.png"):
        a, b = imread(out / name), imread(tmp_path / name)
        assert a.shape == b.shape and np.array_equal(a, b), name


def test_fig8b_without_a_reached_snapshot_step_is_missing_not_a_crash(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Fig. 8b shows the growth's critical states at the preset's snapshot steps; a growth that
    reaches none of them gives no Fig. 8b (listed as missing), and the rest of the job is
    written."""
    from dataclasses import replace

    from rustfrac import fig7 as fig7_mod

    presets = dict(fig7_mod.PRESETS)
    presets["fast"] = replace(presets["fast"], snapshot_steps=(900, 999))
    monkeypatch.setattr(fig7_mod, "PRESETS", presets)
    s = fig7(tmp_path, preset="fast", log=None)
    assert s["missing"] == ["fig8b.png"] and s["complete"] is False
    assert s["time_split_s"]["figures_beside_runs"] >= 0.0
    assert not (tmp_path / "fig8b.png").exists() and (tmp_path / "fig7.png").is_file()


# -- one unit, partial outputs marked -------------------------------------------------------


def _stop_at(*runs: str):
    """A progress factory that interrupts the runs ``runs`` (as Ctrl-C would; CCM-PD runs beside
    the XFEM runs, so a Ctrl-C during one of these may find it finished or not)."""

    def progress(name: str):
        if name not in runs:
            return None

        def cb(done: int, total: int, message: str) -> None:
            raise KeyboardInterrupt

        return cb

    return progress


def test_summary_checks_its_result_folders(fast_run: tuple[Path, dict], tmp_path: Path) -> None:
    import shutil

    from rustfrac.fig7 import load_summary

    out, summary = fast_run
    assert load_summary(out)["parts"] == summary["parts"]
    assert summary["complete"] is True and summary["missing"] == []
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    rf.load(copy / "xfem").save(copy / "xfem")  # the same numbers, but another save
    with pytest.raises(rf.InvalidResultError, match="does not belong to") as e:
        load_summary(copy)
    assert e.value.path == copy / "xfem"


def test_a_second_run_replaces_the_whole_folder(tmp_path: Path) -> None:
    from rustfrac.fig7 import Fig7Interrupted, load_summary

    fig7(tmp_path, preset="fast", log=None)
    assert (tmp_path / "ccm_pd" / "result.json").is_file()
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(Fig7Interrupted) as e:
        fig7(tmp_path, preset="fast", log=None, progress=_stop_at("xfem_growth", "ccm_pd"))
    s = load_summary(tmp_path)  # the interrupted run's folder, whole: no part of the first run
    assert s == e.value.summary
    assert s["complete"] is False and s["parts"] == {}
    assert {"run xfem_growth", "run ccm_pd", "xfem/", "ccm_pd/", "fig8a.png"} <= set(s["missing"])
    assert not (tmp_path / "xfem").exists() and not (tmp_path / "ccm_pd").exists()
    assert not (tmp_path / "fig8a.png").exists()
    assert (tmp_path / "notes.txt").read_text() == "mine"  # not a fig7 file: kept


@pytest.mark.parametrize(
    ("plot", "missing"),
    [
        # drawn here first: the rest is not drawn, the child drawing fig8a and fig6 is killed
        ("plot_fig7", ["fig7.png", "fig7.csv", "fig8a.png", "fig8b.png", "fig6.png"]),
        # drawn in the child, which fails: drawn again here after fig8b, where the Ctrl-C lands
        ("plot_damage", ["fig8a.png", "fig6.png"]),
    ],
)
def test_ctrl_c_while_plotting_lists_the_missing_files(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    plot: str,
    missing: list[str],
) -> None:
    from rustfrac import figures
    from rustfrac.cli import main

    def interrupted(*a: object, **k: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(figures, plot, interrupted)
    assert main(["fig7", "--out", str(tmp_path), "--preset", "fast", "-q"]) == 130
    err = capsys.readouterr().err
    assert f"missing: {', '.join(missing)}" in err
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["interrupted"] is True and s["complete"] is False
    assert s["missing"] == missing
    for f in s["files"]:
        assert (tmp_path / f).is_file(), f
    for f in missing:
        assert not (tmp_path / f).exists(), f
    assert not list(tmp_path.glob(".*.tmp")), "a staged figure left behind"
    assert f"**Missing:** {', '.join(missing)}" in (tmp_path / "summary.md").read_text()
    assert rf.load(tmp_path / "ccm_pd").method == "ccm_pd"  # the runs are kept


def test_out_naming_a_file_fails_before_the_runs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from rustfrac import study
    from rustfrac.cli import main

    calls: list[object] = []
    monkeypatch.setattr(study, "run", lambda *a, **k: calls.append(a))
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(rf.OutputError, match="it is a file, not a folder"):
        fig7(f, preset="fast", log=None)
    assert main(["fig7", "--out", str(f), "--preset", "fast"]) == 2
    assert "it is a file" in capsys.readouterr().err
    assert calls == []


def test_summary_carries_the_agreement_along_the_curve(fast_run: tuple[Path, dict]) -> None:
    out, summary = fast_run
    cur = summary["agreement"]["curve"]
    assert cur["window"] == agreement.DEFAULT_WINDOW
    for k in agreement.READINGS:
        assert cur[k]["n"] > 5, k
        # the fast preset's coarse PD grid: within 25 % of LEFM everywhere along the overlap
        assert abs(cur[k]["mean_rel_diff"]) < 0.25, (k, cur[k])
    assert json.loads((out / "summary.json").read_text())["agreement"]["curve"] == cur
    assert "running mean over" in (out / "summary.md").read_text()


def test_summary_carries_the_energy_audit(fast_run: tuple[Path, dict]) -> None:
    out, summary = fast_run
    en = summary["energy"]
    # LEFM growth dissipates G0 per unit area (tests/test_energy.py); CCM-PD: its measured ratio
    assert en["xfem"]["ratio"] == pytest.approx(1.0, abs=0.01)
    assert 0.5 < en["ccm_pd"]["ratio"] < 2.0
    assert "Energy audit" in (out / "summary.md").read_text()


def test_summary_splits_the_job_time(fast_run: tuple[Path, dict]) -> None:
    """The job's own time split (computation, figures, result folders,
    summaries) in summary.json and summary.md; the parts add up to the total."""
    out, summary = fast_run
    t = summary["time_split_s"]
    assert set(t) == {
        "compute", "figures", "figures_beside_runs", "files", "summaries", "other", "total"
    }  # fmt: skip
    assert all(v >= 0.0 for v in t.values())
    parts = t["compute"] + t["figures"] + t["files"] + t["summaries"] + t["other"]
    assert parts == pytest.approx(t["total"], rel=1e-9, abs=1e-9)
    # Fig. 8b is drawn while CCM-PD computes: inside the computation's time, not beside it
    assert 0.0 < t["figures_beside_runs"] < t["compute"]
    # the runs are inside it: the XFEM runs one after the other, CCM-PD beside them in a worker
    # thread (so the sum of all runs may exceed it: that flaked under load)
    times = summary["times_s"]
    in_turn = sum(v for k, v in times.items() if k != "ccm_pd")
    assert t["compute"] >= max(in_turn, times.get("ccm_pd", 0.0)) - 1e-9
    assert "Job time: computation" in (out / "summary.md").read_text()


def test_full_preset_runs_ccm_pd_on_the_adaptive_region_to_the_xfem_end() -> None:
    from rustfrac import _core
    from rustfrac.fig7 import PRESETS, _scenes

    pd = _scenes(PRESETS["full"], "free")["ccm_pd"].pd
    stop = _core.scene_constants()["DEFAULT_A_STOP_FRACTION"] * 11.0
    assert pd.region == "adaptive" and pd.stop_crack_length == pytest.approx(stop)
    assert _scenes(PRESETS["paper"], "free")["ccm_pd"].pd.region == "fixed"


def test_full_disk_while_staging_a_result_folder_leaves_the_folder_as_it_was(
    fast_run: tuple[Path, dict], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The result folders are staged in worker threads beside the drawing: their failure still
    fails the whole job (OutputError, after the temporary-folder fallback fails the same way)
    and leaves the fig7 folder as it was, without temporaries or new empty folders."""
    import errno
    import shutil

    from rustfrac import result as result_mod

    def full(path: object, res: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(result_mod, "write_vtu", full)
    old, new = tmp_path / "old", tmp_path / "new"
    shutil.copytree(fast_run[0], old)
    before = {p: p.read_bytes() for p in old.rglob("*") if p.is_file()}
    for out in (old, new):
        with pytest.raises(rf.OutputError, match="No space left"):
            fig7(out, preset="fast", log=None)
    assert {p: p.read_bytes() for p in old.rglob("*") if p.is_file()} == before
    assert not new.exists() or list(new.rglob("*")) == []


def test_the_cpu_parts_benchmark_accounts_for_every_part(
    root: Path, child_env: dict[str, str]
) -> None:
    """``benches/fig7_cpu_parts.py`` (RESULTS.md, "The two targets not reached") runs every part
    of the job and prints a total that is the sum of its parts."""
    p = subprocess.run(
        [sys.executable, str(root / "benches" / "fig7_cpu_parts.py"), "--preset", "fast"],
        capture_output=True, text=True, check=False, env=child_env,
    )  # fmt: skip
    assert p.returncode == 0, p.stderr
    rows = [line.split(" s  ", 1) for line in p.stdout.splitlines()]
    parts = {name: float(s) for s, name in rows}
    for name in ("run xfem_growth", "run ccm_pd", "draw fig7.png", "draw fig6.png",
                 "result folder ccm_pd/"):  # fmt: skip
        assert name in parts, p.stdout
    total = parts.pop("CPU in all (user + system, every thread of this process)")
    assert total == pytest.approx(sum(parts.values()), abs=0.01)
    assert all(s >= 0.0 for s in parts.values())
