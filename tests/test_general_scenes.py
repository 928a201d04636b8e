"""General scenes from Python: the [[hole]], [[notch]], [[support]], [[load]] and
[[probe]] tables, the literature specimens (rustfrac.specimens) against their references, the
region responses of results, the load-path figure and the command line.

References: Yau, Wang and Corten (1980) and Moes, Dolbow and Belytschko (1999, fig. 13) for the
edge crack under shear (K_I = 34.0, K_II = 4.55); Srawley (1976), ASTM E399, for the SENB beam
with S/W = 4. The Rust test crates/rustfrac-core/tests/suite/general_scenes.rs does the fine-mesh
checks; these run coarse meshes in well under a second each.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from general_support import HOLES_REFUSED, has_holes, needs_holes
from rustfrac import specimens
from rustfrac.cli import main
from rustfrac.errors import DiscretisationWarning
from rustfrac.handbook import srawley_senb_F
from rustfrac.scene import Hole, Notch, Probe, RegionLoad, Scene, Support


def _rel(a: float, b: float) -> float:
    return abs(a - b) / abs(b)


# ----------------------------------------------------------------------------------------------
# scenes: the new tables


def _every_table_dict() -> dict:
    """A TOML-shaped scene with every new table (holes and notches included) and graded grids."""
    return {
        "method": "xfem",
        "name": "every table",
        "plate": {"width": 7.0, "height": 16.0},
        "material": {"E": 3e7, "nu": 0.25},
        "crack": {"kind": "edge", "a0": 3.5, "y": 8.0},
        "mesh": {"nx": 28, "ny": 64, "refine": [3.0, 7.5, 4.0, 8.5], "refine_h": 0.1},
        "hole": [
            {"shape": "circle", "center": [5.0, 3.0], "radius": 0.5},
            {"shape": "rect", "min": [1.0, 12.0], "max": [2.0, 13.0]},
            {"shape": "polygon", "points": [[4.0, 12.0], [5.0, 12.0], [4.5, 13.0]]},
        ],
        "notch": [{"side": "right", "at": 4.0, "width": 0.2, "depth": 1.0}],
        "support": [
            {"region": "edge", "side": "bottom"},
            {"region": "edge_part", "side": "left", "from": 0.0, "to": 2.0, "fix": "u1"},
        ],
        "load": [
            {"region": "edge", "side": "top", "shear": 1.0},
            {"region": "point", "point": [7.0, 16.0], "force": [0.0, 0.5]},
        ],
        "probe": [
            {"name": "corner", "point": [7.0, 16.0]},
            {"name": "mouth", "kind": "opening", "point": [0.0, 8.0]},
        ],
    }


def _no_cuts(d: dict) -> dict:
    return {k: v for k, v in d.items() if k not in ("hole", "notch")}


def test_toml_round_trip_with_every_new_table() -> None:
    """to_toml / from_toml_str and to_dict / from_dict give the same scene, pair lists and the
    keyword key "from" included; section objects and dicts are accepted alike."""
    d = _no_cuts(_every_table_dict())
    s = Scene.from_dict(d)
    assert len(s.supports) == 2 and len(s.loads) == 2 and len(s.probes) == 2
    assert s.supports[1].from_ == 0.0 and s.supports[1].to == 2.0 and s.load == rf.scene.Load()
    assert Scene.from_toml_str(s.to_toml()) == s
    assert Scene.from_dict(s.to_dict()) == s
    assert (
        "[[support]]" in s.to_toml() and "[[load]]" in s.to_toml() and "[load]\n" not in s.to_toml()
    )
    built = Scene(
        method="xfem", name="every table", plate=s.plate, material=s.material, crack=s.crack,
        mesh=s.mesh,
        supports=[Support(region="edge", side="bottom"), d["support"][1]],
        loads=[RegionLoad(side="top", shear=1.0), d["load"][1]],
        probes=[Probe(name="corner", point=(7.0, 16.0)), d["probe"][1]],
    )  # fmt: skip
    assert built == s
    r = s.replace(probes=[])
    assert r.probes == () and r.supports == s.supports
    assert "support" in s._repr_html_() and "shear 1 on top edge" in s.describe()


@needs_holes
def test_toml_round_trip_with_holes_and_notches() -> None:
    s = Scene.from_dict(_every_table_dict())
    assert len(s.holes) == 3 and s.holes[2].points == ((4.0, 12.0), (5.0, 12.0), (4.5, 13.0))
    assert Scene.from_toml_str(s.to_toml()) == s
    assert "3 hole(s)" in s.describe()


def test_hole_and_notch_sections_are_typed_from_the_schema() -> None:
    """The section classes come from the core's schema; pair lists are tuples of pairs."""
    h = Hole(shape="polygon", points=[[1.0, 1.0], [2.0, 1.0], [1.5, 2.0]])
    assert h.points == ((1.0, 1.0), (2.0, 1.0), (1.5, 2.0))
    assert h.to_dict()["points"] == [[1.0, 1.0], [2.0, 1.0], [1.5, 2.0]]
    n = Notch(side="bottom", at=2.0, width=0.1, depth=0.5)
    # an entry states what differs from the schema's defaults and what the core requires
    assert n.to_dict() == {"at": 2.0, "width": 0.1, "depth": 0.5}
    assert Notch.from_dict(n.to_dict()) == n
    assert Support(region="edge", side="bottom").to_dict() == {"side": "bottom"}  # required
    assert "radius" not in h.to_dict()  # a polygon states no radius
    with pytest.raises(rf.InvalidParameterError) as e:
        Hole(center=(1.0, 1.0))  # no radius
    assert e.value.param == "hole.radius"


