"""Scenes: complete, validated descriptions of one run.

A :class:`Scene` says which method runs (``"fem" | "xfem" | "pd" | "ccm_pd"``) on which plate,
material, load and crack, with the method's own options. It is validated when it is built, before
any Rust runs: every bad value raises :class:`~rustfrac.errors.InvalidParameterError` (a
``ValueError``) naming the parameter (``section.key``) and its valid range; unknown keys raise
:class:`~rustfrac.errors.UnknownParameterError` listing the allowed ones; wrong types raise
:class:`~rustfrac.errors.InvalidTypeError` (also a ``TypeError``).

Units are consistent and up to the user; the paper's case uses N, mm and MPa (E = 10000 MPa).

TOML layout (only ``method`` is required; omitted sections and keys take the paper's values)::

    method = "fem"            # "fem" | "xfem" | "pd" | "ccm_pd"
    name = "paper plate"      # optional label

    [plate]     width = 11.0, height = 21.0                         # W along x1, L along x2
    [material]  E = 10000.0, nu = 0.25, plane = "strain", thickness = 1.0, G0 = 0.367
    [load]      bc = "free", u0 = 0.01, traction = 9.993            # bc: free | clamped | traction
    [crack]     kind = "seam", a0 = 1.1, y = 10.5, angle = 0.0, x = 5.5, side = "left"
                # fem: none | seam; xfem: edge | center; pd, ccm_pd: none | edge (angle 0)
    [mesh]      nx = 44, ny = 83, gauss = 2                         # fem and xfem
    [xfem]      nsub = 4, tip_nsub = 0, r_I = 2.5, fixed_area_radius = 0.0,
                area_threshold = 1e-4, growth_steps = 0, da = 0.0, a_stop = 0.0   # xfem only
    [pd]        dx = 0.0666..., m = 4, center = [1.70, 10.5], size = [2.73, 1.67],
                sla_steps = 500, tie_tol = 0.0, refactor_every = 0, fast = true,
                stop_crack_length = 0.0, damage_at_steps = []       # pd and ccm_pd only

(Each section is a TOML table with one ``key = value`` per line; the one-line form above is
a summary.)

Cracks: ``kind = "edge"`` starts on the left edge at (0, ``y``) and runs a length ``a0`` at
``angle`` degrees from the x1 axis (counter-clockwise; PD: 0 only); ``kind = "center"`` (XFEM) is
an interior crack of half-length ``a0`` centred at (``x``, ``y``) at ``angle`` degrees; ``"seam"``
(FEM) duplicates the nodes of the grid line nearest ``y`` from x1 = 0 to ``a0``. The crack must lie
inside the plate (tips strictly inside). An XFEM edge crack may start on any ``side`` ("left",
"right": at height ``y``; "bottom", "top": at abscissa ``x``), ``angle`` then being measured
counter-clockwise from that side's inward normal.

Several cracks (XFEM only): write an array of tables instead of the single ``[crack]`` table,
one ``[[crack]]`` per crack (the first is the primary crack: CMOD and the history's ``a`` refer
to it); in Python pass ``crack=[Crack(...), ...]`` (or ``extra_cracks``). Cracks must neither
cross nor touch each other; errors name ``crack[k].<key>`` for the k-th crack (k >= 1).


``[pd]``: ``center``/``size`` give the PD rectangle of ``ccm_pd`` (pure ``pd`` covers the whole plate
and ignores them); ``sla_steps`` bond breaks at most; ``tie_tol`` breaks together every bond within
that relative tolerance of the step's load factor; ``refactor_every`` re-condenses the fast solver
after that many breaks (0 = never); ``fast = false`` runs the refactorise-every-step oracle;
``stop_crack_length`` stops the SLA once the crack reaches that length (0 = no such stop);
``damage_at_steps`` stores the damage field after those steps too.
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Callable, ClassVar, Union

from .errors import InvalidParameterError, InvalidTypeError, UnknownParameterError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "METHODS",
    "Crack",
    "Load",
    "Material",
    "MeshOptions",
    "PdOptions",
    "Plate",
    "Scene",
    "XfemOptions",
]

METHODS: tuple[str, ...] = ("fem", "xfem", "pd", "ccm_pd")
BCS: tuple[str, ...] = ("free", "clamped", "traction")
PD_NU = 0.25
PathLike = Union[str, Path]

# ----------------------------------------------------------------------------------------------
# field specifications


@dataclass(frozen=True)
class _Spec:
    """How one key is checked: its kind, a predicate and the valid range in words."""

    kind: str  # "float" | "int" | "str" | "pair" | "bool" | "intlist"
    valid: str
    ok: Callable[[Any], bool] = lambda v: True


#: magnitudes accepted for dimensional values (lengths, moduli, stresses, G0), as in the core
#: (rustfrac_core::error::MAG_MIN/MAG_MAX): the physics is scale invariant
#: (tests/test_scale_invariance.py), so the only limit is double precision, where products such as
#: the PD micromodulus E / (h delta^3) or an energy E l^2 must neither overflow nor underflow. Any
#: consistent unit system fits (SI steel: E = 2e11 Pa, lengths 1e-3 m).
MAG_MIN = 1e-30
MAG_MAX = 1e30
#: largest FEM/XFEM mesh (elements) and PD grid (nodes): rustfrac_core::mesh::MAX_ELEMENTS (one FEM
#: solve of 1000 x 1000 elements takes ~5 GB and ~25 s on 2 cores)
MAX_ELEMENTS = 2_000_000
#: largest SLA step count, re-condensation period and damage snapshot step (the core's limit)
MAX_STEPS = 1_000_000


def _finite(v: float) -> bool:
    return math.isfinite(v) and abs(v) <= MAG_MAX


def _pos(v: float) -> bool:
    return math.isfinite(v) and MAG_MIN <= v <= MAG_MAX


_POS = _Spec("float", "a finite number in [1e-30, 1e30]", _pos)
_FINITE = _Spec("float", "a finite number with |value| <= 1e30", _finite)


def _choice(*opts: str) -> _Spec:
    return _Spec("str", "one of " + ", ".join(repr(o) for o in opts), lambda v: v in opts)


def _int_at_least(lo: int, hi: int | None = None) -> _Spec:
    valid = f"an integer >= {lo}" if hi is None else f"an integer in {lo}..{hi}"
    return _Spec("int", valid, lambda v: v >= lo and (hi is None or v <= hi))


def _count(lo: int) -> _Spec:
    """A step count or period: an integer >= lo, at most MAX_STEPS (the core's limit)."""
    return _Spec("int", f"an integer >= {lo} (at most {MAX_STEPS})", lambda v: lo <= v <= MAX_STEPS)


def _show(v: Any) -> str:
    """A short repr for messages (huge ints and containers are cut, never raise)."""
    if isinstance(v, int) and not isinstance(v, bool) and v.bit_length() > 200:
        return f"an integer of {v.bit_length()} bits"
    try:
        r = repr(v)
    except Exception:  # e.g. a recursive or broken __repr__
        r = f"<{type(v).__name__}>"
    return r if len(r) <= 120 else r[:117] + "..."


def _key(k: Any) -> str:
    """A dict key as text for messages (TOML keys are strings; dicts may hold anything)."""
    return k if isinstance(k, str) and k else _show(k)


def _float(name: str, spec: _Spec, v: int | float) -> float:
    try:
        return float(v)
    except OverflowError:  # an int beyond the double range
        raise InvalidParameterError(
            f"invalid {name}: expected {spec.valid}, got an integer of {v.bit_length()} bits", name
        ) from None


def _coerce(name: str, spec: _Spec, v: Any) -> Any:
    """Checks the type of ``v`` (ints are accepted for floats) and its range."""
    if spec.kind == "float":
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InvalidTypeError(
                f"{name} must be a number ({spec.valid}), got {type(v).__name__} {_show(v)}", name
            )
        v = _float(name, spec, v)
    elif spec.kind == "int":
        if isinstance(v, bool) or not isinstance(v, int):
            raise InvalidTypeError(
                f"{name} must be an integer ({spec.valid}), got {type(v).__name__} {_show(v)}", name
            )
    elif spec.kind == "str":
        if not isinstance(v, str):
            raise InvalidTypeError(
                f"{name} must be a string ({spec.valid}), got {type(v).__name__} {_show(v)}", name
            )
    elif spec.kind == "pair":
        if (
            not isinstance(v, (list, tuple))
            or len(v) != 2
            or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in v)
        ):
            raise InvalidTypeError(
                f"{name} must be a pair of numbers ({spec.valid}), got {_show(v)}", name
            )
        v = (_float(name, spec, v[0]), _float(name, spec, v[1]))
    elif spec.kind == "bool":
        if not isinstance(v, bool):
            raise InvalidTypeError(
                f"{name} must be true or false ({spec.valid}), got {type(v).__name__} {_show(v)}", name
            )
    elif spec.kind == "intlist":
        if not isinstance(v, (list, tuple)) or any(
            isinstance(x, bool) or not isinstance(x, int) for x in v
        ):
            raise InvalidTypeError(
                f"{name} must be a list of integers ({spec.valid}), got {_show(v)}", name
            )
        v = tuple(v)
    if not spec.ok(v):
        raise InvalidParameterError(f"invalid {name}: expected {spec.valid}, got {_show(v)}", name)
    return v


