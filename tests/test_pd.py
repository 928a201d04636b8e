"""PD and CCM-PD from Python: the binding, the runner, the SLA history, results, CLI, examples.

Coarse grids (dx = 0.2) keep these fast; one paper-grid CCM-PD run (dx = 1/15, a few SLA steps)
checks the reference-load values against the core."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from pd_scenes import coarse
from rustfrac import _core
from rustfrac.cli import main

GAMMA_M4 = 0.988895997195466  # the paper's gamma for m = 4
PAPER_SIGMA22, PAPER_CMOD = 9.992, 0.005374  # the paper's CCM-PD values at u0 = 0.01
# the core's values for Problem::paper("ccm_pd") before any break (crates/rustfrac-core, sla::run)
CORE_SIGMA22, CORE_CMOD = 9.9392407854836, 0.0061716324384645796

HISTORY_KEYS = (
    "step",
    "load_factor",
    "sigma22",
    "cmod",
    "u0",
    "crack_length",
    "bond",
    "n_broken",
    "node_i",
    "node_j",
    "n_detached",
)


def strip(fast: bool = True) -> rf.Scene:
    """A small pure-PD strip that the SLA cuts through (mirrors the core's separation test)."""
    return rf.scenes.edge_crack_plate(
        method="pd",
        width=1.2,
        height=2.2,
        a0=0.5,
        crack_y=1.1,
        dx=0.2,
        m=2,
        sla_steps=2000,
        fast=fast,
    )


@pytest.fixture(scope="module")
def paper() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate(method="ccm_pd", sla_steps=5, damage_at_steps=[2]))


@pytest.fixture(scope="module")
def small() -> rf.Result:
    return rf.run(coarse(30, damage_at_steps=[1, 10]))


# ---------------------------------------------------------------------------------------------
# the binding


def _coarse_native(**pd: object) -> dict[str, object]:
    return {
        "method": "ccm_pd",
        "pd": {"dx": 0.2, "center": [2.5, 10.5], "size": [4.4, 2.4], **pd},
    }


def test_binding_dict_keys_and_shapes() -> None:
    out = _core.run(_coarse_native(sla_steps=4, damage_at_steps=[2, 3]))
    assert set(out) == {
        "method", "sigma22", "cmod", "n_dofs", "wall_time_s", "fields", "history", "scalars",
        "meta",
    }  # fmt: skip
    f, h, meta = out["fields"], out["history"], out["meta"]
    assert set(out["scalars"]) == {"gamma", "c", "s0", "delta"}
    assert set(f) == {
        "node_xy", "u", "u_final", "pd_nodes", "pd_node_xy", "damage", "broken", "bond_nodes",
        "damage_at_steps", "damage_at", "detached_nodes",
    }  # fmt: skip
    assert set(h) == set(HISTORY_KEYS)
    counts = meta["counts"]
    n, p, b = counts["n_nodes"], counts["n_pd_nodes"], counts["n_bonds"]
    assert n == 56 * 106 and out["n_dofs"] == 2 * n
    assert f["node_xy"].shape == (n, 2) and f["u"].shape == f["u_final"].shape == (2 * n,)
    assert f["pd_nodes"].shape == (p,) and f["pd_nodes"].dtype == np.int64
    assert f["pd_node_xy"].shape == (p, 2) and f["damage"].shape == (p,)
    assert f["broken"].shape == (b,) and f["broken"].dtype == np.bool_
    assert f["bond_nodes"].shape == (b, 2) and f["bond_nodes"].dtype == np.int64
    assert len(meta["out_of_balance"]) == len(meta["anchor_xy"]) == 2
    assert f["damage_at_steps"].tolist() == [2, 3] and f["damage_at"].shape == (2, p)
    for k in HISTORY_KEYS:
        assert h[k].shape == (5,), k  # the unloaded origin, then 4 steps
    assert h["step"].tolist() == [0, 1, 2, 3, 4]
    assert f["broken"].sum() == counts["n_precrack_bonds"] + h["n_broken"].sum()
    np.testing.assert_array_equal(f["node_xy"][f["pd_nodes"]], f["pd_node_xy"])
    assert meta["status"] == "completed" and meta["bc"] == "free" and out["method"] == "ccm_pd"
    assert meta["peak_memory_bytes"] is None or meta["peak_memory_bytes"] > 0
    assert meta["sla_steps_done"] == 4


