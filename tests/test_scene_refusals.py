"""Scene refusals and warnings: every value the user gave is used or refused by name, every
default that does not fit the scene warns (a DiscretisationWarning saying what was chosen)
before the run, a support's reaction holds only what it carries, and markers say "not
computed" (NaN)."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import runner
from rustfrac.cli import main


def _refused(scene: Any) -> str:
    with pytest.raises(rf.InvalidParameterError) as e:
        rf.run(scene)
    return e.value.param


@pytest.mark.parametrize("args", [["--workers", "0"], ["--repeats", "0"], ["--workers", "-1"]])
def test_sweep_counts_below_one_are_refused(args: list[str], tmp_path: Path) -> None:
    # before: 0 meant the defaults (all cores, 3 repeats) and the sweep ran
    with pytest.raises(SystemExit) as e:
        main(["sweep", "--out", str(tmp_path / "s"), "--preset", "tiny", *args])
    assert e.value.code == 2


def test_bond_based_pd_refuses_another_poissons_ratio_by_name() -> None:
    with pytest.raises(rf.InvalidParameterError, match="fixes nu") as e:
        rf.specimens.senb(method="ccm_pd", nu=0.3)
    assert e.value.param == "nu"
    with pytest.raises(rf.InvalidParameterError) as e:
        rf.specimens.senb(method="pd", plane="stress")
    assert e.value.param == "plane"
    # the literature's default is replaced, and a warning says so
    with pytest.warns(rf.DiscretisationWarning, match="nu = 0.25"):
        s = rf.specimens.senb(method="ccm_pd")
    assert (s.material.nu, s.material.plane) == (0.25, "strain")
    # the other methods run the literature's values
    assert rf.specimens.senb(method="xfem").material.nu == 0.3


def test_a_default_grid_of_flat_elements_warns_before_the_run(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the paper's 44 x 83 grid on a 20 x 10 plate: elements of aspect 3.8 (K_I about 5 % low)
    s = rf.Scene.from_dict(
        {
            "method": "fem",
            "plate": {"width": 20.0, "height": 10.0},
            "crack": {"kind": "seam", "y": 5.0, "a0": 2.0},
        }
    )

    def not_run(*_: Any) -> Any:
        raise RuntimeError("the run started")

    monkeypatch.setitem(runner._RUNNERS, "fem", not_run)
    with pytest.warns(rf.DiscretisationWarning, match=r"aspect 3\.7"), pytest.raises(RuntimeError):
        rf.run(s)
    monkeypatch.undo()
    with pytest.warns(rf.DiscretisationWarning, match="aspect") as rec:
        res = rf.run(s)
    assert any("aspect" in w for w in res.meta["warnings"])
    assert sum("aspect" in str(w.message) for w in rec) == 1  # said once
    # near-square elements: no such warning
    with warnings.catch_warnings():
        warnings.simplefilter("error", rf.DiscretisationWarning)
        rf.run(s.replace(mesh__nx=80, mesh__ny=40))


def test_the_paper_crack_on_another_plate_warns() -> None:
    s = rf.Scene.from_dict({"method": "xfem", "plate": {"width": 22.0, "height": 42.0}})
    with pytest.warns(rf.DiscretisationWarning, match="the paper's crack"):
        rf.run(s)
    with warnings.catch_warnings():
        warnings.simplefilter("error", rf.DiscretisationWarning)
        rf.run(s.replace(crack__y=21.0))


def test_a_run_past_the_cost_budget_warns_with_its_estimate(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    s = rf.scenes.edge_crack_plate("xfem", growth_steps=100_000, da=1e-5)

    def not_run(*_: Any) -> Any:
        raise RuntimeError("the run started")

    monkeypatch.setitem(runner._RUNNERS, "xfem", not_run)
    with pytest.warns(rf.DiscretisationWarning, match=r"cost: about .* s estimated"):
        with pytest.raises(RuntimeError):
            rf.run(s)


def test_grid_lines_report_the_grid_that_runs() -> None:
    xs = [0.0, 2.0, 4.0, 6.0, 8.0, 11.0]
    s = rf.Scene.from_dict({"method": "fem", "crack": {"kind": "none"}, "mesh": {"xs": xs}})
    assert s.mesh.nx == len(xs) - 1
    res = rf.run(s)
    assert res.meta["scene"]["mesh"]["nx"] == len(xs) - 1
    with pytest.raises(rf.InvalidParameterError) as e:
        rf.Scene.from_dict({"method": "fem", "mesh": {"xs": [1.0]}})
    assert e.value.param == "mesh.xs"


@pytest.mark.parametrize("h", [1e-8, 1e-30])
def test_a_graded_grid_too_fine_is_refused_by_name(h: float) -> None:
    # before: 1e-8 allocated 24 GB, 1e-30 aborted the process
    mesh = {"refine": [0.5, 10.0, 2.5, 11.0], "refine_h": h, "grading": 1.0}
    assert _refused({"method": "xfem", "mesh": mesh}) == "mesh.refine_h"


def test_an_inclined_pre_crack_outside_the_pd_rectangle_is_refused_by_name() -> None:
    # before: SingularSystemError from the FEM block of the splice matrix
    with pytest.raises(rf.InvalidParameterError, match="inclined pre-crack") as e:
        rf.run(rf.scenes.edge_crack_plate(method="ccm_pd", crack_angle=30.0))
    assert e.value.param == "pd.center"


def test_two_probes_of_one_name_are_refused() -> None:
    p = [{"name": "a", "point": [3.0, 5.0]}, {"name": "a", "point": [4.0, 5.0]}]
    assert _refused({"method": "fem", "probe": p}) == "probe[1].name"


def test_the_seam_moved_to_its_grid_line_warns_and_is_what_the_scene_draws() -> None:
    s = rf.scenes.edge_crack_plate("fem", a0=1.0)  # y = 10.5 lies between grid lines of 83
    with pytest.warns(rf.DiscretisationWarning, match="moved"):
        res = rf.run(s)
    y = res.meta["seam_y"]
    assert y != 10.5
    assert s.crack_polylines() == [[(0.0, y), (pytest.approx(1.0), y)]]


def test_a_support_reaction_holds_only_its_prescribed_components() -> None:
    # a self-equilibrated pull: the supports carry nothing; before, the left-edge support (u1
    # only) reported the top and bottom loads' share at its corner nodes in u2
    s = {
        "method": "fem",
        "plate": {"width": 4.0, "height": 2.0},
        "mesh": {"nx": 8, "ny": 4},
        "crack": {"kind": "none"},
        "support": [
            {"region": "edge", "side": "left", "fix": "u1"},
            {"region": "point", "point": [0.0, 0.0], "fix": "u2"},
        ],
        "load": [
            {"region": "edge", "side": "top", "normal": 1.0},
            {"region": "edge", "side": "bottom", "normal": 1.0},
        ],
    }
    res = rf.run(s)
    r0, r1 = res.reaction("support[0]"), res.reaction("support[1]")
    assert r0[1] == 0.0 and r1[0] == 0.0
    assert abs(r0[0]) < 1e-10 and abs(r1[1]) < 1e-10
    assert res.reaction("load[0]") == pytest.approx((0.0, 4.0), abs=1e-12)
    assert res.reaction("load[1]") == pytest.approx((0.0, -4.0), abs=1e-12)


def test_the_kink_angle_says_its_unit() -> None:
    rows = [e for e in rf.result_schema() if "kink_angle" in e["name"] and "xfem" in e["methods"]]
    assert len(rows) == 2 and all(e["unit"] == "rad" and "radians" in e["doc"] for e in rows)


def test_xfem_results_carry_the_reactions() -> None:
    res = rf.run(rf.scenes.edge_crack_plate("xfem", mesh=(22, 42), a0=2.75))
    r = np.asarray(res.fields["reactions"]).reshape(-1, 2)
    xy = np.asarray(res.fields["coords"])
    assert r.shape == xy.shape
    top = r[np.isclose(xy[:, 1], 21.0), 1].sum()
    bottom = r[np.isclose(xy[:, 1], 0.0), 1].sum()
    # the grips' edge force is sigma22 W, and the plate is in equilibrium
    assert top == pytest.approx(res.sigma22 * 11.0, rel=1e-9)
    assert bottom == pytest.approx(-top, rel=1e-9)
    assert abs(r[:, 0].sum()) < 1e-9 * abs(top)