class _Section:
    """Base of the scene sections: validates its fields against ``_specs`` after init."""

    _name: ClassVar[str] = ""
    _specs: ClassVar[dict[str, _Spec]] = {}

    def __post_init__(self) -> None:
        for f in fields(self):  # type: ignore[arg-type]
            spec = self._specs[f.name]
            object.__setattr__(
                self, f.name, _coerce(f"{self._name}.{f.name}", spec, getattr(self, f.name))
            )

    @classmethod
    def from_dict(cls, d: Any) -> Any:
        if not isinstance(d, Mapping):
            raise InvalidTypeError(
                f"[{cls._name}] must be a table/dict, got {type(d).__name__}", cls._name
            )
        allowed = [f.name for f in fields(cls)]  # type: ignore[arg-type]
        unknown = sorted(set(d) - set(allowed), key=str)
        if unknown:
            raise UnknownParameterError(
                f"unknown key(s) {', '.join(cls._name + '.' + _key(k) for k in unknown)}; "
                f"allowed in [{cls._name}]: {', '.join(allowed)}",
                f"{cls._name}.{_key(unknown[0])}",
            )
        return cls(**d)

    def to_dict(self) -> dict[str, Any]:
        out = {}
        for f in fields(self):  # type: ignore[arg-type]
            v = getattr(self, f.name)
            out[f.name] = list(v) if isinstance(v, tuple) else v
        return out


