"""Numerical extremes through Python: the condition estimate of every solve in the
results (and saved with them), the ill-conditioning warning, and cracks the mesh cannot resolve
refused with a clear error. The geometry and mesh extremes themselves are measured in
crates/rustfrac-core/tests/suite/xfem_extremes.rs."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import _core, runner


@pytest.fixture(scope="module")
def xfem_growth() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate(method="xfem", mesh=(22, 41), a0=2.0, growth_steps=3))


def test_condition_estimate_in_xfem_and_fem_results(xfem_growth: rf.Result) -> None:
    c = xfem_growth.condition
    assert c is not None and math.isfinite(c)
    # a well-posed plate: far above 1 (a stiffness matrix), far below the warning threshold
    assert 1e3 < c < _core.COND_WARN
    assert xfem_growth.scalars["condition_pivot_ratio"] <= c
    hist = xfem_growth.history["condition"]
    assert np.isnan(hist[0])  # the unloaded origin has no solve: not computed
    assert np.isnan(xfem_growth.history["r_I"][0])
    assert np.all(np.isfinite(hist[1:])) and np.all(hist[1:] > 1e3)
    assert hist[1] == pytest.approx(c, rel=1e-12)  # the first critical state reuses the solve
    assert xfem_growth.warnings == []
    fem = rf.run(rf.scenes.edge_crack_plate(method="fem", crack="seam", mesh=(22, 42), a0=1.0))
    assert fem.condition is not None and 1e2 < fem.condition < _core.COND_WARN
    assert fem.warnings == []


def test_condition_is_dimensionless() -> None:
    """Same plate in other units (lengths x 1000, E x 1e-3): the same condition estimate."""
    kw = {"method": "xfem", "mesh": (22, 41)}
    a = rf.run(rf.scenes.edge_crack_plate(**kw, a0=2.0))
    b = rf.run(
        rf.scenes.edge_crack_plate(
            **kw, width=11000.0, height=21000.0, a0=2000.0, crack_y=10500.0, u0=10.0, E=10.0
        )
    )
    assert b.condition == pytest.approx(a.condition, rel=1e-6)


def test_condition_saved_and_loaded(xfem_growth: rf.Result, tmp_path: Path) -> None:
    xfem_growth.save(tmp_path, vtu=False)
    back = rf.load(tmp_path)
    assert back.condition == xfem_growth.condition
    assert back.scalars["condition_pivot_ratio"] == xfem_growth.scalars["condition_pivot_ratio"]
    np.testing.assert_array_equal(back.history["condition"], xfem_growth.history["condition"])
    assert back.warnings == []


@pytest.mark.parametrize("kind", _core.WARNING_KINDS)
def test_warnings_become_python_warnings(monkeypatch: pytest.MonkeyPatch, kind: str) -> None:
    """A result whose core reported a warning warns on run() with the class of its kind, not of
    its text: every message below mentions a condition estimate."""
    real = runner._RUNNERS["fem"]
    cls = rf.errors.WARNING_CLASSES[kind]
    others = [c for k, c in rf.errors.WARNING_CLASSES.items() if k != kind]

    def flagged(scene: rf.Scene, progress: runner.ProgressCallback | None, cond: bool) -> rf.Result:
        res = real(scene, progress, cond)
        res.meta["warnings"] = [f"solve: condition estimate 3.00e+13 ({kind})"]
        res.meta["warning_kinds"] = [kind]
        return res

    monkeypatch.setitem(runner._RUNNERS, "fem", flagged)
    with pytest.warns(cls, match="3.00e") as rec:
        res = rf.run(rf.scenes.edge_crack_plate(method="fem", mesh=(8, 16), a0=1.375))
    assert [type(w.message) for w in rec] == [cls]
    assert not any(issubclass(cls, o) or issubclass(o, cls) for o in others)
    assert res.warnings and res.warning_kinds == [kind]
    assert issubclass(rf.IllConditionedWarning, RuntimeWarning)
    assert issubclass(rf.LockingWarning, rf.AccuracyWarning)
    assert issubclass(rf.DiscretisationWarning, rf.AccuracyWarning)
    monkeypatch.setitem(runner._RUNNERS, "fem", real)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rf.run(rf.scenes.edge_crack_plate(method="fem", mesh=(8, 16), a0=1.375))


@pytest.mark.parametrize(
    ("a0", "mesh", "what"),
    [
        (0.11, (44, 83), "crack 0.44 elements long"),
        (10.9, (44, 83), "ligament of 0.4 elements"),
        (10.5, (22, 41), "one element across the ligament"),
    ],
)
def test_unresolved_cracks_are_refused(a0: float, mesh: tuple[int, int], what: str) -> None:
    with pytest.raises(rf.InvalidParameterError, match="cannot resolve") as e:
        rf.run(rf.scenes.edge_crack_plate(method="xfem", a0=a0, mesh=mesh, r_I=0.5))
    assert e.value.param == "crack.a0", what
    assert "element lengths" in str(e.value)


def test_deep_crack_runs_with_finite_numbers() -> None:
    """a/W = 0.9 on 88 x 167 (ligament 8.8 elements): finite K, CMOD and condition."""
    res = rf.run(rf.scenes.edge_crack_plate(method="xfem", a0=9.9, mesh=(88, 167)))
    assert all(math.isfinite(v) for v in (res.K_I, res.K_II, res.cmod, res.sigma22))
    assert res.K_I > 0 and res.condition < _core.COND_WARN
