"""Scenes: complete, validated descriptions of one run.

A :class:`Scene` says which method runs (``"fem" | "xfem" | "pd" | "ccm_pd"``) on which plate,
material, load and crack, with the method's own options. Every rule of a scene (the keys of each
section, their kinds, defaults and valid ranges, and the checks between parameters) lives in the
Rust core, which this module reads (``rustfrac._core.scene_schema()``): a scene is checked there
when it is built, before anything runs. A bad value raises
:class:`~rustfrac.errors.InvalidParameterError` (a ``ValueError``) whose ``param`` is the scene key
(``section.key``, ``crack[k].key`` for the k-th further crack) and whose message states the valid
range; unknown keys raise :class:`~rustfrac.errors.UnknownParameterError` listing the allowed ones;
a missing required key (``method``, a circle hole's ``radius``: the schema's ``required``) raises
:class:`~rustfrac.errors.MissingParameterError`; wrong types raise
:class:`~rustfrac.errors.InvalidTypeError` (also a ``TypeError``).

Units are consistent and up to the user; the paper's case uses N, mm and MPa (E = 10000 MPa).

TOML layout (only ``method`` is required; omitted sections and keys take the paper's values)::

    method = "fem"            # "fem" | "xfem" | "pd" | "ccm_pd"
    name = "paper plate"      # optional label

    [plate]     width, height                                  # W along x1, L along x2
    [material]  E, nu, plane, thickness, G0
    [load]      bc, u0, traction                               # bc: free | clamped | traction
    [crack]     kind, a0, y, angle, x, side                    # or [[crack]] tables (XFEM)
    [mesh]      nx, ny, gauss, xs, ys, refine, refine_h, grading     # fem and xfem
    [xfem]      nsub, tip_nsub, r_I, fixed_area_radius, area_threshold, growth_steps,
                tip_tie_tol, da, kink_rule, a_stop             # kink_rule: hoop | predictor_corrector
    [pd]        dx, m, center, size, hole_volumes, surface_correction, fem_grading,
                fem_coarse, sla_steps, tie_tol, refactor_every, fast, engine, s0_calibration,
                stop_crack_length, damage_at_steps, checkpoint_every, checkpoint_path,
                resume_from                                    # pd and ccm_pd

    # the general scene: list tables, each optional, any number of each (Scene fields holes,
    # notches, supports, loads, probes; section classes Hole, Notch, Support, RegionLoad, Probe)
    [[hole]]    shape, center, radius, min, max, points        # circle | rect | polygon
    [[notch]]   side, at, width, depth
    [[support]] region, side, from, to, point, box, fix, u1, u2 # edge | edge_part | point | box
    [[load]]    region, side, from, to, point, normal, shear, force   # edge | edge_part | point
    [[probe]]   name, kind, point, crack                       # displacement | opening

``[[load]]`` tables (loads on regions) and ``[[support]]`` replace the grips of a ``[load]``
table: a scene has one or the other (the core refuses both; the result's ``meta["bc"]`` is then
"regions" and ``sigma22`` the mean normal stress on the first loaded edge, or the force of a
point load along its direction). The k-th entry of each list is named ``support[k]``,
``load[k]``, ``hole[k]`` in errors (``support[1].point``) and in results
(``Result.reaction("support[0]")``). Every method reads supports, region loads, probes, holes
and notches; what a method cannot model yet (e.g. a CCM-PD hole cutting a hybrid element) the
core refuses by name when the scene is run. In Python the key ``from`` is the attribute ``from_`` (``Support(from_=1.0)``);
dicts use ``"from"``.

:func:`keys` lists every key with its default, valid range and meaning (the section classes'
docstrings too).

Cracks: ``kind = "edge"`` starts on the left edge at (0, ``y``) and runs a length ``a0`` at
``angle`` degrees from the x1 axis (PD: 0 only); ``kind = "center"`` (XFEM) is an interior crack
of half-length ``a0`` centred at (``x``, ``y``) at ``angle`` degrees; ``"seam"`` (FEM) duplicates
the nodes of the grid line nearest ``y`` from x1 = 0 to ``a0``. An XFEM edge crack may start on
any ``side`` ("left", "right": at height ``y``; "bottom", "top": at abscissa ``x``), ``angle`` then
being measured counter-clockwise from that side's inward normal. Several cracks (XFEM only): one
``[[crack]]`` table per crack (the first is the primary crack: CMOD and the history's ``a`` refer
to it); in Python ``crack=[Crack(...), ...]`` (or ``extra_cracks``).
"""

