"""Results as meshio meshes and ParaView files (:meth:`Result.to_meshio`, ``result.vtu``,
``result.pvd``); meshio is optional (``pip install 'rustfrac[io]'``). The VTU files are written
by :func:`write_vtu` (the VTK XML format meshio writes, without its XML tree: 2.5x faster, and
meshio is needed only for :func:`to_meshio` and :func:`series`).

What a mesh holds (every vector has 3 components, z = 0, as ParaView expects). Cells come in one
block per cell type (``quad``, ``triangle``, ``line``, ``vertex``), so that every meshio format
(XDMF for FEniCSx, MED, Gmsh) can write them:

- FEM: the Q4 mesh as ``quad`` cells; point data ``displacement`` (u), ``nodal_stress``
  [s11, s22, s12] and ``reaction``; cell data ``stress`` (the mean of the element's Gauss-point
  stresses) and ``element_id``.
- XFEM (one state: the single solve at the reference load, or a growth run's critical state,
  see below): the standard (non-enriched) elements as ``quad`` cells on the mesh nodes; every
  element with an enriched node replaced by its cut cells (the element's sub-polygons on each
  side of the crack), with points of their own appended after the mesh nodes and the enriched
  displacement of their own side, so both crack faces exist and the opening shows as a gap; a
  cut polygon of 4 vertices is a ``quad``, one of 3 a ``triangle``, a larger one (convex) a fan
  of triangles. Then every crack polyline as ``line`` cells on points of its own, whose
  displacement is zero (the line marks the crack in the reference configuration: Warp By Vector
  leaves it where the crack was cut). Cell data: ``element_id`` (the parent element; -1 for crack
  lines), ``kind`` (0 standard element, 1 cut cell, 2 crack line), ``cut_cell`` (the cut polygon
  a cell comes from, -1 otherwise), ``crack`` (the crack index of a line, -1 for elements),
  ``stress`` (standard elements: the mean of their Gauss-point stresses; a cut cell: the enriched
  stress of its own side at its polygon's centroid; crack lines 0) and ``enrichment`` (the
  largest enrichment of the parent element's nodes for that state's cracks: 0 none, 1
  Heaviside, 2 tip; -1 for crack lines).
- PD / CCM-PD: the grid nodes; ``quad`` cells of the FEM part (the grid cells with a FEM
  corner: CCM-PD only), the PD nodes as ``vertex`` cells and every broken bond as a ``line``
  cell between its end nodes. Point data ``displacement`` (reference load, before any break),
  ``displacement_final`` (after the last break; absent when the body separated), ``damage`` (0
  at FEM nodes), ``is_pd`` and ``broken_bonds`` (the number of broken bonds at each node: their
  sum is twice the number of broken bonds); cell data ``kind`` (3 FEM cell, 4 PD node, 5 broken
  bond) and ``bond`` (the bond of a line, -1 otherwise).

``result.vtu`` is the result's last state: a growth run's last kept critical state (its cracks,
cut cells, displacement and stresses at its critical load), else the single solve with the
initial cracks; an SLA run after its last step.

Time series (:func:`series`, ``result.pvd``, timestep = the history row or the SLA step):

- XFEM growth: one state per kept critical state (``xfem.state_every``, the fields
  ``state_*``), each the whole plate as above with that state's cracks, cut cells, displacement
  and stresses; first the unloaded origin (row 0: the first state's mesh, displacement and stress
  zero). Field data: that row of every history column (``a``, ``load_factor``, ``K_I``,
  ``K_II``, ...) and ``row``.
- SLA runs with damage snapshots (``damage_at_steps``): one state per snapshot, the grid as
  above with the bonds broken by that step (the pre-crack's and each step's critical bond),
  ``damage`` and ``is_pd``; field data: that step's history row.
"""

from __future__ import annotations

import base64
import sys
import zlib
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import IO, Any, Protocol

import numpy as np

from .errors import PlotDataError


class Result(Protocol):
    """What the writers read of a :class:`rustfrac.Result` (structural, so that this module,
    which ``result.py`` imports, does not import it back)."""

    method: str
    fields: dict[str, Any]
    history: dict[str, Any]
    meta: dict[str, Any]

    @property
    def crack_polylines(self) -> list[np.ndarray]: ...


