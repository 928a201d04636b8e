"""Results as meshio meshes and ParaView files: result.vtu written through
meshio and read back, the XFEM cut cells on both crack faces, FEM element stresses, PD broken
bonds and FEM cells, the time series result.pvd (every growth state the whole plate with that
state's crack, opening and stresses; every SLA snapshot with its broken bonds), the formats of
other meshio readers (Gmsh, XDMF), the files without meshio, and the result folder as one unit
with the new files."""

from __future__ import annotations

import hashlib
import json
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import rustfrac as rf
from rustfrac import _vtk, handbook

meshio = pytest.importorskip("meshio")

MESH = (22, 41)


@pytest.fixture(scope="module")
def xfem() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate("xfem", mesh=MESH))


@pytest.fixture(scope="module")
def growth() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate("xfem", mesh=MESH, growth_steps=5))


@pytest.fixture(scope="module")
def fem() -> rf.Result:
    with pytest.warns(rf.DiscretisationWarning):
        return rf.run(rf.scenes.edge_crack_plate("fem", mesh=MESH))


@pytest.fixture(scope="module")
def ccm() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate("ccm_pd", sla_steps=20, damage_at_steps=[5, 10]))


def cells_by(mesh: Any, key: str) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(cell type, connectivity, cell data ``key``) of every block."""
    return [(b.type, b.data, d) for b, d in zip(mesh.cells, mesh.cell_data[key])]


def read_back(res: rf.Result, d: Path) -> Any:
    res.save(d)
    return meshio.read(d / "result.vtu")


def test_vtu_is_binary_compressed(xfem: rf.Result, tmp_path: Path) -> None:
    xfem.save(tmp_path)
    root = ET.parse(tmp_path / "result.vtu").getroot()
    assert root.get("compressor") == "vtkZLibDataCompressor"
    formats = {a.get("format") for a in root.iter("DataArray")}
    assert formats == {"binary"}


def _assert_same_mesh(a: Any, b: Any) -> None:
    """Points, cell blocks, point and cell data of two meshio meshes: equal, of equal dtype."""
    np.testing.assert_array_equal(a.points, b.points)
    assert [c.type for c in a.cells] == [c.type for c in b.cells]
    for x, y in zip(a.cells, b.cells):
        np.testing.assert_array_equal(x.data, y.data)
    assert set(a.point_data) == set(b.point_data) and set(a.cell_data) == set(b.cell_data)
    pairs = [(k, a.point_data[k], b.point_data[k]) for k in b.point_data]
    for k in b.cell_data:
        assert len(a.cell_data[k]) == len(b.cell_data[k]), k
        pairs += [(k, x, y) for x, y in zip(a.cell_data[k], b.cell_data[k])]
    for k, x, y in pairs:
        assert x.dtype == y.dtype, k
        np.testing.assert_array_equal(x, y, err_msg=k)


@pytest.mark.parametrize("name", ["xfem", "growth", "fem", "ccm"])
def test_direct_vtu_writer_reads_back_as_meshio_writes(
    name: str, request: pytest.FixtureRequest, tmp_path: Path
) -> None:
    """rustfrac's VTU writer (``_vtk.write_vtu``, no XML tree) against meshio's own: each file
    (result.vtu and every state of the series) read back by meshio gives the same mesh as the
    file meshio writes from the same parts."""
    res = request.getfixturevalue(name)
    states = [(None, _vtk.mesh_parts(res)), *_vtk.series_parts(res)]
    assert len(states) > (1 if name in ("growth", "ccm") else 0)
    for k, (_, parts) in enumerate(states):
        points, cells, pdata, cdata, fdata = parts
        ours, ref = tmp_path / f"ours{k}.vtu", tmp_path / f"ref{k}.vtu"
        _vtk.write_vtu(ours, parts)
        mesh = meshio.Mesh(points, cells, point_data=pdata, cell_data=cdata)
        meshio.write(ref, mesh, file_format="vtu", binary=True, compression="zlib")
        back = meshio.read(ours)
        _assert_same_mesh(back, meshio.read(ref))
        # meshio's writer has no field data; ours writes it and meshio reads it back
        assert set(back.field_data) == set(fdata)
        for key, v in fdata.items():
            np.testing.assert_array_equal(back.field_data[key], v, err_msg=key)


def test_xfem_cut_cells_show_the_crack_opening(xfem: rf.Result, tmp_path: Path) -> None:
    m = read_back(xfem, tmp_path)
    f = xfem.fields
    n = len(f["coords"])
    u = m.point_data["displacement"]
    assert u.shape[1] == 3 and not np.isnan(u).any() and (u[:, 2] == 0).all()
    # one block per cell type (meshio's other formats need it), no polygons
    types = [b.type for b in m.cells]
    assert len(types) == len(set(types)) and set(types) <= {"quad", "triangle", "line"}
    kinds = np.concatenate(m.cell_data["kind"])
    ids = np.concatenate(m.cell_data["element_id"])
    poly = np.concatenate(m.cell_data["cut_cell"])
    # every cut polygon of the result is drawn (as one or more cells), replacing its element
    assert sorted(set(poly[kinds == _vtk.CUT])) == list(range(len(f["cut_element"])))
    assert (poly[kinds != _vtk.CUT] == -1).all()
    np.testing.assert_array_equal(ids[kinds == _vtk.CUT], f["cut_element"][poly[kinds == _vtk.CUT]])
    std = ids[kinds == _vtk.STANDARD]
    assert not set(std) & set(f["cut_element"])
    assert len(std) + len(np.unique(f["cut_element"])) == len(f["elements"])
    # the standard cells sit on the mesh nodes and carry u there
    cut_pts: list[int] = []
    for ctype, conn, kind in cells_by(m, "kind"):
        sc = conn[kind == _vtk.STANDARD]
        assert len(sc) == 0 or (ctype == "quad" and sc.max() < n)
        np.testing.assert_array_equal(m.points[sc, :2], f["coords"][sc])
        np.testing.assert_array_equal(u[sc, :2], xfem.displacement[sc])
        cc = conn[kind == _vtk.CUT]
        assert len(cc) == 0 or cc.min() >= n
        cut_pts.extend(cc.ravel())
    np.testing.assert_array_equal(m.points[cut_pts, :2], f["cut_points"][np.array(cut_pts) - n])
    np.testing.assert_array_equal(u[cut_pts, :2], f["cut_disp"][np.array(cut_pts) - n])
    # at the crack mouth the two faces' u2 differ by the CMOD
    mouth = f["crack"][0]
    at = [p for p in set(cut_pts) if np.allclose(m.points[p, :2], mouth, atol=1e-12)]
    assert len(at) == 2
    opening = abs(u[at[0], 1] - u[at[1], 1])
    assert opening == pytest.approx(xfem.cmod, rel=1e-6)
    # the crack polyline as line cells on points of their own, with zero displacement
    lines = [(conn, c) for t, conn, c in cells_by(m, "crack") if t == "line"]
    assert len(lines) == 1 and len(lines[0][0]) == len(f["crack"]) - 1
    conn = lines[0][0]
    np.testing.assert_array_equal(m.points[conn[:, 0], :2], f["crack"][:-1])
    assert (u[conn] == 0).all()
    enr = np.concatenate(m.cell_data["enrichment"])
    assert set(enr[kinds == _vtk.CUT]) <= {1, 2} and (enr[kinds == _vtk.CRACK] == -1).all()


def test_cut_polygons_of_an_inclined_crack_become_triangles(tmp_path: Path) -> None:
    """A crack at an angle cuts cells into triangles and pentagons: the pentagons become fans
    of triangles covering the polygon's area, and the mesh is written by meshio's Gmsh writer
    (which refuses polygon cells)."""
    res = rf.run(rf.Scene.from_toml(rf.examples.path("inclined_crack.toml")))
    f = res.fields
    points, blocks, _, cdata, _ = _vtk.mesh_parts(res)
    assert [t for t, _ in blocks] == ["quad", "triangle", "line"]
    sizes = np.diff(f["cut_offsets"])
    assert (sizes == 5).any() and (sizes == 3).any()
    # the cells of each cut polygon cover its area exactly (the shoelace formula)
    area = np.zeros(len(sizes))
    for (_, conn), poly in zip(blocks, cdata["cut_cell"]):
        xy = points[conn, :2]
        a = 0.5 * np.abs(
            np.sum(
                xy[:, :, 0] * np.roll(xy[:, :, 1], -1, 1)
                - np.roll(xy[:, :, 0], -1, 1) * xy[:, :, 1],
                axis=1,
            )
        )
        np.add.at(area, poly[poly >= 0], a[poly >= 0])
    ref = np.array(
        [
            0.5 * abs(np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1]))
            for q in np.split(f["cut_points"], f["cut_offsets"][1:-1])
        ]
    )
    np.testing.assert_allclose(area, ref, rtol=1e-12, atol=1e-15)
    mesh = res.to_meshio()
    meshio.write(tmp_path / "plate.msh", mesh, file_format="gmsh22", binary=False)
    text = (tmp_path / "plate.msh").read_text().split("\n")
    n_cells = sum(len(c) for _, c in blocks)
    assert int(text[text.index("$Elements") + 1]) == n_cells
    # meshio's Gmsh writer has no polygon cells: the mesh of the old layout is refused
    with pytest.raises(KeyError):
        meshio.write(
            tmp_path / "old.msh",
            meshio.Mesh(points, [("polygon", np.zeros((1, 5), dtype=np.int64))]),
            file_format="gmsh22",
            binary=False,
        )


def test_xfem_mesh_writes_as_xdmf_for_fenicsx(growth: rf.Result, tmp_path: Path) -> None:
    pytest.importorskip("h5py")  # meshio's XDMF writer needs it
    mesh = growth.to_meshio()
    meshio.write(tmp_path / "plate.xdmf", mesh)
    back = meshio.read(tmp_path / "plate.xdmf")
    np.testing.assert_allclose(back.points, mesh.points)
    assert [b.type for b in back.cells] == [b.type for b in mesh.cells]


def test_fem_stress_is_the_element_mean_of_gauss_stress(fem: rf.Result, tmp_path: Path) -> None:
    m = read_back(fem, tmp_path)
    f = fem.fields
    assert [b.type for b in m.cells] == ["quad"]
    np.testing.assert_array_equal(m.cells[0].data, f["elements"])
    ne = len(f["elements"])
    gs = f["gauss_stress"]
    mean = np.array([gs[4 * e : 4 * e + 4].mean(axis=0) for e in range(ne)])
    np.testing.assert_allclose(m.cell_data["stress"][0], mean, rtol=1e-14, atol=0)
    np.testing.assert_array_equal(m.cell_data["element_id"][0], np.arange(ne))
    np.testing.assert_array_equal(m.point_data["displacement"][:, :2], fem.displacement)
    assert (m.point_data["displacement"][:, 2] == 0).all()


def test_pd_broken_bond_counts(ccm: rf.Result, tmp_path: Path) -> None:
    m = read_back(ccm, tmp_path)
    f = ccm.fields
    assert [b.type for b in m.cells] == ["quad", "vertex", "line"]
    counts = m.point_data["broken_bonds"]
    n_broken = int(f["broken"].sum())
    assert n_broken > 0 and int(counts.sum()) == 2 * n_broken
    i, j = f["bond_nodes"][f["broken"]][0]
    assert counts[i] >= 1 and counts[j] >= 1
    np.testing.assert_array_equal(m.point_data["displacement"][:, :2], ccm.displacement)
    np.testing.assert_array_equal(
        m.point_data["displacement_final"][:, :2], f["u_final"].reshape(-1, 2)
    )
    np.testing.assert_array_equal(m.point_data["damage"][f["pd_nodes"]], f["damage"])
    assert int(m.point_data["is_pd"].sum()) == len(f["pd_nodes"])
    quads, vertices, lines = (b.data for b in m.cells)
    # the PD nodes as vertices, every broken bond as a line between its end nodes
    np.testing.assert_array_equal(vertices[:, 0], np.sort(f["pd_nodes"]))
    np.testing.assert_array_equal(lines, f["bond_nodes"][f["broken"]])
    np.testing.assert_array_equal(m.cell_data["bond"][2], np.flatnonzero(f["broken"]))
    # the FEM cells: grid cells of one spacing, each with a FEM corner, covering the plate
    # outside the PD rectangle (whose inner cells have PD corners only)
    xy = f["node_xy"]
    is_pd = m.point_data["is_pd"]
    assert ((is_pd[quads] == 0).any(axis=1)).all()
    side = np.ptp(xy[quads], axis=1)
    np.testing.assert_allclose(side, ccm.meta["scene"].get("pd", {}).get("dx", 1 / 15), rtol=1e-9)
    w, h = np.ptp(xy, axis=0)
    (x0, y0, x1, y1) = ccm.meta["pd_regions"][0]
    inner = (x1 - x0 - 2 / 15) * (y1 - y0 - 2 / 15)  # the cells whose corners are all PD
    assert len(quads) * (1 / 15) ** 2 == pytest.approx(w * h - inner, rel=0.05)


def series_of(d: Path) -> list[tuple[float, Path]]:
    root = ET.parse(d / "result.pvd").getroot()
    assert root.get("type") == "Collection"
    return [(float(e.get("timestep")), d / e.get("file")) for e in root.iter("DataSet")]


def test_growth_series_has_one_state_per_history_row(growth: rf.Result, tmp_path: Path) -> None:
    growth.save(tmp_path)
    states = series_of(tmp_path)
    rows = len(growth.history["a"])
    assert rows == 6 and [t for t, _ in states] == list(range(rows))
    f = growth.fields
    np.testing.assert_array_equal(f["state_rows"], np.arange(1, rows))
    for row, (_, p) in enumerate(states):
        assert p.is_file() and p.parent.name == "result_series", p
        m = meshio.read(p)
        u = m.point_data["displacement"][:, :2]
        kinds = np.concatenate(m.cell_data["kind"])
        # the whole plate: every element is a standard cell or cut into cells
        ids = np.concatenate(m.cell_data["element_id"])
        assert set(ids[kinds != _vtk.CRACK]) == set(range(len(f["elements"])))
        # history values as field data
        assert int(m.field_data["row"][0]) == row
        for key in ("a", "load_factor", "K_I", "K_II", "sigma22", "cmod"):
            assert m.field_data[key][0] == growth.history[key][row], key
        if row == 0:  # the unloaded origin: the first state's mesh, undeformed
            assert (u == 0).all() and (np.concatenate(m.cell_data["stress"]) == 0).all()
        else:  # the standard nodes carry that state's displacement
            n = len(f["coords"])
            np.testing.assert_array_equal(u[:n], f["state_u"][row - 1].reshape(-1, 2))
    # the final state's crack (result.vtu and the last state) has grown: one line per segment
    for p in (tmp_path / "result.vtu", states[-1][1]):
        lines = [b for b in meshio.read(p).cells if b.type == "line"]
        assert sum(len(b.data) for b in lines) == len(f["crack"]) - 1


def _opening_profile(mesh: Any, tip: np.ndarray, direction: np.ndarray, h: float) -> np.ndarray:
    """(r, opening) of the crack faces 0.5 .. 2.5 element lengths ``h`` behind ``tip`` (the crack
    running along ``direction`` into the tip): the cut cells' vertices on the crack line, which
    the two faces share as points of their own, and the jump of their displacement normal to the
    crack."""
    pts = np.asarray(mesh.points)[:, :2]
    u = mesh.point_data["displacement"][:, :2]
    normal = np.array([-direction[1], direction[0]])
    cut = np.unique(
        np.concatenate(
            [b.data[k == _vtk.CUT].ravel() for b, k in zip(mesh.cells, mesh.cell_data["kind"])]
        )
    )
    rel = pts[cut] - tip
    r, off = -(rel @ direction), rel @ normal
    on = cut[(np.abs(off) < 1e-9 * h) & (r > 0.5 * h) & (r < 2.5 * h)]
    out = []
    for key in np.unique(np.round(pts[on] / (1e-6 * h)), axis=0):
        same = on[np.all(np.round(pts[on] / (1e-6 * h)) == key, axis=1)]
        jumps = u[same] @ normal
        if len(same) >= 2:
            out.append((float(-(pts[same[0]] - tip) @ direction), float(np.ptp(jumps))))
    return np.array(sorted(out))


def _check_state(mesh: Any, res: rf.Result, row: int) -> None:
    """The state of history row ``row`` read back: near its own tip the crack opens as LEFM says
    for its own K_I, delta(r) = 8 K_I / E' sqrt(r / (2 pi)) (the Williams / Irwin near-tip field,
    E' = E / (1 - nu^2) in plane strain), the largest s22 and the tip enrichment sit at its own
    tip."""
    scene = rf.Scene.from_dict(res.meta["scene"])
    mat = scene.material
    h = scene.plate.width / scene.mesh.nx
    e_prime = handbook.e_prime(mat.E, mat.nu, mat.plane)
    k_i = res.history["K_I"][row]
    tip = np.array([res.history["tip_x"][row], res.history["tip_y"][row]])
    lines = [b.data for b in mesh.cells if b.type == "line"]
    seg = np.asarray(mesh.points)[lines[0][-1], :2]
    direction = (seg[1] - seg[0]) / np.linalg.norm(seg[1] - seg[0])
    prof = _opening_profile(mesh, tip, direction, h)
    assert len(prof) >= 3, prof
    lefm = 8 * k_i / e_prime * np.sqrt(prof[:, 0] / (2 * np.pi))
    np.testing.assert_allclose(prof[:, 1], lefm, rtol=0.12)
    # the stress peak is at this state's tip
    best, at = -np.inf, None
    pts = np.asarray(mesh.points)[:, :2]
    for b, k, s in zip(mesh.cells, mesh.cell_data["kind"], mesh.cell_data["stress"]):
        if b.type == "line":
            continue
        c = pts[b.data].mean(axis=1)
        i = int(np.argmax(np.where(k != _vtk.CRACK, s[:, 1], -np.inf)))
        if s[i, 1] > best:
            best, at = s[i, 1], c[i]
    assert at is not None and np.linalg.norm(at - tip) < 1.0 * h, (at, tip)
    # the tip-enriched cells are those around this state's tip
    enr = np.concatenate(mesh.cell_data["enrichment"])
    c = np.concatenate([pts[b.data].mean(axis=1) for b in mesh.cells])
    assert (enr == 2).any() and np.all(np.linalg.norm(c[enr == 2] - tip, axis=1) < 2.5 * h)


def test_every_growth_state_opens_and_peaks_at_its_own_tip(tmp_path: Path) -> None:
    """Each state of a growth read back from the series: the crack opening near its tip follows
    the LEFM sqrt(r) profile with that state's own K_I and the s22 peak sits at that state's
    tip; a file of the initial solve with the final crack lines (what result.vtu held before the
    states were kept) fails the same check."""
    res = rf.run(rf.scenes.edge_crack_plate("xfem", mesh=(44, 83), bc="traction", growth_steps=4))
    res.save(tmp_path)
    states = series_of(tmp_path)
    assert [t for t, _ in states] == [0, 1, 2, 3, 4]
    assert len(set(res.history["tip_x"][1:])) == 4  # the tip moves from state to state
    for row, p in states[1:]:
        _check_state(meshio.read(p), res, int(row))
    _check_state(meshio.read(tmp_path / "result.vtu"), res, 4)
    # the old file: the initial solve's cut cells and displacement, the final crack lines
    old = _vtk.initial_state(res)
    old = _vtk.XfemState(
        4,
        old.u,
        old.stress,
        old.cut_points,
        old.cut_disp,
        old.cut_offsets,
        old.cut_element,
        old.cut_stress,
        res.crack_polylines,
    )
    _vtk.write_vtu(tmp_path / "old.vtu", _vtk.xfem_parts(res, old))
    with pytest.raises(AssertionError):
        _check_state(meshio.read(tmp_path / "old.vtu"), res, 4)


def test_sla_series_has_one_state_per_damage_snapshot(ccm: rf.Result, tmp_path: Path) -> None:
    ccm.save(tmp_path)
    states = series_of(tmp_path)
    f = ccm.fields
    assert [t for t, _ in states] == [5.0, 10.0]
    crit = ccm.history["bond"][1:]  # the steps' critical bonds (tie_tol = 0: one a step)
    pre = np.setdiff1d(np.flatnonzero(f["broken"]), crit)  # the pre-crack's
    assert len(pre) > 0
    for (step, p), dmg in zip(states, f["damage_at"]):
        m = meshio.read(p)
        np.testing.assert_array_equal(m.point_data["damage"][f["pd_nodes"]], dmg)
        # the bonds broken by that step, as lines between their end nodes
        (lines,) = [b.data for b in m.cells if b.type == "line"]
        want = np.union1d(pre, crit[: int(step)])
        np.testing.assert_array_equal(lines, f["bond_nodes"][want])
        assert m.field_data["step"][0] == step
        assert m.field_data["load_factor"][0] == ccm.history["load_factor"][int(step)]
    assert not np.array_equal(f["damage_at"][0], f["damage_at"][1])


def test_new_files_are_listed_in_the_checksums(growth: rf.Result, tmp_path: Path) -> None:
    growth.save(tmp_path)
    doc = json.loads((tmp_path / "result.json").read_text())
    on_disk = {
        p.relative_to(tmp_path).as_posix()
        for p in tmp_path.rglob("*")
        if p.is_file() and p.name != "result.json"
    }
    assert "result.pvd" in on_disk and "result_series/state_0005.vtu" in on_disk
    assert set(doc["files"]) == on_disk
    for name, entry in doc["files"].items():
        assert hashlib.sha256((tmp_path / name).read_bytes()).hexdigest() == entry["sha256"]
    rf.load(tmp_path)


def test_a_later_save_removes_the_series(
    growth: rf.Result, xfem: rf.Result, tmp_path: Path
) -> None:
    (tmp_path / "result_series").mkdir()
    (tmp_path / "result_series" / "notes.txt").write_text("mine")
    growth.save(tmp_path)
    xfem.save(tmp_path)  # no growth: no series
    assert not (tmp_path / "result.pvd").exists()
    assert [p.name for p in (tmp_path / "result_series").iterdir()] == ["notes.txt"]
    growth.save(tmp_path)
    (tmp_path / "result_series" / "notes.txt").unlink()
    growth.save(tmp_path, vtu=False)  # vtu=False: no VTU output at all
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fields.npz", "result.json"]


def test_failure_while_staging_the_series_keeps_the_previous_folder(
    growth: rf.Result, xfem: rf.Result, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    xfem.save(tmp_path)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    real, calls = _vtk.write_vtu, []

    def full(path: Path, parts: Any) -> None:
        calls.append(path)
        if len(calls) == 4:  # result.vtu and two states are written
            raise OSError(28, "No space left on device")
        real(path, parts)

    monkeypatch.setattr(_vtk, "write_vtu", full)
    with pytest.raises(rf.OutputError, match="No space left"):
        growth.save(tmp_path)
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before  # no result_series/
    assert rf.load(tmp_path).history == {}


def test_without_meshio_the_same_files_are_written(
    growth: rf.Result, ccm: rf.Result, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # rustfrac writes result.vtu and the time series itself: without meshio the files are the
    # same, byte for byte, and meshio (an independent reader) reads them back as to_meshio's mesh
    for res, name in ((growth, "growth"), (ccm, "ccm")):
        with_meshio, without = tmp_path / f"{name}_with", tmp_path / f"{name}_without"
        res.save(with_meshio)
        with monkeypatch.context() as mp:
            mp.setitem(sys.modules, "meshio", None)  # import meshio fails
            res.save(without)
            with pytest.raises(ImportError, match=r"meshio.*rustfrac\[io\]"):
                res.to_meshio()
        files = sorted(p.relative_to(with_meshio) for p in with_meshio.rglob("*.vt?"))
        assert files == sorted(p.relative_to(without) for p in without.rglob("*.vt?"))
        assert Path("result.vtu") in files
        for f in files:
            assert (with_meshio / f).read_bytes() == (without / f).read_bytes(), f
        m, ref = meshio.read(without / "result.vtu"), res.to_meshio()
        np.testing.assert_array_equal(m.points, ref.points)
        for key, a in ref.point_data.items():
            np.testing.assert_array_equal(m.point_data[key], a, err_msg=key)
        rf.load(without)
    assert (tmp_path / "growth_without" / "result.pvd").exists()
    m = meshio.read(tmp_path / "ccm_without" / "result.vtu")
    assert int(m.point_data["broken_bonds"].sum()) == 2 * int(ccm.fields["broken"].sum())


def test_to_meshio_needs_a_mesh() -> None:
    with pytest.raises(rf.PlotDataError, match="mesh"):
        rf.Result("pd", 1.0, 0.0, 1, 0.0).to_meshio()


def test_to_pyvista_without_pyvista(fem: rf.Result, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pyvista", None)
    with pytest.raises(ImportError, match=r"pyvista.*rustfrac\[viz\]"):
        fem.to_pyvista()


def test_to_pyvista(fem: rf.Result) -> None:
    pytest.importorskip("pyvista")
    grid = fem.to_pyvista()
    assert grid.n_points == len(fem.coords) and grid.n_cells == len(fem.elements)
    np.testing.assert_array_equal(grid.point_data["displacement"][:, :2], fem.displacement)


def test_xfem_cells_carry_the_enriched_stress(tmp_path: Path) -> None:
    # traction grips: far from the crack s22 is the applied traction; the cut cells along the
    # crack faces near the mouth carry the stress of their own side, which the traction-free
    # faces make small (LEFM: s22 = s12 = 0 on the faces), mirrored on the two sides
    res = rf.run(rf.scenes.edge_crack_plate("xfem", mesh=(44, 83), bc="traction"))
    mesh = read_back(res, tmp_path)
    t = res.sigma22
    pts = np.asarray(mesh.points)[:, :2]
    kind = np.concatenate(mesh.cell_data["kind"])
    stress = np.concatenate(mesh.cell_data["stress"])
    c = np.concatenate([pts[b.data].mean(axis=1) for b in mesh.cells])
    faces = (kind == _vtk.CUT) & (c[:, 0] < 0.6) & (np.abs(c[:, 1] - 10.5) < 0.1)
    assert faces.any()
    assert np.all(np.abs(stress[faces, 1]) < 0.05 * t), stress[faces]
    above, below = faces & (c[:, 1] > 10.5), faces & (c[:, 1] < 10.5)
    assert above.any() and above.sum() == below.sum()
    # mode I: the two faces mirror each other, s12 of opposite signs (the cells pair by x1)
    a = np.flatnonzero(above)[np.argsort(c[above, 0])]
    b = np.flatnonzero(below)[np.argsort(c[below, 0])]
    np.testing.assert_allclose(c[a, 0], c[b, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(stress[a, :2], stress[b, :2], rtol=1e-6, atol=1e-6 * t)
    np.testing.assert_allclose(stress[a, 2], -stress[b, 2], rtol=1e-6, atol=1e-6 * t)
    assert np.all(np.abs(stress[faces, 2]) < 0.1 * t)
    far = (kind == _vtk.STANDARD) & (np.abs(c[:, 1] - 3.0) < 0.3)
    assert far.any() and np.allclose(stress[far, 1], t, rtol=0.02), stress[far, 1]


@pytest.mark.parametrize("every", [0, 2])
def test_state_every_limits_the_kept_states(every: int, tmp_path: Path) -> None:
    """``xfem.state_every = k`` keeps every k-th growth step's state and the last one (the
    series holds those and the origin); 0 keeps none: no series, and result.vtu is the single
    solve with the initial crack (its own cut cells and opening, not the grown crack's lines)."""
    scene = rf.scenes.edge_crack_plate("xfem", mesh=MESH, growth_steps=4)
    res = rf.run(scene.replace(xfem__state_every=every))
    rows = len(res.history["a"])
    assert rows == 5
    kept = list(res.fields["state_rows"])
    assert kept == ([] if every == 0 else [1, 3, 4])
    assert res.fields["state_u"].shape == (len(kept), len(res.fields["u"]))
    assert res.fields["state_stress"].shape == (len(kept), len(res.fields["elements"]), 3)
    res.save(tmp_path)
    if every == 0:
        assert not (tmp_path / "result.pvd").exists()
        m = meshio.read(tmp_path / "result.vtu")
        lines = [b for b in m.cells if b.type == "line"]
        assert sum(len(b.data) for b in lines) == len(res.fields["crack_initial"]) - 1
        np.testing.assert_array_equal(
            m.point_data["displacement"][: len(res.coords), :2], res.displacement
        )
    else:
        assert [t for t, _ in series_of(tmp_path)] == [0, 1, 3, 4]


def test_state_every_out_of_range_names_the_key() -> None:
    scene = rf.scenes.edge_crack_plate("xfem", mesh=MESH, growth_steps=2)
    with pytest.raises(rf.InvalidParameterError, match=r"\[0, 100000\]") as e:
        rf.run(scene.replace(xfem__state_every=-1))
    assert e.value.param == "xfem.state_every"
