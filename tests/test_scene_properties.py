"""Property tests (hypothesis): any valid scene survives TOML and dict round trips exactly; any nu
outside (-1, 0.5) is refused naming material.nu; hostile scenes, dicts and TOML text (random
types, nested garbage, unicode, huge and tiny numbers, missing and extra keys, huge meshes) are
refused by name or run to finite results, quickly."""

from __future__ import annotations

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import event, given, settings  # noqa: E402
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


# ----------------------------------------------------------------------------------------------
# hostile input: random types, nested garbage, unicode, huge/tiny numbers, missing/extra keys,
# broken TOML, huge meshes. Nothing may crash the interpreter, hang or return NaN, and every
# refusal is an InvalidParameterError (a ValueError) naming the parameter.

import math  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from typing import Any  # noqa: E402

from rustfrac.scene import MAX_ELEMENTS, METHODS  # noqa: E402

WILD_FLOATS = st.one_of(
    st.floats(),
    st.sampled_from([0.0, -0.0, 5e-324, 1e-300, 1e-30, 1e30, 1.0000001e30, 1e300, math.inf]),
)
WILD_INTS = st.one_of(
    st.integers(-5, 200), st.integers(), st.sampled_from([2**63, -(2**63), 10**400])
)
WILD_TEXT = st.text(st.characters(codec=None), max_size=12)
SCALARS = st.one_of(st.none(), st.booleans(), WILD_FLOATS, WILD_INTS, WILD_TEXT)
GARBAGE = st.recursive(
    SCALARS,
    lambda ch: st.lists(ch, max_size=3) | st.dictionaries(WILD_TEXT, ch, max_size=3),
    max_leaves=8,
)


def _small(method: str) -> dict[str, Any]:
    """A small valid scene of each method (fast to run)."""
    kw: dict[str, Any] = {"mesh": (8, 12)}
    if method == "xfem":  # the r_I = 2.5 element q-domain must fit between tip and edges
        kw = {"mesh": (16, 30), "a0": 3.0, "growth_steps": 2}
    if method in ("pd", "ccm_pd"):
        kw = dict(
            width=3.0,
            height=2.5,
            crack_y=1.125,
            a0=1.1,
            dx=0.25,
            sla_steps=3,
            pd_center=(1.5, 1.125),
            pd_size=(2.5, 2.0),
        )
    return rf.scenes.edge_crack_plate(method, **kw).to_dict()


def _names_param(e: rf.InvalidParameterError) -> None:
    assert isinstance(e, ValueError) and isinstance(e, rf.RustfracError)
    assert isinstance(e.param, str) and e.param, repr(e)
    assert e.param.split(".")[-1] in str(e), (e.param, str(e))


@st.composite
def mutated_scene(draw: Any, garbage: bool = True) -> dict[str, Any]:
    """A small valid scene dict with a few random edits: values replaced (by garbage or by a
    number scaled far out), keys deleted or added, whole sections replaced."""
    method = draw(st.sampled_from(METHODS))
    d = _small(method)
    for _ in range(draw(st.integers(0, 3))):
        secs = sorted(k for k in d if isinstance(d[k], dict) and d[k])
        if not secs:
            break
        sec = draw(st.sampled_from(secs))
        key = draw(st.sampled_from(sorted(d[sec], key=str)))
        edit = draw(st.sampled_from(["scale", "value", "delete", "extra", "section", "top"]))
        if edit == "scale" and isinstance(d[sec][key], float):
            d[sec][key] *= draw(st.sampled_from([-1.0, 0.0, 1e-40, 1e-3, 0.5, 2.0, 1e3, 1e40]))
        elif edit == "delete":
            d[sec].pop(key)
        elif garbage and edit == "value":
            d[sec][key] = draw(GARBAGE)
        elif garbage and edit == "extra":
            d[sec][draw(WILD_TEXT)] = draw(GARBAGE)
        elif garbage and edit == "section":
            d[sec] = draw(GARBAGE)
        elif garbage and edit == "top":
            d[draw(st.sampled_from(["method", "name", "solver", "mesh", "pd", "xfem"]))] = draw(
                GARBAGE
            )
    return d


@settings(max_examples=300, deadline=2000)
@given(d=mutated_scene())
def test_hostile_scene_dicts_refused_by_name_or_valid(d: dict[str, Any]) -> None:
    try:
        s = Scene.from_dict(d)
    except rf.InvalidParameterError as e:
        _names_param(e)
        return
    assert Scene.from_dict(s.to_dict()) == s
    assert Scene.from_toml_str(s.to_toml()) == s


@settings(max_examples=200, deadline=2000)
@given(d=GARBAGE)
def test_garbage_is_refused(d: Any) -> None:
    for build in (Scene.from_dict, rf.run):
        try:
            build(d)
        except rf.InvalidParameterError as e:
            _names_param(e)
        except OSError:  # run() reads a str as a scene file path, and there is no such file
            assert build is rf.run and isinstance(d, str)
        else:  # pragma: no cover - garbage is never a valid scene
            raise AssertionError(f"accepted {d!r}")


