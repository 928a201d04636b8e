"""The convergence study of the energy audit (benches/audit_convergence.py):
its rate fit on data with a known rate, the audit along the crack (its bins add up to the
total), and XFEM's G / G0 approaching 1 under mesh refinement (LEFM's known answer). No result
of the study itself is asserted."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import energy

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def study():
    spec = importlib.util.spec_from_file_location(
        "audit_convergence", ROOT / "benches" / "audit_convergence.py"
    )
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def test_rate_fit_recovers_a_known_rate(study) -> None:
    """q = 1 + 0.3 h^1.5 on non-uniform levels: the log-log fit against the known limit gives
    p = 1.5, C = 0.3 with zero residual, Richardson the limit and the rate; a perturbed level
    leaves a residual; a sign change of the differences is no asymptotic range."""
    h = np.array([0.4, 0.25, 0.15, 0.1, 0.06])
    q = 1.0 + 0.3 * h**1.5
    r = study.rates(h, q, 1.0)
    assert r["fit"]["p"] == pytest.approx(1.5, abs=1e-10)
    assert r["fit"]["C"] == pytest.approx(0.3, rel=1e-10)
    assert r["fit"]["residual"] < 1e-10
    assert r["richardson"]["status"] == "ok"
    assert r["richardson"]["value"] == pytest.approx(1.0, abs=1e-10)
    assert r["richardson"]["rate"] == pytest.approx(1.5, abs=1e-8)
    assert np.all(np.array(r["differences"]) < 0)
    noisy = q * (1.0 + np.array([0.0, 0.02, 0.0, -0.02, 0.0]))
    assert study.fit_rate(h, noisy, 1.0)["residual"] > 0.01
    zigzag = np.array([1.3, 1.1, 1.2, 1.05, 1.15])
    assert study.rates(h, zigzag, 1.0)["richardson"]["status"] == "not in the asymptotic range"
    assert study.fit_rate(h, np.ones(5), 1.0)["p"] is None


def test_audit_along_the_crack_adds_up_to_the_total(study) -> None:
    """The bins of energy.along partition the dissipated energy: their length-weighted mean over
    edges spanning the whole advance is the audit's total ratio (XFEM and a coarse CCM-PD run
    of the study); XFEM's bins are each G0 within the mesh's 0.5 %."""
    res = rf.run(study.pd_scene(5, 4))
    for au in (
        energy.audit(res),
        energy.audit(rf.run(rf.scenes.edge_crack_plate(method="xfem", growth_steps=200))),
    ):
        a_end = float(au["a"][-1])
        edges = np.linspace(au["a0"], a_end, 4)
        bins = energy.along(au, edges)
        mean = float(np.sum(bins * np.diff(edges)) / (a_end - au["a0"]))
        assert mean == pytest.approx(au["ratio"], rel=1e-12)
        if au["method"] == "xfem":
            assert np.all(np.abs(bins - 1.0) < 0.005)
    assert np.isnan(energy.along(au, [a_end + 1.0, a_end + 2.0])[0])
    with pytest.raises(ValueError, match="edges"):
        energy.along(au, [2.0, 1.0])


def test_xfem_audit_moves_towards_g0_with_the_mesh(study) -> None:
    """LEFM growth dissipates G0 per unit crack area; on two meshes of the study's family (the
    tip at the same fraction of its element) the audit is within 0.5 % of 1 and closer on the
    finer one (measured 0.99867, 0.99924: an error of the I-integral's K, which converges)."""
    rows = [study.xfem_row(m)[0] for m in ((44, 83), (84, 161))]
    err = [abs(r["G_ratio"] - 1.0) for r in rows]
    print("XFEM G/G0:", [round(r["G_ratio"], 5) for r in rows])
    assert max(err) < 0.005
    assert err[1] < err[0]


def test_along_spreads_each_interval_over_its_advance() -> None:
    """A hand-made audit: advances 1 -> 1.5 -> 2 (energy 0.5 each), a break that leaves the
    front at 2 (0.2), an advance 2 -> 3 (1.0); G0 = t = 1."""
    au = {
        "a0": 1.0, "a": [1.5, 2.0, 2.0, 3.0], "dissipated": [0.5, 0.5, 0.2, 1.0],
        "G0": 1.0, "thickness": 1.0,
    }  # fmt: skip
    assert energy.along(au, [1.0, 2.0, 3.0]) == pytest.approx([1.2, 1.0])
    # edges starting past a0: what lies behind counts in the first interval
    assert energy.along(au, [1.5, 2.5, 3.0]) == pytest.approx([1.7, 1.0])
    # an interval the crack covers only in part: divided by the covered length
    assert energy.along(au, [1.0, 2.5, 4.0]) == pytest.approx([1.7 / 1.5, 0.5 / 0.5])


def test_interpolation_refuses_to_extrapolate(study) -> None:
    xs, ys = np.array([1.1, 1.558, 2.0]), np.array([30.0, 26.0, 24.0])
    assert study.interp_inside(1.5, xs, ys) == pytest.approx(30.0 - 4.0 * 0.4 / 0.458)
    with pytest.raises(ValueError, match="outside"):
        study.interp_inside(1.0, xs, ys)
