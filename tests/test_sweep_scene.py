"""Sweeps of the user's own scene: ``rustfrac sweep SCENE.toml --param ...``
and ``rustfrac.sweep.sweep_scene``: levels, quantities, repeated timings, Richardson, dask."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from rustfrac import handbook
from rustfrac.cli import main
from rustfrac.errors import InvalidParameterError, UnknownParameterError
from rustfrac.scene import Scene
from rustfrac.scenes import edge_crack_plate
from rustfrac.sweep import extrapolate, scene_points, sweep_scene

#: a user scene: an inclined XFEM edge crack (K_II != 0), small meshes
USER_TOML = """\
method = "xfem"
name = "my plate"

[plate]
width = 11.0
height = 21.0

[crack]
kind = "edge"
a0 = 2.0
y = 10.5
angle = 20.0

[mesh]
nx = 22
ny = 41
"""


@pytest.fixture(scope="module")
def user_toml(tmp_path_factory: pytest.TempPathFactory) -> Path:
    p = tmp_path_factory.mktemp("scene") / "my_plate.toml"
    p.write_text(USER_TOML)
    return p


@pytest.fixture(scope="module")
def local_cli(user_toml: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    out = tmp_path_factory.mktemp("sweep_local")
    argv = ["sweep", str(user_toml), "--param", "mesh", "--levels", "22x41,2", "--quantity",
            "K_II", "--repeats", "2", "--workers", "2", "--out", str(out), "-q"]  # fmt: skip
    assert main(argv) == 0
    return {"out": out, "doc": json.loads((out / "sweep.json").read_text())}


# -- Richardson ---------------------------------------------------------------------------------


@pytest.mark.parametrize(("hs", "p"), [((0.4, 0.2, 0.1), 2.0), ((1.0, 0.6, 0.25), 1.3)])
def test_richardson_recovers_limit_rate_and_errors(hs: tuple[float, ...], p: float) -> None:
    q_star, c = 2.5, -0.8
    qs = [q_star + c * h**p for h in hs]
    r = extrapolate([9.0, *hs], [q_star + c * 9.0**p, *qs])  # the coarsest level is not used
    assert r["status"] == "ok" and r["levels"] == [1, 2, 3]
    assert r["value"] == pytest.approx(q_star, rel=1e-9)
    assert r["rate"] == pytest.approx(p, rel=1e-6)
    for h, e in zip((9.0, *hs), r["error_estimates"]):
        assert e["abs"] == pytest.approx(c * h**p, rel=1e-6, abs=1e-12)
    if hs[0] / hs[1] == hs[1] / hs[2]:  # constant ratio: the closed form
        d1, d2 = qs[1] - qs[0], qs[2] - qs[1]
        assert r["constant_ratio"] and r["rate"] == pytest.approx(
            math.log(abs(d1) / abs(d2)) / math.log(hs[0] / hs[1]), rel=1e-6
        )
    else:
        assert r["constant_ratio"] is False


def test_richardson_refuses_outside_the_asymptotic_range() -> None:
    hs = (0.4, 0.2, 0.1)
    for qs, why in (
        ([1.0, 2.0, 1.5], "change sign"),  # oscillating
        ([1.0, 1.1, 1.4], "outside"),  # growing differences: p < 0
        ([1.0, 1.0, 1.0], "zero"),
    ):
        r = extrapolate(hs, qs)
        assert r["status"] == "not in the asymptotic range" and why in r["why"]
        assert r["value"] is None and r["rate"] is None
        assert r["error_estimates"] == [None] * 3
    assert extrapolate((0.4, 0.2), (1.0, 1.1))["status"] == "not applicable"
    assert "length scale" in extrapolate((None, None, None), (1.0, 1.1, 1.2))["why"]


# -- levels --------------------------------------------------------------------------------------


def test_mesh_multipliers_keep_the_crack_inside_its_row() -> None:
    pts = scene_points(edge_crack_plate("xfem"), "mesh", [1, 2, 4])
    # the paper's levels: the crack at x2 = 10.5 stays halfway across an element row
    assert [p["value"] for p in pts] == [[44, 83], [88, 167], [176, 333]]
    assert pts[0]["h"] > pts[1]["h"] > pts[2]["h"]
    with pytest.raises(InvalidParameterError, match="aspect") as e:
        scene_points(edge_crack_plate("xfem"), "mesh", [(44, 83), (88, 83)])
    assert e.value.param == "levels"
    with pytest.raises(InvalidParameterError, match="same mesh"):
        scene_points(edge_crack_plate("xfem"), "mesh", [1, (44, 83)])


def test_params_refused_with_the_valid_ones() -> None:
    pd = edge_crack_plate("ccm_pd", dx=1 / 5, sla_steps=2)
    with pytest.raises(InvalidParameterError, match=r"pd\.dx") as e:
        scene_points(pd, "mesh", [1, 2])
    assert e.value.param == "param"
    with pytest.raises(InvalidParameterError, match="mesh"):
        scene_points(edge_crack_plate("xfem"), "pd.dx", [0.2])
    with pytest.raises(InvalidParameterError, match=r"section\.key"):
        scene_points(edge_crack_plate("xfem"), "nsub", [1, 2])
    with pytest.raises(UnknownParameterError):
        scene_points(edge_crack_plate("xfem"), "xfem.nosuch", [1])
    # a dx that does not fit the plate: the core's own error, naming pd.dx, before any run
    with pytest.raises(InvalidParameterError) as e:
        scene_points(pd, "pd.dx", [1 / 5, 1 / 4])
    assert e.value.param in ("pd.dx", "pd.size")  # the core names the rule it checks
    assert [p["h"] for p in scene_points(pd, "pd.dx", [1 / 5, 1 / 9])] == [1 / 5, 1 / 9]


def test_unknown_quantity_lists_the_valid_ones() -> None:
    sc = edge_crack_plate("xfem", mesh=(22, 41))
    with pytest.raises(InvalidParameterError, match="K_II") as e:
        sweep_scene(sc, "mesh", [1, 2], "K_III", repeats=1, workers=1)
    assert e.value.param == "quantity" and "xfem" in str(e.value) and "peak_" not in str(e.value)
    with pytest.raises(InvalidParameterError, match="repeats"):
        sweep_scene(sc, "mesh", [1], repeats=0)


def test_generic_key_sweep_has_no_richardson() -> None:
    st = sweep_scene(
        edge_crack_plate("xfem", mesh=(22, 41), growth_steps=2), "xfem.nsub", [1, 2, 4],
        "peak_sigma22", repeats=1, workers=2,
    )  # fmt: skip
    assert [r["value"] for r in st["levels"]] == [1, 2, 4]
    assert all(r["q"] > 0 for r in st["levels"])  # the peak of the growth history
    assert st["richardson"]["status"] == "not applicable" and st["presets"] == {}


# -- a real XFEM K_I sweep against the handbook ---------------------------------------------------


def test_xfem_k_i_extrapolates_to_the_handbook() -> None:
    """Tada's edge crack, a/W = 0.3 (the shipped tall-strip example on 20 x 81 .. 80 x 325)."""
    from rustfrac import examples

    sc = Scene.from_toml(examples.path("tall_plate_handbook")).replace(mesh__nx=20, mesh__ny=81)
    st = sweep_scene(sc, "mesh", [1, 2, 4], "K_I", repeats=2, workers=2)
    rich = st["richardson"]
    assert rich["status"] == "ok" and 0.5 < rich["rate"] < 2.0
    k_hb = math.sqrt(math.pi * 0.3) * float(handbook.tada_F(0.3))  # 1.6068
    assert abs(rich["value"] - k_hb) / k_hb < 0.005  # Tada's formula: 0.5 %
    coarse = st["levels"][0]
    assert abs(rich["value"] - k_hb) < abs(coarse["q"] - k_hb)
    errs = [r["rel_err_est"] for r in st["levels"]]
    assert errs[0] > errs[1] > errs[2] > 0  # each level's estimated error falls with h
    assert all(r["repeats"] == 2 and r["wall_time_s"] > 0 for r in st["levels"])
    assert st["presets"]["fast"]["point"] is not None


