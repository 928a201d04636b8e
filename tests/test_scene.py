"""Scene construction, validation and TOML round trips."""

from __future__ import annotations

import keyword
import math
from pathlib import Path
from typing import Any, Callable

import pytest

import rustfrac as rf
from rustfrac.scene import Scene

PAPER_TOML = """
method = "fem"
[plate]
width = 11.0
height = 21.0
[material]
E = 10000.0
nu = 0.25
[load]
bc = "free"
u0 = 0.01
[crack]
kind = "seam"
a0 = 1.1
y = 10.5
[mesh]
nx = 44
ny = 83
"""


def _edit(old: str, new: str) -> Callable[[], Any]:
    assert old in PAPER_TOML
    return lambda: Scene.from_toml_str(PAPER_TOML.replace(old, new))


def _kw(**kw: Any) -> Callable[[], Any]:
    return lambda: rf.scenes.edge_crack_plate(**kw)


# (case, builder, expected exception, text the message must contain)
BAD = [
    ("negative E", _kw(E=-1.0), rf.InvalidParameterError, "material.E"),
    ("zero E (toml)", _edit("E = 10000.0", "E = 0.0"), rf.InvalidParameterError, "material.E"),
    ("nu = 0.5", _kw(nu=0.5), rf.InvalidParameterError, "material.nu"),
    ("nu > 0.5 (toml)", _edit("nu = 0.25", "nu = 0.7"), rf.InvalidParameterError, "-1 < nu < 0.5"),
    ("nx = 0", _kw(mesh=(0, 83)), rf.InvalidParameterError, "mesh.nx"),
    ("ny = 0 (toml)", _edit("ny = 83", "ny = 0"), rf.InvalidParameterError, "mesh.ny"),
    ("NaN E", _kw(E=math.nan), rf.InvalidParameterError, "material.E"),
    ("NaN u0 (toml)", _edit("u0 = 0.01", "u0 = nan"), rf.InvalidParameterError, "load.u0"),
    ("inf width", _kw(width=math.inf), rf.InvalidParameterError, "plate.width"),
    ("missing method", _edit('method = "fem"', ""), rf.MissingParameterError, "method"),
    ("unknown key", _edit("nx = 44", "nx = 44\nnz = 3"), rf.UnknownParameterError, "mesh.nz"),
    (
        "unknown top key",
        _edit('method = "fem"', 'method = "fem"\nsolver = 1'),
        rf.UnknownParameterError,
        "solver",
    ),
    (
        "section of another method",
        _edit("[mesh]", "[pd]\ndx = 0.1\n[mesh]"),
        rf.UnknownParameterError,
        "do not apply to method 'fem'",
    ),
    (
        "wrong type str",
        _edit("E = 10000.0", 'E = "ten thousand"'),
        rf.InvalidTypeError,
        "material.E",
    ),
    ("wrong type float for int", _edit("nx = 44", "nx = 44.0"), rf.InvalidTypeError, "mesh.nx"),
    ("wrong type bool", _kw(E=True), rf.InvalidTypeError, "material.E"),
    (
        "section not a table",
        _edit("[plate]\nwidth = 11.0\nheight = 21.0", "plate = 3"),
        rf.InvalidTypeError,
        "plate",
    ),
    ("unknown method", _kw(method="bem"), rf.InvalidParameterError, "method"),
    (
        "unknown method (toml)",
        _edit('method = "fem"', 'method = "FEM"'),
        rf.InvalidParameterError,
        "'fem', 'xfem', 'pd', 'ccm_pd'",
    ),
    ("bad bc", _kw(bc="glued"), rf.InvalidParameterError, "load.bc"),
    ("bad plane", _kw(plane="3d"), rf.InvalidParameterError, "material.plane"),
    ("crack longer than plate", _kw(a0=12.0), rf.InvalidParameterError, "crack.a0"),
    ("crack outside plate", _kw(crack_y=30.0), rf.InvalidParameterError, "crack.y"),
    (
        "seam crack for xfem",
        _kw(method="xfem", crack="seam"),
        rf.InvalidParameterError,
        "crack.kind",
    ),
    ("pd needs nu = 1/4", _kw(method="pd", nu=0.3), rf.InvalidParameterError, "nu = 0.25"),
    (
        "ccm_pd needs nu = 1/4",
        _kw(method="ccm_pd", nu=0.2),
        rf.InvalidParameterError,
        "material.nu",
    ),
    ("pd grid must fit", _kw(method="pd", dx=0.07), rf.InvalidParameterError, "pd.dx"),
    (
        "pd region outside",
        _kw(method="ccm_pd", pd_center=(0.5, 10.5)),
        rf.InvalidParameterError,
        "pd.center",
    ),
    ("pd horizon m = 0", _kw(method="pd", m=0), rf.InvalidParameterError, "pd.m"),
    ("xfem nsub = 0", _kw(method="xfem", nsub=0), rf.InvalidParameterError, "xfem.nsub"),
    ("xfem r_I < 0", _kw(method="xfem", r_I=-2.5), rf.InvalidParameterError, "xfem.r_I"),
    ("gauss = 6", _kw(gauss=6), rf.InvalidParameterError, "mesh.gauss"),
    ("bad TOML syntax", lambda: Scene.from_toml_str("method = "), rf.InvalidParameterError, "TOML"),
    (
        "TOML nested 5000 deep",
        lambda: Scene.from_toml_str('method = "fem"\nx = ' + "[" * 5000 + "]" * 5000),
        rf.InvalidParameterError,
        "nests arrays or tables too deeply",
    ),
    (
        "TOML tables nested 5000 deep",
        lambda: Scene.from_toml_str('method = "fem"\nx = ' + "{a = " * 5000 + "1" + "}" * 5000),
        rf.InvalidParameterError,
        "too deeply",
    ),
    (
        "TOML text over the size limit",
        lambda: Scene.from_toml_str(
            'method = "pd"\n[pd]\ndamage_at_steps = [' + "1, " * 400_000 + "1]\n"
        ),
        rf.InvalidParameterError,
        "larger than the limit of 1048576 bytes",
    ),
]