#: ``kind`` cell data
STANDARD, CUT, CRACK, FEM_CELL, PD_NODE, BROKEN_BOND = 0, 1, 2, 3, 4, 5


def meshio_or_none() -> ModuleType | None:
    """The meshio module, or None when it is not installed."""
    try:
        import meshio
    except ImportError:
        return None
    return meshio


def require_meshio(what: str) -> ModuleType:
    """The meshio module; without it an ImportError naming the package and the extra."""
    meshio = meshio_or_none()
    if meshio is None:
        raise ImportError(
            f"{what} needs meshio, which is not installed: pip install 'rustfrac[io]' "
            "(or pip install meshio)"
        )
    return meshio


def _vec3(a: np.ndarray) -> np.ndarray:
    """(n, 2) or interleaved (2n,) -> (n, 3) with z = 0."""
    a = np.asarray(a, dtype=float).reshape(-1, 2)
    return np.column_stack([a, np.zeros(len(a))])


def element_stress(res: Result) -> np.ndarray | None:
    """The mean of every element's Gauss-point stresses (m, 3) [s11, s22, s12], or None when the
    result has none (``gauss_stress`` holds the element's points one after the other)."""
    gs, els = res.fields.get("gauss_stress"), res.fields.get("elements")
    if gs is None or els is None or len(els) == 0 or len(gs) % len(els):
        return None
    return np.asarray(gs, dtype=float).reshape(len(els), -1, gs.shape[-1]).mean(axis=1)


def pd_point_fields(res: Result) -> dict[str, np.ndarray]:
    """PD / CCM-PD point data on the grid nodes: ``damage`` (0 at FEM nodes), ``is_pd`` and
    ``broken_bonds`` (broken bonds per node, from ``broken`` and ``bond_nodes``)."""
    f = res.fields
    n = len(f["node_xy"])
    pd_nodes = np.asarray(f.get("pd_nodes", ()), dtype=np.int64)
    damage = np.zeros(n)
    if "damage" in f and len(f["damage"]) == len(pd_nodes):
        damage[pd_nodes] = f["damage"]
    is_pd = np.zeros(n, dtype=np.int64)
    is_pd[pd_nodes] = 1
    out = {"damage": damage, "is_pd": is_pd}
    if "broken" in f and "bond_nodes" in f:
        ends = np.asarray(f["bond_nodes"], dtype=np.int64)[np.asarray(f["broken"], dtype=bool)]
        out["broken_bonds"] = np.bincount(ends.ravel(), minlength=n).astype(np.int64)
    return out


#: (points, cell blocks, point data, cell data (one array per block), field data) of one mesh
_Parts = tuple[
    np.ndarray, list[tuple[str, np.ndarray]], dict[str, Any], dict[str, Any], dict[str, Any]
]


def to_meshio(res: Result) -> Any:
    """``res`` as a ``meshio.Mesh`` (see the module docstring for what each method holds)."""
    meshio = require_meshio("Result.to_meshio()")
    return _mesh(meshio, mesh_parts(res))


def _mesh(meshio: ModuleType, parts: _Parts) -> Any:
    points, cells, pdata, cdata, fdata = parts
    return meshio.Mesh(points, cells, point_data=pdata, cell_data=cdata, field_data=fdata)


def mesh_parts(res: Result) -> _Parts:
    """``res`` as (points (n, 3), cell blocks [(type, connectivity)], point data, cell data (a
    list of one array per block), field data): what :func:`to_meshio` and ``result.vtu``
    hold."""
    f = res.fields
    if "coords" in f and "elements" in f:
        if "cut_offsets" in f and "cut_points" in f:
            states = xfem_states(res)
            if states:
                return xfem_parts(res, states[-1])
            return xfem_parts(res, initial_state(res))
        return _fem(res)
    if "node_xy" in f:
        return _pd(res, None)
    raise PlotDataError(
        f"a {res.method} result without a mesh or grid (fields coords and elements, or "
        "node_xy) has nothing to write as a mesh"
    )


