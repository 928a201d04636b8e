"""Results of a run: scalars, numpy fields, history, metadata; saving and loading.

``Result.save(dir)`` writes, as one unit (``_folder``: each file staged under a temporary name,
then all renamed into place under the folder's lock, the JSON last):

- ``result.json`` (written last): scalars and metadata (version, scene, boundary-condition variant, anchor node,
  timings) -- plain JSON, floats written with full precision -- and the save id, the arrays'
  shapes and the SHA-256 of the other files;
- ``fields.npz``: the arrays (mesh, displacement, stresses, ...) and the history;
- ``result.vtu``: the result for ParaView (or meshio), a binary, zlib-compressed VTK unstructured
  grid of the mesh :meth:`Result.to_meshio` gives (the last state), written directly
  (``_vtk.write_vtu``, meshio not needed; FEM quads with displacement and stress; XFEM standard
  quads plus the enriched elements' cut cells on each side of the crack, with their own
  displacements and stresses, and the crack lines; PD and CCM-PD grid nodes with the FEM cells,
  the PD nodes and the broken bonds, displacements, damage, a PD-node flag and broken bonds per
  node; see ``rustfrac._vtk``);
- ``result.pvd`` + ``result_series/state_NNNN.vtu``: a ParaView time series, one state per
  kept critical state of an XFEM growth run (the whole plate with that state's crack, opening
  and stresses; ``xfem.state_every``) or per damage snapshot of an SLA run
  (``damage_at_steps``), timestep = the history row / the SLA step, the history row as field
  data.

:func:`load` reads the JSON and NPZ back to the same numbers, after checking them.
"""

from __future__ import annotations

import hashlib
import io
import json
import math
import re
import secrets
import zipfile
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any, Union

import numpy as np

from . import _core, _vtk
from ._folder import FolderWriter, locked, writing
from .errors import InvalidParameterError, InvalidResultError, ResultNotFoundError

__all__ = ["STATUSES", "Result", "load", "result_entry", "result_schema"]

PathLike = Union[str, Path]
JSON_NAME = "result.json"
NPZ_NAME = "fields.npz"
VTU_NAME = "result.vtu"
PVD_NAME = "result.pvd"
#: the time series' states, referenced by result.pvd
SERIES_DIR = "result_series"
SERIES_PATTERN = f"{SERIES_DIR}/state_*.vtu"
_HISTORY_PREFIX = "history__"
#: 2: result.json holds save_id, the arrays' shapes and the checksums of the other files
FORMAT_VERSION = 2
#: PNGs ``rustfrac run --plot`` writes into a result folder
PLOT_NAMES = ("s22.png", "u2.png", "damage.png", "tip_x50.png", "load_path.png")
#: every name a result folder's writer owns: replaced together, removed when a new save lacks them
OWNED_NAMES = (JSON_NAME, NPZ_NAME, VTU_NAME, PVD_NAME, SERIES_PATTERN, *PLOT_NAMES)


#: the core's table of every result entry and status (``_core.result_schema()``)
_SCHEMA: dict[str, Any] = _core.result_schema()
#: each method's statuses (``meta["status"]``): method -> {name: meaning}; FEM has none
STATUSES: dict[str, dict[str, str]] = {
    m: {s["name"]: s["doc"] for s in rows} for m, rows in _SCHEMA["statuses"].items()
}


def result_schema(method: str | None = None) -> list[dict[str, Any]]:
    """The table of result entries the core emits (``_core.result_schema()``), all or those of
    ``method``: dicts with methods, group ("headline" | "fields" | "history" | "scalars" |
    "meta"), name (``<region>`` / ``<name>`` stand for any region or probe name; ``table.key``
    a nested table's key), kind, shape (e.g. "(n_nodes, 2)"), nullable, unit ("length",
    "stress", "1", ...; "" for text, tables and indices), presence and doc."""
    return [dict(e) for e in _SCHEMA["entries"] if method is None or method in e["methods"]]


def _pattern(name: str) -> re.Pattern[str]:
    return re.compile(
        "".join(
            "[^:]+" if p.startswith("<") else re.escape(p)
            for p in re.split(r"(<[^>]*>)", name)
            if p
        )
        + r"\Z"
    )


_PATTERNS: dict[str, re.Pattern[str]] = {e["name"]: _pattern(e["name"]) for e in _SCHEMA["entries"]}


def result_entry(group: str, key: str, method: str | None = None) -> dict[str, Any] | None:
    """The schema entry of the result key ``key`` of ``group`` (of ``method``, or of the first
    method that has it), None when the table has none."""
    for e in _SCHEMA["entries"]:
        if e["group"] == group and (method is None or method in e["methods"]):
            if _PATTERNS[e["name"]].match(key):
                return dict(e)
    return None


