"""LEFM against PD side by side (``rustfrac compare``, :mod:`rustfrac.compare`,
:mod:`rustfrac.paths`): the ridge extraction on pre-cracks the core breaks, the XFEM path and the
PD ridge on a small inclined crack, the PD rectangle's placement and cost guard, and the command
on a tiny scene."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import compare, paths, pd_region
from rustfrac.cli import main

#: a small inclined edge crack under the free grips: XFEM 16 x 32 (h = 0.25), PD dx = h, m = 3
TINY_INCLINED = {
    "method": "xfem",
    "name": "tiny inclined edge crack",
    "plate": {"width": 4.0, "height": 8.0},
    "material": {"E": 10000.0, "nu": 0.25, "G0": 0.367},
    "load": {"bc": "free", "u0": 0.01},
    "crack": {"kind": "edge", "a0": 1.0, "y": 4.1, "angle": 30.0},
    "mesh": {"nx": 16, "ny": 32},
}

TINY_CCM_PD_TOML = """\
# a tiny CCM-PD scene: compare derives the XFEM mesh from dx (16 x 32)
method = "ccm_pd"
name = "tiny CCM-PD inclined crack"

[plate]
width = 4.0
height = 8.0

[material]
E = 10000.0
nu = 0.25

[load]
bc = "free"

[crack]
kind = "edge"
a0 = 1.0
y = 4.1
angle = 30.0