def _fem(res: Result) -> _Parts:
    f = res.fields
    n, els = len(f["coords"]), np.asarray(f["elements"], dtype=np.int64)
    pdata: dict[str, Any] = {}
    if "u" in f and len(f["u"]) == 2 * n:
        pdata["displacement"] = _vec3(f["u"])
    if "nodal_stress" in f and len(f["nodal_stress"]) == n:
        pdata["nodal_stress"] = np.asarray(f["nodal_stress"], dtype=float)
    if "reactions" in f and len(f["reactions"]) == 2 * n:
        pdata["reaction"] = _vec3(f["reactions"])
    cdata: dict[str, Any] = {"element_id": [np.arange(len(els), dtype=np.int64)]}
    stress = element_stress(res)
    if stress is not None:
        cdata["stress"] = [stress]
    return _vec3(f["coords"]), [("quad", els)], pdata, cdata, {}


@dataclass(frozen=True)
class XfemState:
    """One state of an XFEM result: the single solve at the reference load, or a growth run's
    critical state (the fields ``state_*``) at its critical load.

    Attributes:
        row: the history row (0 for the single solve and the unloaded origin).
        u: nodal displacements (n_nodes, 2).
        stress: element stresses (n_elements, 3), or None.
        cut_points, cut_disp: the cut polygons' vertices and their displacements (p, 2).
        cut_offsets: start of each cut polygon in ``cut_points`` (and the end).
        cut_element: the element of each cut polygon.
        cut_stress: the stress at each cut polygon's centroid (c, 3), or None.
        cracks: the crack polylines of the state.
        enrichment: each node's enrichment for the state's cracks (0, 1 Heaviside, 2 tip), or
            None.
    """

    row: int
    u: np.ndarray
    stress: np.ndarray | None
    cut_points: np.ndarray
    cut_disp: np.ndarray
    cut_offsets: np.ndarray
    cut_element: np.ndarray
    cut_stress: np.ndarray | None
    cracks: list[np.ndarray]
    enrichment: np.ndarray | None = None

    def unloaded(self) -> XfemState:
        """The same mesh and cracks with zero displacement and stress (row 0, the origin)."""
        zero = None if self.stress is None else np.zeros_like(self.stress)
        cut_zero = None if self.cut_stress is None else np.zeros_like(self.cut_stress)
        return XfemState(
            0,
            np.zeros_like(self.u),
            zero,
            self.cut_points,
            np.zeros_like(self.cut_disp),
            self.cut_offsets,
            self.cut_element,
            cut_zero,
            self.cracks,
            self.enrichment,
        )


def initial_state(res: Result) -> XfemState:
    """The single solve of an XFEM result (reference load, initial cracks)."""
    f = res.fields
    cut_stress = f.get("cut_stress")
    if cut_stress is not None and len(cut_stress) != len(f["cut_element"]):
        cut_stress = None
    initial = res.meta.get("cracks_initial")
    cracks = (
        [np.asarray(c, dtype=float).reshape(-1, 2) for c in initial]
        if isinstance(initial, list)
        else res.crack_polylines
    )
    return XfemState(
        0,
        np.asarray(f["u"], dtype=float).reshape(-1, 2),
        element_stress(res),
        np.asarray(f["cut_points"], dtype=float).reshape(-1, 2),
        np.asarray(f["cut_disp"], dtype=float).reshape(-1, 2),
        np.asarray(f["cut_offsets"], dtype=np.int64),
        np.asarray(f["cut_element"], dtype=np.int64),
        None if cut_stress is None else np.asarray(cut_stress, dtype=float),
        [c for c in cracks if len(c) >= 2],
        np.asarray(f["enrichment"], dtype=np.int64) if "enrichment" in f else None,
    )


