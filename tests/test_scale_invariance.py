"""Scale invariance through the whole Python path (scene -> TOML -> validation -> native run):
lengths times l (1e-6 .. 1e3), E times e (1e-6 .. 1e12), G0 times e l give the same dimensionless
results to 1e-9 relative: sigma22 / E, CMOD / l, K / (E sqrt(l)), the critical load factors, the
crack path / l and the SLA's sequence of broken bonds. No validation threshold or core tolerance
may be absolute (the Rust side of this check: crates/rustfrac-core/tests/scale_invariance.rs)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import rustfrac as rf
from rustfrac.scene import Scene

TOL = 1e-9
SCALES = [(1e-6, 1e12, 1e-6), (1e3, 1e-6, 1e3), (1e-6, 1e-6, 1.0)]


def _scene(method: str, l: float, e: float, t: float, **kw: Any) -> Scene:
    base: dict[str, Any] = dict(
        width=11.0 * l,
        height=21.0 * l,
        a0=1.1 * l,
        crack_y=10.5 * l,
        E=1e4 * e,
        G0=0.367 * e * l,
        thickness=t,
        u0=0.01 * l,
        traction=9.993 * e,
    )
    if method in ("pd", "ccm_pd"):
        base.update(dx=0.2 * l, pd_center=(2.5 * l, 10.5 * l), pd_size=(4.4 * l, 2.4 * l))
    base.update(kw)
    s = rf.scenes.edge_crack_plate(method, **base)
    # through TOML: the file format must carry every scale exactly
    s2 = Scene.from_toml_str(s.to_toml())
    assert s2 == s
    return s2


def _close(got: Any, want: Any, size: float, what: str) -> None:
    got, want = np.asarray(got, float), np.asarray(want, float)
    assert np.all(np.isfinite(got)), what
    err = float(np.max(np.abs(got - want), initial=0.0)) / abs(size)
    assert err <= TOL, f"{what}: relative deviation {err:.2e}"


@pytest.mark.parametrize("l,e,t", SCALES)
def test_fem_scale_invariant(l: float, e: float, t: float) -> None:
    r0 = rf.run(_scene("fem", 1.0, 1.0, 1.0, mesh=(22, 42)))
    r = rf.run(_scene("fem", l, e, t, mesh=(22, 42)))
    _close(r.sigma22 / e, r0.sigma22, r0.sigma22, "sigma22 / E")
    _close(r.cmod / l, r0.cmod, r0.cmod, "CMOD / l")


@pytest.mark.parametrize("l,e,t", SCALES)
def test_xfem_growth_scale_invariant(l: float, e: float, t: float) -> None:
    kw: dict[str, Any] = dict(mesh=(22, 42), crack_angle=15.0, growth_steps=3, bc="traction")
    kw["a0"] = 2.0 * l
    r0 = rf.run(_scene("xfem", 1.0, 1.0, 1.0, **{**kw, "a0": 2.0}, a_stop=3.5))
    r = rf.run(_scene("xfem", l, e, t, **kw, a_stop=3.5 * l))
    ks = e * math.sqrt(l)
    k0 = math.hypot(r0.K_I, r0.K_II)
    _close(r.K_I / ks, r0.K_I, k0, "K_I / (E sqrt(l))")
    _close(r.K_II / ks, r0.K_II, k0, "K_II / (E sqrt(l))")
    _close(r.J / (e * l), r0.J, r0.J, "J / (E l)")
    _close(r.sigma22 / e, r0.sigma22, r0.sigma22, "sigma22 / E")
    _close(r.cmod / l, r0.cmod, r0.cmod, "CMOD / l")
    h, h0 = r.history, r0.history
    assert len(h["a"]) == len(h0["a"]) == 4
    _close(h["load_factor"], h0["load_factor"], max(h0["load_factor"]), "load factor")
    _close(h["traction"] / e, h0["traction"], max(h0["traction"]), "critical traction / E")
    _close(h["cmod"] / l, h0["cmod"], max(h0["cmod"]), "critical CMOD / l")
    _close(h["tip_x"] / l, h0["tip_x"], 11.0, "crack path x / l")
    _close(h["tip_y"] / l, h0["tip_y"], 11.0, "crack path y / l")
    _close(h["kink_angle"], h0["kink_angle"], 1.0, "kink angle")


@pytest.mark.parametrize("l,e,t", SCALES)
def test_ccm_pd_scale_invariant(l: float, e: float, t: float) -> None:
    r0 = rf.run(_scene("ccm_pd", 1.0, 1.0, 1.0, sla_steps=8))
    r = rf.run(_scene("ccm_pd", l, e, t, sla_steps=8))
    _close(r.sigma22 / e, r0.sigma22, r0.sigma22, "first-step sigma22 / E")
    _close(r.cmod / l, r0.cmod, r0.cmod, "first-step CMOD / l")
    h, h0 = r.history, r0.history
    assert list(h["bond"]) == list(h0["bond"]), "different bonds broke"
    assert list(h["node_i"]) == list(h0["node_i"])
    _close(h["load_factor"], h0["load_factor"], max(h0["load_factor"]), "SLA load factors")
    _close(h["sigma22"] / e, h0["sigma22"], max(h0["sigma22"]), "SLA sigma22 / E")
    _close(h["cmod"] / l, h0["cmod"], max(h0["cmod"]), "SLA CMOD / l")
    assert np.array_equal(r.damage, r0.damage)