from __future__ import annotations

import dataclasses
import json
import keyword
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, make_dataclass
from pathlib import Path
from typing import Any, ClassVar, Union

from . import _core
from .errors import InvalidParameterError, InvalidTypeError, UnknownParameterError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "MAX_SCENE_BYTES",
    "METHODS",
    "Crack",
    "Hole",
    "Load",
    "Material",
    "MeshOptions",
    "Notch",
    "PdOptions",
    "Plate",
    "Probe",
    "RegionLoad",
    "Scene",
    "Support",
    "XfemOptions",
    "keys",
]

PathLike = Union[str, Path]

_SCHEMA: list[dict[str, Any]] = _core.scene_schema()
_CONST: dict[str, Any] = _core.scene_constants()
#: the methods a scene can run: "fem", "xfem", "pd", "ccm_pd"
METHODS: tuple[str, ...] = tuple(_CONST["METHODS"])
#: sections each method reads (the others must not appear in its scene files)
METHOD_SECTIONS: dict[str, tuple[str, ...]] = {
    m: tuple(s) for m, s in _CONST["METHOD_SECTIONS"].items()
}
#: largest FEM/XFEM mesh (elements) and PD grid (nodes), the core's memory guard
MAX_ELEMENTS: int = _CONST["MAX_ELEMENTS"]
#: largest SLA step count, re-condensation period and damage snapshot step
MAX_STEPS: int = _CONST["MAX_STEPS"]
#: Poisson's ratio of bond-based PD (the only one it represents, in plane strain)
PD_NU: float = _CONST["PD_NU"]
#: largest scene file / TOML text (bytes): a scene holds a few kB; a bound keeps a runaway list
#: from becoming gigabytes of memory and of result.json
MAX_SCENE_BYTES: int = 1 << 20

_PY_TYPES = {
    "float": float,
    "int": int,
    "str": str,
    "bool": bool,
    "pair": tuple,
    "intlist": tuple,
    "floatlist": tuple,
    "pairlist": tuple,
}


def keys(section: str | None = None) -> list[dict[str, Any]]:
    """Every scene key (or those of one section): dicts with ``section``, ``key``, ``kind``,
    ``default``, ``valid`` (the range in words), ``role`` ("physics", "solver" or "output": what
    the value changes), ``required`` (None, or ``{key: [values]}``: required when each key has
    one of its values, ``{}``: always), ``required_words`` and ``doc``, as the core defines
    them."""
    return [dict(k) for k in _SCHEMA if section is None or k["section"] == section]


def _normalised(kinds: dict[str, str], values: Mapping[str, Any]) -> dict[str, Any]:
    """The core's checked values with pairs and lists as tuples (sections are immutable)."""

    def norm(k: str, v: Any) -> Any:
        kind = kinds.get(k)
        if kind == "pairlist":
            return tuple(tuple(p) for p in v)
        return tuple(v) if kind in ("pair", "intlist", "floatlist") else v

    return {k: norm(k, v) for k, v in values.items()}


def _attr(key: str) -> str:
    """The Python attribute of a scene key: the key itself, ``from_`` for ``from`` (a keyword)."""
    return key + "_" if keyword.iskeyword(key) else key


def _key(attr: str) -> str:
    """The scene key of a section attribute (inverse of :func:`_attr`)."""
    return attr[:-1] if attr.endswith("_") and keyword.iskeyword(attr[:-1]) else attr


def _plain(v: Any) -> Any:
    """Tuples (pairs, lists, pair lists) as lists, for TOML and JSON."""
    return [_plain(x) for x in v] if isinstance(v, tuple) else v


