"""Results as meshio meshes and ParaView files (:meth:`Result.to_meshio`, ``result.vtu``,
``result.pvd``); meshio is optional (``pip install 'rustfrac[io]'``). The VTU files are written
by :func:`write_vtu` (the VTK XML format meshio writes, without its XML tree: 2.5x faster, and
meshio is needed only for :func:`to_meshio` and :func:`series`).

What a mesh holds (every vector has 3 components, z = 0, as ParaView expects):

- FEM: the Q4 mesh as ``quad`` cells; point data ``displacement`` (u), ``nodal_stress``
  [s11, s22, s12] and ``reaction``; cell data ``stress`` (the mean of the element's Gauss-point
  stresses) and ``element_id``.
- XFEM: the standard (non-enriched) elements as ``quad`` cells on the mesh nodes; every element
  with an enriched node replaced by its cut cells (``cut_points`` / ``cut_offsets``: the element's
  sub-polygons on each side of the crack), with points of their own appended after the mesh nodes
  and the enriched displacement of their own side (``cut_disp``), so both crack faces exist and
  the opening shows as a gap; cells of 3 and 4 vertices are ``triangle`` and ``quad`` cells,
  larger ones ``polygon`` cells (one block per vertex count; VTU writes them as VTK_POLYGON and
  reads them back). Then every crack polyline as ``line`` cells on points of its own, whose
  displacement is zero (the line marks the crack in the reference configuration: Warp By Vector
  leaves it where the crack was cut). Cell data: ``element_id`` (the parent element; -1 for crack
  lines), ``kind`` (0 standard element, 1 cut cell, 2 crack line), ``enrichment`` (the largest
  enrichment of the parent element's nodes: 0 none, 1 Heaviside, 2 tip; -1 for crack lines),
  ``crack`` (the crack index of a line, -1 for elements) and, when the result has Gauss-point
  stresses, ``stress`` (standard elements: the mean of their Gauss-point stresses; a cut cell:
  the enriched stress of its own side at its centroid, ``cut_stress``; crack lines 0).
- PD / CCM-PD: the grid nodes as ``vertex`` cells; point data ``displacement`` (reference load,
  before any break), ``displacement_final`` (after the last break; absent when the body
  separated), ``damage`` (0 at FEM nodes), ``is_pd`` and ``broken_bonds`` (the number of broken
  bonds at each node: their sum is twice the number of broken bonds).

Time series (:func:`series`, ``result.pvd``): XFEM growth runs give one state per history row
(the deformed patch ``snapshot_cells`` / ``snapshot_disp``: snapshot k belongs to row k + 1; row 0,
the unloaded origin, is the first patch with zero displacement), timestep = the history row; SLA
runs with damage snapshots (``damage_at_steps``) one state per snapshot (the grid nodes with the
``damage`` and ``is_pd`` of that step), timestep = the SLA step.
"""

from __future__ import annotations

import base64
import sys
import zlib
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


#: cell types of the cut cells by vertex count (others: "polygon")
_FIXED = {3: "triangle", 4: "quad"}
#: ``kind`` cell data
STANDARD, CUT, CRACK = 0, 1, 2


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


#: (points, cell blocks, point data, cell data) of one mesh
_Parts = tuple[np.ndarray, list[tuple[str, np.ndarray]], dict[str, Any], dict[str, Any]]


def to_meshio(res: Result) -> Any:
    """``res`` as a ``meshio.Mesh`` (see the module docstring for what each method holds)."""
    meshio = require_meshio("Result.to_meshio()")
    points, cells, pdata, cdata = mesh_parts(res)
    return meshio.Mesh(points, cells, point_data=pdata, cell_data=cdata)


def mesh_parts(res: Result) -> _Parts:
    """``res`` as (points (n, 3), cell blocks [(type, connectivity)], point data, cell data (a
    list of one array per block)): what :func:`to_meshio` and ``result.vtu`` hold."""
    f = res.fields
    if "coords" in f and "elements" in f:
        return _xfem(res) if "cut_offsets" in f and "cut_points" in f else _fem(res)
    if "node_xy" in f:
        return _pd(res)
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
    return _vec3(f["coords"]), [("quad", els)], pdata, cdata