def _param(d: dict) -> str:
    with pytest.raises(rf.RustfracError) as e:
        Scene.from_dict(d)
    return str(e.value.param)


def test_bad_entries_are_named_with_the_cores_keys() -> None:
    base = _no_cuts(_every_table_dict())
    # a point support outside the plate
    d = {**base, "support": [base["support"][0], {"region": "point", "point": [3.0, 40.0]}]}
    assert _param(d) == "support[1].point"
    # a self-intersecting polygon
    d = {**base, "hole": [{"shape": "polygon",
                           "points": [[1.0, 1.0], [2.0, 2.0], [2.0, 1.0], [1.0, 2.0]]}]}  # fmt: skip
    assert _param(d) == "hole[0].points"
    # the grips of a [load] table beside [[support]]
    d = {**base, "load": {"bc": "clamped"}}
    assert _param(d) == "load"
    # and from Python: grips beside region loads (one TOML key cannot hold both)
    s = Scene.from_dict(base)
    with pytest.raises(rf.InvalidParameterError) as e:
        s.replace(load={"bc": "clamped"})
    assert e.value.param == "load"
    # a dict entry is checked under its scene name
    with pytest.raises(rf.RustfracError) as e:
        s.replace(supports=[{"region": "edge", "side": "nope"}])
    assert e.value.param == "support[0].side"
    with pytest.raises(rf.InvalidTypeError) as e:
        s.replace(probes=[3])
    assert e.value.param == "probe[0]"


def test_traction_on_a_point_region_is_refused_by_name() -> None:
    base = _no_cuts(_every_table_dict())
    d = {**base, "load": [{"region": "point", "point": [7.0, 16.0], "force": [0.0, 1.0],
                           "shear": 1.0}]}  # fmt: skip
    assert _param(d) == "load[0].shear"
    d = {**base, "load": [{"region": "edge", "side": "top", "force": [0.0, 1.0]}]}
    assert _param(d) == "load[0].force"


