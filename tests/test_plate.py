"""The paper's plate through the Python API (plain FEM)."""

from __future__ import annotations

import threading
import time
from typing import Any

import numpy as np
import pytest

import rustfrac as rf

E, NU, U0, W, L = 10000.0, 0.25, 0.01, 11.0, 21.0
SIGMA_EXACT = E / (1 - NU**2) * 2 * U0 / L  # uniaxial plane strain, u1 free


def test_uncracked_free_grips_exact(uncracked: rf.Result) -> None:
    assert uncracked.method == "fem"
    assert uncracked.sigma22 == pytest.approx(SIGMA_EXACT, rel=1e-10, abs=0)
    assert uncracked.cmod == 0.0
    assert uncracked.n_dofs == 2 * 45 * 84
    assert uncracked.wall_time_s > 0
    assert uncracked.meta["bc"] == "free"
    assert uncracked.meta["anchor_node"] is not None
    # the exact field: s22 uniform, s11 = s12 = 0 at every node
    s = uncracked.fields["nodal_stress"]
    assert s.shape == (45 * 84, 3)
    np.testing.assert_allclose(s[:, 1], SIGMA_EXACT, rtol=1e-10)
    np.testing.assert_allclose(s[:, [0, 2]], 0.0, atol=1e-10 * SIGMA_EXACT)
    assert uncracked.displacement.shape == (45 * 84, 2)
    assert uncracked.elements.dtype == np.int64


def test_clamped_grips_are_stiffer(uncracked: rf.Result) -> None:
    clamped = rf.run(rf.scenes.edge_crack_plate(method="fem", crack="none", bc="clamped"))
    rel = clamped.sigma22 / uncracked.sigma22 - 1
    print(
        f"clamped grips: sigma22 = {clamped.sigma22:.6f} vs free {uncracked.sigma22:.6f} "
        f"(+{100 * rel:.3f} %)"
    )
    assert clamped.meta["bc"] == "clamped"
    assert clamped.meta["anchor_node"] is None
    # constrained lateral contraction: stiffer, but bounded by the fully constrained modulus
    # E (1 - nu) / ((1 + nu)(1 - 2 nu)) = 1.2 E at nu = 0.25, i.e. +12.5 % over E/(1-nu^2)
    assert 1e-3 < rel < 0.125


def test_traction_gives_applied_stress() -> None:
    res = rf.run(rf.scenes.edge_crack_plate(method="fem", crack="none", bc="traction"))
    assert res.sigma22 == pytest.approx(9.993, rel=1e-10)


def test_seam_crack_opens(seam: rf.Result, uncracked: rf.Result) -> None:
    assert seam.cmod > 0
    assert seam.sigma22 < uncracked.sigma22  # the crack adds compliance
    assert seam.n_dofs > uncracked.n_dofs  # duplicated seam nodes
    assert seam.meta["seam_y"] == pytest.approx(10.5, abs=21 / 83)
    print(f"seam crack 44x83: sigma22 = {seam.sigma22:.6f}, CMOD = {seam.cmod:.6g}")


def test_singular_native_grid_without_supports() -> None:
    with pytest.raises(rf.SingularSystemError):
        rf._core.solve_fem_grid(
            width=1.0, height=1.0, nx=3, ny=3, e=1.0, nu=0.3, fixed_dofs=[], fixed_values=[]
        )
    # only u2 fixed on the bottom: the x translation is free
    with pytest.raises(rf.SingularSystemError):
        rf._core.solve_fem_grid(
            width=1.0,
            height=1.0,
            nx=3,
            ny=3,
            e=1.0,
            nu=0.3,
            fixed_dofs=[2 * n + 1 for n in range(4)],
            fixed_values=[0.0] * 4,
        )


def test_native_grid_uniaxial_exact() -> None:
    nx = ny = 3
    bottom = list(range(nx + 1))
    top = [ny * (nx + 1) + i for i in range(nx + 1)]
    dofs = [2 * n + 1 for n in bottom + top] + [0]
    vals = [0.0] * len(bottom) + [0.1] * len(top) + [0.0]
    out = rf._core.solve_fem_grid(
        width=2.0,
        height=1.0,
        nx=nx,
        ny=ny,
        e=100.0,
        nu=0.3,
        plane="stress",
        fixed_dofs=dofs,
        fixed_values=vals,
    )
    np.testing.assert_allclose(out["nodal_stress"][:, 1], 100.0 * 0.1, rtol=1e-10)


def _hook(name: str) -> Any:
    """A native test hook, present in builds with the cargo feature "test-hooks" (.ci/run)."""
    hook = getattr(rf._core, name, None)
    if hook is None:
        pytest.skip(f"native test hook {name} not built (cargo feature test-hooks)")
    return hook


def test_panic_becomes_exception() -> None:
    with pytest.raises(rf.InternalError, match="deliberate panic"):
        _hook("_panic_demo")()


def test_core_errors_map_to_value_error() -> None:
    # the native layer checks too (bypassing Scene validation), naming the scene key
    small = {"method": "fem", "mesh": {"nx": 4, "ny": 4}}
    with pytest.raises(rf.InvalidParameterError, match="nu") as e:
        rf._core.run({**small, "material": {"E": 1.0, "nu": 0.7}})
    assert isinstance(e.value, ValueError) and e.value.param == "material.nu"
    with pytest.raises(rf.InvalidParameterError, match="bc") as e:
        rf._core.run({**small, "load": {"bc": "glued"}})
    assert e.value.param == "load.bc"


def test_progress_is_throttled_and_final_call_made() -> None:
    calls: list[tuple[int, int, str]] = []
    n = _hook("_progress_demo")(50, 0.01, lambda *a: calls.append(a))
    assert n == len(calls)
    assert calls[-1][:2] == (50, 50)  # the last report always arrives
    assert 2 <= len(calls) <= 12  # ~0.5 s of work at <= 1 call per 0.1 s (+ first and last)


def test_progress_exception_propagates() -> None:
    def boom(done: int, total: int, msg: str) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        _hook("_progress_demo")(20, 0.01, boom)


def test_gil_released_during_native_call() -> None:
    ticks = 0
    stop = False

    def spin() -> None:
        nonlocal ticks
        while not stop:
            ticks += 1
            time.sleep(0.001)

    demo = _hook("_progress_demo")
    t = threading.Thread(target=spin)
    t.start()
    demo(30, 0.01)  # 0.3 s in Rust, without the GIL
    stop = True
    t.join()
    assert ticks > 20


def test_run_progress_callback_on_fem() -> None:
    calls: list[tuple[int, int, str]] = []
    rf.run(rf.scenes.edge_crack_plate(mesh=(8, 16)), progress=lambda *a: calls.append(a))
    assert calls and calls[-1][0] == calls[-1][1]


@pytest.mark.parametrize("method", ["fem", "xfem", "pd", "ccm_pd"])
def test_every_method_is_bound(method: str) -> None:
    from rustfrac.runner import _RUNNERS

    assert method in _RUNNERS
