"""The energy audit (rustfrac.energy) on cases with a known answer: LEFM growth
in mode I dissipates G0 per unit of new crack area, and a PD strip breaking across releases at
least the energy of the bonds it breaks, which is the grid's discrete fracture energy computed
here independently (bond by bond, partial volumes by sub-sampling)."""

from __future__ import annotations

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import energy


def test_xfem_mode_one_growth_dissipates_g0() -> None:
    """Each critical state has K_eq = K_Ic, i.e. G = G0 (Irwin, plane strain E' = E/(1-nu^2)):
    the areas between successive secants of the load path must give G0 per unit of new crack
    area. The secant triangle is exact to second order in the step da, and the I-integral's K on
    the paper's 44 x 83 mesh is within a few 0.1 %: 1 % covers both (measured 0.9987, each step
    0.998-0.999). A wrong E' (plane stress) would be 6 % off."""
    res = rf.run(rf.scenes.edge_crack_plate(method="xfem", growth_steps=200))
    a = energy.audit(res)
    print(f"XFEM: G / G0 = {a['ratio']:.5f} over {a['crack_area']:.3f} of new crack")
    assert a["ratio"] == pytest.approx(1.0, abs=0.01)
    steps = a["ratio_per_step"][np.isfinite(a["ratio_per_step"])]
    assert steps.size > 20 and np.all(np.abs(steps - 1.0) < 0.01)


def _cell_fraction_in_horizon(xi: np.ndarray, dx: float, delta: float, n: int = 64) -> np.ndarray:
    """The fraction of the neighbour's dx x dx cell inside the horizon, by n x n sub-sampling
    (an independent partial-volume rule)."""
    g = ((np.arange(n) + 0.5) / n - 0.5) * dx
    gx, gy = np.meshgrid(g, g)
    return np.array([np.mean(np.hypot(v[0] + gx, v[1] + gy) <= delta) for v in xi])


def test_pd_strip_breaking_across_and_the_discrete_fracture_energy() -> None:
    """A 2 x 2 PD plate (dx = 0.1, m = 3) pulled apart by its grips from a 0.3 edge pre-crack
    until it separates. The discrete fracture energy of the grid, the energy of the bonds crossing
    the pre-crack's line ahead of it, 1/2 c s0^2 |xi| beta V^2 each, per unit length, is G0 to the
    grid's discretisation (measured +1.05 %). The SLA releases at least the energy of the bonds it
    breaks (removing a spring at fixed displacement lowers the minimum energy by at least the
    spring's own), and those bonds cut the plate once (their energy is the line's to 10 %, the
    crack leaves the line here and there). Measured: released / discrete 1.21 (the snapping of
    each break, 1.15, and the crack's detours, 1.06): the SLA is not energy-neutral."""
    w, dx, a0, yc = 2.0, 0.1, 0.3, 1.05
    s = rf.scenes.edge_crack_plate(
        method="pd", width=w, height=2.0, dx=dx, m=3, a0=a0, crack_y=yc, sla_steps=5000
    )
    res = rf.run(s)
    assert res.meta["status"] == "separated"
    au = energy.audit(res)
    g0, v = au["G0"], dx * dx
    sc, f = res.scalars, res.fields
    xy = f["node_xy"]
    bn = np.asarray(f["bond_nodes"])
    broken = np.asarray(f["broken"], bool)
    xi = xy[bn[:, 1]] - xy[bn[:, 0]]
    length = np.hypot(xi[:, 0], xi[:, 1])
    ya, yb = xy[bn[:, 0], 1], xy[bn[:, 1], 1]
    cross = (np.minimum(ya, yb) < yc) & (np.maximum(ya, yb) > yc)
    xc = xy[bn[:, 0], 0] + (yc - ya) / np.where(cross, xi[:, 1], 1.0) * xi[:, 0]
    ahead, pre = cross & (xc > a0), cross & (xc <= a0)

    def bond_energy(sel: np.ndarray) -> float:
        beta = _cell_fraction_in_horizon(xi[sel], dx, sc["delta"])
        return float(np.sum(0.5 * sc["c"] * sc["s0"] ** 2 * length[sel] * beta * v * v))

    g_line = bond_energy(ahead) / (w - a0)
    broken_energy = bond_energy(broken & ~pre)
    released = au["energy"]
    print(
        f"discrete G / G0 = {g_line / g0:.4f}; released / broken-bond energy = "
        f"{released / broken_energy:.4f}; broken-bond energy / line = "
        f"{broken_energy / (g_line * (w - a0)):.4f}; released / line = "
        f"{released / (g_line * (w - a0)):.4f}; audit ratio (damage front) {au['ratio']:.4f}"
    )
    assert g_line / g0 == pytest.approx(1.0, abs=0.05)
    assert released >= broken_energy * (1 - 1e-9)
    assert broken_energy / (g_line * (w - a0)) == pytest.approx(1.0, abs=0.10)
    assert 1.0 <= released / (g_line * (w - a0)) < 1.5