@dataclass
class Result:
    """The outcome of :func:`rustfrac.run`. Every key of its groups is an entry of the core's
    result schema (:func:`result_schema`: kind, shape, unit, meaning; :attr:`schema`,
    :meth:`unit`), and ``meta["status"]`` one of :data:`STATUSES`.

    Attributes:
        method: "fem" | "xfem" | "pd" | "ccm_pd".
        sigma22: mean normal stress on the loaded top edge (reaction / width), stress units;
            with supports and loads on regions (``meta["bc"] == "regions"``) the mean normal
            stress on the first loaded edge region, or the force of a point load along its
            direction.
        cmod: crack-mouth opening displacement at x1 = 0 (0 when uncracked), length units.
        n_dofs: number of unknowns (displacement dofs, Dirichlet ones included).
        wall_time_s: wall time of the Rust run, in seconds.
        fields: numpy arrays: ``coords`` (n, 2), ``elements`` (m, 4), ``u`` (2n,) interleaved
            [u1, u2], ``reactions`` (2n,), ``nodal_stress`` (n, 3) [s11, s22, s12], ...
            XFEM: ``u_enriched`` (n_dofs,), ``heaviside_nodes``, ``tip_nodes``, ``crack`` (k, 2)
            (final polyline), ``crack_initial``, ``radii`` (r, 5) [radius, K_I, K_II, J_from_K,
            J_domain], ``radii_factor``, ``tips`` (t, 6) [x1, x2, K_I, K_II, J_from_K,
            J_domain] for every tip (see :attr:`tip_sifs`), ``tip_crack`` (t,), ``cracks``
            (P, 2) with ``cracks_offsets`` (final polylines of all cracks), growth runs
            ``tip_history_<x|y|K_I|K_II|kink_angle|r_I|grows>`` (s, t) (every tip at every
            history row), ``deformed_cells`` / ``deformed_disp`` (c, 4, 2) near the tip.
        history: growth / SLA runs: equal-length arrays ("load_factor", "sigma22", "cmod", "u0",
            ...; XFEM adds "traction", "a", "K_I", "K_II", "kink_angle", "tip_x", "tip_y",
            "r_I" (the SIF q-radius, shrunk where a hole would enter it), "condition", with the unloaded origin first); empty for a single linear solve.
        scalars: further scalars (energy, residual, K_I, K_II, J, gamma, condition, ...).
        meta: version, scene (as a dict), bc variant, anchor node, timings, warnings.
    """

    method: str
    sigma22: float
    cmod: float
    n_dofs: int
    wall_time_s: float
    fields: dict[str, np.ndarray] = field(default_factory=dict)
    history: dict[str, np.ndarray] = field(default_factory=dict)
    scalars: dict[str, Any] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        lengths = {k: len(v) for k, v in self.history.items()}
        if len(set(lengths.values())) > 1:
            raise ValueError(f"history arrays must have equal lengths, got {lengths}")

    # -- the schema ----------------------------------------------------------------------------

    @property
    def schema(self) -> dict[tuple[str, str], dict[str, Any]]:
        """This method's result entries (:func:`result_schema`) by (group, name)."""
        return {(e["group"], e["name"]): e for e in result_schema(self.method)}

    def unit(self, key: str, group: str = "history") -> str | None:
        """The unit of the result key ``key`` of ``group`` ("length", "stress", "1", ...; ""
        for text and indices), None when the schema has no such key."""
        e = result_entry(group, key, self.method)
        return None if e is None else str(e["unit"])

    @property
    def statuses(self) -> dict[str, str]:
        """The statuses this method's run may end with (``meta["status"]``): name -> meaning."""
        return dict(STATUSES.get(self.method, {}))

    # -- convenient views ---------------------------------------------------------------------

    @property
    def coords(self) -> np.ndarray:
        """Node coordinates, shape (n, 2)."""
        return self.fields["coords"]

    @property
    def elements(self) -> np.ndarray:
        """Q4 connectivity (counter-clockwise), shape (m, 4)."""
        return self.fields["elements"]

    @property
    def displacement(self) -> np.ndarray:
        """Nodal displacements, shape (n, 2) (a view of ``fields["u"]``)."""
        return self.fields["u"].reshape(-1, 2)

    @property
    def K_I(self) -> float | None:
        """Mode-I stress intensity factor at the reference load (XFEM), else None."""
        return self.scalars.get("K_I")

    @property
    def K_II(self) -> float | None:
        """Mode-II stress intensity factor at the reference load (XFEM), else None."""
        return self.scalars.get("K_II")

    @property
    def J(self) -> float | None:
        """J-integral at the reference load (XFEM), else None."""
        return self.scalars.get("J")

    @property
    def tip_sifs(self) -> list[dict[str, float]]:
        """XFEM: the SIFs of every crack tip at the reference load, one dict per tip with keys
        ``crack`` (index: 0 the primary crack, k the k-th further crack), ``x1``, ``x2``, ``K_I``,
        ``K_II``, ``J`` (from K) and ``J_domain``; tips are numbered crack by crack. Empty for
        other methods."""
        tips = self.fields.get("tips")
        if tips is None:
            return []
        crack = self.fields.get("tip_crack", np.zeros(len(tips), dtype=np.int64))
        keys = ("x1", "x2", "K_I", "K_II", "J", "J_domain")
        return [
            {"crack": int(c), **{k: float(v) for k, v in zip(keys, row)}}
            for c, row in zip(crack, tips)
        ]

    @property
    def crack_polylines(self) -> list[np.ndarray]:
        """XFEM: the final polyline (k, 2) of every crack (the primary crack first)."""
        pts, off = self.fields.get("cracks"), self.fields.get("cracks_offsets")
        if pts is None or off is None:
            return [self.fields["crack"]] if "crack" in self.fields else []
        return [pts[off[k] : off[k + 1]] for k in range(len(off) - 1)]

    @property
    def condition(self) -> float | None:
        """Dimensionless condition estimate of the (first) solve: the Hager-Higham 1-norm
        estimate of the Jacobi-scaled stiffness (FEM and XFEM); None for the PD methods and when
        not computed (``run(..., condition=False)``). Growth runs also have
        ``history["condition"]`` per step."""
        return self.scalars.get("condition")

    @property
    def warnings(self) -> list[str]:
        """Numerical and accuracy warnings of the run (messages, e.g. a condition estimate
        above 1e12); their kinds are :attr:`warning_kinds`."""
        return list(self.meta.get("warnings", []))

    @property
    def warning_kinds(self) -> list[str | None]:
        """Kind of each of :attr:`warnings` (``rustfrac._core.WARNING_KINDS``: "ill_conditioned",
        "locking", "discretisation"; the Python class is ``errors.WARNING_CLASSES[kind]``); None
        for results saved before kinds were recorded."""
        kinds = self.meta.get("warning_kinds")
        return list(kinds) if kinds is not None else [None] * len(self.warnings)

    @property
    def gamma(self) -> float | None:
        """PD stiffness correction factor (PD and CCM-PD), else None."""
        return self.scalars.get("gamma")

    @property
    def damage(self) -> np.ndarray | None:
        """Nodal damage index (PD and CCM-PD), else None."""
        return self.fields.get("damage")

    # -- responses of general scenes (supports, loads on regions, probes) ----------------------

    @property
    def regions(self) -> dict[str, dict[str, Any]]:
        """The responses of every region (``support[k]``, ``load[k]``): dicts with ``force``
        [F1, F2] (the reaction of a support, the applied resultant of a load; per thickness:
        force units), ``mean_stress`` (mean normal traction on an edge region, stress; None for
        point and box regions) and ``displacement`` [u1, u2] (mean, length), read from the
        scalars ``force:<name>:1|2``, ``mean_stress:<name>`` and ``displacement:<name>:1|2``.
        Empty without regions."""
        out: dict[str, dict[str, Any]] = {}
        for key in self.scalars:
            if key.startswith("force:") and key.endswith(":1"):
                name = key[len("force:") : -2]
                sc = self.scalars
                out[name] = {
                    "force": [sc[f"force:{name}:1"], sc[f"force:{name}:2"]],
                    "mean_stress": sc.get(f"mean_stress:{name}"),
                    "displacement": [
                        sc.get(f"displacement:{name}:1"),
                        sc.get(f"displacement:{name}:2"),
                    ],
                }
        return out

    def _region(self, name: str) -> dict[str, Any]:
        regions = self.regions
        if name not in regions:
            raise InvalidParameterError(
                f"invalid name: the result has no region {name!r}; valid: "
                f"{', '.join(regions) or 'none (the scene has no [[support]] or [[load]])'}",
                "name",
            )
        return regions[name]

    def reaction(self, name: str) -> tuple[float, float]:
        """(F1, F2) of the region ``name`` (``"support[0]"``, ``"load[1]"``) at the reference
        load: a support's reaction, a load's resultant (force units, per the scene's
        thickness). The forces of all regions sum to zero (equilibrium)."""
        f = self._region(name)["force"]
        return float(f[0]), float(f[1])

    def mean_stress(self, name: str) -> float | None:
        """The mean normal traction on the edge region ``name`` (stress units; tension
        positive), None for point and box regions."""
        v = self._region(name)["mean_stress"]
        return None if v is None else float(v)

    @property
    def probes(self) -> dict[str, tuple[float, float]]:
        """Every probe's value at the reference load: name -> (a, b), the displacement (u1, u2)
        or the crack opening (normal, sliding jump) at the probe (length units); the scalars
        ``probe:<name>:1|2``."""
        sc = self.scalars
        return {
            k[len("probe:") : -2]: (float(sc[k]), float(sc[k[:-1] + "2"]))
            for k in sc
            if k.startswith("probe:") and k.endswith(":1")
        }

    def probe(self, name: str) -> tuple[float, float]:
        """The value (a, b) of the probe ``name`` at the reference load (see :attr:`probes`)."""
        probes = self.probes
        if name not in probes:
            raise InvalidParameterError(
                f"invalid name: the result has no probe {name!r}; valid: "
                f"{', '.join(probes) or 'none (the scene has no [[probe]])'}",
                "name",
            )
        return probes[name]

    def probe_history(self, name: str) -> np.ndarray:
        """Growth runs (XFEM) and SLA runs (PD, CCM-PD; row 0 the unloaded origin): the probe
        ``name`` at every history row, shape (s, 2) (columns ``probe:<name>:1`` and
        ``probe:<name>:2`` of :attr:`history`)."""
        cols = [f"probe:{name}:{k}" for k in (1, 2)]
        if not all(c in self.history for c in cols):
            have = sorted({c.split(":")[1] for c in self.history if c.startswith("probe:")})
            raise InvalidParameterError(
                f"invalid name: the history has no probe {name!r}; probes in the history: "
                f"{', '.join(have) or 'none (growth and SLA runs have a history)'}",
                "name",
            )
        return np.column_stack([np.asarray(self.history[c], dtype=float) for c in cols])

    def summary(self) -> str:
        """A short human-readable summary."""
        s = (
            f"{self.method}: sigma22 = {self.sigma22:.6g}, CMOD = {self.cmod:.6g}, "
            f"{self.n_dofs} unknowns, {self.wall_time_s:.3g} s"
        )
        if self.K_I is not None:
            s += f", K_I = {self.K_I:.6g}, K_II = {self.K_II:.3g}"
        if self.condition is not None:
            s += f", condition {self.condition:.2g}"
        elif "condition" in self.scalars:
            s += ", condition not computed"
        if self.history:
            s += f", {len(next(iter(self.history.values())))} history points"
        if "bc" in self.meta:
            s += f", bc {self.meta['bc']}"
        if "sla_steps_done" in self.meta:
            s += f", SLA {self.meta.get('status')} after {self.meta['sla_steps_done']} steps"
        elif "status" in self.meta:
            s += f", status {self.meta['status']}"
        if self.meta.get("anchor_node") is not None:
            s += f" (u1 anchor at node {self.meta['anchor_node']})"
        for name, r in self.regions.items():
            f = r["force"]
            s += f"\n  {name}: force ({f[0]:.6g}, {f[1]:.6g})"
            if r.get("mean_stress") is not None:
                s += f", mean stress {r['mean_stress']:.6g}"
        for name, (a, b) in self.probes.items():
            s += f"\n  probe {name}: ({a:.6g}, {b:.6g})"
        return s

    def __repr__(self) -> str:
        return f"<Result {self.summary().splitlines()[0]}>"

    def _repr_html_(self) -> str:
        """Jupyter's view: a table of the scalars, status, history columns and fields."""
        from ._html import result_html

        return result_html(self)

    def history_frame(self) -> Any:
        """``history`` as a pandas DataFrame, one column per history array (empty for a single
        solve). Needs pandas (``pip install pandas``); without it raises ImportError saying so."""
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError(
                "Result.history_frame() needs pandas, which is not installed: pip install pandas "
                "(or read Result.history, a dict of numpy arrays)"
            ) from e
        return pd.DataFrame({k: np.asarray(v) for k, v in self.history.items()})

    # -- meshes -------------------------------------------------------------------------------

    def to_meshio(self) -> Any:
        """This result as a ``meshio.Mesh``, what ``result.vtu`` holds, one cell block per cell
        type (so that meshio writes it as XDMF, Gmsh, MED, ...): FEM the Q4 mesh with point data
        ``displacement`` and cell data ``stress`` (element means of the Gauss-point stresses) and
        ``element_id``; XFEM the whole plate at the last state (a growth run's last kept
        critical state, else the single solve): the standard elements, the cut cells of the
        enriched ones (``quad`` and ``triangle`` cells on points of their own on each side of
        the crack, with that side's displacement and stress) and the crack lines, cell data
        ``element_id``, ``kind``, ``cut_cell``, ``crack``, ``stress``; PD and CCM-PD the grid
        nodes with the FEM cells, the PD nodes as vertices and the broken bonds as lines, point
        data ``displacement``, ``displacement_final``, ``damage``, ``is_pd`` and
        ``broken_bonds``. Vectors have 3 components (z = 0). Details and the time series:
        ``rustfrac._vtk``.

        Raises:
            ImportError: meshio is not installed (``pip install 'rustfrac[io]'``).
            PlotDataError: the result has neither a mesh nor a grid.
        """
        return _vtk.to_meshio(self)

    def to_pyvista(self) -> Any:
        """This result as a ``pyvista.UnstructuredGrid`` (from :meth:`to_meshio`).

        Raises:
            ImportError: pyvista (or meshio) is not installed (``pip install 'rustfrac[viz]'``).
        """
        try:
            import pyvista as pv
        except ImportError as e:
            raise ImportError(
                "Result.to_pyvista() needs pyvista, which is not installed: pip install "
                "'rustfrac[viz]' (or pip install pyvista meshio; or use Result.to_meshio() / the "
                "saved result.vtu)"
            ) from e
        return pv.from_meshio(self.to_meshio())

    # -- files --------------------------------------------------------------------------------

    def save(self, directory: PathLike, *, vtu: bool = True) -> Path:
        """Writes result.json, fields.npz and (``vtu=True``) result.vtu, and for growth and SLA
        snapshot runs the ParaView time series result.pvd + result_series/, into
        ``directory`` (created if needed) as one unit: a reader sees the previous set or the new
        one, never a mix (see the README's "Result folders"). Returns the directory.

        Raises:
            OutputError: the folder cannot be written (it is a file, read-only, the disk is
                full, ...); the folder is left as it was.
        """
        return save_result(self, directory, vtu=vtu)

    def _stage(self, w: FolderWriter, *, vtu: bool, save_id: str | None = None) -> str:
        """Stages this result's files into the pending folder ``w`` (the JSON last, with the
        save id and the checksums of the others); returns the save id."""
        doc: dict[str, Any] = {
            "format": "rustfrac-result",
            "format_version": FORMAT_VERSION,
            "save_id": save_id or secrets.token_hex(8),
            "method": self.method,
            "sigma22": self.sigma22,
            "cmod": self.cmod,
            "n_dofs": self.n_dofs,
            "wall_time_s": self.wall_time_s,
            "scalars": self.scalars,
            "meta": self.meta,
            "fields": sorted(self.fields),
            "history": sorted(self.history),
        }
        json.dumps(_jsonable(doc), allow_nan=False)  # fails before anything is written
        arrays = dict(self.fields)
        arrays.update({_HISTORY_PREFIX + k: v for k, v in self.history.items()})
        doc["shapes"] = {k: list(np.shape(v)) for k, v in sorted(arrays.items())}
        files = {NPZ_NAME: w.stage(NPZ_NAME)}
        with open(files[NPZ_NAME], "wb") as f:
            _savez(f, arrays)
        if vtu and _has_mesh(self):
            files[VTU_NAME] = w.stage(VTU_NAME)
            write_vtu(files[VTU_NAME], self)
            files.update(_stage_series(w, self))
        doc["files"] = {
            n: {"sha256": _sha256(p), "bytes": p.stat().st_size} for n, p in files.items()
        }
        w.stage(JSON_NAME).write_text(_dumps(_jsonable(doc)), encoding="utf-8")
        return str(doc["save_id"])


