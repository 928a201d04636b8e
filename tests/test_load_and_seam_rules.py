"""Loads too small (or too large) for floating point are refused
naming the load key, the FEM seam's real length is reported (with a warning when it is not
``crack.a0``) and a seam that leaves no ligament is refused, one-point Gauss quadrature is
refused for Q4 elasticity (its hourglass modes)."""

from __future__ import annotations

import pytest

import rustfrac as rf


@pytest.mark.parametrize("method", ["fem", "xfem", "pd", "ccm_pd"])
@pytest.mark.parametrize("u0", [5e-324, 1e-250, -1e-290])
def test_underflowing_displacements_are_refused(method: str, u0: float) -> None:
    # before: u0 = 5e-324 gave sigma22 = -1.8e-321 (wrong sign) and K_I = 0, PD stopped with
    # "no_bond_in_tension" after 0 steps
    scene = rf.scenes.edge_crack_plate(method, u0=u0)
    with pytest.raises(rf.InvalidParameterError, match="underflow") as e:
        rf.run(scene)
    assert e.value.param == "load.u0"


def test_underflowing_traction_is_refused() -> None:
    scene = rf.scenes.edge_crack_plate("xfem", bc="traction", traction=1e-300)
    with pytest.raises(rf.InvalidParameterError, match="underflow") as e:
        rf.run(scene)
    assert e.value.param == "load.traction"


def test_small_but_representable_loads_scale_linearly() -> None:
    ref = rf.run(rf.scenes.edge_crack_plate("fem"))
    tiny = rf.run(rf.scenes.edge_crack_plate("fem", u0=0.01 * 1e-150))
    assert tiny.sigma22 > 0
    assert tiny.sigma22 == pytest.approx(ref.sigma22 * 1e-150, rel=1e-12)


def test_fem_zero_load_is_still_a_valid_fem_run() -> None:
    r = rf.run(rf.scenes.edge_crack_plate("fem", u0=0.0))
    assert r.sigma22 == 0.0


def test_seam_reports_its_real_length() -> None:
    # 44 elements across W = 11: nodes every 0.25; the seam runs to the first node >= a0
    exact = rf.run(rf.scenes.edge_crack_plate("fem", a0=1.0))
    assert exact.meta["seam_length"] == pytest.approx(1.0, abs=1e-12)
    assert not any("real length" in w for w in exact.meta["warnings"])
    off = rf.run(rf.scenes.edge_crack_plate("fem", a0=1.0000001))
    assert off.meta["seam_length"] == pytest.approx(1.25, abs=1e-12)
    assert any("real length is 1.250000" in w for w in off.meta["warnings"]), off.meta["warnings"]
    # the seam of 1.25 is what ran: more compliant than the 1.0 seam
    assert off.sigma22 < exact.sigma22


@pytest.mark.parametrize("a0", [10.8, 10.76, 10.99])
def test_seam_without_ligament_is_refused(a0: float) -> None:
    # before: any a0 in (10.75, 11) cut the plate through to one hinge node (sigma22 = 0.900)
    with pytest.raises(rf.InvalidParameterError, match="ligament") as e:
        rf.run(rf.scenes.edge_crack_plate("fem", a0=a0))
    assert e.value.param == "crack.a0"
    # the last seam with one element of ligament still runs
    r = rf.run(rf.scenes.edge_crack_plate("fem", a0=10.75))
    assert r.meta["seam_length"] == pytest.approx(10.75)


def test_one_point_gauss_is_refused() -> None:
    # before: SingularSystemError blaming a rigid mode (free grips), a CMOD 16 % too high
    # without a warning (clamped grips)
    for bc in ("free", "clamped"):
        with pytest.raises(rf.InvalidParameterError, match="hourglass") as e:
            rf.scenes.edge_crack_plate("fem", bc=bc, gauss=1)
        assert e.value.param == "mesh.gauss"