def test_ccm_pd_edge_shear_balances_its_load() -> None:
    """CCM-PD on the edge-shear specimen (PD around the tip, nu = 1/4 as bond-based PD fixes
    it): the applied shear is exact, and the bottom support's reaction balances it up to the
    splice coupling's out-of-balance forces (Ongaro et al. 2021: the coupling is not in
    equilibrium; 1.6 % here, with the PD rectangle reaching the crack's faces); a few SLA steps
    run."""
    s = specimens.edge_shear("ccm_pd", pd__sla_steps=3)
    assert s.material.nu == 0.25
    res = rf.run(s)
    assert res.reaction("load[0]")[0] == pytest.approx(7.0, rel=1e-9)
    assert res.reaction("support[0]")[0] == pytest.approx(-7.0, rel=0.03)
    assert len(res.history["load_factor"]) == 4


def test_ccm_pd_hole_in_the_fem_part() -> None:
    """CCM-PD with a hole in its FEM part (cut elements, as FEM): the SLA runs, the applied shear
    stays exact, the hole (near the bottom right, far from the crack) changes the first load factor
    a little; a hole across
    the PD rectangle's boundary (hybrid elements) is refused by name."""
    s = specimens.edge_shear("ccm_pd", pd__sla_steps=3, pd__dx=0.125)
    plain = rf.run(s)
    res = rf.run(s.replace(holes=[{"center": [5.5, 3.0], "radius": 0.5}]))
    assert res.reaction("load[0]")[0] == pytest.approx(7.0, rel=1e-9)
    lf, lf0 = res.history["load_factor"][1], plain.history["load_factor"][1]
    assert lf != lf0 and lf == pytest.approx(lf0, rel=0.1)
    (cx, cy), (sx, _) = s.pd.center, s.pd.size
    with pytest.raises(rf.InvalidParameterError, match="hybrid element") as e:
        rf.run(s.replace(holes=[{"center": [cx + 0.5 * sx, cy], "radius": 0.3}]))
    assert e.value.param == "hole[0]"


def test_sla_history_carries_the_probes(tmp_path: Path) -> None:
    """PD and CCM-PD SLA histories record every probe at each step's load (row 0: unloaded):
    before any break the state is the reference one, so row 1 is its load factor times the
    reference probe (the scalar, from a full solve); the load path takes the columns."""
    s = specimens.edge_shear("ccm_pd", pd__sla_steps=3).replace(
        probes=[{"name": "corner", "point": [7.0, 16.0]}]
    )
    res = rf.run(s)
    ph = res.probe_history("corner")
    assert ph.shape == (4, 2) and np.all(ph[0] == 0.0)
    lam = res.history["load_factor"][1]
    assert ph[1] == pytest.approx(lam * np.asarray(res.probe("corner")), rel=1e-9)
    assert ph[1, 0] > 0, "the top corner moves with the shear"
    fig = rf.plotting.plot_load_path(res, x="probe:corner:1", y="sigma22")
    fig.savefig(tmp_path / "lp.png")


# ----------------------------------------------------------------------------------------------
# specimens against the literature


def test_edge_shear_xfem_matches_yau_and_moes() -> None:
    """K_I = 34.0, K_II = 4.55 (Yau et al. 1980; Moes et al. 1999) within 3 % and 6 % on the
    28 x 64 mesh; the top edge carries the shear load, the bottom support balances it."""
    res = rf.run(specimens.edge_shear("xfem", mesh=(28, 64)))
    assert res.meta["bc"] == "regions"
    assert _rel(res.K_I, 34.0) < 0.03, res.K_I
    assert _rel(res.K_II, 4.55) < 0.06, res.K_II
    f_top = res.reaction("load[0]")
    assert _rel(f_top[0], 7.0 * 1.0) < 1e-9  # shear 1 along +x1 over the width 7
    f_bottom = res.reaction("support[0]")
    assert abs(f_top[0] + f_bottom[0]) < 1e-9 * 7.0 and abs(f_top[1] + f_bottom[1]) < 1e-9 * 7.0
    assert res.mean_stress("load[0]") == pytest.approx(0.0, abs=1e-9)  # pure shear
    with pytest.raises(rf.InvalidParameterError, match=r"valid: support\[0\], load\[0\]"):
        res.reaction("load[3]")