class _Section:
    """Base of the scene sections: the core checks the fields after init."""

    _name: ClassVar[str] = ""
    _kinds: ClassVar[dict[str, str]] = {}
    #: an entry of a list table: only the keys that differ from the schema's defaults are
    #: handed to the core (and written), plus those the core says the entry must state
    _entry: ClassVar[bool] = False

    def __post_init__(self) -> None:
        values = {_key(f.name): getattr(self, f.name) for f in fields(self)}  # type: ignore[arg-type]
        if self._entry:
            values = self._stated(values)
        checked = _core.check_section(self._name, values)
        for k, v in _normalised(self._kinds, checked).items():
            object.__setattr__(self, _attr(k), v)

    @classmethod
    def _stated(cls, values: Mapping[str, Any]) -> dict[str, Any]:
        """The keys of a list entry worth stating: those that differ from their default, and
        those the core's schema requires for the entry's shape or region (a polygon hole states
        no radius; an edge support states its side even when it is the default one)."""
        defaults = {f.name: f.default for f in fields(cls)}  # type: ignore[arg-type]
        norm = _normalised(cls._kinds, values)
        out = {k: v for k, v in values.items() if norm[k] != defaults[_attr(k)]}
        for s in keys(cls._name):
            req, key = s["required"], s["key"]
            if (
                req is not None
                and key in values
                and all(values.get(k) in v for k, v in req.items())
            ):
                out[key] = values[key]
        return dict(sorted(out.items(), key=lambda kv: list(values).index(kv[0])))

    @classmethod
    def from_dict(cls, d: Any, name: str | None = None) -> Any:
        """The section of a (TOML-shaped) dict; ``name`` is the scene name errors carry
        (``crack[2]`` for the third crack, ``support[1]`` for the second support)."""
        checked = _core.check_section(cls._name, d, name)
        return cls._from_checked(checked)

    @classmethod
    def _from_checked(cls, checked: Mapping[str, Any]) -> Any:
        """The section of values the core has checked (keys as the scene names them)."""
        return cls(**{_attr(k): v for k, v in _normalised(cls._kinds, checked).items()})

    def to_dict(self) -> dict[str, Any]:
        """The section's keys (as the scene names them: ``from``, not ``from_``) and values;
        pairs and lists as lists."""
        values = {_key(f.name): _plain(getattr(self, f.name)) for f in fields(self)}  # type: ignore[arg-type]
        return self._stated(values) if self._entry else values


def _section_class(cls_name: str, section: str, doc: str, **methods: Any) -> Any:
    """A frozen dataclass of the section's keys as the core's schema lists them."""
    specs = keys(section)
    flds = [
        (
            _attr(s["key"]),
            _PY_TYPES[s["kind"]],
            field(default=tuple(s["default"]) if isinstance(s["default"], list) else s["default"]),
        )
        for s in specs
    ]
    lines = [
        f"- ``{s['key']}``"
        + (f" (attribute ``{_attr(s['key'])}``)" if _attr(s["key"]) != s["key"] else "")
        + f" ({s['default']!r}; {s['valid']}"
        + (f"; {s['required_words']}" if s["required_words"] else "")
        + f"): {s['doc']}"
        for s in specs
    ]
    namespace = {
        "_name": section,
        "_kinds": {s["key"]: s["kind"] for s in specs},
        "__doc__": doc + "\n\nKeys (default; valid range): meaning\n\n" + "\n".join(lines),
        "__module__": __name__,
        **methods,
    }
    return make_dataclass(cls_name, flds, bases=(_Section,), frozen=True, namespace=namespace)


def _crack_polyline(self: Any, plate: Any = None) -> list[tuple[float, float]]:
    """The crack as two points: (mouth, tip) for "edge" and "seam", (tip, tip) for "center";
    empty for "none" (computed by the core, as the solvers see it)."""
    if self.kind == "none":
        return []
    method = "fem" if self.kind == "seam" else "xfem"
    scene = {"method": method, "crack": self.to_dict()}
    if plate is not None:
        scene["plate"] = plate.to_dict()
    return [tuple(q) for q in _core.crack_polylines(scene)[0]]