TOKENS = [
    "nan",
    "inf",
    "-inf",
    "+inf",
    "1e999",
    "-1e999",
    "1e-400",
    "0",
    "-1",
    "0.0",
    "true",
    '"x"',
    '"\\u00e9\\u4e2d"',
    "[1, 2]",
    "[]",
    "{a = 1}",
    "9223372036854775807",
    "1_000_000_000",
    '"strain"',
    '"fem"',
    "2.5e-31",
    "3.0e30",
    "[nan, 1.0]",
    '"""multi\nline"""',
]


@settings(max_examples=300, deadline=2000)
@given(
    method=st.sampled_from(METHODS),
    edits=st.lists(
        st.tuples(
            st.integers(0, 60),
            st.sampled_from(["value", "drop", "dup", "junk"]),
            st.one_of(st.sampled_from(TOKENS), WILD_TEXT),
        ),
        max_size=4,
    ),
)
def test_hostile_toml_refused_by_name_or_valid(method: str, edits: list[Any]) -> None:
    lines = Scene.from_dict(_small(method)).to_toml().splitlines()
    for at, kind, tok in edits:
        i = at % len(lines)
        if kind == "value" and " = " in lines[i]:
            lines[i] = lines[i].split(" = ")[0] + " = " + tok
        elif kind == "drop":
            lines.pop(i)
        elif kind == "dup":
            lines.insert(i, lines[i])
        elif kind == "junk":
            lines.insert(i, tok)
        if not lines:
            lines = [""]
    text = "\n".join(lines)
    try:
        s = Scene.from_toml_str(text)
    except rf.InvalidParameterError as e:
        _names_param(e)
        return
    assert Scene.from_toml_str(s.to_toml()) == s


@settings(max_examples=100, deadline=2000)
@given(text=st.text(st.characters(codec=None), max_size=200))
def test_random_text_is_not_a_scene(text: str) -> None:
    try:
        Scene.from_toml_str(text)
    except rf.InvalidParameterError as e:
        _names_param(e)


@settings(max_examples=60, deadline=None)
@given(d=mutated_scene(garbage=False), nu=st.floats(-0.999, 0.4999))
def test_mostly_valid_scenes_run_finite_or_refuse_by_name(d: dict[str, Any], nu: float) -> None:
    """Small scenes with numbers scaled far out or keys dropped, run through the native solvers:
    finite results or a named refusal / SingularSystemError, never NaN, within seconds."""
    if d.get("method") in ("fem", "xfem") and isinstance(d.get("material"), dict):
        d["material"]["nu"] = nu
    try:
        s = Scene.from_dict(d)
    except rf.InvalidParameterError as e:
        _names_param(e)
        event("refused by the scene")
        return
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", rf.AccuracyWarning)
            r = rf.run(s)
    except rf.InvalidParameterError as e:
        _names_param(e)
        event("refused by the core")
        return
    except rf.SingularSystemError:
        event("singular")
        return
    event(f"ran {s.method}")
    assert time.perf_counter() - t0 < 30
    for v in (r.sigma22, r.cmod, *r.scalars.values()):
        assert math.isfinite(v), (v, s)
    for k, h in r.history.items():
        if h.dtype.kind == "f":  # row 0, the unloaded origin: NaN where nothing was computed
            assert np.all(np.isfinite(h[1:])) and not np.isinf(h[:1]).any(), k