def xfem_states(res: Result) -> list[XfemState]:
    """The kept critical states of an XFEM growth run (fields ``state_*``, history order; see
    ``xfem.state_every``), empty without them."""
    f = res.fields
    rows = np.asarray(f.get("state_rows", ()), dtype=np.int64)
    if not len(rows):
        return []
    n_cracks = (len(f["state_cracks_offsets"]) - 1) // len(rows)
    c_off = np.asarray(f["state_cut_offsets"], dtype=np.int64)
    p_off = np.asarray(f["state_cut_point_offsets"], dtype=np.int64)
    k_off = np.asarray(f["state_cracks_offsets"], dtype=np.int64)
    pts, disp = np.asarray(f["state_cut_points"]), np.asarray(f["state_cut_disp"])
    cracks = np.asarray(f["state_cracks"], dtype=float)
    out = []
    for k, row in enumerate(rows):
        a, b = c_off[k], c_off[k + 1]
        p0, p1 = p_off[a], p_off[b]
        lines = [
            cracks[k_off[k * n_cracks + c] : k_off[k * n_cracks + c + 1]] for c in range(n_cracks)
        ]
        out.append(
            XfemState(
                int(row),
                np.asarray(f["state_u"][k], dtype=float).reshape(-1, 2),
                np.asarray(f["state_stress"][k], dtype=float),
                pts[p0:p1],
                disp[p0:p1],
                p_off[a : b + 1] - p0,
                np.asarray(f["state_cut_element"][a:b], dtype=np.int64),
                np.asarray(f["state_cut_stress"][a:b], dtype=float),
                [c for c in lines if len(c) >= 2],
                np.asarray(f["state_enrichment"][k], dtype=np.int64)
                if "state_enrichment" in f
                else None,
            )
        )
    return out


def _fan(off: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The cut polygons (vertices ``off[i] .. off[i + 1]``, convex) as cells of at most 4
    vertices: (quads (q, 4), their polygons, triangles (t, 3), their polygons); 4 vertices give a
    quad, 3 a triangle, k > 4 a fan of k - 2 triangles from the first vertex."""
    sizes = np.diff(off)
    quad_poly = np.flatnonzero(sizes == 4)
    quads = off[quad_poly][:, None] + np.arange(4)[None, :]
    tri_poly = np.repeat(np.arange(len(sizes)), np.where(sizes == 4, 0, np.maximum(sizes - 2, 0)))
    # the j-th triangle of polygon i: vertices 0, j + 1, j + 2
    first = np.concatenate([[0], np.cumsum(np.where(sizes == 4, 0, np.maximum(sizes - 2, 0)))])
    j = np.arange(len(tri_poly)) - first[tri_poly]
    base = off[tri_poly]
    tris = np.column_stack([base, base + j + 1, base + j + 2])
    return quads, quad_poly, tris, tri_poly


def xfem_parts(res: Result, st: XfemState) -> _Parts:
    """One XFEM state as mesh parts (see the module docstring); field data: the state's history
    row of every history column (growth runs)."""
    f = res.fields
    coords, els = np.asarray(f["coords"], dtype=float), np.asarray(f["elements"], dtype=np.int64)
    n = len(coords)
    std = np.setdiff1d(np.arange(len(els)), st.cut_element)
    quads, quad_poly, tris, tri_poly = _fan(st.cut_offsets)
    cracks = st.cracks
    n_lines = sum(len(c) - 1 for c in cracks)
    base = n + len(st.cut_points)
    segs, crack_of = [], []
    for i, c in enumerate(cracks):
        segs.append(base + np.column_stack([np.arange(len(c) - 1), np.arange(1, len(c))]))
        crack_of.append(np.full(len(c) - 1, i))
        base += len(c)
    lines = np.concatenate(segs) if segs else np.zeros((0, 2), dtype=np.int64)

    # per cell, block by block: quad (standard elements, then 4-vertex cut cells), triangle, line
    poly = np.concatenate([np.full(len(std), -1), quad_poly, tri_poly, np.full(n_lines, -1)])
    poly = poly.astype(np.int64)
    parent = np.where(poly >= 0, st.cut_element[np.maximum(poly, 0)], -1)
    parent[: len(std)] = std
    kind = np.full(len(poly), CUT, dtype=np.int64)
    kind[: len(std)] = STANDARD
    kind[len(poly) - n_lines :] = CRACK
    crack_id = np.full(len(poly), -1, dtype=np.int64)
    if n_lines:
        crack_id[len(poly) - n_lines :] = np.concatenate(crack_of)
    blocks = [
        ("quad", np.concatenate([els[std], n + quads]).astype(np.int64)),
        ("triangle", (n + tris).astype(np.int64)),
        ("line", lines.astype(np.int64)),
    ]
    sizes = [len(b[1]) for b in blocks]
    keep = [k for k, m in enumerate(sizes) if m]

    def per_block(a: np.ndarray) -> list[np.ndarray]:
        parts = np.split(a, np.cumsum(sizes)[:-1])
        return [parts[k] for k in keep]

    cdata: dict[str, Any] = {
        "element_id": per_block(parent),
        "kind": per_block(kind),
        "cut_cell": per_block(poly),
        "crack": per_block(crack_id),
    }
    if st.enrichment is not None and len(els):
        enr_el = st.enrichment[els].max(axis=1)
        cdata["enrichment"] = per_block(np.where(parent >= 0, enr_el[np.maximum(parent, 0)], -1))
    if st.stress is not None:
        s = np.where((parent >= 0)[:, None], st.stress[np.maximum(parent, 0)], 0.0)
        if st.cut_stress is not None:
            # a cut cell carries the enriched stress of its own side (at its centroid)
            cut = poly >= 0
            s[cut] = st.cut_stress[poly[cut]]
        cdata["stress"] = per_block(s)
    crack_pts = np.concatenate(cracks) if cracks else np.zeros((0, 2))
    points = _vec3(np.concatenate([coords, st.cut_points, crack_pts]))
    disp = _vec3(np.concatenate([st.u, st.cut_disp, np.zeros_like(crack_pts)]))
    return points, [blocks[k] for k in keep], {"displacement": disp}, cdata, _row(res, st.row)


def _row(res: Result, row: int | None) -> dict[str, Any]:
    """Field data: history row ``row`` of every history column and ``row`` itself (none for a
    single solve)."""
    if row is None or not res.history:
        return {}
    out: dict[str, Any] = {"row": np.array([row], dtype=np.int64)}
    for k, v in res.history.items():
        a = np.asarray(v)
        if a.ndim == 1 and row < len(a):
            out[k] = a[row : row + 1].astype(np.int64 if a.dtype.kind in "biu" else np.float64)
    return out


def _fem_cells(xy: np.ndarray, is_pd: np.ndarray) -> np.ndarray:
    """The quads of the grid (a tensor grid of the nodes ``xy``, uniform or graded) whose four
    corners are nodes and at least one is a FEM node (``is_pd`` 0): CCM-PD's FEM part."""
    if len(xy) == 0 or is_pd.all():
        return np.zeros((0, 4), dtype=np.int64)
    span = float(np.ptp(xy, axis=0).max()) or 1.0
    q = np.round(xy / (1e-9 * span)).astype(np.int64)
    xs, ix = np.unique(q[:, 0], return_inverse=True)
    ys, iy = np.unique(q[:, 1], return_inverse=True)
    grid = np.full((len(xs), len(ys)), -1, dtype=np.int64)
    grid[ix, iy] = np.arange(len(xy))
    c = np.stack([grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]], axis=-1).reshape(
        -1, 4
    )
    c = c[(c >= 0).all(axis=1)]
    return c[(is_pd[c] == 0).any(axis=1)]