def test_binding_errors_name_the_parameter() -> None:
    with pytest.raises(rf.InvalidParameterError, match="method") as e:
        _core.run({**_coarse_native(), "method": "xfemm"})
    assert e.value.param == "method"
    with pytest.raises(rf.InvalidParameterError, match="tie_tol") as e:
        _core.run(_coarse_native(tie_tol=1.0))
    assert e.value.param == "pd.tie_tol"
    with pytest.raises(rf.InvalidParameterError, match="bc") as e:
        _core.run({**_coarse_native(), "load": {"bc": "glued"}})
    assert e.value.param == "load.bc"


def test_progress_is_forwarded_and_a_raising_callback_stops_the_run() -> None:
    calls: list[tuple[int, int, str]] = []
    rf.run(coarse(20), progress=lambda *a: calls.append(a))
    assert calls[0][0] == 0 and calls[-1][0] == calls[-1][1] == 20
    assert "after 20 steps" in calls[-1][2]
    assert all(c[1] == 20 for c in calls)

    class Stop(Exception):
        pass

    seen: list[int] = []

    def stop(done: int, total: int, message: str) -> None:
        seen.append(done)
        if done > 0:
            raise Stop

    t0 = time.perf_counter()
    with pytest.raises(Stop):
        rf.run(coarse(2000), progress=stop)
    # stopped at the first reported step (the 2000 steps take ~25 s), not only re-raised at the end
    assert len(seen) == 2 and 0 < seen[1] < 2000 and time.perf_counter() - t0 < 10.0


# ---------------------------------------------------------------------------------------------
# numbers


def test_gamma_m4_through_python(small: rf.Result) -> None:
    assert small.gamma is not None
    assert abs(small.gamma - GAMMA_M4) < 1e-10
    pd = rf.run(strip())
    assert pd.gamma is not None and math.isfinite(pd.gamma)
    assert abs(pd.gamma - GAMMA_M4) > 1e-6  # m = 2: computed from its own discretisation
    assert pd.scalars["delta"] == pytest.approx(0.4, rel=1e-12)
    s0 = math.sqrt(5 * math.pi * 0.367 / (12 * 1e4 * small.scalars["delta"]))
    assert small.scalars["s0"] == pytest.approx(s0, rel=1e-12)  # eq. 48


def test_paper_grid_before_any_break(paper: rf.Result) -> None:
    counts = paper.meta["counts"]
    print(
        f"\npaper grid CCM-PD ({counts['n_dofs']} unknowns, {counts['n_pd_nodes']} PD nodes, "
        f"{counts['n_bonds']} bonds): sigma22 = {paper.sigma22:.6f} (paper {PAPER_SIGMA22}), "
        f"CMOD = {paper.cmod:.6f} (paper {PAPER_CMOD}); gamma = {paper.gamma:.15f}; "
        f"setup {paper.meta['timings']['setup_s']:.2f} s, 5 SLA steps "
        f"{paper.meta['timings']['sla_s']:.3f} s"
    )
    assert counts["n_nodes"] == 166 * 316 and counts["n_pd_nodes"] == 40 * 26
    assert paper.sigma22 == pytest.approx(CORE_SIGMA22, rel=1e-9)
    assert paper.cmod == pytest.approx(CORE_CMOD, rel=1e-9)
    # the minimal scene (every key the core's default) is the same model as the paper scene
    out = _core.run({"method": "ccm_pd", "pd": {"sla_steps": 5}})
    assert out["sigma22"] == paper.sigma22 and out["cmod"] == paper.cmod
    np.testing.assert_array_equal(out["history"]["load_factor"], paper.history["load_factor"])
    # u is the reference-load solution, before any break: sigma22 scales with it
    assert paper.history["sigma22"][1] == pytest.approx(
        paper.history["load_factor"][1] * paper.sigma22, rel=1e-12
    )
    assert abs(paper.gamma - GAMMA_M4) < 1e-10
    assert paper.fields["damage_at"].shape == (1, counts["n_pd_nodes"])