@pytest.mark.parametrize(("case", "build", "exc", "text"), BAD, ids=[b[0] for b in BAD])
def test_bad_input(case: str, build: Callable[[], Any], exc: type, text: str) -> None:
    with pytest.raises(exc) as info:
        build()
    msg = str(info.value)
    assert text in msg, msg
    assert isinstance(info.value, rf.RustfracError)
    assert isinstance(info.value, ValueError)  # every bad input is a ValueError


def test_scene_file_over_the_size_limit_names_file_and_limit(tmp_path: Path) -> None:
    from rustfrac.scene import MAX_SCENE_BYTES

    f = tmp_path / "huge.toml"
    f.write_text('method = "pd"\n[pd]\ndamage_at_steps = [' + "1, " * MAX_SCENE_BYTES + "1]\n")
    with pytest.raises(rf.InvalidParameterError, match="larger than the limit") as e:
        Scene.from_toml(f)
    assert str(f) in str(e.value) and str(MAX_SCENE_BYTES) in str(e.value)
    ok = tmp_path / "ok.toml"
    ok.write_text('method = "fem"\n' + "# padding\n" * 1000)  # below the limit: read
    assert Scene.from_toml(ok).method == "fem"


def test_unknown_key_lists_allowed() -> None:
    with pytest.raises(rf.UnknownParameterError) as e:
        Scene.from_toml_str(PAPER_TOML.replace("E = 10000.0", "E = 10000.0\nYoung = 1.0"))
    assert "allowed in [material]: E, nu, plane, thickness, G0" in str(e.value)
    assert e.value.param == "material.Young"


def test_range_in_message() -> None:
    with pytest.raises(
        rf.InvalidParameterError, match=r"expected a finite number in \[1e-30, 1e30\], got -1.0"
    ):
        rf.scenes.edge_crack_plate(E=-1.0)


def test_paper_defaults() -> None:
    s = rf.scenes.edge_crack_plate()
    assert (s.method, s.plate.width, s.plate.height) == ("fem", 11.0, 21.0)
    assert (s.material.E, s.material.nu, s.material.G0, s.material.plane) == (
        10000.0,
        0.25,
        0.367,
        "strain",
    )
    assert (s.load.bc, s.load.u0, s.load.traction) == ("free", 0.01, 9.993)
    assert (s.crack.kind, s.crack.a0, s.crack.y) == ("seam", 1.1, 10.5)
    assert (s.mesh.nx, s.mesh.ny) == (44, 83)
    x = rf.scenes.edge_crack_plate(method="xfem")
    assert (x.crack.kind, x.xfem.nsub, x.xfem.r_I) == ("edge", 4, 2.5)
    p = rf.scenes.edge_crack_plate(method="ccm_pd")
    assert p.pd.dx == pytest.approx(1 / 15) and p.pd.m == 4
    assert p.pd.center == (1.70, 10.5) and p.pd.size == (2.73, 1.67)


def test_paper_toml_equals_keyword_scene() -> None:
    assert Scene.from_toml_str(PAPER_TOML) == rf.scenes.edge_crack_plate()