def _grid_energy_subsampled(m: int) -> float:
    """The grid's discrete fracture energy over G0 on an infinite x1-parallel line between node
    rows, with partial volumes and gamma both from sub-sampling (independent of the core's exact
    cell/disc areas): a bond of offset (di, dj), dj > 0, crosses the line dj times per column;
    c s0^2 = 4 gamma G0 / (h m^4 dx^4) (eqs. 47, 48), so G / G0 = 2 gamma / m^4 sum dj |xi| beta
    in grid units."""
    r = m + 1
    offs = np.array(
        [(i, j) for j in range(-r, r + 1) for i in range(-r, r + 1) if (i, j) != (0, 0)], float
    )
    beta = _cell_fraction_in_horizon(offs, 1.0, float(m), n=256)
    length = np.hypot(offs[:, 0], offs[:, 1])
    gamma = np.pi * m**3 / 4 / np.sum(offs[:, 0] ** 4 / length**3 * beta)
    up = offs[:, 1] > 0
    return float(2 * gamma / m**4 * np.sum(offs[up, 1] * length[up] * beta[up]))


@pytest.mark.parametrize("m", [1, 3, 4, 7])
def test_s0_calibration_grid_is_the_discrete_fracture_energy(m: int) -> None:
    """``pd.s0_calibration = "grid"``: the core's G_ref / G0 (exact partial volumes) against the
    sub-sampled sum (256 x 256 points a cell: measured agreement within 3e-5 for m = 1, 3, 4, 7); the factor
    makes it G0. The run itself is a tiny pure-PD plate without steps."""
    s = rf.scenes.edge_crack_plate(
        method="pd", width=3.0, height=3.0, dx=0.1, m=m, a0=0.3, crack_y=1.45, sla_steps=0,
        s0_calibration="grid",
    )  # fmt: skip
    cal = rf.run(s).meta["s0_calibration"]
    ref = _grid_energy_subsampled(m)
    print(f"m = {m}: core {cal['G_ref_over_G0']:.6f}, sub-sampled {ref:.6f}")
    assert cal["rule"] == "grid"
    assert cal["G_ref_over_G0"] == pytest.approx(ref, abs=2e-4)
    assert cal["factor"] ** 2 * cal["G_ref_over_G0"] == pytest.approx(1.0, rel=1e-12)


def test_s0_calibration_sla_transfers_to_another_strip() -> None:
    """``pd.s0_calibration = "sla"`` makes the core's reference strip (6 x 8 horizons, free grips,
    an edge pre-crack of one horizon and half a cell) release G0 per unit of new crack area. Here the
    2 x 2 strip above (20 x 20 cells = 6.7 horizons square, pre-crack 3 cells), a different
    strip, breaks across with the calibrated s0: measured 1.016 G0 (continuum s0: 1.226). The
    tolerance, 10 %, is the spread of the release ratio over strip sizes at m = 3 measured in
    the core's size study (1.18 .. 1.32 for 6 x 8 .. 10 x 10 horizons, free and clamped grips:
    the crack's detours differ from strip to strip); the calibration's factor is exact (the run
    equals the continuum run rescaled, tests/suite/s0_calibration.rs)."""
    w, dx, a0, yc = 2.0, 0.1, 0.3, 1.05
    kw = dict(method="pd", width=w, height=2.0, dx=dx, m=3, a0=a0, crack_y=yc, sla_steps=5000)
    base = rf.run(rf.scenes.edge_crack_plate(**kw))
    res = rf.run(rf.scenes.edge_crack_plate(**kw, s0_calibration="sla"))
    assert res.meta["status"] == "separated"
    cal = res.meta["s0_calibration"]
    g = energy.audit(res)["energy"] / (w - a0) / energy.audit(res)["G0"]
    g_base = energy.audit(base)["energy"] / (w - a0) / energy.audit(base)["G0"]
    print(
        f"sla: G_ref / G0 = {cal['G_ref_over_G0']:.5f}, factor {cal['factor']:.5f}; the strip "
        f"releases {g:.4f} G0 per unit area (continuum s0: {g_base:.4f})"
    )
    assert g == pytest.approx(g_base * cal["factor"] ** 2, rel=1e-9)
    assert g == pytest.approx(1.0, abs=0.10)


def test_s0_calibration_unknown_choice() -> None:
    with pytest.raises(rf.InvalidParameterError, match=r"pd\.s0_calibration"):
        rf.scenes.edge_crack_plate(method="ccm_pd", s0_calibration="exact")


def test_the_audit_needs_a_conjugate_load() -> None:
    res = rf.run(rf.scenes.edge_crack_plate(method="xfem", bc="traction", growth_steps=3))
    assert res.meta["work_conjugate"] is None
    with pytest.raises(rf.PlotDataError, match="work_conjugate"):
        energy.audit(res)
    single = rf.run(rf.scenes.edge_crack_plate(method="xfem"))
    with pytest.raises(rf.PlotDataError, match="load path"):
        energy.audit(single)


def test_the_audit_states_its_units_from_the_result_schema() -> None:
    """The audit's entries carry the units of the core's result table (no unit written in the
    reader): energies as the strain energy, G0 as J (energy per area), lengths as the history's
    crack length."""
    table = {(e["group"], e["name"]): e["unit"] for e in rf.result_schema("xfem")}
    table.update({(e["group"], e["name"]): e["unit"] for e in rf.result_schema("fem")})
    res = rf.run(rf.scenes.edge_crack_plate(method="xfem", growth_steps=4))
    units = energy.audit(res)["units"]
    assert units == {
        "G0": table["scalars", "J"],
        "energy": table["scalars", "energy"],
        "dissipated": table["scalars", "energy"],
        "a": table["history", "a"],
        "a0": table["history", "a"],
    }
    assert units["G0"] == f"{units['energy']}/area" and units["a"] == table["fields", "coords"]