def test_fast_sla_matches_oracle() -> None:
    n = 30
    fast = rf.run(coarse(n))
    oracle = rf.run(coarse(n, fast=False))
    periodic = rf.run(coarse(n, refactor_every=7))
    assert "fast" in fast.meta["solver"] and "oracle" in oracle.meta["solver"]
    assert periodic.meta["n_refactorisations"] > 1
    worst = 0.0
    for other in (oracle, periodic):
        assert len(fast.history["step"]) == len(other.history["step"]) == n + 1
        np.testing.assert_array_equal(fast.history["bond"], other.history["bond"])
        np.testing.assert_array_equal(fast.history["n_broken"], other.history["n_broken"])
        np.testing.assert_array_equal(fast.fields["broken"], other.fields["broken"])
        for k in ("load_factor", "sigma22", "cmod", "u0"):
            a, b = fast.history[k][1:], other.history[k][1:]
            worst = max(worst, float(np.max(np.abs(a - b) / np.abs(b))))
    print(f"\nfast vs oracle / periodic re-condensation, {n} steps: worst relative {worst:.2e}")
    assert worst < 1e-8


def test_sparse_engine_matches_oracle() -> None:
    """pd.engine = "sparse" (sparse factor of the condensed PD system + SMW) against the oracle:
    same bonds, load factors within 1e-8; the choice and the cost estimates reach meta."""
    n = 30
    sparse = rf.run(coarse(n, engine="sparse", refactor_every=10))
    oracle = rf.run(coarse(n, engine="oracle"))
    auto = rf.run(coarse(n))
    assert sparse.meta["solver"].startswith("fast, sparse"), sparse.meta["solver"]
    assert "estimated" in sparse.meta["solver"] and "oracle" in oracle.meta["solver"]
    assert "auto" in auto.meta["solver"]
    assert sparse.meta["n_refactorisations"] >= 3
    np.testing.assert_array_equal(sparse.history["bond"], oracle.history["bond"])
    for k in ("load_factor", "sigma22", "cmod"):
        a, b = sparse.history[k][1:], oracle.history[k][1:]
        assert float(np.max(np.abs(a - b) / np.abs(b))) < 1e-8, k


def test_history_starts_at_the_origin(small: rf.Result) -> None:
    h = small.history
    assert set(HISTORY_KEYS) <= set(h)
    assert len({len(v) for v in h.values()}) == 1 and len(h["step"]) == 31
    for k in ("load_factor", "sigma22", "cmod", "u0"):
        assert h[k][0] == 0.0, k
        assert np.all(np.isfinite(h[k])) and np.all(h[k][1:] > 0), k
    assert h["step"].tolist() == list(range(31))
    assert h["crack_length"][0] == pytest.approx(1.1) and np.all(np.diff(h["crack_length"]) >= 0)
    assert h["bond"][0] == -1 and h["n_broken"][0] == 0 and np.all(h["n_broken"][1:] >= 1)
    # each step is recorded at its own load: sigma22 = lambda sigma22_ref (displacement grips)
    np.testing.assert_allclose(h["u0"][1:], h["load_factor"][1:] * 0.01, rtol=1e-14)
    assert small.meta["status"] == "completed" and small.meta["sla_steps_done"] == 30


def test_damage_in_unit_interval_and_snapshots(small: rf.Result) -> None:
    d = small.damage
    assert d is not None and d.shape == (small.meta["counts"]["n_pd_nodes"],)
    assert np.all((d >= 0) & (d <= 1)) and d.max() > 0
    snaps = small.fields["damage_at"]
    assert small.fields["damage_at_steps"].tolist() == [1, 10]
    assert np.all((snaps >= 0) & (snaps <= 1))
    assert np.all(snaps[1] >= snaps[0]) and np.all(d >= snaps[1])  # damage only grows


def test_mode_one_symmetry_with_clamped_grips() -> None:
    r = rf.run(coarse(60, bc="clamped", tie_tol=1e-9))
    assert r.meta["status"] == "completed" and r.meta["anchor_node"] is None
    xy, d = r.fields["pd_node_xy"], r.damage
    index = {(round(x * 1e6), round(y * 1e6)): k for k, (x, y) in enumerate(xy)}
    mirror = np.array([index[(round(x * 1e6), round((21.0 - y) * 1e6))] for x, y in xy])
    worst = float(np.max(np.abs(d - d[mirror])))
    print(f"\nclamped mode I, 60 steps: max |D(x, y) - D(x, 21 - y)| = {worst:.2e}")
    assert d.max() > 0.1 and worst < 1e-12
    assert r.history["crack_length"][-1] > 1.1