Plate = _section_class(
    "Plate", "plate", "The rectangle [0, width] x [0, height]: width W along x1, height L along x2."
)
Material = _section_class(
    "Material",
    "material",
    "Isotropic linear elasticity (E, nu, plane strain or stress, thickness) and the critical "
    "energy release rate G0.",
)
Load = _section_class("Load", "load", "Loading on the top and bottom edges (eq. 61).")
Crack = _section_class(
    "Crack", "crack", "A straight crack (see the module docstring).", polyline=_crack_polyline
)
MeshOptions = _section_class(
    "MeshOptions", "mesh", "Structured Q4 mesh of nx x ny elements (FEM and XFEM)."
)
XfemOptions = _section_class(
    "XfemOptions", "xfem", "XFEM options (paper section 2.1; defaults are the paper's)."
)
PdOptions = _section_class(
    "PdOptions",
    "pd",
    "Peridynamics (grid, horizon, the CCM-PD rectangle) and the sequentially linear analysis.",
)

Hole = _section_class(
    "Hole",
    "hole",
    "A hole cut out of the plate (``[[hole]]``): a circle, a rectangle or a simple polygon. "
    "Holes must lie inside the plate and not overlap the cracks or each other (the core checks).",
    _entry=True,
)
Notch = _section_class(
    "Notch",
    "notch",
    "A flat-ended slot cut from one side of the plate (``[[notch]]``), ``width`` wide and "
    "``depth`` deep, centred at ``at`` along the side.",
    _entry=True,
)
Support = _section_class(
    "Support",
    "support",
    "Prescribed displacements on a region of the boundary (``[[support]]``): a whole side "
    "(``edge``), part of one (``edge_part``: ``from_`` to ``to``), the node nearest a ``point``, "
    "or the nodes in a ``box``; ``fix`` names the prescribed components (values ``u1``, ``u2`` "
    "at the reference load). Its reaction is in ``Result.reaction('support[k]')``.",
    _entry=True,
)
RegionLoad = _section_class(
    "RegionLoad",
    "region_load",
    "A load on a region of the boundary (a ``[[load]]`` table): tractions ``normal`` (tension "
    "positive) and ``shear`` on a side or part of one, or a point ``force`` at the node nearest "
    "``point`` (per unit thickness). Its force and mean stress are in "
    "``Result.reaction('load[k]')``, ``Result.mean_stress('load[k]')``.",
    _entry=True,
)
Probe = _section_class(
    "Probe",
    "probe",
    "A response read at a point (``[[probe]]``): the displacement there, or the opening (jump "
    "of u) of a crack at its point nearest ``point``; ``Result.probe(name)``.",
    _entry=True,
)

#: the single tables of a scene ([plate], [material], ...): Scene field -> section class
_TABLES: dict[str, Any] = {
    "plate": Plate,
    "material": Material,
    "load": Load,
    "crack": Crack,
    "mesh": MeshOptions,
    "xfem": XfemOptions,
    "pd": PdOptions,
}


#: the scene's list tables: Scene field -> (TOML key, section class, key in check_scene's tree)
_LISTS: dict[str, tuple[str, Any, str]] = {
    "holes": ("hole", Hole, "hole"),
    "notches": ("notch", Notch, "notch"),
    "supports": ("support", Support, "support"),
    "loads": ("load", RegionLoad, "loads"),
    "probes": ("probe", Probe, "probe"),
}


#: every section of the core's schema -> its class (the list tables' entries included)
_SECTIONS: dict[str, Any] = {**_TABLES, **{sec._name: sec for _, sec, _ in _LISTS.values()}}


