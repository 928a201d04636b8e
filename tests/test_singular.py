"""Singular systems through Python: a free rigid-body mode is named, a separated body is
reported, never NaN; the condition estimate can be skipped (``condition=False``); warnings carry a
kind that survives saving. The Rust side (pivot test per unknown, COND_SINGULAR, scale disparity
of 1e12 between unknowns) is tested in crates/rustfrac-core/tests/suite/singular_detection.rs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import _core


def _grid_u2_only(nx: int, ny: int, **kw: object) -> dict:
    """u2 prescribed on the bottom and top rows only: the x1 translation is free."""
    bottom = [2 * i + 1 for i in range(nx + 1)]
    top = [2 * ((nx + 1) * ny + i) + 1 for i in range(nx + 1)]
    args = dict(
        width=11.0,
        height=21.0,
        nx=nx,
        ny=ny,
        e=10000.0,
        nu=0.25,
        fixed_dofs=bottom + top,
        fixed_values=[-0.01] * len(bottom) + [0.01] * len(top),
    )
    args.update(kw)
    return args


def test_free_x1_translation_of_60_x_110_plate_is_named() -> None:
    # the case: before, this factorised (round-off pivot) and returned a solution
    with pytest.raises(rf.SingularSystemError, match=r"free: x1 translation"):
        _core.solve_fem_grid(**_grid_u2_only(60, 110))
    # one u1 more and it solves
    args = _grid_u2_only(60, 110)
    args["fixed_dofs"] = [0, *args["fixed_dofs"]]
    args["fixed_values"] = [0.0, *args["fixed_values"]]
    out = _core.solve_fem_grid(**args)
    assert np.all(np.isfinite(out["u"]))


def test_free_rotation_is_named() -> None:
    # u1 and u2 of the bottom-left node only: rotation about it is free
    args = _grid_u2_only(4, 4, fixed_dofs=[0, 1], fixed_values=[0.0, 0.0])
    with pytest.raises(
        rf.SingularSystemError, match=r"1 rigid-body mode\(s\) free: rotation about"
    ):
        _core.solve_fem_grid(**args)


def test_crack_through_the_width_is_refused() -> None:
    """An XFEM crack cutting the plate in two is refused up front (a FEM seam through the width
    is reported singular: crates/rustfrac-core/tests/suite/singular_detection.rs)."""
    with pytest.raises(rf.InvalidParameterError, match="cut the plate in two") as e:
        _core.run({"method": "xfem", "mesh": {"nx": 11, "ny": 21}, "crack": {"a0": 11.0}})
    assert e.value.param == "crack.a0"


@pytest.mark.parametrize("method", ["fem", "xfem"])
def test_condition_opt_out(method: str, tmp_path: Path) -> None:
    kw = {"crack": "seam"} if method == "fem" else {"a0": 2.0}
    scene = rf.scenes.edge_crack_plate(method=method, mesh=(22, 42), **kw)  # type: ignore[arg-type]
    on = rf.run(scene)
    off = rf.run(scene, condition=False)
    assert on.condition is not None and math.isfinite(on.condition)
    assert off.condition is None and off.scalars["condition_pivot_ratio"] is None
    # the estimate does not touch the numbers
    assert off.sigma22 == on.sigma22 and off.cmod == on.cmod
    assert "condition not computed" in off.summary()
    back = rf.load(off.save(tmp_path / "off", vtu=False))
    assert back.condition is None


@pytest.mark.parametrize("bad", ["no", 0, None])
def test_condition_keyword_must_be_a_bool(bad: object) -> None:
    scene = rf.scenes.edge_crack_plate(method="fem", mesh=(8, 12))
    with pytest.raises(rf.InvalidTypeError) as e:
        rf.run(scene, condition=bad)  # type: ignore[arg-type]
    assert e.value.param == "condition" and "condition" in str(e.value)


def test_condition_opt_out_in_growth() -> None:
    scene = rf.scenes.edge_crack_plate(method="xfem", mesh=(22, 41), a0=2.0, growth_steps=2)
    off = rf.run(scene, condition=False)
    assert off.condition is None and "condition" not in off.history
    assert len(off.history["K_I"]) == 3


def test_warning_kinds_round_trip(tmp_path: Path) -> None:
    scene = rf.scenes.edge_crack_plate("fem", nu=0.4999, mesh=(8, 12), a0=1.375)
    with pytest.warns(rf.LockingWarning):
        res = rf.run(scene)
    assert res.warning_kinds == ["locking"] and "0.4999" in res.warnings[0]
    d = res.save(tmp_path / "r", vtu=False)
    back = rf.load(d)
    assert back.warnings == res.warnings and back.warning_kinds == ["locking"]
    # a result saved before kinds were recorded still loads, kinds unknown
    js = next(p for p in d.iterdir() if p.suffix == ".json")
    doc = json.loads(js.read_text())
    del doc["meta"]["warning_kinds"]
    js.write_text(json.dumps(doc))
    old = rf.load(d)
    assert old.warnings == res.warnings and old.warning_kinds == [None]


def test_native_warning_pairs() -> None:
    scene = {
        "method": "fem",
        "mesh": {"nx": 8, "ny": 12},
        "material": {"nu": 0.4999},
        "crack": {"a0": 1.375},  # the seam on a grid node: no seam-length warning
    }
    out = _core.run(scene, None, False)
    assert out["scalars"]["condition"] is None and out["scalars"]["condition_pivot_ratio"] is None
    [kind], [msg] = out["meta"]["warning_kinds"], out["meta"]["warnings"]
    assert kind == "locking" and kind in _core.WARNING_KINDS and "0.4999" in msg
    assert set(_core.WARNING_KINDS) == set(rf.errors.WARNING_CLASSES)
    assert _core.COND_SINGULAR == 1e14 > _core.COND_WARN
