"""Property tests: any valid scene survives TOML and dict round trips exactly; any nu outside
(-1, 0.5) is refused naming material.nu."""

from __future__ import annotations

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import rustfrac as rf  # noqa: E402
from rustfrac.scene import Scene  # noqa: E402

pos = st.floats(min_value=1e-6, max_value=1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(
    method=st.sampled_from(["fem", "xfem"]),
    bc=st.sampled_from(["free", "clamped", "traction"]),
    E=pos,
    nu=st.floats(min_value=-0.99, max_value=0.499),
    width=st.floats(min_value=1.0, max_value=100.0),
    frac=st.floats(min_value=0.01, max_value=0.99),
    nx=st.integers(min_value=1, max_value=500),
    u0=st.floats(min_value=-1.0, max_value=1.0),
    name=st.text(max_size=20),
)
def test_valid_scene_round_trips(
    method: str,
    bc: str,
    E: float,
    nu: float,
    width: float,
    frac: float,
    nx: int,
    u0: float,
    name: str,
) -> None:
    s = rf.scenes.edge_crack_plate(
        method=method,
        bc=bc,
        E=E,
        nu=nu,
        width=width,
        a0=frac * width,
        mesh=(nx, 7),
        u0=u0,
        name=name,
    )
    assert Scene.from_toml_str(s.to_toml()) == s
    assert Scene.from_dict(s.to_dict()) == s


@settings(max_examples=40, deadline=None)
@given(nu=st.one_of(st.floats(min_value=0.5), st.floats(max_value=-1.0), st.just(float("nan"))))
def test_bad_nu_refused(nu: float) -> None:
    with pytest.raises(rf.InvalidParameterError, match=r"material\.nu"):
        rf.scenes.edge_crack_plate(nu=nu)
