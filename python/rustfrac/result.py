"""Results of a run: scalars, numpy fields, history, metadata; saving and loading.

``Result.save(dir)`` writes, each atomically (a temporary file in ``dir``, then ``os.replace``):

- ``result.json`` (written last): scalars and metadata (version, scene, boundary-condition variant, anchor node,
  timings) -- plain JSON, floats written with full precision;
- ``fields.npz``: the arrays (mesh, displacement, stresses, ...) and the history;
- ``result.vtu``: the deformed-state mesh for ParaView (ASCII VTK unstructured grid of quads with
  displacement and stress as point data). PD and CCM-PD results (no Q4 mesh) write the grid nodes as
  VTK_VERTEX cells instead, with the displacements before the first and after the last break, the
  damage (0 at FEM nodes) and a PD-node flag as point data (:func:`write_vtu_points`).

:func:`load` reads the JSON and NPZ back to the same numbers.
"""

from __future__ import annotations

import json
import math
import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any, Union

import numpy as np

__all__ = ["Result", "load"]

PathLike = Union[str, Path]
JSON_NAME = "result.json"
NPZ_NAME = "fields.npz"
VTU_NAME = "result.vtu"
_HISTORY_PREFIX = "history__"


@dataclass
class Result:
    """The outcome of :func:`rustfrac.run`.

    Attributes:
        method: "fem" | "xfem" | "pd" | "ccm_pd".
        sigma22: mean normal stress on the loaded top edge (reaction / width), stress units.
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
            ``tip_history_<x|y|K_I|K_II|kink_angle|grows>`` (s, t) (every tip at every history
            row), ``deformed_cells`` / ``deformed_disp`` (c, 4, 2) near the tip.
        history: growth / SLA runs: equal-length arrays ("load_factor", "sigma22", "cmod", "u0",
            ...; XFEM adds "traction", "a", "K_I", "K_II", "kink_angle", "tip_x", "tip_y",
            "condition", with the unloaded origin first); empty for a single linear solve.
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
        return s

    def __repr__(self) -> str:
        return f"<Result {self.summary()}>"

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

    # -- files --------------------------------------------------------------------------------

    def save(self, directory: PathLike, *, vtu: bool = True) -> Path:
        """Writes result.json, fields.npz and (``vtu=True``) result.vtu into ``directory``
        (created if needed), each atomically. Returns the directory."""
        d = Path(directory)
        d.mkdir(parents=True, exist_ok=True)
        doc = {
            "format": "rustfrac-result",
            "format_version": 1,
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
        text = json.dumps(_jsonable(doc), indent=2, allow_nan=False) + "\n"  # fails before writing
        arrays = dict(self.fields)
        arrays.update({_HISTORY_PREFIX + k: v for k, v in self.history.items()})
        with _atomic(d / NPZ_NAME, "wb") as f:
            np.savez_compressed(f, **arrays)
        if vtu and "coords" in self.fields and "elements" in self.fields:
            with _atomic(d / VTU_NAME, "w") as f:
                write_vtu(f, self)
        elif vtu and "node_xy" in self.fields:
            with _atomic(d / VTU_NAME, "w") as f:
                write_vtu_points(f, self)
        # the JSON goes last: it names the fields, so a reader never sees it before them
        with _atomic(d / JSON_NAME, "w") as f:
            f.write(text)
        return d


def load(directory: PathLike) -> Result:
    """Reads a result saved by :meth:`Result.save`."""
    d = Path(directory)
    doc = json.loads((d / JSON_NAME).read_text(encoding="utf-8"))
    if doc.get("format") != "rustfrac-result":
        raise ValueError(f"{d / JSON_NAME} is not a rustfrac result file")
    fields: dict[str, np.ndarray] = {}
    history: dict[str, np.ndarray] = {}
    with np.load(d / NPZ_NAME, allow_pickle=False) as z:
        for k in z.files:
            if k.startswith(_HISTORY_PREFIX):
                history[k[len(_HISTORY_PREFIX) :]] = z[k]
            else:
                fields[k] = z[k]
    return Result(
        method=doc["method"],
        sigma22=_float(doc["sigma22"]),
        cmod=_float(doc["cmod"]),
        n_dofs=int(doc["n_dofs"]),
        wall_time_s=_float(doc["wall_time_s"]),
        fields=fields,
        history=history,
        scalars={
            k: v if v is None and k in _OPTIONAL_SCALARS else _float(v) if v is None else v
            for k, v in doc.get("scalars", {}).items()
        },
        meta=doc.get("meta", {}),
    )


# ----------------------------------------------------------------------------------------------
# helpers


#: scalars whose None means "not computed" (``run(..., condition=False)``), not a NaN saved as
#: null: they are never NaN (a non-finite condition estimate is an error)
_OPTIONAL_SCALARS = ("condition", "condition_pivot_ratio")


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


@contextmanager
def _atomic(path: Path, mode: str) -> Iterator[IO[Any]]:
    """Writes to a temporary file next to ``path`` and renames it over ``path`` on success."""
    # like mkstemp, but the file gets the usual permissions (0666 minus the umask), not 0600
    tmp = path.parent / f".{path.name}.{os.getpid()}.{secrets.token_hex(6)}.tmp"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, mode, **({} if "b" in mode else {"encoding": "utf-8"})) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


def _vtk_array(f: IO[str], name: str, a: np.ndarray, vtype: str = "Float64") -> None:
    a = np.asarray(a)
    ncomp = 1 if a.ndim == 1 else a.shape[1]
    f.write(
        f'        <DataArray type="{vtype}" Name="{name}" NumberOfComponents="{ncomp}" '
        'format="ascii">\n'
    )
    fmt = "%.17g" if vtype.startswith("Float") else "%d"
    np.savetxt(f, a.reshape(len(a), -1), fmt=fmt, delimiter=" ")
    f.write("        </DataArray>\n")


def write_vtu(f: IO[str], res: Result) -> None:
    """Writes ``res`` as an ASCII VTK XML unstructured grid of quads (VTK cell type 9) with the
    point fields displacement (3 components, u3 = 0), stress [s11, s22, s12] and any other
    array with one row per node."""
    xy = np.asarray(res.coords, dtype=float)
    n = len(xy)
    cells = np.asarray(res.elements, dtype=np.int64)
    m = len(cells)
    pts = np.column_stack([xy, np.zeros(n)])
    f.write('<?xml version="1.0"?>\n')
    f.write('<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">\n')
    f.write("  <UnstructuredGrid>\n")
    f.write(f'    <Piece NumberOfPoints="{n}" NumberOfCells="{m}">\n')
    f.write("      <PointData>\n")
    if "u" in res.fields and len(res.fields["u"]) == 2 * n:
        _vtk_array(f, "displacement", np.column_stack([res.displacement, np.zeros(n)]))
    if "nodal_stress" in res.fields:
        _vtk_array(f, "stress", res.fields["nodal_stress"])
    for k, a in res.fields.items():
        if k in ("coords", "u", "nodal_stress", "reactions") or np.asarray(a).dtype.kind != "f":
            continue
        if len(a) == n and np.asarray(a).ndim <= 2:
            _vtk_array(f, k, a)
    f.write("      </PointData>\n")
    f.write("      <Points>\n")
    _vtk_array(f, "Points", pts)
    f.write("      </Points>\n")
    f.write("      <Cells>\n")
    _vtk_array(f, "connectivity", cells.reshape(-1), "Int64")
    _vtk_array(f, "offsets", 4 * np.arange(1, m + 1, dtype=np.int64), "Int64")
    _vtk_array(f, "types", np.full(m, 9, dtype=np.uint8), "UInt8")
    f.write("      </Cells>\n")
    f.write("    </Piece>\n")
    f.write("  </UnstructuredGrid>\n")
    f.write("</VTKFile>\n")


def write_vtu_points(f: IO[str], res: Result) -> None:
    """Writes a PD / CCM-PD result (fields ``node_xy``, ``u``, ``u_final``, ``pd_nodes``,
    ``damage``) as an ASCII VTK XML unstructured grid of VTK_VERTEX cells (type 1), one per grid
    node, with point data displacement (reference load, before any break), displacement_final
    (after the last break; absent when the body separated), damage (0 at FEM nodes) and is_pd."""
    xy = np.asarray(res.fields["node_xy"], dtype=float)
    n = len(xy)
    pts = np.column_stack([xy, np.zeros(n)])
    f.write('<?xml version="1.0"?>\n')
    f.write('<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">\n')
    f.write("  <UnstructuredGrid>\n")
    f.write(f'    <Piece NumberOfPoints="{n}" NumberOfCells="{n}">\n')
    f.write("      <PointData>\n")
    for key, name in (("u", "displacement"), ("u_final", "displacement_final")):
        u = np.asarray(res.fields.get(key, ()), dtype=float)
        if len(u) == 2 * n:
            _vtk_array(f, name, np.column_stack([u.reshape(-1, 2), np.zeros(n)]))
    pd_nodes = np.asarray(res.fields.get("pd_nodes", ()), dtype=np.int64)
    damage = np.zeros(n)
    if "damage" in res.fields and len(res.fields["damage"]) == len(pd_nodes):
        damage[pd_nodes] = res.fields["damage"]
    is_pd = np.zeros(n, dtype=np.int64)
    is_pd[pd_nodes] = 1
    _vtk_array(f, "damage", damage)
    _vtk_array(f, "is_pd", is_pd, "Int64")
    f.write("      </PointData>\n")
    f.write("      <Points>\n")
    _vtk_array(f, "Points", pts)
    f.write("      </Points>\n")
    f.write("      <Cells>\n")
    _vtk_array(f, "connectivity", np.arange(n, dtype=np.int64), "Int64")
    _vtk_array(f, "offsets", np.arange(1, n + 1, dtype=np.int64), "Int64")
    _vtk_array(f, "types", np.ones(n, dtype=np.uint8), "UInt8")
    f.write("      </Cells>\n")
    f.write("    </Piece>\n")
    f.write("  </UnstructuredGrid>\n")
    f.write("</VTKFile>\n")