def _srawley(scene: Scene) -> float:
    """K_I of ASTM E399 / Srawley (1976) for the specimen's beam: P S / (B W^1.5) f(a/W)."""
    w, b, a = 1.0, scene.material.thickness, scene.crack.a0
    span = 4.0
    return 1.0 * span / (b * w**1.5) * float(srawley_senb_F(a / w))


@pytest.mark.parametrize("alpha", [0.3, 0.5])
def test_senb_xfem_k_i_matches_srawley(alpha: float) -> None:
    """XFEM's K_I of the SENB beam (40 elements per depth) within 2 % of Srawley (1976);
    symmetric: K_II = 0; the two supports carry half the load each."""
    s = specimens.senb("xfem", a=alpha)
    res = rf.run(s)
    assert _rel(res.K_I, _srawley(s)) < 0.02, (res.K_I, _srawley(s))
    assert abs(res.K_II) < 1e-6 * res.K_I
    assert res.reaction("support[0]")[1] == pytest.approx(0.5, rel=1e-9)
    assert res.reaction("support[1]")[1] == pytest.approx(0.5, rel=1e-9)
    # the crack-mouth opening probe opens (u1 jump > 0), the load point moves down
    assert res.probe("cmod")[0] > 0 and res.probe("load_point")[1] < 0


def test_senb_fem_k_i_by_compliance_matches_srawley() -> None:
    """FEM (seam crack, the beam turned a quarter turn): K_I from the compliance,
    G = P^2 / (2 B) dC/da with C = load-point displacement / P (central difference over two
    element lengths), K_I = sqrt(E G) (plane stress), within 2 % of Srawley (1976) at a/W = 0.5
    on 80 elements per depth."""
    n, a, da = 80, 0.5, 2 / 80
    c = []
    for ak in (a - da, a + da):
        s = specimens.senb("fem", a=ak, mesh=(n, round(4.4 * n)))
        assert s.plate.width == 1.0 and s.crack.kind == "seam"
        res = rf.run(s)
        c.append(res.scalars["load_displacement"])  # P = 1
    g = (c[1] - c[0]) / (2 * da) / 2
    k = math.sqrt(s.material.E * g)
    ref = _srawley(specimens.senb("xfem", a=a))
    assert _rel(k, ref) < 0.02, (k, ref)


def test_reactions_balance_the_applied_load() -> None:
    """Equilibrium: the forces of all regions (supports' reactions and loads' resultants) sum
    to zero, relative to the applied load, for FEM and XFEM."""
    for s in (specimens.senb("fem"), specimens.senb("xfem"), specimens.edge_shear("fem"),
              specimens.edge_shear("xfem")):  # fmt: skip
        res = rf.run(s)
        forces = np.array([res.reaction(n) for n in res.regions])
        scale = np.abs(forces).max()
        assert np.abs(forces.sum(axis=0)).max() < 1e-9 * scale, (s.name, s.method, forces)


# ----------------------------------------------------------------------------------------------
# the specimens' example files


@pytest.mark.parametrize("name", list(specimens.SPECIMENS))
def test_every_specimen_example_loads_and_equals_its_function(name: str) -> None:
    sp = specimens.SPECIMENS[name]
    path = rf.examples.path(sp.example)
    if HOLES_REFUSED is not None and has_holes(path):
        with pytest.raises(rf.InvalidParameterError) as e:
            Scene.from_toml(path)
        assert str(e.value.param).startswith(("hole", "notch"))
        pytest.skip(f"this build's core refuses holes: {HOLES_REFUSED}")
    assert Scene.from_toml(path) == sp.build(sp.example_method)


def test_every_shipped_example_loads() -> None:
    for name in rf.examples.list():
        p = rf.examples.path(name)
        if HOLES_REFUSED is not None and has_holes(p):
            continue
        assert Scene.from_toml(p).method in rf.METHODS