# -- CLI and dask ---------------------------------------------------------------------------------


def test_cli_scene_sweep_writes_the_files(local_cli: dict[str, Any]) -> None:
    out, doc = local_cli["out"], local_cli["doc"]
    assert doc["complete"] is True and doc["missing_points"] == [] and doc["kind"] == "scene"
    assert doc["param"] == "mesh" and doc["quantity"] == "K_II"
    # an inclined crack crosses the rows anyway: plain multiples, no snapping of ny
    assert [r["value"] for r in doc["levels"]] == [[22, 41], [44, 82]]
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert [r["value"] for r in rows] == ["22x41", "44x82"]
    assert all(abs(float(r["K_II"])) > 1e-3 for r in rows)  # inclined crack: mixed mode
    assert "Richardson" in (out / "sweep.md").read_text()
    assert doc["richardson"]["status"] == "not applicable"  # two levels
    assert all(len(p["wall_times_s"]) == 2 for p in doc["points"])
    assert not list(out.glob(".*.tmp"))


def test_dask_local_cluster_gives_identical_numbers(
    local_cli: dict[str, Any], user_toml: Path, tmp_path: Path
) -> None:
    pytest.importorskip("distributed")
    argv = ["sweep", str(user_toml), "--param", "mesh", "--levels", "1,2", "--quantity",
            "K_II", "--repeats", "1", "--dask", "local", "--workers", "1", "--out",
            str(tmp_path), "-q"]  # fmt: skip
    assert main(argv) == 0
    remote = json.loads((tmp_path / "sweep.json").read_text())
    local = local_cli["doc"]
    assert [r["name"] for r in remote["points"]] == [r["name"] for r in local["points"]]
    for a, b in zip(local["points"], remote["points"]):
        assert a["quantities"] == b["quantities"]  # every response, bit for bit
    assert [r["q"] for r in remote["levels"]] == [r["q"] for r in local["levels"]]
    # value .. rel_err_est (the level column says "1" here, "22x41" there)
    assert (tmp_path / "sweep.csv").read_text().splitlines()[1].split(",")[2:8] == (
        (local_cli["out"] / "sweep.csv").read_text().splitlines()[1].split(",")[2:8]
    )


def test_cli_scene_sweep_bad_input_exits_2(
    user_toml: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["sweep", str(user_toml), "--out", str(tmp_path), "-q"]) == 2
    assert "--param and --levels" in capsys.readouterr().err
    assert main(["sweep", "--param", "mesh", "--levels", "1", "--out", str(tmp_path)]) == 2
    assert "need a scene file" in capsys.readouterr().err
    argv = ["sweep", str(user_toml), "--param", "pd.dx", "--levels", "0.2", "--out",
            str(tmp_path), "-q"]  # fmt: skip
    assert main(argv) == 2
    assert "pd.dx" in capsys.readouterr().err
    assert not (tmp_path / "sweep.json").exists()


def test_quantities_of_covers_every_scalar() -> None:
    from rustfrac import run
    from rustfrac.sweep import quantities_of

    res = run(edge_crack_plate("xfem", mesh=(22, 41)))
    q = quantities_of(res)
    assert {"K_I", "K_II", "J", "sigma22", "cmod", "n_dofs"} <= set(q)
    assert q["K_I"] == res.K_I and q["K_II"] == res.K_II
    assert all(isinstance(v, float) and np.isfinite(v) for v in q.values())
