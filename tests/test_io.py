"""Saving and loading results; VTU; plots."""

from __future__ import annotations

import base64
import json
import sys
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf


def test_save_load_round_trip(seam: rf.Result, tmp_path: Path) -> None:
    out = seam.save(tmp_path / "a" / "b")
    assert sorted(p.name for p in out.iterdir()) == ["fields.npz", "result.json", "result.vtu"]
    back = rf.load(out)
    assert back.method == seam.method
    assert back.sigma22 == seam.sigma22  # identical, not approximately
    assert back.cmod == seam.cmod
    assert back.n_dofs == seam.n_dofs
    assert back.wall_time_s == seam.wall_time_s
    assert back.scalars == seam.scalars
    assert set(back.fields) == set(seam.fields)
    for k, v in seam.fields.items():
        np.testing.assert_array_equal(back.fields[k], v)
        assert back.fields[k].dtype == v.dtype
    doc = json.loads((out / "result.json").read_text())
    assert doc["meta"]["bc"] == "free"
    assert doc["meta"]["version"] == rf.__version__
    assert doc["meta"]["scene"] == rf.scenes.edge_crack_plate().to_dict()
    assert rf.Scene.from_dict(back.meta["scene"]) == rf.scenes.edge_crack_plate()


def test_history_round_trip(tmp_path: Path) -> None:
    h = {
        "load_factor": np.linspace(0, 1, 5),
        "sigma22": np.arange(5.0),
        "cmod": np.ones(5),
        "u0": np.full(5, 0.01),
    }
    r = rf.Result(
        method="pd",
        sigma22=1.0,
        cmod=2.0,
        n_dofs=3,
        wall_time_s=0.5,
        history=h,
        scalars={"gamma": 0.988895997195466},
    )
    back = rf.load(r.save(tmp_path))
    assert back.gamma == r.gamma
    for k in h:
        np.testing.assert_array_equal(back.history[k], h[k])
    assert not (tmp_path / "result.vtu").exists()  # no mesh, no VTU
    with pytest.raises(ValueError, match="equal lengths"):
        rf.Result(
            method="pd",
            sigma22=1,
            cmod=1,
            n_dofs=1,
            wall_time_s=0,
            history={"a": np.ones(2), "b": np.ones(3)},
        )


def test_save_is_atomic_and_overwrites(uncracked: rf.Result, tmp_path: Path) -> None:
    uncracked.save(tmp_path)
    uncracked.save(tmp_path)  # overwriting works
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".") or "tmp" in p.name]


def test_failed_save_leaves_no_temp_file(tmp_path: Path) -> None:
    r = rf.Result(
        method="fem", sigma22=1.0, cmod=0.0, n_dofs=1, wall_time_s=0.0, scalars={"bad": object()}
    )
    with pytest.raises(TypeError):
        r.save(tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_vtu_is_valid_unstructured_grid(
    uncracked: rf.Result, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # without meshio: rustfrac's binary VTU, decoded here by hand from the VTK XML format (a
    # UInt64 header of block count, block size, last block size and compressed sizes, then the
    # zlib blocks, base64 encoded); tests/test_meshio.py reads the same file with meshio
    monkeypatch.setitem(sys.modules, "meshio", None)
    uncracked.save(tmp_path)
    root = ET.parse(tmp_path / "result.vtu").getroot()
    assert root.get("compressor") == "vtkZLibDataCompressor"
    assert root.get("header_type") == "UInt64"
    piece = root.find("UnstructuredGrid/Piece")
    assert piece is not None
    n, m = len(uncracked.coords), len(uncracked.elements)
    assert int(piece.get("NumberOfPoints")) == n
    assert int(piece.get("NumberOfCells")) == m
    arrays = {a.get("Name"): a for a in piece.iter("DataArray")}
    assert {"displacement", "stress", "Points", "connectivity", "offsets", "types"} <= set(arrays)

    def decode(name: str) -> np.ndarray:
        # the header and the blocks are base64-encoded separately, the header first
        a = arrays[name]
        text = a.text.strip()
        nb = int(np.frombuffer(base64.b64decode(text[:12])[:8], dtype="<u8")[0])
        head = 4 * -(-8 * (3 + nb) // 3)  # base64 characters of the header
        sizes = np.frombuffer(base64.b64decode(text[:head]), dtype="<u8")[3:]
        raw, data, pos = base64.b64decode(text[head:]), b"", 0
        for c in sizes:
            data += zlib.decompress(raw[pos : pos + int(c)])
            pos += int(c)
        dtype = {"Float64": "<f8", "Int64": "<i8", "UInt8": "u1"}[a.get("type")]
        return np.frombuffer(data, dtype=dtype).reshape(-1, int(a.get("NumberOfComponents", 1)))

    np.testing.assert_array_equal(decode("Points")[:, :2], uncracked.coords)
    np.testing.assert_array_equal(decode("connectivity").reshape(-1, 4), uncracked.elements)
    assert set(decode("types").ravel()) == {9}
    np.testing.assert_array_equal(decode("displacement")[:, :2], uncracked.displacement)


def test_plot(seam: rf.Result, tmp_path: Path) -> None:
    from rustfrac.plotting import save_plot

    p = save_plot(seam, tmp_path / "s22.png")
    assert p.stat().st_size > 1000


def test_saved_files_respect_umask(uncracked: rf.Result, tmp_path: Path) -> None:
    import os

    old = os.umask(0o022)
    try:
        uncracked.save(tmp_path)
    finally:
        os.umask(old)
    for p in tmp_path.iterdir():
        assert p.stat().st_mode & 0o777 == 0o644, p