@pytest.mark.parametrize("method", ["fem", "xfem", "pd", "ccm_pd"])
@pytest.mark.parametrize("bc", ["free", "clamped", "traction"])
def test_toml_round_trip(method: str, bc: str, tmp_path: Path) -> None:
    s = rf.scenes.edge_crack_plate(method=method, bc=bc, a0=1.3, name=f"rt {method}")
    assert Scene.from_toml_str(s.to_toml()) == s
    assert Scene.from_dict(s.to_dict()) == s
    p = s.save_toml(tmp_path / "s.toml")
    assert Scene.from_toml(p) == s
    # only the sections this method reads are written
    assert ("xfem" in s.to_dict()) == (method == "xfem")
    assert ("pd" in s.to_dict()) == (method in ("pd", "ccm_pd"))


def test_replace_validates() -> None:
    s = rf.scenes.edge_crack_plate()
    assert s.replace(material__E=2e5).material.E == 2e5
    with pytest.raises(rf.InvalidParameterError, match=r"material\.nu"):
        s.replace(material__nu=0.6)
    with pytest.raises(rf.UnknownParameterError, match=r"material\.EE"):
        s.replace(material__EE=1.0)


def test_example_files_load(root: Path) -> None:
    for name in ("paper_fem_uncracked.toml", "paper_fem_seam.toml"):
        s = Scene.from_toml(rf.examples.path(name))
        assert s.method == "fem"


def test_run_accepts_dict_and_path(root: Path) -> None:
    r1 = rf.run(rf.examples.path("paper_fem_uncracked.toml"))
    r2 = rf.run(Scene.from_toml(rf.examples.path("paper_fem_uncracked.toml")).to_dict())
    assert r1.sigma22 == r2.sigma22
    with pytest.raises(rf.InvalidTypeError):
        rf.run(42)  # type: ignore[arg-type]


def test_scene_from_keywords_and_dicts() -> None:
    s = Scene(method="fem", material={"E": 200.0, "nu": 0.3}, mesh={"nx": 4, "ny": 8})
    assert s.material.E == 200.0 and s.material.nu == 0.3 and s.material.G0 == 0.367
    assert s.crack.kind == "seam"
    assert Scene(method="xfem").crack.kind == "edge"
    assert Scene(method="xfem") == rf.scenes.edge_crack_plate(method="xfem")
    assert Scene(method="pd").crack == Scene.from_dict({"method": "pd"}).crack
    with pytest.raises(rf.UnknownParameterError, match=r"material\.G"):
        Scene(material={"G": 1.0})
    with pytest.raises(rf.InvalidTypeError, match="material"):
        Scene(material=3)  # type: ignore[arg-type]


# ----------------------------------------------------------------------------------------------
# the core owns every scene rule


def test_sections_are_the_cores_schema() -> None:
    """Every key of the core's schema is a field of its section class with the core's default,
    and the section docstrings show each key's range and meaning."""
    from rustfrac import _core
    from rustfrac.scene import _SECTIONS, keys

    schema = _core.scene_schema()
    assert keys() == schema and {k["section"] for k in schema} == set(_SECTIONS)
    for k in schema:
        cls = _SECTIONS[k["section"]]
        # the dataclass default (a list table's entry, e.g. a hole, has required keys: Hole()
        # is refused by the core)
        attr = k["key"] + "_" if keyword.iskeyword(k["key"]) else k["key"]
        default = cls.__dataclass_fields__[attr].default
        want = tuple(k["default"]) if isinstance(k["default"], list) else k["default"]
        assert default == want, (k["section"], k["key"])
        assert k["valid"] in (cls.__doc__ or ""), (k["section"], k["key"])


def test_core_errors_carry_the_scene_key() -> None:
    """No message parsing: the error's param is the core's scene key, for sections built alone,
    whole scenes, and the cross-parameter checks (a PD pre-crack along a node row names
    crack.y, not crack.a0)."""
    with pytest.raises(rf.InvalidParameterError) as e:
        rf.scene.XfemOptions(r_I=0.1)
    assert e.value.param == "xfem.r_I"
    with pytest.raises(rf.InvalidParameterError) as e:
        rf.scenes.edge_crack_plate("ccm_pd", crack_y=10.0)
    assert e.value.param == "crack.y" and "node" in str(e.value)
    with pytest.raises(rf.UnknownParameterError) as e:
        rf.Scene.from_dict({"method": "fem", "mesh": {"nxx": 4}})
    assert e.value.param == "mesh.nxx"
    with pytest.raises(rf.InvalidTypeError) as e:
        rf.Scene.from_dict({"method": "fem", "plate": {"width": "wide"}})
    assert e.value.param == "plate.width"