def _broken_by(res: Result, step: int | None) -> np.ndarray:
    """The bonds broken after SLA step ``step`` (None: at the end): the pre-crack's (broken at
    the end but no step's critical bond) and the critical bonds of steps 1 .. step."""
    f = res.fields
    broken = np.flatnonzero(np.asarray(f.get("broken", ()), dtype=bool))
    if step is None or "bond" not in res.history:
        return broken
    crit = np.asarray(res.history["bond"], dtype=np.int64)
    steps = np.asarray(res.history.get("step", np.arange(len(crit))), dtype=np.int64)
    pre = np.setdiff1d(broken, crit[crit >= 0])
    return np.union1d(pre, crit[(crit >= 0) & (steps <= step)])


def _pd(res: Result, snapshot: tuple[int, np.ndarray] | None) -> _Parts:
    """The PD / CCM-PD grid at the end (``snapshot`` None) or after a snapshot's step (step,
    damage of the PD nodes) as mesh parts (see the module docstring)."""
    f = res.fields
    xy = np.asarray(f["node_xy"], dtype=float)
    n = len(xy)
    pf = pd_point_fields(res)
    pdata: dict[str, Any] = {}
    if snapshot is None:
        for key, name in (("u", "displacement"), ("u_final", "displacement_final")):
            if key in f and len(f[key]) == 2 * n:
                pdata[name] = _vec3(f[key])
        pdata.update(pf)
    else:
        damage = np.zeros(n)
        damage[np.asarray(f["pd_nodes"], dtype=np.int64)] = snapshot[1]
        pdata.update({"damage": damage, "is_pd": pf["is_pd"]})
    quads = _fem_cells(xy, pf["is_pd"])
    vertices = np.flatnonzero(pf["is_pd"])[:, None].astype(np.int64)
    bonds = _broken_by(res, None if snapshot is None else snapshot[0])
    ends = np.asarray(f.get("bond_nodes", np.zeros((0, 2))), dtype=np.int64)
    lines = ends[bonds] if len(ends) else np.zeros((0, 2), dtype=np.int64)
    if len(ends) == 0:
        bonds = np.zeros(0, dtype=np.int64)
    blocks = [("quad", quads), ("vertex", vertices), ("line", lines)]
    kinds = [FEM_CELL, PD_NODE, BROKEN_BOND]
    keep = [k for k, (_, c) in enumerate(blocks) if len(c)]
    cdata: dict[str, Any] = {
        "kind": [np.full(len(blocks[k][1]), kinds[k], dtype=np.int64) for k in keep],
        "bond": [
            bonds.astype(np.int64) if k == 2 else np.full(len(blocks[k][1]), -1, dtype=np.int64)
            for k in keep
        ],
    }
    if not keep:  # no cells at all: the nodes as vertices
        blocks, keep = [("vertex", np.arange(n, dtype=np.int64)[:, None])], [0]
        cdata = {}
    row = None
    if snapshot is not None and "step" in res.history:
        hit = np.flatnonzero(np.asarray(res.history["step"]) == snapshot[0])
        row = int(hit[0]) if len(hit) else None
    return _vec3(xy), [blocks[k] for k in keep], pdata, cdata, _row(res, row)