def test_traction_grips() -> None:
    r = rf.run(coarse(5, bc="traction"))
    h = r.history
    assert r.sigma22 == pytest.approx(9.993, rel=1e-9)  # the applied traction
    np.testing.assert_allclose(h["sigma22"][1:], h["load_factor"][1:] * 9.993, rtol=1e-9)
    assert np.all(h["u0"] == 0.0)


def test_stop_at_crack_length() -> None:
    calls: list[tuple[int, int, str]] = []

    def progress(done: int, total: int, message: str) -> None:
        calls.append((done, total, message))
        if len(calls) <= 6:
            time.sleep(0.11)  # past the 0.1 s throttle: the next step is reported too

    r = rf.run(coarse(400, stop_crack_length=1.5), progress=progress)
    h = r.history
    assert r.meta["status"] == "crack_length_reached"
    assert h["crack_length"][-1] >= 1.5 and h["crack_length"][-2] < 1.5
    # the reports count the crack's advance to the stop (thousandths), not the 400 steps it
    # does not reach: each step's report is the larger of its crack and step fractions
    assert all(c[1] == 1000 for c in calls) and calls[-1][0] == 1000
    steps = [(d, m) for d, _, m in calls if m.startswith("sla: step ")]
    assert len(steps) >= 5 and len(h["step"]) - 1 < 400
    a0 = h["crack_length"][0]
    for done, msg in steps:
        k = int(msg.split()[2].rstrip(","))
        assert f"crack length {h['crack_length'][k]:.3f} of 1.500" in msg
        frac = max(k / 400, (h["crack_length"][k] - a0) / (1.5 - a0))
        assert done == math.floor(1000 * frac + 0.5)  # rounded half away from zero
    assert [d for d, _ in steps] == sorted(d for d, _ in steps)


def test_separated_strip_is_a_status_without_nan(tmp_path: Path) -> None:
    runs = [rf.run(strip(fast)) for fast in (True, False)]
    back = rf.load(runs[0].save(tmp_path))  # strict JSON (no NaN) and a VTU without a final state
    assert back.meta["status"] == "separated" and (tmp_path / "result.vtu").exists()
    assert 'Name="displacement_final"' not in (tmp_path / "result.vtu").read_text()
    for r in runs:
        assert r.meta["status"] == "separated"
        for k, v in r.history.items():
            assert np.all(np.isfinite(v)), k
        for k, v in r.fields.items():
            if v.dtype.kind == "f":
                assert np.all(np.isfinite(v)), k
        assert r.fields["u_final"].size == 0  # no final state once separated
        assert math.isfinite(r.sigma22) and math.isfinite(r.cmod)
    np.testing.assert_array_equal(runs[0].history["bond"], runs[1].history["bond"])
    np.testing.assert_allclose(
        runs[0].history["load_factor"], runs[1].history["load_factor"], rtol=1e-8
    )


# ---------------------------------------------------------------------------------------------
# scenes