def test_specimens_take_overrides_and_refuse_unknown_keywords() -> None:
    s = specimens.edge_shear("xfem", a=3.0, xfem__growth_steps=2, mesh=(14, 32))
    assert s.crack.a0 == 3.0 and s.xfem.growth_steps == 2 and s.mesh.nx == 14
    with pytest.raises(rf.UnknownParameterError):
        specimens.edge_shear("xfem", nonsense=1)
    assert specimens.sent("xfem", a0=2.0) == rf.scenes.edge_crack_plate(
        "xfem", a0=2.0, name=specimens.sent().name
    )
    with pytest.raises(rf.InvalidParameterError) as e:
        specimens.get("nope")
    assert "edge_shear" in str(e.value)


# ----------------------------------------------------------------------------------------------
# growth histories and the load-path figure


@pytest.fixture(scope="module")
def senb_growth() -> rf.Result:
    return rf.run(specimens.senb("xfem", a=0.3, mesh=(88, 20), xfem__growth_steps=3))


def test_probe_history_and_columns(senb_growth: rf.Result) -> None:
    h = senb_growth.history
    for col in ("load_displacement", "probe:cmod:1", "force:load[0]:2", "force:support[0]:2"):
        assert col in h, col
    ph = senb_growth.probe_history("cmod")
    assert ph.shape == (len(h["a"]), 2)
    assert np.array_equal(ph[:, 0], h["probe:cmod:1"])
    with pytest.raises(rf.InvalidParameterError, match=r"probes in the history: cmod, load_point"):
        senb_growth.probe_history("nope")


def test_load_path_with_custom_axes(senb_growth: rf.Result) -> None:
    from matplotlib.figure import Figure

    units = rf.plotting.Units("in", "lbf", "psi")
    fig = rf.plotting.plot_load_path(
        senb_growth, x="probe:load_point:2", y="force:load[0]:2", units=units
    )
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "probe:load_point:2 [in]"
    assert ax.get_ylabel() == "force:load[0]:2 [lbf]"
    fig = rf.plotting.plot_load_path(senb_growth, x="load_displacement", y="sigma22")
    assert fig.axes[0].get_xlabel() == "load_displacement [length]"
    with pytest.raises(rf.InvalidParameterError, match=r"valid: .*probe:cmod:1") as e:
        rf.plotting.plot_load_path(senb_growth, x="probe:nope:1")
    assert e.value.param == "x"


# ----------------------------------------------------------------------------------------------
# the command line