# ----------------------------------------------------------------------------------------------
# sections


@dataclass(frozen=True)
class Plate(_Section):
    """The rectangle [0, width] x [0, height]: width W along x1, height L along x2."""

    width: float = 11.0
    height: float = 21.0
    _name: ClassVar[str] = "plate"
    _specs: ClassVar[dict[str, _Spec]] = {"width": _POS, "height": _POS}


@dataclass(frozen=True)
class Material(_Section):
    """Isotropic linear elasticity: Young's modulus E, Poisson's ratio nu, plane strain or stress,
    thickness, and the critical energy release rate G0 (PD bond strength; force/length)."""

    E: float = 10000.0
    nu: float = 0.25
    plane: str = "strain"
    thickness: float = 1.0
    G0: float = 0.367
    _name: ClassVar[str] = "material"
    _specs: ClassVar[dict[str, _Spec]] = {
        "E": _POS,
        "nu": _Spec("float", "-1 < nu < 0.5", lambda v: math.isfinite(v) and -1.0 < v < 0.5),
        "plane": _choice("strain", "stress"),
        "thickness": _POS,
        "G0": _POS,
    }


@dataclass(frozen=True)
class Load(_Section):
    """Loading on the top and bottom edges (eq. 61): ``bc = "free"`` (u2 = +-u0, u1 free, one
    anchor node removes the rigid translation), ``"clamped"`` (u2 = +-u0, u1 = 0) or
    ``"traction"`` (uniform normal stress ``traction`` on both edges)."""

    bc: str = "free"
    u0: float = 0.01
    traction: float = 9.993
    _name: ClassVar[str] = "load"
    _specs: ClassVar[dict[str, _Spec]] = {
        "bc": _choice(*BCS),
        "u0": _FINITE,
        "traction": _FINITE,
    }


_SIDES: tuple[str, ...] = ("left", "right", "bottom", "top")


@dataclass(frozen=True)
class Crack(_Section):
    """A straight crack. ``kind``: "none" (uncracked), "seam" (FEM: duplicated nodes on the grid
    line nearest x2 = ``y``, from x1 = 0 to ``a0``), "edge" (from (0, ``y``), length ``a0``, at
    ``angle`` degrees from x1, -90 < angle < 90; XFEM level set / PD pre-broken bonds, PD angle 0
    only) or "center" (XFEM: interior crack centred at (``x``, ``y``), half-length ``a0``, at
    ``angle`` degrees). ``x`` is used by "center" cracks and by edge cracks on the bottom or top.
    ``side`` (XFEM edge cracks): the edge the crack starts from, "left" (default; mouth (0, y)),
    "right" (mouth (width, y)), "bottom" (mouth (x, 0)) or "top" (mouth (x, height)); ``angle``
    is measured counter-clockwise from that side's inward normal (+x1 for "left")."""

    kind: str = "seam"
    a0: float = 1.1
    y: float = 10.5
    angle: float = 0.0
    x: float = 5.5
    side: str = "left"
    _name: ClassVar[str] = "crack"
    _specs: ClassVar[dict[str, _Spec]] = {
        "kind": _choice("none", "seam", "edge", "center"),
        "a0": _POS,
        "y": _POS,
        "angle": _Spec(
            "float", "-180 <= angle <= 180 degrees", lambda v: math.isfinite(v) and abs(v) <= 180
        ),
        "x": _POS,
        "side": _choice(*_SIDES),
    }

    def polyline(self, plate: Plate | None = None) -> list[tuple[float, float]]:
        """The crack as two points: (mouth, tip) for "edge" and "seam", (tip, tip) for "center";
        empty for "none". Edge cracks on the right or top side need the ``plate``."""
        if self.kind == "none":
            return []
        t = math.radians(self.angle)
        c, s = math.cos(t), math.sin(t)
        if self.kind == "center":
            return [
                (self.x - self.a0 * c, self.y - self.a0 * s),
                (self.x + self.a0 * c, self.y + self.a0 * s),
            ]
        if self.kind == "seam":
            return [(0.0, self.y), (self.a0, self.y)]
        if self.side in ("right", "top") and plate is None:
            raise ValueError(f"an edge crack on the {self.side} side needs the plate")
        w = plate.width if plate is not None else 0.0
        h = plate.height if plate is not None else 0.0
        # mouth and inward normal of the side; the crack turns by angle from the normal
        mouth, n = {
            "left": ((0.0, self.y), (1.0, 0.0)),
            "right": ((w, self.y), (-1.0, 0.0)),
            "bottom": ((self.x, 0.0), (0.0, 1.0)),
            "top": ((self.x, h), (0.0, -1.0)),
        }[self.side]
        d = (n[0] * c - n[1] * s, n[0] * s + n[1] * c)
        return [mouth, (mouth[0] + self.a0 * d[0], mouth[1] + self.a0 * d[1])]


@dataclass(frozen=True)
class MeshOptions(_Section):
    """Structured Q4 mesh of nx x ny elements (FEM and XFEM); ``gauss`` points per direction."""

    nx: int = 44
    ny: int = 83
    gauss: int = 2
    _name: ClassVar[str] = "mesh"
    _specs: ClassVar[dict[str, _Spec]] = {
        "nx": _int_at_least(1),
        "ny": _int_at_least(1),
        "gauss": _int_at_least(1, 5),
    }

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.nx * self.ny > MAX_ELEMENTS:
            raise InvalidParameterError(
                f"invalid mesh.nx * mesh.ny: expected at most {MAX_ELEMENTS} elements "
                f"(a documented memory guard), got {_show(self.nx)} x {_show(self.ny)}",
                "mesh.nx",
            )


