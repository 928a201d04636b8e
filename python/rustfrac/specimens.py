"""Specimens of the fracture literature as ready-made scenes (``rf.specimens``).

Each function returns a :class:`~rustfrac.scene.Scene` for ``method = "fem" | "xfem" | "pd" |
"ccm_pd"`` with the published geometry, material and load as defaults and keyword overrides of
them; further scene keys are passed as ``section__key=value`` (``xfem__growth_steps=10``,
``pd__dx=0.2``: :meth:`Scene.replace`). ``mesh=(nx, ny)`` sets the FEM / XFEM grid. Every value is
checked by the core when the scene is built.

Units are those of the reference (stated in each docstring); rustfrac itself is unit-agnostic.

Layouts: XFEM cracks may start on any side. FEM seams and PD pre-cracks start on the left edge
and run along x1, so for those methods a specimen whose crack starts from the bottom (``senb``,
``bittencourt_beam``) is built turned a quarter turn clockwise: the beam's depth runs along x1,
its length along x2 (``(x, y) -> (y, L - x)``), the cracked face is the left edge, the loaded face
the right one. The responses (reactions, probes, K_I) are the same; their vectors turn with it.

Every method reads supports, loads on regions, probes, holes and notches (a fictitious domain
for FEM and XFEM, removed cells and bonds for PD, either in CCM-PD's FEM part, which may not cut
the hybrid elements at a PD rectangle's boundary; the README's general scenes section says what
each method reads, and what it still refuses). A refused scene raises
the core's :class:`~rustfrac.errors.InvalidParameterError` (its ``param`` names the scene key,
e.g. ``support[0]`` or ``hole[0]``, and its message the valid range) when it is run.

:data:`SPECIMENS` lists every specimen; each is also shipped as an example scene
(``rf.examples.path(SPECIMENS[name].example)``).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Callable, ClassVar

from ._log import logger
from .errors import (
    DiscretisationWarning,
    InvalidParameterError,
    InvalidTypeError,
    UnknownParameterError,
)
from .scene import METHODS, PD_NU, PdOptions, Scene
from .scenes import edge_crack_plate

__all__ = [
    "SPECIMENS",
    "Specimen",
    "bittencourt_beam",
    "double_edge",
    "edge_shear",
    "get",
    "plate_with_hole",
    "senb",
    "sent",
]

Point = tuple[float, float]


@dataclass(frozen=True)
class Specimen:
    """A specimen of :data:`SPECIMENS`: its function, the example file that holds its default
    scene (for ``example_method``), its reference and the methods it runs with today."""

    name: str
    build: Callable[..., Scene]
    example: str
    example_method: str
    reference: str


def _mesh(mesh: tuple[int, int] | None) -> dict[str, int]:
    if mesh is None:
        return {}
    try:
        nx, ny = mesh
    except (TypeError, ValueError):
        raise InvalidTypeError(f"mesh must be a pair (nx, ny), got {mesh!r}", "mesh") from None
    return {"nx": nx, "ny": ny}


def _material(
    method: str,
    E: float,
    nu: float | None,
    plane: str | None,
    literature: tuple[float, str],
    **more: float,
) -> dict[str, Any]:
    """The material of a specimen: the keywords given, else the literature's ``(nu, plane)``.
    Bond-based PD (methods "pd", "ccm_pd") fixes nu = PD_NU in plane strain: a given other value
    is refused by name, the literature's is replaced with a :class:`DiscretisationWarning`
    saying so."""
    if method not in ("pd", "ccm_pd"):
        nu_, plane_ = literature
        return {"E": E, "nu": nu_ if nu is None else nu, "plane": plane or plane_, **more}
    for key, given, fixed in (("nu", nu, PD_NU), ("plane", plane, "strain")):
        if given is not None and given != fixed:
            raise InvalidParameterError(
                f"invalid {key}: bond-based peridynamics (method {method!r}) fixes nu = "
                f"{PD_NU} in plane strain (pd.model = 'lps', the state-based model of method 'pd', takes any), got "
                f"{key} = {given!r}; use method 'fem' or 'xfem' for another {key}",
                key,
            )
    if (nu, plane) != (PD_NU, "strain") and literature != (PD_NU, "strain"):
        warnings.warn(
            f"specimen: method {method!r} runs bond-based PD's nu = {PD_NU}, plane strain in "
            f"place of the specimen's nu = {literature[0]}, plane {literature[1]}",
            DiscretisationWarning,
            stacklevel=3,
        )
    return {"E": E, "nu": PD_NU, "plane": "strain", **more}


def _finish(d: dict[str, Any], overrides: Mapping[str, Any]) -> Scene:
    """The scene of ``d`` (checked by the core) with the ``section__key`` overrides applied."""
    for k in overrides:
        if "__" not in k:
            raise UnknownParameterError(
                f"unknown keyword {k!r}: a specimen takes its own keywords and scene keys as "
                "section__key (e.g. xfem__growth_steps=10)",
                k,
            )
    # the method's own sections only (a PD scene has no [mesh]): the core refuses the others
    if d["method"] not in ("fem", "xfem"):
        d.pop("mesh", None)
        pd_layout(d)
    if d["method"] != "xfem":
        d.pop("xfem", None)
    scene = Scene.from_dict(d)
    if overrides:
        scene = scene.replace(**overrides)
    logger.debug("specimen %s", scene.describe())
    return scene


#: the half-size of a CCM-PD specimen's PD rectangle around the crack tip, in horizons
_PD_REGION_HORIZONS = 6.0


def pd_layout(d: dict[str, Any]) -> None:
    """Lays out a PD scene dict ``d`` in place (a "pd" / "ccm_pd" specimen, and the PD scene of
    :func:`rustfrac.compare.plan`): Poisson's ratio the core's bond-based value (PD_NU, the
    literature's value cannot be represented) in plane strain (the PD methods' only plane), the
    crack moved by half a grid spacing when it would run along a node row (the core refuses a
    pre-crack through nodes), and for CCM-PD a PD rectangle of ``_PD_REGION_HORIZONS`` horizons
    around the crack tip unless the specimen sets one."""
    pd = d.setdefault("pd", {})
    dx = pd.get("dx", PdOptions().dx)
    m = pd.get("m", PdOptions().m)
    mat = d.setdefault("material", {})
    if mat.get("nu", PD_NU) != PD_NU:
        logger.info(
            "specimen: bond-based PD fixes nu = %s (the specimen's nu = %s is replaced)",
            PD_NU,
            mat["nu"],
        )
    mat["nu"] = PD_NU
    if mat.get("plane", "strain") != "strain":
        logger.info(
            "specimen: the PD methods are plane strain (the specimen's plane stress is replaced)"
        )
    mat["plane"] = "strain"
    crack = d.get("crack")
    if isinstance(crack, dict) and crack.get("kind", "edge") != "none":
        key = "y" if crack.get("side", "left") in ("left", "right") else "x"
        v = crack.get(key)
        if v is not None and abs(v / dx - round(v / dx)) < 1e-9:
            crack[key] = v + 0.5 * dx
    if d["method"] == "ccm_pd" and "center" not in pd and isinstance(crack, dict):
        scene = Scene.from_dict(_as_xfem(d))
        tip = scene.crack_polylines()[0][-1]
        half = _PD_REGION_HORIZONS * m * dx
        box = [
            (max(0.0, t - half), min(size, t + half))
            for t, size in zip(tip, (scene.plate.width, scene.plate.height))
        ]
        pd["center"] = [0.5 * (lo + hi) for lo, hi in box]
        pd["size"] = [hi - lo for lo, hi in box]


def _as_xfem(d: dict[str, Any]) -> dict[str, Any]:
    """The specimen's scene as XFEM (to read its crack's polyline from the core)."""
    return {**{k: v for k, v in d.items() if k != "pd"}, "method": "xfem"}


class _Layout:
    """The specimen's coordinates in its drawn layout (crack from the bottom, length L along
    x1) or turned a quarter turn clockwise for methods whose cracks start on the left edge."""

    _SIDES: ClassVar[dict[str, str]] = {
        "bottom": "left",
        "top": "right",
        "left": "top",
        "right": "bottom",
    }

    def __init__(self, length: float, depth: float, turned: bool) -> None:
        self.length, self.depth, self.turned = length, depth, turned

    def plate(self) -> dict[str, float]:
        w, h = (self.depth, self.length) if self.turned else (self.length, self.depth)
        return {"width": w, "height": h}

    def pt(self, x: float, y: float) -> list[float]:
        return [y, self.length - x] if self.turned else [x, y]

    def vec(self, f1: float, f2: float) -> list[float]:
        return [f2, 0.0 - f1] if self.turned else [f1, f2]  # no -0.0

    def side(self, s: str) -> str:
        return self._SIDES[s] if self.turned else s

    def fix(self, c: str) -> str:
        return {"u1": "u2", "u2": "u1"}.get(c, c) if self.turned else c

    def bottom_crack(self, method: str, x: float, a: float) -> dict[str, Any]:
        """An edge crack of depth ``a`` from the bottom face at abscissa ``x``."""
        if not self.turned:
            return {"kind": "edge", "side": "bottom", "x": x, "a0": a}
        kind = "seam" if method == "fem" else "edge"
        return {"kind": kind, "y": self.length - x, "a0": a}


def _turned(method: str) -> bool:
    if method not in METHODS:
        Scene.from_dict({"method": method})  # raises, naming 'method'
    return method != "xfem"


# ----------------------------------------------------------------------------------------------
# the specimens


def sent(method: str = "fem", **overrides: Any) -> Scene:
    """The paper's single-edge-cracked plate under grips (section 3): exactly
    :func:`rustfrac.scenes.edge_crack_plate` (same keywords; N, mm, MPa): W x L = 11 x 21, edge
    crack a0 = 1.1 at x2 = 10.5, E = 10000, nu = 0.25, grips u2 = +-0.01. Runs with every
    method."""
    overrides.setdefault("name", "the paper's edge-cracked plate (SENT)")
    return edge_crack_plate(method, **overrides)


def edge_shear(
    method: str = "xfem",
    *,
    width: float = 7.0,
    height: float = 16.0,
    a: float = 3.5,
    shear: float = 1.0,
    E: float = 3.0e7,
    nu: float | None = None,
    plane: str | None = None,
    mesh: tuple[int, int] | None = (28, 64),
    name: str = "edge crack under shear (Yau et al. 1980)",
    **overrides: Any,
) -> Scene:
    """The edge crack under shear: Yau, Wang and Corten (1980), J. Appl. Mech. 47, 335-341;
    Moes, Dolbow and Belytschko (1999), Int. J. Numer. Meth. Eng. 46, 131-150, fig. 13.

    A ``width`` x ``height`` = 7 x 16 plate, an edge crack of length ``a`` = 3.5 from the left
    edge at mid-height, the bottom edge fixed (u1 = u2 = 0), a uniform shear traction ``shear``
    = 1 (along +x1) on the top edge; E = 3e7, nu = 0.25, plane strain. Published (numerical)
    values: K_I = 34.0, K_II = 4.55 (force/length^2 length^1/2). Consistent units (the
    literature gives none: e.g. psi and in).

    FEM runs it with a seam crack (no K); the PD methods refuse supports and region loads for
    now. ``mesh`` (28 x 64: h = 0.25, crack tip on a node) is the FEM / XFEM grid.
    """
    d: dict[str, Any] = {
        "method": method,
        "name": name,
        "plate": {"width": width, "height": height},
        "material": _material(method, E, nu, plane, (0.25, "strain")),
        "crack": {"kind": "seam" if method == "fem" else "edge", "a0": a, "y": height / 2},
        "mesh": _mesh(mesh),
        "support": [{"region": "edge", "side": "bottom"}],
        "load": [{"region": "edge", "side": "top", "shear": shear}],
    }
    return _finish(d, overrides)


def senb(
    method: str = "xfem",
    *,
    depth: float = 1.0,
    span: float | None = None,
    overhang: float | None = None,
    a: float = 0.5,
    force: float = 1.0,
    E: float = 1000.0,
    nu: float | None = None,
    plane: str | None = None,
    thickness: float = 1.0,
    mesh: tuple[int, int] | None = None,
    name: str = "single-edge notched bend beam (ASTM E399)",
    **overrides: Any,
) -> Scene:
    """The single-edge notched bend (SENB, three-point bend) beam of ASTM E399, S/W = 4.

    A beam of depth W = ``depth`` (1), span S = ``span`` (default 4 W) between two point supports
    on the bottom face (a pin at the left: u1 = u2 = 0; a roller at the right: u2 = 0), the
    beam reaching ``overhang`` (default 0.05 S) beyond each support; a point force ``force``
    (1, downwards) at the top centre; an edge crack of depth ``a`` (0.5 W) from the bottom
    centre. E = 1000, nu = 0.3, plane stress, thickness B = 1; consistent units.

    Reference: Srawley (1976), Int. J. Fract. 12, 475-476 (ASTM E399):
    K_I = P S / (B W^1.5) f(a/W), ``rustfrac.handbook.srawley_senb_F``, within 0.5 %.
    The point loads make the compliance converge slowly (about h^0.5): on the default grid
    (40 elements per depth) XFEM gives K_I within about 1.5 % of it.

    For "fem" and the PD methods the beam is turned a quarter turn (see the module docstring):
    the seam runs from the left edge, the force pushes in -x1 on the right edge. FEM has no K;
    the compliance method (two crack lengths, ``scalars["load_displacement"]``) gives it. The PD
    methods refuse supports and region loads for now.
    """
    span = 4.0 * depth if span is None else span
    overhang = 0.05 * span if overhang is None else overhang
    length = span + 2 * overhang
    lay = _Layout(length, depth, _turned(method))
    mid = length / 2
    n = 40
    nx, ny = (round(n * length / depth), n)
    d: dict[str, Any] = {
        "method": method,
        "name": name,
        "plate": lay.plate(),
        "material": _material(method, E, nu, plane, (0.3, "stress"), thickness=thickness),
        "crack": lay.bottom_crack(method, mid, a),
        "mesh": _mesh(mesh) or _mesh((ny, nx) if lay.turned else (nx, ny)),
        "support": [
            {"region": "point", "point": lay.pt(overhang, 0.0)},
            {"region": "point", "point": lay.pt(length - overhang, 0.0), "fix": lay.fix("u2")},
        ],
        "load": [{"region": "point", "point": lay.pt(mid, depth), "force": lay.vec(0.0, -force)}],
        "probe": [
            {"name": "load_point", "point": lay.pt(mid, depth)},
            {"name": "cmod", "kind": "opening", "point": lay.pt(mid, 0.0)},
        ],
    }
    return _finish(d, overrides)


def plate_with_hole(
    method: str = "xfem",
    *,
    width: float = 10.0,
    height: float = 20.0,
    hole_center: Point = (6.0, 10.0),
    hole_radius: float = 1.5,
    a: float = 2.5,
    traction: float = 1.0,
    E: float = 1000.0,
    nu: float | None = None,
    plane: str | None = None,
    mesh: tuple[int, int] | None = (40, 80),
    name: str = "edge-cracked plate with a hole, tension",
    **overrides: Any,
) -> Scene:
    """A plate under uniform tension with a circular hole beside an edge crack: a demonstration
    of a crack growing towards a hole (no closed-form reference; cf. the crack-hole interaction
    studies of Bittencourt et al. 1996 and of Sukumar et al. 2001, Comput. Methods Appl. Mech.
    Eng. 190, 6183-6200).

    A ``width`` x ``height`` = 10 x 20 plate, the paper's traction grips (``[load] bc =
    "traction"``, stress ``traction`` = 1 on the top and bottom edges), an edge crack of length
    ``a`` = 2.5 from the left edge at mid-height, a hole of radius ``hole_radius`` = 1.5 centred
    at ``hole_center`` = (6, 10) ahead of the tip; E = 1000, nu = 0.3, plane strain; consistent
    units.
    """
    d: dict[str, Any] = {
        "method": method,
        "name": name,
        "plate": {"width": width, "height": height},
        "material": _material(method, E, nu, plane, (0.3, "strain")),
        "load": {"bc": "traction", "traction": traction},
        "crack": {"kind": "seam" if method == "fem" else "edge", "a0": a, "y": height / 2},
        "mesh": _mesh(mesh),
        "hole": [{"shape": "circle", "center": list(hole_center), "radius": hole_radius}],
    }
    return _finish(d, overrides)


#: Bittencourt et al. (1996): notch depth and offset from mid-span of the published cases (in)
BITTENCOURT_OFFSETS: tuple[float, ...] = (4.0, 5.0, 6.0)


def bittencourt_beam(
    method: str = "xfem",
    *,
    offset: float = 5.0,
    notch_depth: float = 1.5,
    force: float = 1.0,
    E: float = 29.0e6,
    nu: float | None = None,
    plane: str | None = None,
    hole_centers: Sequence[Point] = ((6.0, 2.25), (6.0, 4.25), (6.0, 6.25)),
    hole_diameter: float = 0.5,
    mesh: tuple[int, int] | None = None,
    name: str = "drilled three-point bend beam (Bittencourt et al. 1996)",
    **overrides: Any,
) -> Scene:
    """The drilled three-point bend beam of Bittencourt, Wawrzynek, Ingraffea and Sousa (1996),
    "Quasi-automatic simulation of crack propagation for 2D LEFM problems", Eng. Fract. Mech.
    55(2), 321-334 (also Ingraffea and Grigoriu 1990; Ventura et al. 2003 for XFEM).

    A beam 20 x 8 in (length x depth), pin and roller supports on the bottom 1 in from each
    end (span 18 in), a point force ``force`` (lbf, downwards) at the top centre, three holes of
    diameter ``hole_diameter`` = 0.5 in at ``hole_centers`` (in; default x = 6 in, 4 in left of
    mid-span, at heights 2.25, 4.25 and 6.25 in), and an initial crack (the notch) of depth
    ``notch_depth`` = 1.5 in from the bottom at ``offset`` in left of mid-span (the paper's
    cases: 4, 5 and 6 in, :data:`BITTENCOURT_OFFSETS`); the crack curves into the holes or
    between them depending on the offset. Material: E = 29e6 psi, nu = 0.3, plane stress:
    placeholders, not the paper's (the LEFM crack path does not depend on E; nu changes it
    little). Units: in, lbf, psi. ``mesh`` defaults to 160 x 64 (h = 0.125 in, 4 elements per
    hole diameter) in the drawn layout.

    Geometry as recalled from the paper's figure (the holes' heights and their abscissa are the
    commonly quoted values; check them against the source before a quantitative comparison).
    """
    length, depth, end = 20.0, 8.0, 1.0
    lay = _Layout(length, depth, _turned(method))
    mid = length / 2
    d: dict[str, Any] = {
        "method": method,
        "name": name,
        "plate": lay.plate(),
        "material": _material(method, E, nu, plane, (0.3, "stress")),
        "crack": lay.bottom_crack(method, mid - offset, notch_depth),
        "mesh": _mesh(mesh) or _mesh((64, 160) if lay.turned else (160, 64)),
        "support": [
            {"region": "point", "point": lay.pt(end, 0.0)},
            {"region": "point", "point": lay.pt(length - end, 0.0), "fix": lay.fix("u2")},
        ],
        "load": [{"region": "point", "point": lay.pt(mid, depth), "force": lay.vec(0.0, -force)}],
        "hole": [
            {"shape": "circle", "center": lay.pt(*c), "radius": hole_diameter / 2}
            for c in hole_centers
        ],
        "probe": [{"name": "load_point", "point": lay.pt(mid, depth)}],
    }
    return _finish(d, overrides)


def double_edge(
    method: str = "xfem",
    *,
    width: float = 1.0,
    height: float = 4.0,
    a: float = 0.2,
    traction: float = 1.0,
    E: float = 1000.0,
    nu: float | None = None,
    plane: str | None = None,
    mesh: tuple[int, int] | None = (40, 161),
    growth_steps: int = 4,
    name: str = "double-edge-cracked strip",
    **overrides: Any,
) -> Scene:
    """Two symmetric edge cracks of depth ``a`` = 0.2 from both sides of a strip of width
    2b = ``width`` = 1 and height 4 under uniform tension ``traction`` = 1 (the paper's traction
    grips); E = 1000, nu = 0.3, plane strain; consistent units. Tada, Paris and Irwin, The
    Stress Analysis of Cracks Handbook (tan form): K_I = sigma sqrt(pi a) F(a/b),
    F(0.4) = 1.1315, K_I = 0.8969 (XFEM on 40 x 161: 0.8942 at both tips). The example
    ``double_edge_crack.toml``.

    Several cracks need XFEM: the other methods raise the core's error (``param`` "crack").
    ``growth_steps`` (XFEM) grows both tips together.
    """
    d: dict[str, Any] = {
        "method": method,
        "name": name,
        "plate": {"width": width, "height": height},
        "material": _material(method, E, nu, plane, (0.3, "strain")),
        "load": {"bc": "traction", "traction": traction},
        "crack": [
            {"kind": "edge", "side": "left", "a0": a, "y": height / 2},
            {"kind": "edge", "side": "right", "a0": a, "y": height / 2},
        ],
        "mesh": _mesh(mesh),
        "xfem": {"growth_steps": growth_steps},
    }
    return _finish(d, overrides)


#: every specimen by name
SPECIMENS: dict[str, Specimen] = {
    s.name: s
    for s in (
        Specimen("sent", sent, "specimen_sent.toml", "fem",
                 "the paper's plate (section 3)"),
        Specimen("edge_shear", edge_shear, "specimen_edge_shear.toml", "xfem",
                 "Yau, Wang and Corten 1980; Moes, Dolbow and Belytschko 1999"),
        Specimen("senb", senb, "specimen_senb.toml", "xfem",
                 "ASTM E399; Srawley 1976"),
        Specimen("plate_with_hole", plate_with_hole, "specimen_plate_with_hole.toml", "xfem",
                 "demonstration (crack beside a hole)"),
        Specimen("bittencourt_beam", bittencourt_beam, "specimen_bittencourt_beam.toml", "xfem",
                 "Bittencourt, Wawrzynek, Ingraffea and Sousa 1996"),
        Specimen("double_edge", double_edge, "double_edge_crack.toml", "xfem",
                 "Tada, Paris and Irwin (handbook)"),
    )
}  # fmt: skip


def get(name: str) -> Specimen:
    """The specimen ``name`` of :data:`SPECIMENS` (an unknown name lists the valid ones)."""
    if name not in SPECIMENS:
        raise InvalidParameterError(
            f"invalid name: no specimen {name!r}; valid: {', '.join(SPECIMENS)}", "name"
        )
    return SPECIMENS[name]