def series(res: Result) -> list[tuple[float, Any]]:
    """The time series of ``res`` as (timestep, ``meshio.Mesh``) pairs: XFEM growth runs one per
    kept critical state (and the origin), SLA runs one per damage snapshot (see the module
    docstring); empty otherwise."""
    meshio = require_meshio("the ParaView time series")
    return [(t, _mesh(meshio, parts)) for t, parts in series_parts(res)]


def series_parts(res: Result) -> list[tuple[float, _Parts]]:
    """The time series of ``res`` (:func:`series`) as (timestep, mesh parts) pairs (the parts as
    :func:`mesh_parts` gives them)."""
    f = res.fields
    out: list[tuple[float, _Parts]] = []
    if "coords" in f and "cut_offsets" in f:
        states = xfem_states(res)
        if states and states[0].row == 1:
            states.insert(0, states[0].unloaded())
        out += [(float(st.row), xfem_parts(res, st)) for st in states]
    steps = np.asarray(f.get("damage_at_steps", ()), dtype=np.int64)
    if "node_xy" in f and len(steps):
        for step, dmg in zip(steps, np.asarray(f["damage_at"], dtype=float)):
            out.append((float(step), _pd(res, (int(step), dmg))))
    return out


#: VTK cell type of each cell block type
_VTK_CELL = {"vertex": 1, "line": 3, "triangle": 5, "quad": 9}
#: VTU type name of each array dtype
_VTU_TYPE = {
    np.dtype(np.float64): "Float64",
    np.dtype(np.float32): "Float32",
    np.dtype(np.int64): "Int64",
    np.dtype(np.int32): "Int32",
    np.dtype(np.uint8): "UInt8",
}
#: uncompressed bytes per zlib block (VTK's vtkZLibDataCompressor default)
_BLOCK = 32768
#: zlib level of the VTU blocks: 1, the fastest (the float data compresses little at any level)
_ZLIB_LEVEL = 1