@pytest.mark.parametrize(
    ("kw", "param", "text"),
    [
        ({"method": "pd", "nu": 0.3}, "material.nu", "bond-based peridynamics"),
        ({"method": "ccm_pd", "nu": 0.2}, "material.nu", "nu = 0.25"),
        ({"method": "pd", "m": 0}, "pd.m", r"integer in \[1, 12\]"),
        ({"method": "pd", "m": 13}, "pd.m", r"integer in \[1, 12\]"),
        ({"method": "ccm_pd", "pd_size": (2.73, 0.5)}, "pd.size", "two horizons"),
        ({"method": "pd", "width": 0.4, "dx": 0.1, "a0": 0.2}, "plate.width", "two horizons"),
        ({"method": "pd", "checkpoint_every": 5}, "pd.checkpoint_path", "needs a checkpoint"),
        ({"method": "pd", "dx": 0.07}, "pd.dx", "fit the plate"),
        ({"method": "ccm_pd", "pd_center": (12.0, 10.5)}, "pd.center", "inside the plate"),
        ({"method": "ccm_pd", "pd_center": (5.0, 10.5)}, "pd.center", "crack tip"),
        ({"method": "pd", "sla_steps": -1}, "pd.sla_steps", r"integer in \[0, 1000000\]"),
        ({"method": "pd", "tie_tol": 1.0}, "pd.tie_tol", "0 <= tie_tol < 1"),
        ({"method": "pd", "tie_tol": -1e-3}, "pd.tie_tol", "0 <= tie_tol < 1"),
        ({"method": "pd", "refactor_every": -1}, "pd.refactor_every", r"integer in \[0, "),
        ({"method": "pd", "engine": "cholesky"}, "pd.engine", "sparse"),
        ({"method": "pd", "fast": False, "engine": "dense"}, "pd.engine", "fast = false"),
        ({"method": "pd", "stop_crack_length": -1.0}, "pd.stop_crack_length", r"0 \(no stop\) or"),
        ({"method": "pd", "damage_at_steps": [0]}, "pd.damage_at_steps", r"integers in \[1, "),
        ({"method": "pd", "plane": "stress"}, "material.plane", "strain"),
        ({"method": "pd", "fem_grading": 1.2}, "pd.fem_grading", "method 'ccm_pd'"),
        ({"method": "ccm_pd", "fem_grading": 2.5}, "pd.fem_grading", "1 <= fem_grading"),
        ({"method": "ccm_pd", "fem_coarse": 0.5}, "pd.fem_coarse", "1 <= fem_coarse"),
        ({"method": "ccm_pd", "surface_correction": "volume"}, "pd.surface_correction", "energy"),
    ],
)
def test_bad_pd_inputs(kw: dict[str, object], param: str, text: str) -> None:
    with pytest.raises(rf.InvalidParameterError, match=text) as e:
        rf.scenes.edge_crack_plate(**kw)  # type: ignore[arg-type]
    assert e.value.param == param
    assert param in str(e.value)


def test_bad_pd_types() -> None:
    with pytest.raises(rf.InvalidTypeError, match=r"pd\.fast"):
        rf.scenes.edge_crack_plate(method="pd", fast="yes")  # type: ignore[arg-type]
    with pytest.raises(rf.InvalidTypeError, match=r"pd\.damage_at_steps"):
        rf.scenes.edge_crack_plate(method="pd", damage_at_steps=[1.5])  # type: ignore[list-item]
    with pytest.raises(rf.InvalidTypeError, match=r"pd\.damage_at_steps"):
        rf.scenes.edge_crack_plate(method="pd", damage_at_steps=5)  # type: ignore[arg-type]


def test_pd_options_round_trip_toml() -> None:
    s = coarse(
        12, tie_tol=1e-9, refactor_every=5, fast=False, stop_crack_length=2.0,
        damage_at_steps=[3, 7],
    )  # fmt: skip
    text = s.to_toml()
    assert "damage_at_steps = [3, 7]" in text and "fast = false" in text
    back = rf.Scene.from_toml_str(text)
    assert back == s and back.pd.damage_at_steps == (3, 7)
    assert rf.Scene.from_dict(s.to_dict()) == s
    assert rf.Scene.from_toml_str(rf.scenes.edge_crack_plate(method="pd").to_toml()).pd == (
        rf.scene.PdOptions()
    )


def test_surface_correction_is_forwarded_and_reported() -> None:
    """``surface_correction`` reaches the core from ``edge_crack_plate`` and TOML: the default
    ("none") runs the paper's bonds (meta says so, no factors), "energy" stiffens the nodes the
    pre-crack cuts (a smaller CMOD before any break) and reports its factors; the option
    survives a TOML round trip. The numbers are the core's (tests/suite/pd_surface_correction.rs)."""
    plain = rf.run(coarse(3))
    s = coarse(3, surface_correction="energy")
    assert rf.Scene.from_toml_str(s.to_toml()) == s and s.pd.surface_correction == "energy"
    corr = rf.run(s)
    assert plain.meta["surface_correction"] == "none"
    assert "surface_nodes_corrected" not in plain.meta
    m = corr.meta
    assert m["surface_correction"] == "energy"
    assert 0 < m["surface_nodes_corrected"] < m["counts"]["n_pd_nodes"]
    lo, hi = m["surface_node_factor_range"]
    assert lo == 1.0 and 1.0 < hi <= 4.0
    # (a PD-FEM bond takes its FEM node's factor too: here FEM nodes on the plate's edge at the
    # crack mouth, so the bonds' range may pass the PD nodes')
    assert 1.0 <= m["surface_bond_factor_range"][0] < m["surface_bond_factor_range"][1] < 4.0
    assert 0.0 < corr.cmod < plain.cmod