def test_cli_runs_the_edge_shear_example(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "es"
    assert main(["run", str(rf.examples.path("specimen_edge_shear")), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "region  support[0]: force (-7" in printed and "region  load[0]" in printed
    doc = json.loads((out / "result.json").read_text(encoding="utf-8"))
    assert doc["meta"]["bc"] == "regions"
    sc = doc["scalars"]
    assert {k.split(":")[1] for k in sc if k.startswith("force:")} == {"support[0]", "load[0]"}
    assert sc["force:load[0]:1"] == pytest.approx(7.0, rel=1e-9)
    res = rf.load(out)
    assert res.reaction("support[0]")[0] == pytest.approx(-7.0, rel=1e-9)
    assert "support[0]: force" in res.summary()


def test_cli_specimen_then_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "x.toml"
    assert main(["specimen", "senb", "--method", "xfem", "-o", str(f)]) == 0
    assert Scene.from_toml(f) == specimens.senb("xfem")
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 0
    assert "probe   cmod" in capsys.readouterr().out
    assert main(["specimens"]) == 0
    assert "bittencourt_beam" in capsys.readouterr().out
    assert main(["specimen", "nope", "-o", str(f)]) == 2


def test_cli_plot_load_path(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "g.toml"
    specimens.senb("xfem", a=0.3, mesh=(88, 20), xfem__growth_steps=2).save_toml(f)
    assert main(["run", str(f), "--out", str(tmp_path / "o"), "-q"]) == 0
    png = tmp_path / "lp.png"
    argv = ["plot", "load-path", str(tmp_path / "o"), "--x", "load_displacement",
            "--y", "force:load[0]:2", "-o", str(png)]  # fmt: skip
    assert main(argv) == 0 and png.stat().st_size > 1000
    assert main([*argv[:4], "nope", *argv[5:]]) == 2
    assert "valid: " in capsys.readouterr().err


def test_guide_general_section_shows_the_edge_shear_specimen(root: Path) -> None:
    text = (root / "docs" / "guide" / "scenes.md").read_text(encoding="utf-8")
    blocks = [b.split("```")[0] for b in text.split("```toml\n")[1:]]
    (toml,) = [b for b in blocks if "edge crack under shear" in b]
    assert Scene.from_toml_str(toml) == specimens.edge_shear("xfem")


@needs_holes
def test_bittencourt_growth_reaches_the_middle_hole() -> None:
    """The drilled beam (offset 5 in): the XFEM SIF domain shrinks clear of the holes instead of
    stopping the growth as a hole enters it, so the crack passes the lower hole and grows until
    the next tip would come closer than the tip clearance (2 elements) to the middle hole; the
    history's r_I column records the shrunk radii and a warning says so."""
    h_el = 0.125
    with pytest.warns(DiscretisationWarning, match="shrunk"):
        r = rf.run(specimens.bittencourt_beam("xfem", xfem__growth_steps=60))
    h = r.history
    assert r.meta["status"] == "ligament_used_up"
    tip = np.array([h["tip_x"][-1], h["tip_y"][-1]])
    gaps = [float(np.hypot(*(tip - c))) - 0.25 for c in ((6.0, 2.25), (6.0, 4.25), (6.0, 6.25))]
    # measured: 19 steps, last tip (6.017, 3.738), 0.262 from the middle hole (2.1 elements);
    # the old rule stopped at step 9 (tip (5.397, 2.482)), the lower hole entering the domain
    assert len(h["a"]) - 1 > 12
    assert int(np.argmin(gaps)) == 1 and 2.0 * h_el * 0.99 < gaps[1] < 3.0 * h_el
    r_i = np.asarray(h["r_I"][1:]) / h_el
    assert np.all(r_i >= 1.5 - 1e-9) and np.all(r_i <= 2.5 + 1e-9) and np.any(r_i < 2.5 - 1e-6)
    assert r.fields["tip_history_r_I"].shape == (len(h["a"]), 1)


@needs_holes
def test_pd_hole_volumes_key_reaches_the_core() -> None:
    """``pd.hole_volumes`` ("centre" | "exact") is a scene key from the core's schema: the exact
    volumes change a PD plate with a hole; a bad value is refused by name."""
    base = {
        "method": "pd",
        "plate": {"width": 2.0, "height": 2.0},
        "material": {"nu": 0.25},
        "crack": {"y": 1.05, "a0": 0.3},
        "pd": {"dx": 0.1, "m": 3, "sla_steps": 1},
        "hole": [{"center": [1.0, 1.0], "radius": 0.33}],
    }
    assert rf.Scene.from_dict(base).pd.hole_volumes == "centre"
    runs = {}
    for rule in ("centre", "exact"):
        d = json.loads(json.dumps(base))
        d["pd"]["hole_volumes"] = rule
        runs[rule] = rf.run(rf.Scene.from_dict(d))
    uc, ue = runs["centre"].fields["u"], runs["exact"].fields["u"]
    assert np.all(np.isfinite(ue)) and not np.allclose(uc, ue, rtol=1e-6, atol=0.0)
    bad = json.loads(json.dumps(base))
    bad["pd"]["hole_volumes"] = "midpoint"
    with pytest.raises(rf.InvalidParameterError) as e:
        rf.Scene.from_dict(bad)
    assert "hole_volumes" in str(e.value.param)