def write_vtu(path: Path, parts: _Parts) -> None:
    """Writes one mesh (:func:`mesh_parts`) to ``path`` as a VTK XML unstructured grid, its
    arrays binary (base64) in zlib-compressed blocks (the VTK XML file format, "binary" data with
    ``vtkZLibDataCompressor`` and a UInt64 header: block count, block size, last block size, the
    compressed size of each block). The format meshio writes, without building the XML tree;
    the field data (one value per history column) as VTK's ``FieldData`` of the grid, which
    ParaView shows and meshio reads."""
    points, blocks, pdata, cdata, fdata = parts
    n_cells = sum(len(conn) for _, conn in blocks)
    sizes = [np.full(len(conn), conn.shape[1], dtype=np.int64) for _, conn in blocks]
    conn = np.concatenate([c.reshape(-1) for _, c in blocks]) if blocks else np.zeros(0)
    order = "LittleEndian" if sys.byteorder == "little" else "BigEndian"
    out = [
        '<?xml version="1.0"?>\n',
        f'<VTKFile type="UnstructuredGrid" version="0.1" byte_order="{order}" '
        'header_type="UInt64" compressor="vtkZLibDataCompressor">\n',
        "<UnstructuredGrid>\n",
        *(
            [
                "<FieldData>\n",
                *(_data_array(k, v, field=True) for k, v in fdata.items()),
                "</FieldData>\n",
            ]
            if fdata
            else []
        ),
        f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{n_cells}">\n',
        "<Points>\n",
        _data_array("Points", np.asarray(points, dtype=float)),
        "</Points>\n<Cells>\n",
        _data_array("connectivity", conn.astype(np.int64)),
        _data_array("offsets", np.cumsum(np.concatenate([np.zeros(0, np.int64), *sizes]))),
        _data_array(
            "types",
            np.concatenate(
                [np.zeros(0, np.uint8)]
                + [np.full(len(c), _VTK_CELL[t], dtype=np.uint8) for t, c in blocks]
            ),
        ),
        "</Cells>\n",
    ]
    if pdata:
        out += ["<PointData>\n", *(_data_array(k, v) for k, v in pdata.items()), "</PointData>\n"]
    if cdata:
        out += [
            "<CellData>\n",
            *(_data_array(k, np.concatenate(v)) for k, v in cdata.items()),
            "</CellData>\n",
        ]
    out.append("</Piece>\n</UnstructuredGrid>\n</VTKFile>\n")
    with open(path, "w", encoding="ascii") as f:
        f.write("".join(out))


def _data_array(name: str, a: Any, field: bool = False) -> str:
    """One ``DataArray`` element: its bytes in zlib blocks, base64-encoded (header, then data);
    ``field``: an array of the grid's ``FieldData``, which states its ``NumberOfTuples``."""
    a = np.asarray(a)
    if a.dtype == np.bool_:
        a = a.astype(np.uint8)
    vtype = _VTU_TYPE.get(a.dtype)
    if vtype is None:  # another integer or float width: the nearest wide type
        a = a.astype(np.int64 if a.dtype.kind in "biu" else np.float64)
        vtype = _VTU_TYPE[a.dtype]
    data = np.ascontiguousarray(a).tobytes()
    chunks = [zlib.compress(data[i : i + _BLOCK], _ZLIB_LEVEL) for i in range(0, len(data), _BLOCK)]
    last = len(data) - (len(chunks) - 1) * _BLOCK if chunks else 0
    header = np.array([len(chunks), _BLOCK, last, *map(len, chunks)], dtype=np.uint64)
    ncomp = f' NumberOfComponents="{a.shape[1]}"' if a.ndim == 2 else ""
    if field:
        ncomp += f' NumberOfTuples="{len(a)}"'
    return (
        f'<DataArray type="{vtype}" Name={quoteattr(name)}{ncomp} format="binary">'
        + base64.b64encode(header.tobytes()).decode()
        + base64.b64encode(b"".join(chunks)).decode()
        + "</DataArray>\n"
    )


#: XML attribute escapes (xml.sax.saxutils.quoteattr's, which imports urllib: 20 ms of start-up)
_ATTR_ESCAPES = str.maketrans(
    {
        "&": "&amp;",
        "<": "&lt;",
        ">": "&gt;",
        '"': "&quot;",
        "\n": "&#10;",
        "\r": "&#13;",
        "\t": "&#9;",
    }
)


def quoteattr(value: str) -> str:
    """``value`` as a double-quoted XML attribute value."""
    return '"' + value.translate(_ATTR_ESCAPES) + '"'


def write_pvd(f: IO[str], datasets: list[tuple[float, str]]) -> None:
    """Writes a ParaView collection (``.pvd``) of (timestep, relative VTU path) pairs."""
    f.write('<?xml version="1.0"?>\n')
    f.write('<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n')
    f.write("  <Collection>\n")
    for t, name in datasets:
        f.write(f'    <DataSet timestep="{t:.17g}" group="" part="0" file={quoteattr(name)}/>\n')
    f.write("  </Collection>\n")
    f.write("</VTKFile>\n")