def _nonneg(v: float) -> bool:
    return v == 0 or _pos(v)


@dataclass(frozen=True)
class XfemOptions(_Section):
    """XFEM options (paper section 2.1; defaults are the paper's).

    - ``nsub`` (4, 1..32): split and branch-enriched elements are integrated on nsub x nsub
      sub-quads with 2 x 2 Gauss points each.
    - ``tip_nsub`` (0 = same as nsub; else nsub..64): sub-quads per direction in tip elements.
    - ``r_I`` (2.5, 0.5..20): radius of the interaction-integral domain in tip-element lengths.
    - ``fixed_area_radius`` (0 = off; else > 0, length units): enrich every node within this
      distance of a tip with the branch functions (Laborde et al. 2005).
    - ``area_threshold`` (1e-4, 0 < t < 0.5): a Heaviside node is dropped when the smaller part of
      its support cut by the crack is below this fraction of the support area.
    - ``growth_steps`` (0 = solve at the reference load only; else the maximum number of LEFM
      growth steps, each recording the critical state where G = G0 = ``material.G0``).
    - ``da`` (0 = one element length; else > 0): crack extension per growth step.
    - ``a_stop`` (0 = 0.7 ``plate.width``; else 0 < a_stop < width): growth stops once the crack
      length would exceed it (the half-length for a "center" crack).
    """

    nsub: int = 4
    tip_nsub: int = 0
    r_I: float = 2.5
    fixed_area_radius: float = 0.0
    area_threshold: float = 1e-4
    growth_steps: int = 0
    da: float = 0.0
    a_stop: float = 0.0
    _name: ClassVar[str] = "xfem"
    _specs: ClassVar[dict[str, _Spec]] = {
        "nsub": _int_at_least(1, 32),
        "tip_nsub": _Spec(
            "int", "0 (= nsub) or an integer in nsub..64", lambda v: v == 0 or 1 <= v <= 64
        ),
        "r_I": _Spec(
            "float",
            "0.5 <= r_I <= 20 element lengths",
            lambda v: math.isfinite(v) and 0.5 <= v <= 20.0,
        ),
        "fixed_area_radius": _Spec(
            "float", "0 (off) or a length in [1e-30, 1e30]", _nonneg
        ),
        "area_threshold": _Spec(
            "float", "0 < area_threshold < 0.5", lambda v: math.isfinite(v) and 0.0 < v < 0.5
        ),
        "growth_steps": _int_at_least(0, 100_000),
        "da": _Spec(
            "float", "0 (one element length) or a length in [1e-30, 1e30]", _nonneg
        ),
        "a_stop": _Spec("float", "0 (0.7 plate.width) or 0 < a_stop < plate.width", _nonneg),
    }

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.tip_nsub != 0 and self.tip_nsub < self.nsub:
            raise InvalidParameterError(
                f"invalid xfem.tip_nsub: expected 0 (= nsub) or an integer in "
                f"nsub..64 = {self.nsub}..64, got {self.tip_nsub}",
                "xfem.tip_nsub",
            )


@dataclass(frozen=True)
class PdOptions(_Section):
    """Peridynamics: grid spacing dx, horizon delta = m dx, the PD rectangle (``center``,
    ``size``; CCM-PD only: pure PD covers the whole plate and ignores them) and the sequentially
    linear analysis: ``sla_steps`` bond breaks at most, ``tie_tol`` (break together every bond
    whose load factor is within this relative tolerance of the minimum; 0 = one bond per step),
    ``refactor_every`` (fast solver: re-condense after this many breaks; 0 = never), ``fast``
    (condensation + Sherman-Morrison-Woodbury; ``False`` runs the refactorise-every-step oracle),
    ``stop_crack_length`` (stop once the crack is this long; 0 = no such stop) and
    ``damage_at_steps`` (steps after which the damage field is stored too).

    ``m`` = 1 runs but warns (:class:`~rustfrac.errors.AccuracyWarning`: 8 bonds per node); the
    PD rectangle (or, for pure PD, the plate) must span two horizons 2 m dx in each direction.
    ``refactor_every = 0`` lets the fast solver choose its re-condensation interval (n_P / 2,
    which bounds its memory). Long runs: ``checkpoint_every`` steps (0 = never) a checkpoint is
    written atomically to ``checkpoint_path`` (also when the run is interrupted);
    ``resume_from`` names a checkpoint of the same model and solver options to continue from
    (the resumed history equals an uninterrupted run's bit for bit; another model's checkpoint
    is refused). Empty paths mean none."""

    dx: float = 1.0 / 15.0
    m: int = 4
    center: tuple[float, float] = (1.70, 10.5)
    size: tuple[float, float] = (2.73, 1.67)
    sla_steps: int = 500
    tie_tol: float = 0.0
    refactor_every: int = 0
    fast: bool = True
    stop_crack_length: float = 0.0
    damage_at_steps: tuple[int, ...] = ()
    checkpoint_every: int = 0
    checkpoint_path: str = ""
    resume_from: str = ""
    _name: ClassVar[str] = "pd"
    _specs: ClassVar[dict[str, _Spec]] = {
        "dx": _POS,
        "m": _int_at_least(1, 12),
        "center": _Spec(
            "pair", "two finite numbers, |x| <= 1e30", lambda v: all(map(_finite, v))
        ),
        "size": _Spec(
            "pair", "two finite numbers in [1e-30, 1e30]", lambda v: all(map(_pos, v))
        ),
        "sla_steps": _count(1),
        "tie_tol": _Spec("float", "0 <= tie_tol < 1", lambda v: 0.0 <= v < 1.0),
        "refactor_every": _count(0),
        "fast": _Spec("bool", "true or false"),
        "stop_crack_length": _Spec(
            "float", "a finite number >= 0 (0 = no stop; else in [1e-30, 1e30])", _nonneg
        ),
        "damage_at_steps": _Spec(
            "intlist",
            f"a list of integers >= 1 (at most {MAX_STEPS})",
            lambda v: all(1 <= x <= MAX_STEPS for x in v),
        ),
        "checkpoint_every": _int_at_least(0),
        "checkpoint_path": _Spec("str", "a file path (empty: none)"),
        "resume_from": _Spec("str", "a checkpoint file path (empty: none)"),
    }


