"""Scale invariance through the whole Python path (scene -> TOML -> validation -> native run):
lengths times a scale ls (1e-6 .. 1e3), E times e (1e-6 .. 1e12), G0 times e ls give the same dimensionless
results to 1e-9 relative: sigma22 / E, CMOD / ls, K / (E sqrt(ls)), the critical load factors, the
crack path / ls and the SLA's sequence of broken bonds. No validation threshold or core tolerance
may be absolute (the Rust side of this check: crates/rustfrac-core/tests/suite/scale_invariance.rs)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import rustfrac as rf
from rustfrac.scene import Scene

TOL = 1e-9
SCALES = [(1e-6, 1e12, 1e-6), (1e3, 1e-6, 1e3), (1e-6, 1e-6, 1.0)]


def _scene(method: str, ls: float, e: float, t: float, **kw: Any) -> Scene:
    base: dict[str, Any] = dict(
        width=11.0 * ls,
        height=21.0 * ls,
        a0=1.1 * ls,
        crack_y=10.5 * ls,
        E=1e4 * e,
        G0=0.367 * e * ls,
        thickness=t,
        u0=0.01 * ls,
        traction=9.993 * e,
    )
    if method in ("pd", "ccm_pd"):
        base.update(dx=0.2 * ls, pd_center=(2.5 * ls, 10.5 * ls), pd_size=(4.4 * ls, 2.4 * ls))
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


@pytest.mark.parametrize("ls,e,t", SCALES)
def test_fem_scale_invariant(ls: float, e: float, t: float) -> None:
    r0 = rf.run(_scene("fem", 1.0, 1.0, 1.0, mesh=(22, 42)))
    r = rf.run(_scene("fem", ls, e, t, mesh=(22, 42)))
    _close(r.sigma22 / e, r0.sigma22, r0.sigma22, "sigma22 / E")
    _close(r.cmod / ls, r0.cmod, r0.cmod, "CMOD / l")


@pytest.mark.parametrize("ls,e,t", SCALES)
def test_xfem_growth_scale_invariant(ls: float, e: float, t: float) -> None:
    kw: dict[str, Any] = dict(mesh=(22, 42), crack_angle=15.0, growth_steps=3, bc="traction")
    kw["a0"] = 2.0 * ls
    r0 = rf.run(_scene("xfem", 1.0, 1.0, 1.0, **{**kw, "a0": 2.0}, a_stop=3.5))
    r = rf.run(_scene("xfem", ls, e, t, **kw, a_stop=3.5 * ls))
    ks = e * math.sqrt(ls)
    k0 = math.hypot(r0.K_I, r0.K_II)
    _close(r.K_I / ks, r0.K_I, k0, "K_I / (E sqrt(ls))")
    _close(r.K_II / ks, r0.K_II, k0, "K_II / (E sqrt(ls))")
    _close(r.J / (e * ls), r0.J, r0.J, "J / (E ls)")
    _close(r.sigma22 / e, r0.sigma22, r0.sigma22, "sigma22 / E")
    _close(r.cmod / ls, r0.cmod, r0.cmod, "CMOD / l")
    h, h0 = r.history, r0.history
    assert len(h["a"]) == len(h0["a"]) == 4
    _close(h["load_factor"], h0["load_factor"], max(h0["load_factor"]), "load factor")
    _close(h["traction"] / e, h0["traction"], max(h0["traction"]), "critical traction / E")
    _close(h["cmod"] / ls, h0["cmod"], max(h0["cmod"]), "critical CMOD / l")
    _close(h["tip_x"] / ls, h0["tip_x"], 11.0, "crack path x / l")
    _close(h["tip_y"] / ls, h0["tip_y"], 11.0, "crack path y / l")
    _close(h["kink_angle"], h0["kink_angle"], 1.0, "kink angle")


@pytest.mark.parametrize("ls,e,t", SCALES)
def test_ccm_pd_scale_invariant(ls: float, e: float, t: float) -> None:
    r0 = rf.run(_scene("ccm_pd", 1.0, 1.0, 1.0, sla_steps=8))
    r = rf.run(_scene("ccm_pd", ls, e, t, sla_steps=8))
    _close(r.sigma22 / e, r0.sigma22, r0.sigma22, "first-step sigma22 / E")
    _close(r.cmod / ls, r0.cmod, r0.cmod, "first-step CMOD / l")
    h, h0 = r.history, r0.history
    assert list(h["bond"]) == list(h0["bond"]), "different bonds broke"
    assert list(h["node_i"]) == list(h0["node_i"])
    _close(h["load_factor"], h0["load_factor"], max(h0["load_factor"]), "SLA load factors")
    _close(h["sigma22"] / e, h0["sigma22"], max(h0["sigma22"]), "SLA sigma22 / E")
    _close(h["cmod"] / ls, h0["cmod"], max(h0["cmod"]), "SLA CMOD / l")
    assert np.array_equal(r.damage, r0.damage)