def test_pure_pd_ignores_the_rectangle() -> None:
    # a rectangle outside the plate is fine for pure PD: the PD region is the whole plate
    s = strip().replace(pd__center=(50.0, 50.0), pd__sla_steps=3)
    r = rf.run(s)
    assert r.meta["counts"]["n_pd_nodes"] == r.meta["counts"]["n_nodes"] == 7 * 12
    assert r.meta["pd_regions"] == "the whole plate"


# ---------------------------------------------------------------------------------------------
# results, files, CLI, examples


def test_save_load_round_trip(small: rf.Result, tmp_path: Path) -> None:
    small.save(tmp_path)
    back = rf.load(tmp_path)
    assert back.method == "ccm_pd" and back.sigma22 == small.sigma22 and back.cmod == small.cmod
    assert back.gamma == small.gamma and back.n_dofs == small.n_dofs
    assert set(back.fields) == set(small.fields)
    for k in ("node_xy", "pd_node_xy", "damage", "u", "u_final", "broken", "bond_nodes"):
        np.testing.assert_array_equal(back.fields[k], small.fields[k])
        assert back.fields[k].dtype == small.fields[k].dtype
    for k, v in small.history.items():
        np.testing.assert_array_equal(back.history[k], v)
    assert back.meta["status"] == "completed" and back.meta["counts"] == small.meta["counts"]
    assert back.meta["out_of_balance"] == small.meta["out_of_balance"]
    assert rf.Scene.from_dict(back.meta["scene"]) == coarse(30, damage_at_steps=[1, 10])
    vtu = (tmp_path / "result.vtu").read_text()
    n = small.meta["counts"]["n_nodes"]
    assert f'NumberOfPoints="{n}" ' in vtu
    # the PD nodes as vertices, the broken bonds as lines, the FEM part's cells
    n_cells = len(small.fields["pd_nodes"]) + int(small.fields["broken"].sum())
    n_quads = int(vtu.split('NumberOfCells="')[1].split('"')[0]) - n_cells
    assert 0 < n_quads < n
    assert 'Name="damage"' in vtu and 'Name="displacement_final"' in vtu
    doc = json.loads((tmp_path / "result.json").read_text())
    assert doc["scalars"]["gamma"] == small.gamma


def test_summary_mentions_the_sla(small: rf.Result) -> None:
    assert "SLA completed after 30 steps" in small.summary()


def test_cli_runs_the_coarse_pd_example(
    root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["run", str(rf.examples.path("pd_coarse.toml")), "--out", str(tmp_path), "--plot"])
    assert code == 0
    log = capsys.readouterr().out
    assert "method pd" in log and "1344 unknowns" in log
    assert "672 PD nodes" in log and "bonds" in log and "gamma = 0.98889599719" in log
    assert "status completed after 200 steps" in log
    back = rf.load(tmp_path)
    assert back.method == "pd" and len(back.history["step"]) == 201
    assert back.fields["damage_at_steps"].tolist() == [50, 100]
    for name in ("result.vtu", "damage.png", "crack_path.png", "u2.png", "load_path.png"):
        assert (tmp_path / name).exists(), name


@pytest.mark.parametrize(
    ("name", "bc"), [("paper_ccm_pd.toml", "free"), ("paper_ccm_pd_clamped.toml", "clamped")]
)
def test_paper_examples_are_valid(root: Path, name: str, bc: str) -> None:
    s = rf.Scene.from_toml(rf.examples.path(name))
    assert s.method == "ccm_pd" and s.load.bc == bc and s.pd.sla_steps == 500
    assert s.pd == rf.scenes.edge_crack_plate(method="ccm_pd", tie_tol=s.pd.tie_tol).pd