def test_huge_requests_refused_quickly() -> None:
    t0 = time.perf_counter()
    for build in (
        lambda: rf.scenes.edge_crack_plate("fem", mesh=(10**6, 10**6)),
        lambda: rf.scenes.edge_crack_plate("xfem", mesh=(2000, 1001)),
        lambda: rf.scenes.edge_crack_plate("ccm_pd", dx=11.0 / 100_000),
        lambda: rf.scenes.edge_crack_plate("pd", sla_steps=10**12),
        lambda: rf.scenes.edge_crack_plate("xfem", growth_steps=10**9),
        lambda: rf.scenes.edge_crack_plate("fem", mesh=(10**5000, 1)),
    ):
        with pytest.raises(rf.InvalidParameterError) as e:
            build()
        _names_param(e.value)
    assert time.perf_counter() - t0 < 1.0
    # the limit itself is accepted as a scene (not run here)
    rf.scenes.edge_crack_plate("fem", mesh=(1000, MAX_ELEMENTS // 1000))


NON_FINITE = [math.nan, math.inf, -math.inf]
FLOAT_KEYS = [
    ("plate", "width"),
    ("plate", "height"),
    ("material", "E"),
    ("material", "nu"),
    ("material", "thickness"),
    ("material", "G0"),
    ("load", "u0"),
    ("load", "traction"),
    ("crack", "a0"),
    ("crack", "y"),
    ("crack", "angle"),
    ("crack", "x"),
    ("xfem", "r_I"),
    ("xfem", "fixed_area_radius"),
    ("xfem", "area_threshold"),
    ("xfem", "da"),
    ("xfem", "a_stop"),
    ("pd", "dx"),
    ("pd", "tie_tol"),
    ("pd", "fem_grading"),
    ("pd", "fem_coarse"),
    ("pd", "stop_crack_length"),
]


@pytest.mark.parametrize("sec,key", FLOAT_KEYS)
@pytest.mark.parametrize("bad", NON_FINITE)
def test_non_finite_refused_everywhere(sec: str, key: str, bad: float) -> None:
    method = "ccm_pd" if sec == "pd" else "xfem"
    d = _small(method)
    d.setdefault(sec, {})[key] = bad
    for build in (lambda: Scene.from_dict(d), lambda: Scene.from_toml_str(_toml(d))):
        with pytest.raises(rf.InvalidParameterError, match=rf"{sec}\.{key}") as e:
            build()
        _names_param(e.value)
    for pair in ("center", "size"):
        d = _small("ccm_pd")
        d["pd"][pair] = [1.0, bad]
        with pytest.raises(rf.InvalidParameterError, match=rf"pd\.{pair}"):
            Scene.from_dict(d)


def _toml(d: dict[str, Any]) -> str:
    """TOML text of a scene dict, non-finite floats included (TOML has nan and inf)."""

    def val(v: Any) -> str:
        if isinstance(v, float) and not math.isfinite(v):
            return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
        if isinstance(v, list):
            return "[" + ", ".join(map(val, v)) + "]"
        return json_like(v)

    out = [f'method = "{d["method"]}"']
    for k, v in d.items():
        if isinstance(v, dict):
            out.append(f"[{k}]")
            out.extend(f"{kk} = {val(vv)}" for kk, vv in v.items())
    return "\n".join(out) + "\n"


def json_like(v: Any) -> str:
    import json

    return "true" if v is True else "false" if v is False else json.dumps(v)


@pytest.mark.parametrize(
    "kw,param",
    [
        ({"nu": 0.5}, "material.nu"),
        ({"nu": -1.0}, "material.nu"),
        ({"E": 0.0}, "material.E"),
        ({"E": -1e4}, "material.E"),
        ({"G0": 0.0}, "material.G0"),
        ({"G0": -0.3}, "material.G0"),
        ({"thickness": 0.0}, "material.thickness"),
        ({"thickness": -1.0}, "material.thickness"),
    ],
)
def test_invalid_materials_refused_with_range(kw: dict[str, float], param: str) -> None:
    for method in METHODS:
        with pytest.raises(rf.InvalidParameterError, match=param.replace(".", r"\.")) as e:
            rf.scenes.edge_crack_plate(method, **kw)
        assert "expected" in str(e.value) or "<" in str(e.value)


def test_native_entry_points_refuse_by_name() -> None:
    """The native module checks a scene dict itself (Rust validation, bypassing Scene) and the
    error carries the scene key."""
    from rustfrac import _core

    base = {"method": "fem", "plate": {"width": 2.0, "height": 2.0}, "mesh": {"nx": 4, "ny": 4}}
    for sec, bad, name in [
        ("material", {"E": -1.0}, "material.E"),
        ("material", {"E": math.nan}, "material.E"),
        ("material", {"nu": 0.5}, "material.nu"),
        ("material", {"nu": -1.0}, "material.nu"),
        ("material", {"thickness": 0.0}, "material.thickness"),
        ("material", {"thickness": math.inf}, "material.thickness"),
        ("plate", {"width": math.nan}, "plate.width"),
        ("load", {"u0": math.inf}, "load.u0"),
        ("mesh", {"nx": 10**7}, "mesh.nx"),
    ]:
        scene = {**base, sec: {**base.get(sec, {}), **bad}}
        with pytest.raises(rf.InvalidParameterError, match=f"invalid {name}") as e:
            _core.run(scene)
        assert e.value.param.startswith(name)
    with pytest.raises(rf.InvalidParameterError, match=r"invalid material\.G0") as e:
        _core.run(
            {
                "method": "pd",
                "plate": {"width": 3.0, "height": 2.5},
                "material": {"G0": -1.0},
                "crack": {"kind": "none"},
                "pd": {"dx": 0.25, "m": 3, "sla_steps": 1},
            }
        )
    assert e.value.param == "material.G0"


def test_locking_warning() -> None:
    s = rf.scenes.edge_crack_plate("fem", nu=0.4999, mesh=(8, 12), a0=1.375)
    with pytest.warns(rf.LockingWarning, match="lock"):
        r = rf.run(s)
    assert r.meta["warnings"] and "0.4999" in r.meta["warnings"][0]
    assert r.warning_kinds == ["locking"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", rf.AccuracyWarning)
        r = rf.run(s.replace(material__nu=0.3))
    assert r.meta["warnings"] == []
    s = rf.scenes.edge_crack_plate("xfem", nu=0.495, mesh=(44, 83), plane="strain")
    with pytest.warns(rf.AccuracyWarning):
        rf.run(s)
    with warnings.catch_warnings():  # plane stress does not lock
        warnings.simplefilter("error", rf.AccuracyWarning)
        rf.run(s.replace(material__plane="stress"))