def _xfem(res: Result) -> _Parts:
    f = res.fields
    coords, els = np.asarray(f["coords"], dtype=float), np.asarray(f["elements"], dtype=np.int64)
    n = len(coords)
    cut_pts, cut_disp = np.asarray(f["cut_points"], dtype=float), f["cut_disp"]
    off, parent = np.asarray(f["cut_offsets"], dtype=np.int64), f["cut_element"]
    parent = np.asarray(parent, dtype=np.int64)
    sizes = np.diff(off)
    enr_node = np.asarray(f.get("enrichment", np.zeros(n)), dtype=np.int64)
    enr_el = enr_node[els].max(axis=1) if len(els) else np.zeros(0, dtype=np.int64)
    std = np.setdiff1d(np.arange(len(els)), parent)
    stress = element_stress(res)
    cracks = [c for c in res.crack_polylines if len(c) >= 2]

    blocks: list[tuple[str, np.ndarray]] = []
    ids: list[np.ndarray] = []
    kinds: list[np.ndarray] = []
    crack_id: list[np.ndarray] = []

    def add(ctype: str, conn: np.ndarray, parent_ids: np.ndarray, kind: int, crack: int) -> None:
        if len(conn):
            blocks.append((ctype, conn))
            ids.append(parent_ids)
            kinds.append(np.full(len(conn), kind))
            crack_id.append(np.full(len(conn), crack))

    add("quad", els[std], std, STANDARD, -1)
    for k in np.unique(sizes):
        sel = np.flatnonzero(sizes == k)
        conn = n + off[sel][:, None] + np.arange(k)[None, :]
        add(_FIXED.get(int(k), "polygon"), conn, parent[sel], CUT, -1)
    base = n + len(cut_pts)
    for i, c in enumerate(cracks):
        seg = base + np.column_stack([np.arange(len(c) - 1), np.arange(1, len(c))])
        add("line", seg, np.full(len(seg), -1), CRACK, i)
        base += len(c)

    def per_block(a: np.ndarray) -> list[np.ndarray]:
        return np.split(a, np.cumsum([len(b[1]) for b in blocks])[:-1])

    id_all = np.concatenate(ids).astype(np.int64)
    cdata: dict[str, Any] = {
        "element_id": per_block(id_all),
        "kind": per_block(np.concatenate(kinds).astype(np.int64)),
        "enrichment": per_block(np.where(id_all >= 0, enr_el[np.maximum(id_all, 0)], -1)),
        "crack": per_block(np.concatenate(crack_id).astype(np.int64)),
    }
    if stress is not None:
        s = np.where((id_all >= 0)[:, None], stress[np.maximum(id_all, 0)], 0.0)
        if "cut_stress" in f and len(f["cut_stress"]) == len(sizes):
            # a cut cell carries the enriched stress of its own side (at its centroid)
            cut_rows = np.concatenate([np.flatnonzero(sizes == k) for k in np.unique(sizes)])
            start = len(std)
            s[start : start + len(cut_rows)] = np.asarray(f["cut_stress"], dtype=float)[cut_rows]
        cdata["stress"] = per_block(s)
    crack_pts = np.concatenate(cracks) if cracks else np.zeros((0, 2))
    points = _vec3(np.concatenate([coords, cut_pts, crack_pts]))
    u = np.asarray(f["u"], dtype=float).reshape(-1, 2)
    disp = _vec3(np.concatenate([u, np.asarray(cut_disp, dtype=float), np.zeros_like(crack_pts)]))
    return points, blocks, {"displacement": disp}, cdata