def test_progress_bar_shows_eta() -> None:
    import io

    from rustfrac.cli import ProgressBar

    buf = io.StringIO()
    bar = ProgressBar(stream=buf, delay=0.0, log_interval=0.0)  # every report a line
    bar(0, 100, "building")
    bar(10, 100, "sla: step 10/100")
    bar(20, 100, "sla: step 20/100")
    lines = buf.getvalue().splitlines()
    assert "ETA" not in lines[0] and "ETA" not in lines[1] and "ETA" in lines[2]


def test_pd_scenes_round_trip_property() -> None:
    hypothesis = pytest.importorskip("hypothesis")
    st = hypothesis.strategies

    @hypothesis.settings(max_examples=40, deadline=None)
    @hypothesis.given(
        method=st.sampled_from(["pd", "ccm_pd"]),
        bc=st.sampled_from(["free", "clamped", "traction"]),
        m=st.integers(min_value=2, max_value=8),
        steps=st.integers(min_value=1, max_value=10**6),
        tie_tol=st.floats(min_value=0.0, max_value=0.999),
        refactor_every=st.integers(min_value=0, max_value=1000),
        fast=st.booleans(),
        stop=st.one_of(st.just(0.0), st.floats(min_value=1e-6, max_value=100.0)),
        snaps=st.lists(st.integers(min_value=1, max_value=10**6), max_size=5),
    )
    def check(
        method: str,
        bc: str,
        m: int,
        steps: int,
        tie_tol: float,
        refactor_every: int,
        fast: bool,
        stop: float,
        snaps: list[int],
    ) -> None:
        s = rf.scenes.edge_crack_plate(
            method=method, bc=bc, m=m, sla_steps=steps, tie_tol=tie_tol,
            refactor_every=refactor_every, fast=fast, stop_crack_length=stop,
            damage_at_steps=snaps,
        )  # fmt: skip
        assert rf.Scene.from_toml_str(s.to_toml()) == s
        assert rf.Scene.from_dict(s.to_dict()) == s

    check()


def test_ccm_pd_graded_fem_grid_from_python() -> None:
    """pd.fem_grading > 1 grades the FEM part (fewer unknowns), the same first breaks and
    reference CMOD within 0.2 % (tests/suite/ccm_pd_graded.rs measures the Rust side)."""
    uni = rf.run(coarse(10))
    gr = rf.run(coarse(10, fem_grading=1.2, fem_coarse=8.0))
    assert gr.n_dofs < uni.n_dofs / 2
    assert abs(gr.cmod / uni.cmod - 1.0) < 2e-3
    assert abs(gr.history["load_factor"][1] / uni.history["load_factor"][1] - 1.0) < 2e-3


def test_progress_bar_eta_follows_the_recent_rate() -> None:
    """The steps of an adaptive CCM-PD run grow dearer as its region grows: the time left comes
    from the recent rate, not the rate since the start. 50 steps at 0.1 s, then 1 s a step:
    at step 80 the ETA is the 20 steps left at 1 s (the rate since the start would give 8.9 s);
    a report repeating the count keeps it, less the time since; a new total (another phase)
    starts its own rate."""
    import io

    from rustfrac.progress import ProgressBar

    t = [0.0]
    buf = io.StringIO()
    bar = ProgressBar(stream=buf, delay=0.0, clock=lambda: t[0], log_interval=0.0)
    for k in range(1, 81):
        t[0] += 0.1 if k <= 50 else 1.0
        bar(k, 100, f"step {k}")
    eta = float(buf.getvalue().splitlines()[-1].split("ETA ")[1].split(" s")[0])
    assert eta == pytest.approx(20.0, rel=0.02)
    t[0] += 0.5
    bar(80, 100, "step 80 again")  # no new count: the estimate less the time since
    assert buf.getvalue().splitlines()[-1].endswith("ETA 19.5 s")
    bar(1, 10, "phase 2")  # no rate yet for the new total
    t[0] += 0.5
    bar(2, 10, "phase 2")
    lines = buf.getvalue().splitlines()
    assert "ETA" not in lines[-2] and lines[-1].endswith("ETA 4.0 s")