_SECTIONS: dict[str, type] = {
    "plate": Plate,
    "material": Material,
    "load": Load,
    "crack": Crack,
    "mesh": MeshOptions,
    "xfem": XfemOptions,
    "pd": PdOptions,
}
_COMMON = ("plate", "material", "load", "crack")
#: sections each method reads (the others must not appear in its scene files)
METHOD_SECTIONS: dict[str, tuple[str, ...]] = {
    "fem": (*_COMMON, "mesh"),
    "xfem": (*_COMMON, "mesh", "xfem"),
    "pd": (*_COMMON, "pd"),
    "ccm_pd": (*_COMMON, "pd"),
}
_CRACK_KINDS: dict[str, tuple[str, ...]] = {
    "fem": ("none", "seam"),
    "xfem": ("edge", "center"),
    "pd": ("none", "edge"),
    "ccm_pd": ("none", "edge"),
}


def _utf8(v: str) -> bool:
    """Encodable as UTF-8 (TOML and JSON files): no lone surrogates."""
    try:
        v.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _bad(param: str, msg: str) -> InvalidParameterError:
    return InvalidParameterError(f"invalid {param}: {msg}", param)


# ----------------------------------------------------------------------------------------------
# the scene


@dataclass(frozen=True)
class Scene:
    """One validated run description. Build it with :func:`rustfrac.scenes.edge_crack_plate`,
    :meth:`from_dict`, :meth:`from_toml`, or directly from section objects."""

    method: str = "fem"
    plate: Plate = field(default_factory=Plate)
    material: Material = field(default_factory=Material)
    load: Load = field(default_factory=Load)
    #: default: the paper's crack, as a seam for "fem" and as an "edge" crack for the others;
    #: a list of cracks (XFEM) is split into ``crack`` (the first) and ``extra_cracks``
    crack: Crack = None  # type: ignore[assignment]
    mesh: MeshOptions = field(default_factory=MeshOptions)
    xfem: XfemOptions = field(default_factory=XfemOptions)
    pd: PdOptions = field(default_factory=PdOptions)
    name: str = ""
    #: further cracks (XFEM only); ``cracks`` is ``(crack, *extra_cracks)``
    extra_cracks: tuple[Crack, ...] = ()

    @property
    def cracks(self) -> tuple[Crack, ...]:
        """All cracks: the primary ``crack`` first, then ``extra_cracks``."""
        return (self.crack, *self.extra_cracks)

    def __post_init__(self) -> None:
        _coerce("method", _choice(*METHODS), self.method)
        _coerce("name", _Spec("str", "a string of Unicode text", _utf8), self.name)
        extra = self.extra_cracks
        if isinstance(extra, (Crack, Mapping)) or not isinstance(extra, (list, tuple)):
            raise InvalidTypeError(
                f"extra_cracks must be a list of Crack or dicts, got {type(extra).__name__}",
                "extra_cracks",
            )
        if isinstance(self.crack, (list, tuple)):
            if not self.crack:
                raise _bad("crack", "expected at least one crack, got an empty list")
            if extra:
                raise _bad("crack", "give several cracks either as a list or as extra_cracks")
            extra = tuple(self.crack[1:])
            object.__setattr__(self, "crack", self.crack[0])
        cracks = []
        for k, c in enumerate(extra, start=1):
            if isinstance(c, Mapping):
                try:
                    c = Crack.from_dict(c)
                except InvalidParameterError as e:
                    raise _renamed(e, k) from e
            elif not isinstance(c, Crack):
                raise InvalidTypeError(
                    f"crack[{k}] must be a Crack or a dict, got {type(c).__name__}", f"crack[{k}]"
                )
            cracks.append(c)
        object.__setattr__(self, "extra_cracks", tuple(cracks))
        if self.crack is None:
            object.__setattr__(
                self, "crack", Crack(kind="seam" if self.method == "fem" else "edge")
            )
        for key, cls in _SECTIONS.items():
            v = getattr(self, key)
            if isinstance(v, Mapping):
                object.__setattr__(self, key, cls.from_dict(v))
            elif not isinstance(v, cls):
                raise InvalidTypeError(
                    f"{key} must be a {cls.__name__} or a dict, got {type(v).__name__}", key
                )
        self._check_consistency()

    def _check_consistency(self) -> None:
        m, p, c = self.method, self.plate, self.crack
        kinds = _CRACK_KINDS[m]
        if self.extra_cracks and m != "xfem":
            raise _bad(
                "crack",
                f"method {m!r} takes one crack, got {len(self.cracks)}; several cracks need "
                "method 'xfem'",
            )
        for k, ck in enumerate(self.cracks):
            pre = _crack_name(k)
            if ck.kind not in kinds:
                raise _bad(
                    f"{pre}.kind",
                    f"method {m!r} takes one of {', '.join(map(repr, kinds))}, got {ck.kind!r}",
                )
            if ck.kind != "none":
                self._check_crack_geometry(ck, pre)
            if m != "xfem" and ck.side != "left":
                raise _bad(
                    f"{pre}.side",
                    f"method {m!r} supports edge cracks from the left side only, got {ck.side!r}",
                )
        self._check_cracks_apart()
        if m in ("fem", "pd", "ccm_pd") and c.angle != 0.0:
            raise _bad(
                "crack.angle",
                f"method {m!r} supports cracks along x1 only (angle = 0), got {c.angle}; "
                "inclined cracks need method 'xfem'",
            )
        if m == "xfem":
            x = self.xfem
            if x.a_stop != 0.0 and not x.a_stop < p.width:
                raise _bad(
                    "xfem.a_stop",
                    f"expected 0 (0.7 plate.width) or 0 < a_stop < plate.width = {p.width}, "
                    f"got {x.a_stop}",
                )
            a0 = max(ck.a0 for ck in self.cracks)
            if x.a_stop != 0.0 and x.growth_steps > 0 and not x.a_stop > a0:
                raise _bad(
                    "xfem.a_stop",
                    f"growth needs a stop length beyond the initial crack(s): a_stop > crack.a0 = "
                    f"{a0}, got {x.a_stop}",
                )
        if m in ("pd", "ccm_pd"):
            if self.material.nu != PD_NU:
                raise _bad(
                    "material.nu",
                    f"bond-based peridynamics (method {m!r}) fixes nu = {PD_NU}, "
                    f"got {self.material.nu}",
                )
            if self.material.plane != "strain":
                raise _bad("material.plane", f"method {m!r} supports 'strain' only")
            d = self.pd
            nodes = (p.width / d.dx + 1) * (p.height / d.dx + 1)
            if nodes > MAX_ELEMENTS:
                raise _bad(
                    "pd.dx",
                    f"the PD grid would have {nodes:.3g} nodes; at most {MAX_ELEMENTS} "
                    "(a documented memory guard)",
                )
            if d.checkpoint_every > 0 and not d.checkpoint_path:
                raise _bad(
                    "pd.checkpoint_path",
                    f"checkpoint_every = {d.checkpoint_every} needs a checkpoint file path",
                )
            two_h = 2 * d.m * d.dx
            for i, (n, length) in enumerate((("x1", p.width), ("x2", p.height))):
                # a PD region thinner than two horizons has no node with a full family
                span = d.size[i] if m == "ccm_pd" else length
                if span < two_h * (1 - 1e-9):
                    raise _bad(
                        "pd.size" if m == "ccm_pd" else ("plate.width", "plate.height")[i],
                        f"the PD region must span at least two horizons 2 m dx = {two_h:.6g} "
                        f"(m = {d.m}, dx = {d.dx:.6g}) along {n}, got {span:.6g}",
                    )
                cells = length / d.dx
                if abs(cells - round(cells)) > 1e-9 * max(1.0, cells):
                    raise _bad(
                        "pd.dx",
                        f"the grid must fit the plate: {n} size {length} / dx = {cells:.6g} "
                        "is not an integer",
                    )
                if m == "ccm_pd":
                    lo, hi = d.center[i] - d.size[i] / 2, d.center[i] + d.size[i] / 2
                    if lo < 0 or hi > length:
                        raise _bad(
                            "pd.center",
                            f"the PD rectangle must lie inside the plate: its {n} range "
                            f"[{lo:.6g}, {hi:.6g}] leaves [0, {length}]",
                        )
            if m == "ccm_pd" and c.kind != "none":
                x0 = d.center[0] - d.size[0] / 2
                x1 = d.center[0] + d.size[0] / 2
                y0 = d.center[1] - d.size[1] / 2
                y1 = d.center[1] + d.size[1] / 2
                if not (x0 <= c.a0 <= x1 and y0 <= c.y <= y1):
                    raise _bad(
                        "pd.center",
                        f"the crack tip ({c.a0}, {c.y}) must lie in the PD rectangle "
                        f"[{x0:.6g}, {x1:.6g}] x [{y0:.6g}, {y1:.6g}]",
                    )

    def _check_cracks_apart(self) -> None:
        """Refuses cracks that cross or touch (the core cannot model crack junctions)."""
        lines = [c.polyline(self.plate) for c in self.cracks]
        tol = 1e-9 * math.hypot(self.plate.width, self.plate.height)
        for i in range(len(lines)):
            for j in range(i + 1, len(lines)):
                if _segment_distance(*lines[i], *lines[j]) <= tol:
                    raise _bad(
                        _crack_name(j),
                        f"cracks must neither cross nor touch each other (junctions are not "
                        f"modelled): {_crack_name(j)} {lines[j]} meets {_crack_name(i)} "
                        f"{lines[i]}",
                    )

    def _check_crack_geometry(self, c: Crack, pre: str = "crack") -> None:
        p = self.plate
        w, h = p.width, p.height
        if not c.y < h:
            raise _bad(f"{pre}.y", f"expected 0 < y < plate.height = {h}, got {c.y}")
        if c.kind in ("seam", "edge"):
            if c.kind == "edge" and not -90.0 < c.angle < 90.0:
                raise _bad(
                    f"{pre}.angle",
                    f"an edge crack must point into the plate: -90 < angle < 90, got {c.angle}",
                )
            if c.kind == "edge" and c.side in ("bottom", "top") and not c.x < w:
                raise _bad(f"{pre}.x", f"expected 0 < x < plate.width = {w}, got {c.x}")
            tx, ty = c.polyline(p)[1]
            if not (0.0 < tx < w and 0.0 < ty < h):
                raise _bad(
                    f"{pre}.a0",
                    f"the crack tip ({tx:.6g}, {ty:.6g}) must lie inside the plate "
                    f"(0, {w}) x (0, {h})"
                    + (
                        f": expected 0 < a0 < plate.width = {w}, got {c.a0}"
                        if c.angle == 0 and c.side == "left"
                        else ""
                    ),
                )
        elif c.kind == "center":
            if not c.x < w:
                raise _bad(f"{pre}.x", f"expected 0 < x < plate.width = {w}, got {c.x}")
            for tx, ty in c.polyline():
                if not (0.0 < tx < w and 0.0 < ty < h):
                    raise _bad(
                        f"{pre}.a0",
                        f"the centre crack (half-length a0 = {c.a0} at ({c.x}, {c.y}), "
                        f"angle {c.angle}) has a tip at ({tx:.6g}, {ty:.6g}) outside the plate "
                        f"(0, {w}) x (0, {h})",
                    )

    # -- construction -------------------------------------------------------------------------

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Scene:
        """Builds a scene from a (TOML-shaped) dict; ``method`` is required."""
        if not isinstance(d, Mapping):
            raise InvalidTypeError(f"a scene must be a dict, got {type(d).__name__}", "scene")
        if "method" not in d:
            raise UnknownParameterError(
                f"missing required key 'method' (one of {', '.join(map(repr, METHODS))})",
                "method",
            )
        method = _coerce("method", _choice(*METHODS), d["method"])
        allowed = ["method", "name", *METHOD_SECTIONS[method]]
        unknown = sorted(set(d) - set(allowed), key=str)
        if unknown:
            other = [k for k in unknown if k in _SECTIONS]
            hint = (
                f" (section(s) {', '.join(other)} do not apply to method {method!r})"
                if other
                else ""
            )
            raise UnknownParameterError(
                f"unknown key(s) {', '.join(map(_key, unknown))}{hint}; allowed: {', '.join(allowed)}",
                _key(unknown[0]),
            )
        kwargs: dict[str, Any] = {"method": method}
        if "name" in d:
            kwargs["name"] = d["name"]
        for key in METHOD_SECTIONS[method]:
            if key not in d:
                continue
            if key == "crack" and isinstance(d[key], (list, tuple)):
                # [[crack]]: an array of tables, one per crack
                if not d[key]:
                    raise _bad("crack", "expected at least one [[crack]] table, got none")
                cracks = []
                for k, c in enumerate(d[key]):
                    try:
                        cracks.append(Crack.from_dict(c))
                    except (InvalidParameterError, InvalidTypeError) as e:
                        raise _renamed(e, k) from e
                kwargs["crack"] = cracks
            else:
                kwargs[key] = _SECTIONS[key].from_dict(d[key])
        return cls(**kwargs)

    @classmethod
    def from_toml(cls, path: PathLike) -> Scene:
        """Reads a scene from a TOML file (see the module docstring for the layout). A missing or
        unreadable file raises the usual ``OSError``; a file that is not UTF-8 text, or a path
        that cannot name a file (e.g. a NUL character), an :class:`InvalidParameterError`."""
        try:
            text = Path(path).read_text(encoding="utf-8")
        except UnicodeDecodeError as e:
            raise InvalidParameterError(
                f"invalid scene file {_show(str(path))}: not UTF-8 text ({e.reason})", "scene"
            ) from e
        except ValueError as e:  # e.g. "embedded null byte"
            raise InvalidParameterError(f"invalid scene path {_show(path)}: {e}", "scene") from e
        return cls.from_toml_str(text)

    @classmethod
    def from_toml_str(cls, text: str) -> Scene:
        """Reads a scene from TOML text."""
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            raise InvalidParameterError(
                f"invalid toml: the scene is not valid TOML: {e}", "toml"
            ) from e
        return cls.from_dict(data)

    def replace(self, **changes: Any) -> Scene:
        """A copy with some fields replaced; ``"section.key"`` names are accepted as
        ``section__key`` (e.g. ``scene.replace(material__E=2e5, load__bc="clamped")``)."""
        top: dict[str, Any] = {}
        nested: dict[str, dict[str, Any]] = {}
        for k, v in changes.items():
            if "__" in k:
                sec, key = k.split("__", 1)
                if sec not in _SECTIONS:
                    raise UnknownParameterError(
                        f"unknown section {sec!r}; allowed: {', '.join(_SECTIONS)}", sec
                    )
                nested.setdefault(sec, {})[key] = v
            else:
                top[k] = v
        for sec, kv in nested.items():
            cur = getattr(self, sec).to_dict()
            unknown = sorted(set(kv) - set(cur))
            if unknown:
                raise UnknownParameterError(
                    f"unknown key(s) {', '.join(sec + '.' + k for k in unknown)}; "
                    f"allowed in [{sec}]: {', '.join(cur)}",
                    f"{sec}.{unknown[0]}",
                )
            top[sec] = _SECTIONS[sec].from_dict({**cur, **kv})
        unknown = sorted(set(top) - {f.name for f in fields(self)})
        if unknown:
            raise UnknownParameterError(
                f"unknown scene field(s) {', '.join(unknown)}; allowed: "
                + ", ".join(f.name for f in fields(self)),
                unknown[0],
            )
        return dataclasses.replace(self, **top)

    # -- export -------------------------------------------------------------------------------

    def to_dict(self) -> dict[str, Any]:
        """The scene as a TOML-shaped dict holding only the sections its method reads."""
        out: dict[str, Any] = {"method": self.method}
        if self.name:
            out["name"] = self.name
        for key in METHOD_SECTIONS[self.method]:
            out[key] = getattr(self, key).to_dict()
        if self.extra_cracks:
            out["crack"] = [c.to_dict() for c in self.cracks]
        return out

    def to_toml(self) -> str:
        """The scene as TOML text; ``Scene.from_toml_str(s.to_toml()) == s``."""
        d = self.to_dict()
        lines = [
            f"{k} = {_toml_value(v)}" for k, v in d.items() if not isinstance(v, (dict, list))
        ]
        for k, v in d.items():
            tables = [v] if isinstance(v, dict) else v if isinstance(v, list) else []
            for t in tables:
                lines.append("")
                lines.append(f"[{k}]" if isinstance(v, dict) else f"[[{k}]]")
                lines.extend(f"{kk} = {_toml_value(vv)}" for kk, vv in t.items())
        return "\n".join(lines) + "\n"

    def save_toml(self, path: PathLike) -> Path:
        """Writes :meth:`to_toml` to ``path``."""
        p = Path(path)
        p.write_text(self.to_toml(), encoding="utf-8")
        return p

    def describe(self) -> str:
        """One line: method, plate, crack, load variant and discretisation."""
        c = self.crack
        if c.kind == "none":
            crack = "uncracked"
        elif c.kind == "center":
            crack = f"center crack half-length a0={c.a0:g} at ({c.x:g}, {c.y:g})"
        else:
            crack = f"{c.kind} crack a0={c.a0:g} at x2={c.y:g}"
        if c.kind != "none" and c.angle != 0.0:
            crack += f", angle {c.angle:g} deg"
        if self.extra_cracks:
            crack += f" and {len(self.extra_cracks)} more crack(s)"
        if self.method == "xfem" and self.xfem.growth_steps > 0:
            crack += f", up to {self.xfem.growth_steps} growth steps"
        if self.method in ("fem", "xfem"):
            disc = f"mesh {self.mesh.nx}x{self.mesh.ny} Q4"
        else:
            disc = f"PD grid dx={self.pd.dx:.6g}, m={self.pd.m}"
        load = (
            f"traction {self.load.traction:g}"
            if self.load.bc == "traction"
            else f"u0 = +-{self.load.u0:g}"
        )
        return (
            f"method {self.method}, plate {self.plate.width:g} x {self.plate.height:g}, {crack}, "
            f"bc {self.load.bc} ({load}), {disc}"
        )


