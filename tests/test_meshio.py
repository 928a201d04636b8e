"""Results as meshio meshes and ParaView files: result.vtu written through
meshio and read back, the XFEM cut cells on both crack faces, FEM element stresses, PD broken
bonds, the time series result.pvd, the ASCII fallback without meshio, and the result folder as
one unit with the new files."""

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
from rustfrac import _vtk

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
        points, cells, pdata, cdata = parts
        ours, ref = tmp_path / f"ours{k}.vtu", tmp_path / f"ref{k}.vtu"
        _vtk.write_vtu(ours, parts)
        mesh = meshio.Mesh(points, cells, point_data=pdata, cell_data=cdata)
        meshio.write(ref, mesh, file_format="vtu", binary=True, compression="zlib")
        _assert_same_mesh(meshio.read(ours), meshio.read(ref))


def test_xfem_cut_cells_show_the_crack_opening(xfem: rf.Result, tmp_path: Path) -> None:
    m = read_back(xfem, tmp_path)
    f = xfem.fields
    n = len(f["coords"])
    u = m.point_data["displacement"]
    assert u.shape[1] == 3 and not np.isnan(u).any() and (u[:, 2] == 0).all()
    kinds = np.concatenate(m.cell_data["kind"])
    ids = np.concatenate(m.cell_data["element_id"])
    # the cut cells exist, one per polygon of the result, and replace their parent elements
    assert (kinds == _vtk.CUT).sum() == len(f["cut_element"]) > 0
    assert sorted(ids[kinds == _vtk.CUT]) == sorted(f["cut_element"])
    std = ids[kinds == _vtk.STANDARD]
    assert not set(std) & set(f["cut_element"])
    assert len(std) + len(np.unique(f["cut_element"])) == len(f["elements"])
    # the standard cells sit on the mesh nodes and carry u there
    # (meshio reads consecutive cells of one type as one block: select by the kind cell data)
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
    n = len(f["node_xy"])
    assert [b.type for b in m.cells] == ["vertex"] and len(m.cells[0].data) == n
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


def series_of(d: Path) -> list[tuple[float, Path]]:
    root = ET.parse(d / "result.pvd").getroot()
    assert root.get("type") == "Collection"
    return [(float(e.get("timestep")), d / e.get("file")) for e in root.iter("DataSet")]


def test_growth_series_has_one_state_per_history_row(growth: rf.Result, tmp_path: Path) -> None:
    growth.save(tmp_path)
    states = series_of(tmp_path)
    rows = len(growth.history["a"])
    assert rows == 6 and [t for t, _ in states] == list(range(rows))
    off, cells = growth.fields["snapshot_offsets"], growth.fields["snapshot_cells"]
    disp = growth.fields["snapshot_disp"]
    for row, (_, p) in enumerate(states):
        assert p.is_file() and p.parent.name == "result_series", p
        m = meshio.read(p)
        u = m.point_data["displacement"][:, :2]
        if row == 0:  # the unloaded origin: the first patch, undeformed
            assert len(m.cells[0].data) == off[1] and (u == 0).all()
        else:
            k = row - 1
            np.testing.assert_array_equal(
                m.points[:, :2], cells[off[k] : off[k + 1]].reshape(-1, 2)
            )
            np.testing.assert_array_equal(u, disp[off[k] : off[k + 1]].reshape(-1, 2))
    # the final state's crack has grown: one line per segment
    lines = [b for b in meshio.read(tmp_path / "result.vtu").cells if b.type == "line"]
    assert sum(len(b.data) for b in lines) == len(growth.fields["crack"]) - 1


def test_sla_series_has_one_state_per_damage_snapshot(ccm: rf.Result, tmp_path: Path) -> None:
    ccm.save(tmp_path)
    states = series_of(tmp_path)
    f = ccm.fields
    assert [t for t, _ in states] == [5.0, 10.0]
    for (_, p), dmg in zip(states, f["damage_at"]):
        m = meshio.read(p)
        np.testing.assert_array_equal(m.point_data["damage"][f["pd_nodes"]], dmg)
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
    # faces make small (LEFM: s22 = 0 on the faces), with s12 of opposite signs on the two sides
    res = rf.run(rf.scenes.edge_crack_plate("xfem", mesh=(44, 83), bc="traction"))
    mesh = read_back(res, tmp_path)
    t = res.sigma22
    pts = np.asarray(mesh.points)[:, :2]
    for (ctype, conn), kind, stress in zip(
        [(b.type, b.data) for b in mesh.cells],
        mesh.cell_data["kind"],
        mesh.cell_data["stress"],
    ):
        c = (
            pts[conn].mean(axis=1)
            if ctype != "polygon"
            else np.array([pts[row].mean(axis=0) for row in conn])
        )
        if kind[0] == _vtk.CUT:
            faces = (c[:, 0] < 0.6) & (np.abs(c[:, 1] - 10.5) < 0.1)
            assert faces.any()
            assert np.all(np.abs(stress[faces, 1]) < 0.05 * t), stress[faces]
            above = faces & (c[:, 1] > 10.5)
            below = faces & (c[:, 1] < 10.5)
            assert np.all(stress[above, 2] * stress[below, 2].mean() < 0)
        elif kind[0] == _vtk.STANDARD:
            far = np.abs(c[:, 1] - 3.0) < 0.3
            assert np.allclose(stress[far, 1], t, rtol=0.02), stress[far, 1]