[pd]
dx = 0.25
m = 3
center = [2.0, 4.875]
size = [4.0, 3.25]
"""


# ---------------------------------------------------------------------------------------------
# the ridge


@pytest.mark.parametrize("angle", [-45.0, -30.0, -15.0, 10.0, 20.0, 30.0, 40.0, 45.0, 60.0])
@pytest.mark.parametrize("y", [2.53, 2.6])
def test_ridge_of_a_pre_crack_lies_on_it(angle: float, y: float) -> None:
    """The bonds the core pre-breaks across a straight pre-crack at an angle (its own crossing
    rule, not ours): their ridge, at stations every dx along the pre-crack (strips dx long), lies
    on it within dx / 2 wherever the bond families are whole (stations a horizon from the plate's
    edges, and not at the pre-crack's ends, where the strip is cut). Measured over these angles
    and offsets (5 x 5 plate, dx = 0.25, m = 3): at most 0.32 dx. The same ridge against the pre-
    crack moved by one dx is off by more than dx / 2 (the test can fail)."""
    dx, m, w = 0.25, 3, 5.0
    scene = {
        "method": "pd",
        "plate": {"width": w, "height": w},
        "material": {"nu": 0.25},
        "load": {"bc": "free"},
        "crack": {"kind": "edge", "a0": 2.0, "y": y, "angle": angle},
        "pd": {"dx": dx, "m": m, "sla_steps": 0},
    }
    res = rf.run(rf.Scene.from_dict(scene))
    pre = np.asarray(res.meta["precrack"], dtype=float)
    xy = res.fields["node_xy"]
    ij = res.fields["bond_nodes"][res.fields["broken"]]
    assert len(ij) == res.meta["counts"]["n_precrack_bonds"] > 0
    mid = 0.5 * (xy[ij[:, 0]] + xy[ij[:, 1]])
    ridge = paths.bond_ridge(mid, pre, dx, m * dx * 3)
    length = paths.path_length(pre)
    sx = ridge.station_xy
    edge = np.minimum.reduce([sx[:, 0], w - sx[:, 0], sx[:, 1], w - sx[:, 1]])
    inner = (ridge.s >= dx) & (ridge.s <= length - dx) & (edge >= m * dx)
    assert inner.sum() >= 2 and ridge.covered[inner].all()
    d = paths.distance_to_polyline(ridge.xy[inner], pre)
    assert d.max() < 0.5 * dx, (angle, y, d.max() / dx)
    t = (pre[-1] - pre[0]) / length
    moved = pre + dx * np.array([-t[1], t[0]])
    assert paths.distance_to_polyline(ridge.xy[inner], moved).max() > 0.5 * dx


def test_stations_and_distances_on_a_known_polyline() -> None:
    line = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    s, pts, t, n = paths.stations(line, 0.4)
    np.testing.assert_allclose(s, [0.0, 0.4, 0.8, 1.2, 1.6, 2.0])
    np.testing.assert_allclose(pts[3], [1.0, 0.2])
    np.testing.assert_allclose(t[3], [0.0, 1.0])
    np.testing.assert_allclose(n[0], [0.0, 1.0])
    d = paths.distance_to_polyline([[0.5, 0.3], [2.0, 0.5], [1.5, 1.5]], line)
    np.testing.assert_allclose(d, [0.3, 1.0, math.sqrt(0.5)])
    # bonds on a line parallel to the path: the ridge is that line, off by 0.1
    mid = np.column_stack([np.linspace(0, 1, 11), np.full(11, -0.1)])
    r = paths.bond_ridge(mid, line[:2], 0.25, 0.5)
    np.testing.assert_allclose(r.offset, -0.1)
    with pytest.raises(rf.InvalidParameterError) as e:
        paths.bond_ridge(mid, line, 0.0, 0.5)
    assert e.value.param == "spacing"


# ---------------------------------------------------------------------------------------------
# the two methods' paths


def test_xfem_path_and_pd_ridge_agree_on_an_inclined_crack() -> None:
    """Mixed-mode growth of an inclined edge crack (30 degrees) under the grips: the PD ridge
    lies within one horizon of the XFEM path everywhere (mean within half a horizon), and covers
    most of it. Measured (16 x 32, dx = h = 0.25, m = 3, 8 growth steps): mean 0.24, max 0.62
    horizons (0.73 and 1.85 element lengths), 89 % of the stations covered (the SLA stops when
    the PD crack reaches the XFEM tip's advance; the last station lies at the tip). The PD crack
    is a damage band about two horizons wide: one horizon is the resolution of its centre line
    on this grid. On the finer scene of benches/RESULTS.md the max is 0.22 horizons."""
    p = compare.plan(TINY_INCLINED, m=3, growth_steps=8)
    xr = rf.run(p.xfem)
    gp = compare.grown_path(xr)
    assert xr.K_II is not None and abs(xr.K_II) > 0.1 * abs(xr.K_I)  # really mixed mode
    assert len(gp) >= 6
    kink = np.degrees(np.arctan2(*(gp[-1] - gp[0])[::-1]))
    assert abs(kink - 30.0) > 10.0  # the crack turned away from the pre-crack's direction
    pr = rf.run(compare.place(p, gp, gp[-1]))
    assert pr.meta["status"] == "crack_length_reached"
    mid = compare._bond_midpoints(pr, compare.sla_broken_bonds(pr))
    stats, ridge = compare.path_agreement(gp, mid, p.dx, p.delta, p.h)
    assert stats["status"] == "ok" and ridge is not None
    assert stats["covered"] >= 0.8
    assert stats["off_path_bonds"] == 0.0
    assert stats["max_horizons"] < 1.0, stats
    assert stats["mean_horizons"] < 0.5, stats


# ---------------------------------------------------------------------------------------------
# placement and cost guard


def test_plan_derives_both_scenes_from_any_method() -> None:
    """A CCM-PD scene with its own rectangle keeps it unless region="auto"; the XFEM scene gets
    a mesh of element size dx; a crack along a PD node row moves by dx / 2 in both (noted); the
    material becomes nu = 1/4 plane strain (noted)."""
    pd_scene = rf.Scene.from_toml_str(TINY_CCM_PD_TOML)
    p = compare.plan(pd_scene)
    assert p.region_given == (0.0, 3.25, 4.0, 6.5)
    assert (p.xfem.mesh.nx, p.xfem.mesh.ny) == (16, 32) and p.dx == 0.25 and p.m == 3
    assert compare.plan(pd_scene, region="auto").region_given is None
    with pytest.raises(rf.InvalidParameterError) as e:
        compare.plan(pd_scene, region="everywhere")
    assert e.value.param == "region"
    d = {
        **TINY_INCLINED,
        "crack": {"kind": "edge", "a0": 1.0, "y": 4.0},
        "material": {"E": 1.0e4, "nu": 0.3, "plane": "stress"},
    }
    p = compare.plan(d)
    assert p.xfem.crack.y == 4.125 and p.pd["crack"]["y"] == 4.125
    assert p.xfem.material.nu == 0.25 and p.xfem.material.plane == "strain"
    assert any("crack moved" in n for n in p.notes) and any("nu = 0.25" in n for n in p.notes)


def test_plan_forwards_the_surface_correction() -> None:
    """``surface_correction`` (``--surface-correction``) sets the CCM-PD scene's
    ``pd.surface_correction``; without it a PD scene's own value is kept (default: absent)."""
    assert "surface_correction" not in compare.plan(TINY_INCLINED).pd["pd"]
    p = compare.plan(TINY_INCLINED, surface_correction="energy")
    assert p.pd["pd"]["surface_correction"] == "energy"
    pd_scene = rf.Scene.from_toml_str(TINY_CCM_PD_TOML).replace(pd__surface_correction="energy")
    assert compare.plan(pd_scene).pd["pd"]["surface_correction"] == "energy"


def test_pd_region_covers_the_path_and_keeps_off_loaded_edges() -> None:
    path = np.array([[2.0, 5.0], [3.0, 6.0]])
    dx, m = 0.25, 3
    hole = {"center": [4.5, 4.5], "radius": 0.5}
    box = pd_region.pd_region(
        path, (8.0, 8.0), dx, m, holes=[hole], held=["top", "bottom"], margin_horizons=2.0
    )
    delta = m * dx
    assert box[0] == 0.0  # a free side within m + 1 spacings: taken whole
    assert box[1] <= 4.0 - (m + 1) * dx  # the hole taken in whole, with the hybrid band
    assert box[2] >= 5.0 + (m + 1) * dx
    assert box[3] <= 8.0 - 2 * delta  # the loaded top edge stays two horizons away
    for v in box[1:]:
        assert abs(v / dx - 0.5 - round(v / dx - 0.5)) < 1e-9 or v in (0.0, 8.0)


def test_a_pd_rectangle_beyond_the_budget_is_refused_unless_allowed() -> None:
    p = compare.plan(TINY_INCLINED, dx=1.0 / 64.0, m=4)
    gp = np.array([[0.87, 4.6], [2.0, 5.0]])
    with pytest.raises(rf.InvalidParameterError) as e:
        compare.place(p, gp, gp[-1])
    assert e.value.param == "pd.dx" and str(compare.PD_DOFS_BUDGET) in str(e.value)
    p = compare.plan(TINY_INCLINED, dx=1.0 / 64.0, m=4, allow_slow=True)
    scene = compare.place(p, gp, gp[-1])
    assert scene.pd.dx == 1.0 / 64.0 and any("allowed" in n for n in p.notes)


def test_an_automatic_dx_is_coarsened_to_fit_the_budget() -> None:
    d = {**TINY_INCLINED, "mesh": {"nx": 128, "ny": 256}}
    p = compare.plan(d, m=4)
    assert p.dx == 4.0 / 128 and p.dx_auto
    gp = np.array([[0.87, 4.6], [3.0, 6.0]])
    scene = compare.place(p, gp, gp[-1])
    dx = scene.pd.dx
    assert dx > 4.0 / 128 and any("coarsened" in n for n in p.notes)
    (cx, cy), (sx, sy) = scene.pd.center, scene.pd.size
    box = (cx - sx / 2, cy - sy / 2, cx + sx / 2, cy + sy / 2)
    assert pd_region.pd_dofs(box, dx) <= compare.PD_DOFS_BUDGET
    # the next finer spacing that fits the plate would not have fitted the engine
    finer = [v for v in compare._fitting_spacings(4.0, 8.0, 4.0 / 128) if v < dx * (1 - 1e-12)]
    # the rectangle holds the inclined pre-crack whole (the core refuses one it leaves)
    held = np.vstack([np.asarray(p.xfem.crack_polylines()[0]), gp])
    assert box[0] <= 0.0 + 1e-12 and box[1] <= held[0][1]
    box2 = pd_region.pd_region(held, (4.0, 8.0), finer[-1], 4, held=["top", "bottom"])
    assert pd_region.pd_dofs(box2, finer[-1]) > compare.PD_DOFS_BUDGET


# ---------------------------------------------------------------------------------------------
# the command


def test_compare_command_writes_every_file(tmp_path: Path) -> None:
    """``rustfrac compare`` on a tiny CCM-PD scene (the XFEM scene derived from it): every file,
    both result folders reloadable, the summary complete and consistent."""
    scene = tmp_path / "tiny.toml"
    scene.write_text(TINY_CCM_PD_TOML)
    out = tmp_path / "out"
    assert main(["compare", str(scene), "--out", str(out), "--quick", "--quiet"]) == 0
    for f in compare.FILES:
        assert (out / f).is_file() and (out / f).stat().st_size > 0, f
    s = json.loads((out / "summary.json").read_text())
    assert s["complete"] and not s["missing"]
    assert set(s["files"]) == set(compare.FILES)
    assert s["discretisation"]["pd_dx"] == 0.25 and s["discretisation"]["pd_m"] == 3
    assert s["scenes"]["xfem"]["mesh"]["nx"] == 16 and s["scenes"]["xfem"]["mesh"]["ny"] == 32
    assert any("as given" in n for n in s["notes"])  # the scene's own rectangle
    assert s["cost"]["ccm_pd"]["pd_region"] == [[0.0, 3.25, 4.0, 6.5]]
    for part in ("xfem", "ccm_pd"):
        r = rf.load(out / part)
        assert r.method == part
        assert s["cost"][part]["unknowns"] == r.n_dofs and s["cost"][part]["steps"] > 0
    assert s["path"]["status"] == "ok" and s["path"]["covered"] > 0
    # the SLA stops where the XFEM tip is, also for a PD scene (whose stop length was 0)
    assert s["scenes"]["ccm_pd"]["pd"]["stop_crack_length"] > 1.0
    assert s["cost"]["ccm_pd"]["status"] == "crack_length_reached"
    assert s["curves"]["x"] == "cmod" and s["curves"]["y"] == "sigma22"
    assert set(s["energy"]) == {"xfem", "ccm_pd"}
    assert all("ratio" in v for v in s["energy"].values())
    md = (out / "summary.md").read_text()
    for heading in ("## Crack paths", "## Load-response curves", "## Energy audit", "## Cost"):
        assert heading in md


def test_compare_command_refuses_bad_input(tmp_path: Path) -> None:
    scene = tmp_path / "tiny.toml"
    scene.write_text(TINY_CCM_PD_TOML)
    assert main(["compare", str(scene), "--out", str(tmp_path / "o"), "--region", "1,2,3"]) == 2
    assert main(["compare", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o")]) == 2
    uncracked = tmp_path / "uncracked.toml"
    uncracked.write_text('method = "xfem"\n[crack]\nkind = "none"\n')
    assert main(["compare", str(uncracked), "--out", str(tmp_path / "o")]) == 2
    assert not (tmp_path / "o").exists()


def test_an_interrupted_compare_writes_what_finished(tmp_path: Path) -> None:
    """Ctrl-C during the CCM-PD run (a raising progress callback): the XFEM part is written,
    the summary says what is missing, and CompareInterrupted carries it."""

    def progress(name: str):  # type: ignore[no-untyped-def]
        if name != "ccm_pd":
            return None

        def stop(done: int, total: int, msg: str) -> None:
            raise KeyboardInterrupt

        return stop

    out = tmp_path / "out"
    with pytest.raises(compare.CompareInterrupted) as e:
        compare.compare(TINY_INCLINED, out, quick=True, m=3, log=None, progress=progress)
    s = json.loads((out / "summary.json").read_text())
    assert s["missing"] == e.value.summary["missing"]
    assert not s["complete"] and s["interrupted"]
    assert "run ccm_pd" in s["missing"] and "ccm_pd/" in s["missing"]
    assert rf.load(out / "xfem").method == "xfem" and not (out / "ccm_pd").exists()
    assert (out / "compare.png").is_file() and "curves.png" in s["missing"]


def test_bad_spacing_and_zero_growth_are_refused_by_name() -> None:
    """A NaN or non-fitting dx is refused with the core's rule for pd.dx (not a failure inside
    the layout); a comparison without XFEM growth is refused naming xfem.growth_steps."""
    for dx in (float("nan"), -1.0, 0.3):
        with pytest.raises(rf.InvalidParameterError) as e:
            compare.plan(TINY_INCLINED, dx=dx, m=4)
        assert e.value.param == "pd.dx", (dx, e.value)
    with pytest.raises(rf.InvalidParameterError) as e:
        compare.plan(TINY_INCLINED, growth_steps=0)
    assert e.value.param == "xfem.growth_steps"


def test_compare_on_the_adaptive_pd_region(tmp_path: Path) -> None:
    """``--region adaptive``: CCM-PD on the core's adaptive region (no rectangle, no budget), the
    PD crack stopped where the XFEM tip is, every broken bond at least pd.adapt_margin horizons
    from the FEM part."""
    scene = tmp_path / "tiny.toml"
    scene.write_text(TINY_CCM_PD_TOML)
    out = tmp_path / "out"
    args = ["compare", str(scene), "--out", str(out), "--quick", "--quiet", "--region", "adaptive"]
    assert main(args) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["complete"] and any("adaptive PD region" in n for n in s["notes"])
    assert s["scenes"]["ccm_pd"]["pd"]["region"] == "adaptive"
    r = rf.load(out / "ccm_pd")
    margin = s["scenes"]["ccm_pd"]["pd"]["adapt_margin"]
    assert r.meta["pd_region"] == "adaptive" and r.meta["interface_distance_min"] >= margin - 1e-9
    assert s["cost"]["ccm_pd"]["status"] == "crack_length_reached"
    with pytest.raises(rf.errors.InvalidParameterError):
        compare.plan(TINY_INCLINED, region="moving")


#: the two-hole plate with one edge crack: holes r = 2 at (3, 7) and (17, 3), loaded on top and
#: bottom, point supports at mid-width; the path's bounding box plus the margin reaches the holes
#: and the loaded edges, so no rectangle holding the path in whole keeps off both
TWO_HOLES_ONE_CRACK = {
    "method": "xfem",
    "name": "two-hole plate, one crack",
    "plate": {"width": 20.0, "height": 10.0},
    "material": {"E": 1.0, "nu": 0.3},
    "crack": {"kind": "edge", "a0": 1.0, "y": 2.85},
    "mesh": {"nx": 80, "ny": 40},
    "hole": [{"center": [3.0, 7.0], "radius": 2.0}, {"center": [17.0, 3.0], "radius": 2.0}],
    "support": [
        {"region": "point", "point": [10.0, 0.0]},
        {"region": "point", "point": [10.0, 10.0], "fix": "u1"},
    ],
    "load": [{"side": "top", "normal": 1.0}, {"side": "bottom", "normal": 1.0}],
}


def test_the_automatic_pd_region_keeps_off_the_holes_or_is_none() -> None:
    """The rectangle :func:`pd_region.pd_region` gives takes each hole in whole or keeps the
    hybrid band clear of it; where none holding the path with a horizon's margin can (the
    two-hole plate: the top edge's clearance cuts hole[0]), it gives None."""
    dx, m = 0.25, 4
    holes = TWO_HOLES_ONE_CRACK["hole"]
    path = np.array([[1.0, 2.975], [2.0, 2.975]])
    held = ["top", "bottom"]
    assert pd_region.pd_region(path, (20.0, 10.0), dx, m, holes=holes, held=held) is None
    # a short path far from the holes: a rectangle, clear of both
    far = np.array([[9.0, 5.0], [10.0, 5.0]])
    box = pd_region.pd_region(far, (20.0, 10.0), dx, m, holes=holes, held=held)
    band = (m + 1) * dx
    assert box is not None and pd_region.cut_hole(box, holes, (20.0, 10.0), band) is None
    assert box[0] <= 9.0 - m * dx and box[2] >= 10.0 + m * dx
    assert box[1] <= 5.0 - m * dx and box[3] >= 5.0 + m * dx
    assert box[0] >= 5.0 + band  # hole[0] was taken in whole, then left: the top edge cut it


def test_compare_on_the_two_hole_plate_falls_back_to_the_adaptive_region(tmp_path: Path) -> None:
    """No fixed rectangle fits the two-hole plate's path: compare says so in a note and runs the
    adaptive PD region (the core refused the rectangle it chose before: "hole[0] ... cuts the
    hybrid element")."""
    s = compare.compare(TWO_HOLES_ONE_CRACK, tmp_path / "auto", quick=True, log=None)
    assert s["scenes"]["ccm_pd"]["pd"]["region"] == "adaptive"
    assert any("adaptive PD region instead" in n and "--region" in n for n in s["notes"]), s[
        "notes"
    ]
    assert s["cost"]["ccm_pd"]["status"] == "crack_length_reached"


def test_a_given_pd_rectangle_cutting_a_hole_is_refused_naming_the_region_option(
    tmp_path: Path,
) -> None:
    """A rectangle the user gives that cuts a hole is refused before the runs, the message
    naming what the user of compare can give instead (``--region``)."""
    with pytest.raises(rf.InvalidParameterError) as e:
        compare.compare(
            TWO_HOLES_ONE_CRACK, tmp_path / "given", quick=True, log=None,
            region=(0.0, 1.0, 8.0, 6.0),
        )  # fmt: skip
    assert e.value.param == "region"
    assert "hole[0]" in str(e.value) and "--region" in str(e.value)
    assert not (tmp_path / "given").exists() or not any((tmp_path / "given").iterdir())


def test_compare_moves_the_pd_rectangle_off_a_hole_the_loaded_edges_clearance_cuts(
    tmp_path: Path,
) -> None:
    """A centre crack right of hole[0] on the two-hole plate: the rectangle took hole[0] in
    whole, the loaded top edge's clearance then cut it, and the core refused the run ("hole[0]
    ... cuts the hybrid element"). Its left side now moves back off the hole, the path keeps its
    margin, and the core runs the fixed rectangle."""
    d = {
        **TWO_HOLES_ONE_CRACK,
        "material": {"E": 1.0, "nu": 0.25},
        "crack": {"kind": "center", "a0": 0.5, "y": 5.1, "x": 9.5},
    }
    s = compare.compare(d, tmp_path / "out", quick=True, log=None)
    pd = s["scenes"]["ccm_pd"]["pd"]
    assert pd["region"] == "fixed" and s["cost"]["ccm_pd"]["status"] == "completed"
    (cx, cy), (sx, sy) = pd["center"], pd["size"]
    box = (cx - sx / 2, cy - sy / 2, cx + sx / 2, cy + sy / 2)
    dx, m = s["discretisation"]["pd_dx"], s["discretisation"]["pd_m"]
    assert pd_region.cut_hole(box, d["hole"], (20.0, 10.0), (m + 1) * dx) is None
    assert box[0] >= 5.0 and box[0] <= 9.0 - m * dx  # off hole[0], a horizon left of the tip


def test_the_command_refuses_a_rectangle_cutting_a_hole_naming_region(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``rustfrac compare --region x0,y0,x1,y1`` with a rectangle cutting a hole: exit 2 before
    the runs, the message naming the --region choices."""
    scene = tmp_path / "two_holes.toml"
    scene.write_text(rf.Scene.from_dict(TWO_HOLES_ONE_CRACK).to_toml())
    out = tmp_path / "out"
    args = ["compare", str(scene), "--out", str(out), "--quick", "-q", "--region", "0,1,8,6"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "hole[0]" in err and "--region adaptive" in err and "--region auto" in err
    assert not out.exists()