def _crack_name(k: int) -> str:
    """The scene name of crack k: "crack" for the primary crack, "crack[k]" for the others."""
    return "crack" if k == 0 else f"crack[{k}]"


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
    #: holes (``[[hole]]``) and notches (``[[notch]]``) cut out of the plate
    holes: tuple[Hole, ...] = ()
    notches: tuple[Notch, ...] = ()
    #: supports (``[[support]]``) and loads on regions (``[[load]]`` tables), in place of the
    #: grips of ``load`` (which must then keep its defaults: the core refuses both)
    supports: tuple[Support, ...] = ()
    loads: tuple[RegionLoad, ...] = ()
    #: responses read at points (``[[probe]]``)
    probes: tuple[Probe, ...] = ()

    @property
    def uses_regions(self) -> bool:
        """True when supports or loads on regions replace the paper's grips."""
        return bool(self.supports or self.loads)

    @property
    def cracks(self) -> tuple[Crack, ...]:
        """All cracks: the primary ``crack`` first, then ``extra_cracks``."""
        return (self.crack, *self.extra_cracks)

    def __post_init__(self) -> None:
        if not isinstance(self.method, str) or self.method not in METHODS:
            _core.check_scene({"method": self.method})  # raises, naming 'method'
        self._split_cracks()
        if self.crack is None:
            kind = _CONST["DEFAULT_CRACK_KIND"][self.method]
            object.__setattr__(self, "crack", Crack(kind=kind))
        for key, cls in _TABLES.items():
            v = getattr(self, key)
            if isinstance(v, Mapping):
                object.__setattr__(self, key, cls.from_dict(v))
            elif not isinstance(v, cls):
                raise InvalidTypeError(
                    f"{key} must be a {cls.__name__} or a dict, got {type(v).__name__}", key
                )
        for attr, (toml_key, cls, _) in _LISTS.items():
            object.__setattr__(self, attr, _section_list(attr, toml_key, cls, getattr(self, attr)))
        _core.check_scene(self.to_dict())

    def _split_cracks(self) -> None:
        """``crack=[...]`` or ``extra_cracks``: the primary crack and the further ones."""
        extra = self.extra_cracks
        if isinstance(extra, (Crack, Mapping)) or not isinstance(extra, (list, tuple)):
            raise InvalidTypeError(
                f"extra_cracks must be a list of Crack or dicts, got {type(extra).__name__}",
                "extra_cracks",
            )
        if isinstance(self.crack, (list, tuple)):
            if not self.crack:
                raise InvalidParameterError(
                    "invalid crack: expected at least one crack, got an empty list", "crack"
                )
            if extra:
                raise InvalidParameterError(
                    "invalid crack: give several cracks either as a list or as extra_cracks",
                    "crack",
                )
            extra = tuple(self.crack[1:])
            object.__setattr__(self, "crack", self.crack[0])
        cracks = []
        for k, c in enumerate(extra, start=1):
            if isinstance(c, Mapping):
                c = Crack.from_dict(c, _crack_name(k))
            elif not isinstance(c, Crack):
                raise InvalidTypeError(
                    f"crack[{k}] must be a Crack or a dict, got {type(c).__name__}", f"crack[{k}]"
                )
            cracks.append(c)
        object.__setattr__(self, "extra_cracks", tuple(cracks))

    # -- construction -------------------------------------------------------------------------

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Scene:
        """Builds a scene from a (TOML-shaped) dict; ``method`` is required. The core checks it
        (every rule, each error naming its key) and fills in the defaults."""
        if not isinstance(d, Mapping):
            raise InvalidTypeError(f"a scene must be a dict, got {type(d).__name__}", "scene")
        c = _core.check_scene(d)
        method = c["method"]
        sections = {
            key: _TABLES[key]._from_checked(c[key])
            for key in METHOD_SECTIONS[method]
            if key != "crack"
        }
        cracks = [Crack(**_normalised(Crack._kinds, x)) for x in c["crack"]]
        lists = {
            attr: tuple(sec._from_checked(x) for x in c[tree_key])
            for attr, (_, sec, tree_key) in _LISTS.items()
        }
        return cls(method=method, name=c["name"], crack=cracks, **sections, **lists)

    @classmethod
    def from_toml(cls, path: PathLike) -> Scene:
        """Reads a scene from a TOML file (see the module docstring for the layout). A missing or
        unreadable file raises the usual ``OSError``; a file that is not UTF-8 text, larger than
        :data:`MAX_SCENE_BYTES`, or a path that cannot name a file (e.g. a NUL character), an
        :class:`InvalidParameterError`."""
        try:
            with open(path, "rb") as f:
                data = f.read(MAX_SCENE_BYTES + 1)  # bounded: a device or a huge file is refused
        except ValueError as e:  # e.g. "embedded null byte"
            raise InvalidParameterError(f"invalid scene path {_show(path)}: {e}", "scene") from e
        if len(data) > MAX_SCENE_BYTES:
            raise _too_large(f"scene file {_show(str(path))}")
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as e:
            raise InvalidParameterError(
                f"invalid scene file {_show(str(path))}: not UTF-8 text ({e.reason})", "scene"
            ) from e
        return cls.from_toml_str(text)

    @classmethod
    def from_toml_str(cls, text: str) -> Scene:
        """Reads a scene from TOML text (at most :data:`MAX_SCENE_BYTES` long)."""
        if (
            len(text) > MAX_SCENE_BYTES
            or len(text.encode("utf-8", "surrogatepass")) > MAX_SCENE_BYTES
        ):
            raise _too_large("scene text")
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            raise InvalidParameterError(
                f"invalid toml: the scene is not valid TOML: {e}", "toml"
            ) from e
        except RecursionError as e:  # tomllib recurses once per nesting level
            raise InvalidParameterError(
                "invalid toml: the scene nests arrays or tables too deeply to be a scene (a scene "
                "has at most 2 levels)",
                "toml",
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
                if sec not in _TABLES:
                    raise UnknownParameterError(
                        f"unknown section {sec!r}; allowed: {', '.join(_TABLES)} (the list "
                        f"tables {', '.join(_LISTS)} are replaced whole)",
                        sec,
                    )
                nested.setdefault(sec, {})[key] = v
            else:
                top[k] = v
        for sec, kv in nested.items():
            top[sec] = _TABLES[sec].from_dict({**getattr(self, sec).to_dict(), **kv})
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
            if key == "load" and self.uses_regions and self.load == Load():
                continue  # the grips' defaults: not written beside supports and region loads
            out[key] = getattr(self, key).to_dict()
        if self.extra_cracks:
            out["crack"] = [c.to_dict() for c in self.cracks]
        for attr, (toml_key, _, _) in _LISTS.items():
            items = getattr(self, attr)
            if items:
                if isinstance(out.get(toml_key), dict):
                    # grips beside loads on regions: one TOML key cannot hold both
                    raise InvalidParameterError(
                        "invalid load: a scene has either the grips of a [load] table or loads "
                        "on regions ([[load]] tables), not both; got grips "
                        f"{_show(out[toml_key])} and {len(items)} region load(s)",
                        "load",
                    )
                out[toml_key] = [x.to_dict() for x in items]
        return out

    def crack_polylines(self) -> list[list[tuple[float, float]]]:
        """The polyline of every crack, as the solvers see them (empty when uncracked)."""
        return [[tuple(q) for q in line] for line in _core.crack_polylines(self.to_dict())]

    def to_toml(self) -> str:
        """The scene as TOML text; ``Scene.from_toml_str(s.to_toml()) == s``."""
        return _dict_toml(self.to_dict())

    def save_toml(self, path: PathLike) -> Path:
        """Writes :meth:`to_toml` to ``path``."""
        p = Path(path)
        p.write_text(self.to_toml(), encoding="utf-8")
        return p

    def _repr_html_(self) -> str:
        """Jupyter's view: the description line and a table of each section's keys."""
        from ._html import scene_html

        return scene_html(self)

    def describe(self) -> str:
        """One line: method, plate, crack, load variant and discretisation."""
        c = self.crack
        if c.kind == "none":
            crack = "uncracked"
        elif c.kind == "center":
            crack = f"center crack half-length a0={c.a0:g} at ({c.x:g}, {c.y:g})"
        elif c.kind == "edge" and c.side in ("bottom", "top"):
            crack = f"edge crack a0={c.a0:g} from the {c.side} at x1={c.x:g}"
        else:
            crack = f"{c.kind} crack a0={c.a0:g} at x2={c.y:g}"
            if c.kind == "edge" and c.side != "left":
                crack += f" from the {c.side}"
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
        if self.uses_regions:
            bc = (
                "bc regions ("
                + ", ".join(
                    [_region_text("support", s) for s in self.supports]
                    + [_region_text("load", x) for x in self.loads]
                )
                + ")"
            )
        else:
            load = (
                f"traction {self.load.traction:g}"
                if self.load.bc == "traction"
                else f"u0 = +-{self.load.u0:g}"
            )
            bc = f"bc {self.load.bc} ({load})"
        cuts = [
            f"{len(v)} {what}"
            for what, v in (("hole(s)", self.holes), ("notch(es)", self.notches))
            if v
        ]
        if cuts:
            crack += ", " + " and ".join(cuts)
        probes = (
            f", probes {', '.join(p.name or f'probe[{k}]' for k, p in enumerate(self.probes))}"
            if self.probes
            else ""
        )
        return (
            f"method {self.method}, plate {self.plate.width:g} x {self.plate.height:g}, {crack}, "
            f"{bc}, {disc}{probes}"
        )


def _region_text(what: str, r: Any) -> str:
    """A short description of a support or a region load (for :meth:`Scene.describe`)."""
    if r.region == "point":
        where = f"point ({r.point[0]:g}, {r.point[1]:g})"
    elif r.region == "box":
        where = "box [" + ", ".join(f"{v:g}" for v in r.box) + "]"
    elif r.region == "edge_part":
        where = f"{r.side} {r.from_:g}..{r.to:g}"
    else:
        where = f"{r.side} edge"
    if what == "support":
        return f"{where} fixed {r.fix}"
    if r.region == "point":
        return f"force ({r.force[0]:g}, {r.force[1]:g}) at {where}"
    parts = [f"{k} {getattr(r, k):g}" for k in ("normal", "shear") if getattr(r, k) != 0.0]
    return f"{' '.join(parts) or 'no traction'} on {where}"


def _section_list(attr: str, toml_key: str, cls: Any, items: Any) -> tuple[Any, ...]:
    """A list table of the scene (``holes``, ``supports``, ...) as a tuple of section objects;
    dicts are checked by the core under their scene name (``support[1]``)."""
    if isinstance(items, (Mapping, _Section, str)) or not isinstance(items, (list, tuple)):
        raise InvalidTypeError(
            f"{attr} must be a list of {cls.__name__} or dicts, got {type(items).__name__}", attr
        )
    out = []
    for k, x in enumerate(items):
        if isinstance(x, Mapping):
            x = cls.from_dict(x, f"{toml_key}[{k}]")
        elif not isinstance(x, cls):
            raise InvalidTypeError(
                f"{toml_key}[{k}] must be a {cls.__name__} or a dict, got {type(x).__name__}",
                f"{toml_key}[{k}]",
            )
        out.append(x)
    return tuple(out)


def _too_large(what: str) -> InvalidParameterError:
    return InvalidParameterError(
        f"invalid {what}: larger than the limit of {MAX_SCENE_BYTES} bytes (MAX_SCENE_BYTES; a "
        "scene holds a few kB)",
        "scene",
    )


def _show(v: Any) -> str:
    """A short repr for messages."""
    r = repr(v)
    return r if len(r) <= 120 else r[:117] + "..."


def _dict_toml(d: Mapping[str, Any]) -> str:
    """A TOML-shaped scene dict as TOML text: top-level values, then a ``[table]`` per dict and
    a ``[[table]]`` per entry of a list of dicts."""

    def is_tables(v: Any) -> bool:
        return isinstance(v, dict) or (
            isinstance(v, list) and bool(v) and all(isinstance(t, dict) for t in v)
        )

    lines = [f"{k} = {_toml_value(v)}" for k, v in d.items() if not is_tables(v)]
    for k, v in d.items():
        if not is_tables(v):
            continue
        for t in [v] if isinstance(v, dict) else v:
            lines.append("")
            lines.append(f"[{k}]" if isinstance(v, dict) else f"[[{k}]]")
            lines.extend(f"{kk} = {_toml_value(vv)}" for kk, vv in t.items())
    return "\n".join(lines) + "\n"


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