def _pd(res: Result) -> _Parts:
    f = res.fields
    xy = np.asarray(f["node_xy"], dtype=float)
    n = len(xy)
    pdata: dict[str, Any] = {}
    for key, name in (("u", "displacement"), ("u_final", "displacement_final")):
        if key in f and len(f[key]) == 2 * n:
            pdata[name] = _vec3(f[key])
    pdata.update(pd_point_fields(res))
    cells = [("vertex", np.arange(n, dtype=np.int64)[:, None])]
    return _vec3(xy), cells, pdata, {}


def series(res: Result) -> list[tuple[float, Any]]:
    """The time series of ``res`` as (timestep, ``meshio.Mesh``) pairs: XFEM growth runs one per
    history row, SLA runs one per damage snapshot (see the module docstring); empty otherwise."""
    meshio = require_meshio("the ParaView time series")
    return [
        (t, meshio.Mesh(points, cells, point_data=pdata, cell_data=cdata))
        for t, (points, cells, pdata, cdata) in series_parts(res)
    ]


def series_parts(res: Result) -> list[tuple[float, _Parts]]:
    """The time series of ``res`` (:func:`series`) as (timestep, mesh parts) pairs (the parts as
    :func:`mesh_parts` gives them)."""
    f = res.fields
    out: list[tuple[float, _Parts]] = []
    off = np.asarray(f.get("snapshot_offsets", ()), dtype=np.int64)
    if "snapshot_cells" in f and len(off) > 1:
        cells, disp = np.asarray(f["snapshot_cells"]), np.asarray(f["snapshot_disp"])
        rows = len(next(iter(res.history.values()))) if res.history else len(off) - 1
        first = 1 if rows == len(off) else 0  # the unloaded origin has no snapshot of its own
        patches = [
            (cells[off[k] : off[k + 1]], disp[off[k] : off[k + 1]]) for k in range(len(off) - 1)
        ]
        if first:
            patches.insert(0, (patches[0][0], np.zeros_like(patches[0][1])))
        for row, (c, d) in enumerate(patches):
            quads = np.arange(4 * len(c), dtype=np.int64).reshape(-1, 4)
            pdata = {"displacement": _vec3(d.reshape(-1, 2))}
            out.append((float(row), (_vec3(c.reshape(-1, 2)), [("quad", quads)], pdata, {})))
    steps = np.asarray(f.get("damage_at_steps", ()), dtype=np.int64)
    if "node_xy" in f and len(steps):
        xy = _vec3(f["node_xy"])
        pd_nodes = np.asarray(f["pd_nodes"], dtype=np.int64)
        is_pd = pd_point_fields(res)["is_pd"]
        vertices = [("vertex", np.arange(len(xy), dtype=np.int64)[:, None])]
        for step, dmg in zip(steps, np.asarray(f["damage_at"], dtype=float)):
            damage = np.zeros(len(xy))
            damage[pd_nodes] = dmg
            out.append((float(step), (xy, vertices, {"damage": damage, "is_pd": is_pd}, {})))
    return out


#: VTK cell type of each cell block type
_VTK_CELL = {"vertex": 1, "line": 3, "triangle": 5, "polygon": 7, "quad": 9}
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
    compressed size of each block). The format meshio writes, without building the XML tree."""
    points, blocks, pdata, cdata = parts
    n_cells = sum(len(conn) for _, conn in blocks)
    sizes = [np.full(len(conn), conn.shape[1], dtype=np.int64) for _, conn in blocks]
    conn = np.concatenate([c.reshape(-1) for _, c in blocks]) if blocks else np.zeros(0)
    order = "LittleEndian" if sys.byteorder == "little" else "BigEndian"
    out = [
        '<?xml version="1.0"?>\n',
        f'<VTKFile type="UnstructuredGrid" version="0.1" byte_order="{order}" '
        'header_type="UInt64" compressor="vtkZLibDataCompressor">\n',
        "<UnstructuredGrid>\n",
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


def _data_array(name: str, a: Any) -> str:
    """One ``DataArray`` element: its bytes in zlib blocks, base64-encoded (header, then data)."""
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