def save_result(
    res: Result, directory: PathLike, *, vtu: bool = True, save_id: str | None = None
) -> Path:
    """:meth:`Result.save` with a given save id (the package's jobs name their parts' saves in
    their summaries); not part of the user API."""
    with writing(directory, owned=OWNED_NAMES, last=JSON_NAME) as w:
        stage_result(res, w, vtu=vtu, save_id=save_id)
    return w.path


def stage_result(res: Result, w: FolderWriter, *, vtu: bool, save_id: str | None = None) -> str:
    """Stages ``res``'s files into the pending folder ``w`` (a job writing a result folder
    beside its own files, ``rustfrac run --plot``); returns the save id. Not part of the user
    API."""
    return res._stage(w, vtu=vtu, save_id=save_id)


def load(directory: PathLike) -> Result:
    """Reads a result saved by :meth:`Result.save`, checking it: its format and version, the
    method, finite numbers, the arrays against ``result.json`` (names, shapes, checksums: a folder
    holding files of two saves is refused) and the shapes of the mesh and grid arrays.

    Raises:
        ResultNotFoundError: the folder or one of its files does not exist.
        InvalidResultError: anything else wrong (the message names the file and the field).
    """
    d = Path(directory)
    jpath, npath = d / JSON_NAME, d / NPZ_NAME
    if not d.is_dir():
        raise ResultNotFoundError(f"no result folder {d}", d)
    try:
        with locked(d, exclusive=False):  # no writer renames files while both are read
            jbytes = jpath.read_bytes()
            nbytes = npath.read_bytes()
    except FileNotFoundError as e:
        raise ResultNotFoundError(
            f"{e.filename}: no such file (not a result folder, or its save did not finish)",
            e.filename,
        ) from e
    except OSError as e:
        raise InvalidResultError(f"cannot read result {d}: {e.strerror or e}", d) from e
    doc = read_json(jpath, jbytes)
    version = _check_doc(jpath, doc)
    if version >= 2:
        _check_checksums(jpath, doc, NPZ_NAME, nbytes)
    arrays = _read_npz(npath, nbytes)
    fields = {k: v for k, v in arrays.items() if not k.startswith(_HISTORY_PREFIX)}
    history = {
        k[len(_HISTORY_PREFIX) :]: v for k, v in arrays.items() if k.startswith(_HISTORY_PREFIX)
    }
    for key, names in (("fields", fields), ("history", history)):
        listed = set(doc[key])
        if listed != set(names):
            raise InvalidResultError(
                f"{npath} does not match {jpath}: {key} "
                + ", ".join(
                    f"{what} {', '.join(sorted(x))}"
                    for what, x in (
                        ("missing", listed - set(names)),
                        ("not listed", set(names) - listed),
                    )
                    if x
                ),
                npath,
                key,
            )
    if version >= 2:
        for k, v in arrays.items():
            if list(v.shape) != doc["shapes"].get(k):
                raise InvalidResultError(
                    f"{npath}: array {k} has shape {list(v.shape)}, {jpath} says "
                    f"{doc['shapes'].get(k)}",
                    npath,
                    k,
                )
    _check_arrays(npath, fields, history)
    return Result(
        method=doc["method"],
        sigma22=_float(doc["sigma22"]),
        cmod=_float(doc["cmod"]),
        n_dofs=doc["n_dofs"],
        wall_time_s=_float(doc["wall_time_s"]),
        fields=fields,
        history=history,
        scalars={
            k: v if v is None and k in _OPTIONAL_SCALARS else _float(v) if v is None else v
            for k, v in doc["scalars"].items()
        },
        meta=doc["meta"],
    )