def _crack_name(k: int) -> str:
    """The scene name of crack k: "crack" for the primary crack, "crack[k]" for the others."""
    return "crack" if k == 0 else f"crack[{k}]"


def _renamed(e: InvalidParameterError | InvalidTypeError, k: int) -> Any:
    """An error about ``crack.<key>`` re-issued for crack k (``crack[k].<key>``)."""
    if k == 0:
        return e
    param = (e.param or "crack").replace("crack", _crack_name(k), 1)
    msg = str(e).replace("crack.", f"{_crack_name(k)}.").replace("[crack]", f"{_crack_name(k)} ([[crack]] table {k})")
    return type(e)(msg, param)


def _point_segment_distance(
    x: tuple[float, float], a: tuple[float, float], b: tuple[float, float]
) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = min(1.0, max(0.0, ((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / (dx * dx + dy * dy)))
    return math.hypot(x[0] - a[0] - t * dx, x[1] - a[1] - t * dy)


def _segment_distance(
    a: tuple[float, float],
    b: tuple[float, float],
    c: tuple[float, float],
    d: tuple[float, float],
) -> float:
    """Smallest distance between the segments a-b and c-d (0 when they cross)."""

    def cross(o: tuple[float, float], p: tuple[float, float], q: tuple[float, float]) -> float:
        return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])

    if cross(a, b, c) * cross(a, b, d) < 0 and cross(c, d, a) * cross(c, d, b) < 0:
        return 0.0
    return min(
        _point_segment_distance(a, c, d),
        _point_segment_distance(b, c, d),
        _point_segment_distance(c, a, b),
        _point_segment_distance(d, a, b),
    )


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v)  # shortest round-trip repr; finite by validation
    if isinstance(v, str):
        # JSON escapes (\", \\, \n, \uXXXX) are valid TOML; TOML also forbids DEL
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")