# ----------------------------------------------------------------------------------------------
# helpers


#: scalars whose None means "not computed" (``run(..., condition=False)``), not a NaN saved as
#: null: the schema's nullable scalars (never NaN: a non-finite condition estimate is an error)
_OPTIONAL_SCALARS = tuple(
    sorted({e["name"] for e in result_schema() if e["group"] == "scalars" and e["nullable"]})
)


def _float(v: Any) -> float:
    return math.nan if v is None else float(v)


def _jsonable(v: Any) -> Any:
    """numpy scalars/arrays to Python; non-finite floats to None (strict JSON)."""
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, np.ndarray):
        return _jsonable(v.tolist())
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def _dumps(doc: Any) -> str:
    """JSON indented by 2, but each list of plain values on one line (a long list in the scene
    then costs its length, not an indented line per item)."""
    token, lists = secrets.token_hex(8), []

    def fold(v: Any) -> Any:
        if isinstance(v, dict):
            return {k: fold(x) for k, x in v.items()}
        if isinstance(v, list):
            if v and all(x is None or isinstance(x, (bool, int, float, str)) for x in v):
                lists.append(json.dumps(v, allow_nan=False))
                return f"{token}:{len(lists) - 1}"
            return [fold(x) for x in v]
        return v

    text = json.dumps(fold(doc), indent=2, allow_nan=False)
    return re.sub(f'"{token}:(\\d+)"', lambda m: lists[int(m.group(1))], text) + "\n"


#: zlib level of fields.npz: 1, the fastest (float arrays compress little more at numpy's 6:
#: +2 % bytes for half the time of a fig7 job's two result folders)
NPZ_LEVEL = 1


def _savez(f: IO[bytes], arrays: dict[str, Any]) -> None:
    """``np.savez_compressed(f, **arrays)`` at zlib level :data:`NPZ_LEVEL` (numpy's own writer,
    ``numpy.lib.format.write_array`` into a deflated zip member per array, zip64 forced as numpy
    does; ``np.load`` reads it as any ``.npz``)."""
    with zipfile.ZipFile(f, "w", zipfile.ZIP_DEFLATED, compresslevel=NPZ_LEVEL) as z:
        for key, val in arrays.items():
            with z.open(key + ".npy", "w", force_zip64=True) as member:
                np.lib.format.write_array(member, np.asanyarray(val), allow_pickle=False)


def _sha256(p: Path) -> str:
    h = hashlib.sha256()
    with open(p, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def read_json(path: Path, data: bytes) -> dict[str, Any]:
    """Strict JSON of a result / summary file: a dict, no NaN or infinite numbers (the writers
    store a non-finite float as null)."""

    def bad_number(s: str) -> float:
        v = float(s)
        if not math.isfinite(v):
            raise InvalidResultError(f"{path}: the number {s[:40]} is not finite", path)
        return v

    def no_constant(s: str) -> Any:
        raise InvalidResultError(f"{path}: {s} is not allowed (non-finite numbers are null)", path)

    try:
        doc = json.loads(data.decode("utf-8"), parse_float=bad_number, parse_constant=no_constant)
    except UnicodeDecodeError as e:
        raise InvalidResultError(f"{path}: not UTF-8 text ({e.reason})", path) from e
    except json.JSONDecodeError as e:
        raise InvalidResultError(
            f"{path}: not valid JSON ({e.msg}, line {e.lineno} column {e.colno})", path
        ) from e
    except RecursionError as e:
        raise InvalidResultError(f"{path}: nested too deeply to be a rustfrac file", path) from e
    if not isinstance(doc, dict):
        raise InvalidResultError(f"{path}: expected a JSON object, got {type(doc).__name__}", path)
    return doc


def _bad(path: Path, key: str, expected: str, got: Any) -> InvalidResultError:
    r = repr(got)
    r = r if len(r) <= 80 else r[:77] + "..."
    return InvalidResultError(
        f"invalid {key} in {path}: expected {expected}, got {r}",
        path,
        key,
    )


def _check_doc(path: Path, doc: dict[str, Any]) -> int:
    """Checks the keys of a result.json; returns its format version."""
    from .scene import METHODS

    if doc.get("format") != "rustfrac-result":
        raise _bad(
            path, "format", "'rustfrac-result' (not a rustfrac result file)", doc.get("format")
        )
    v: Any = doc.get("format_version")
    if type(v) is not int or not 1 <= v <= FORMAT_VERSION:
        raise _bad(path, "format_version", f"1 to {FORMAT_VERSION} (this rustfrac's)", v)
    if doc.get("method") not in METHODS:
        raise _bad(path, "method", f"one of {', '.join(METHODS)}", doc.get("method"))
    for key in ("sigma22", "cmod"):  # null: a NaN the run produced
        if doc.get(key) is not None and (type(doc.get(key)) not in (int, float)):
            raise _bad(path, key, "a number or null", doc.get(key))
    n: Any = doc.get("n_dofs")
    if type(n) is not int or n < 0:
        raise _bad(path, "n_dofs", "an integer >= 0", n)
    t: Any = doc.get("wall_time_s")
    if type(t) not in (int, float) or t < 0:
        raise _bad(path, "wall_time_s", "a finite number >= 0", t)
    for key in ("scalars", "meta"):
        if not isinstance(doc.setdefault(key, {}), dict):
            raise _bad(path, key, "an object", doc[key])
    for key in ("fields", "history"):
        names = doc.get(key)
        if not isinstance(names, list) or not all(isinstance(x, str) for x in names):
            raise _bad(path, key, "a list of array names", names)
    if v >= 2:
        if not isinstance(doc.get("save_id"), str):
            raise _bad(path, "save_id", "a string", doc.get("save_id"))
        shapes = doc.get("shapes")
        if not isinstance(shapes, dict) or not all(
            isinstance(s, list) and all(type(x) is int and x >= 0 for x in s)
            for s in shapes.values()
        ):
            raise _bad(path, "shapes", "an object of array shapes", shapes)
        files = doc.get("files")
        if (
            not isinstance(files, dict)
            or NPZ_NAME not in files
            or not all(
                isinstance(f, dict) and isinstance(f.get("sha256"), str) for f in files.values()
            )
        ):
            raise _bad(path, "files", f"an object of checksums naming {NPZ_NAME}", files)
    return v


def _check_checksums(jpath: Path, doc: dict[str, Any], name: str, data: bytes) -> None:
    """The file ``name`` must be the one ``result.json`` was written with: a folder holding files
    of two saves is refused. (Checking fields.npz suffices: a writer renames it first and the
    JSON last, so any interrupted commit leaves it unlike the JSON's checksum.)"""
    if hashlib.sha256(data).hexdigest() != doc["files"][name]["sha256"]:
        raise InvalidResultError(
            f"{jpath.parent / name} does not belong to {jpath} (save {doc['save_id']}): its "
            "checksum differs, the folder holds files of two saves (an interrupted or concurrent "
            "save?)",
            jpath.parent / name,
            "files",
        )


def _read_npz(path: Path, data: bytes) -> dict[str, np.ndarray]:
    out: dict[str, np.ndarray] = {}
    key = None
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as z:
            for key in z.files:
                out[key] = z[key]
    except (ValueError, OSError, EOFError, zipfile.BadZipFile, zlib.error) as e:
        where = f" (array {key})" if key else ""
        raise InvalidResultError(
            f"{path}: not a readable NumPy .npz archive{where}: {e}", path, key
        ) from e
    return out


def _check_arrays(
    path: Path, fields: dict[str, np.ndarray], history: dict[str, np.ndarray]
) -> None:
    """The shapes the Result's views rely on: coords (n, 2) finite with elements (m, 4) indexing
    them and u of length 2n; node_xy (n, 2) finite with u, u_final of length 2n (u_final: or 0),
    pd_nodes indexing it and damage one per PD node; history columns 1-D of one length."""

    def need(ok: bool, key: str, expected: str, a: np.ndarray) -> None:
        if not ok:
            raise InvalidResultError(
                f"{path}: array {key} must be {expected}, got shape {list(a.shape)} "
                f"dtype {a.dtype}",
                path,
                key,
            )

    for pts in ("coords", "node_xy"):
        if pts not in fields:
            continue
        xy = fields[pts]
        need(
            xy.ndim == 2 and xy.shape[1:] == (2,) and xy.dtype.kind == "f", pts, "(n, 2) floats", xy
        )
        need(bool(np.isfinite(xy).all()), pts, "finite", xy)
        n = len(xy)
        for key in ("u", "u_final"):  # u_final is empty when the body separated
            if key in fields:
                u = fields[key]
                sizes = ((2 * n,), (0,)) if key == "u_final" else ((2 * n,),)
                need(u.shape in sizes and u.dtype.kind == "f", key, f"({2 * n},) floats", u)
        idx = {"coords": ("elements",), "node_xy": ("pd_nodes",)}[pts]
        for key in idx:
            if key in fields:
                a = fields[key]
                shape_ok = a.ndim == 2 and a.shape[1] == 4 if key == "elements" else a.ndim == 1
                need(
                    shape_ok and a.dtype.kind in "iu", key, "integer indices of the right shape", a
                )
                need(
                    a.size == 0 or (int(a.min()) >= 0 and int(a.max()) < n),
                    key,
                    f"indices in [0, {n})",
                    a,
                )
    if "damage" in fields and "pd_nodes" in fields:
        dmg = fields["damage"]
        need(dmg.shape == fields["pd_nodes"].shape, "damage", "one value per PD node", dmg)
    lengths = set()
    for k, a in history.items():
        need(a.ndim == 1, "history__" + k, "1-D", a)
        lengths.add(len(a))
    if len(lengths) > 1:
        raise InvalidResultError(
            f"{path}: history arrays must have equal lengths, got "
            f"{ {k: len(a) for k, a in history.items()} }",
            path,
            "history",
        )


def _has_mesh(res: Result) -> bool:
    return ("coords" in res.fields and "elements" in res.fields) or "node_xy" in res.fields


def write_vtu(path: Path, res: Result) -> None:
    """Writes ``res`` as ``result.vtu`` to ``path``: the mesh of :meth:`Result.to_meshio` as a
    binary, zlib-compressed VTU (``_vtk.write_vtu``; meshio is not needed)."""
    _vtk.write_vtu(path, _vtk.mesh_parts(res))


def _stage_series(w: FolderWriter, res: Result) -> dict[str, Path]:
    """Stages the time series of ``res`` (result.pvd and one VTU per state); returns the staged
    files by name (none when the result has no series)."""
    states = _vtk.series_parts(res)
    if not states:
        return {}
    files: dict[str, Path] = {}
    datasets: list[tuple[float, str]] = []
    for k, (t, parts) in enumerate(states):
        name = f"{SERIES_DIR}/state_{k:04d}.vtu"
        files[name] = w.stage(name)
        _vtk.write_vtu(files[name], parts)
        datasets.append((t, name))
    files[PVD_NAME] = w.stage(PVD_NAME)
    with open(files[PVD_NAME], "w", encoding="utf-8") as f:
        _vtk.write_pvd(f, datasets)
    return files
