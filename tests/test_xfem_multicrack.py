"""XFEM with several cracks from Python: scenes ([[crack]] tables, ``crack=[...]``), per-tip SIFs,
symmetric growth, save/load, and refused crack sets."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import rustfrac as rf
from rustfrac.errors import InvalidParameterError
from rustfrac.scene import Crack


def dent(a: float = 0.2, **kw: object) -> rf.Scene:
    """Double-edge-cracked strip, width 1 (= 2b), height 4, cracks of depth ``a`` at mid-height."""
    return rf.scenes.edge_crack_plate(
        "xfem",
        width=1.0,
        height=4.0,
        mesh=(40, 161),
        E=1000.0,
        nu=0.3,
        bc="traction",
        traction=1.0,
        cracks=[
            Crack(kind="edge", a0=a, y=2.0),
            {"kind": "edge", "side": "right", "a0": a, "y": 2.0},
        ],
        **kw,  # type: ignore[arg-type]
    )


def tada_dent(x: float) -> float:
    """Tada's double-edge-crack factor (tan form), x = a/b."""
    t = math.pi * x / 2
    return (1 + 0.122 * math.cos(t) ** 4) * math.sqrt(2 / (math.pi * x) * math.tan(t))


def test_two_crack_scene_runs_and_round_trips(tmp_path: Path) -> None:
    scene = dent()
    assert len(scene.cracks) == 2 and scene.extra_cracks[0].side == "right"
    text = scene.to_toml()
    assert text.count("[[crack]]") == 2
    assert rf.Scene.from_toml_str(text) == scene
    res = rf.run(scene)
    tips = res.tip_sifs
    assert [t["crack"] for t in tips] == [0, 1]
    assert tips[0]["x1"] == pytest.approx(0.2) and tips[1]["x1"] == pytest.approx(0.8)
    f = tada_dent(0.4)
    for t in tips:
        assert t["K_I"] / math.sqrt(math.pi * 0.2) == pytest.approx(f, rel=0.03)
        assert abs(t["K_II"]) < 1e-6 * t["K_I"]
    assert tips[0]["K_I"] == pytest.approx(tips[1]["K_I"], rel=1e-9)
    assert res.K_I == tips[0]["K_I"]  # the primary tip
    assert len(res.meta["cracks_initial"]) == 2
    res.save(tmp_path)
    back = rf.load(tmp_path)
    assert back.tip_sifs == tips
    assert [p.tolist() for p in back.crack_polylines] == [
        [[0.0, 2.0], [0.2, 2.0]],
        [[1.0, 2.0], [0.8, 2.0]],
    ]


def test_symmetric_growth_stays_symmetric() -> None:
    res = rf.run(dent(0.1, growth_steps=6))
    f = res.fields
    x, grows = f["tip_history_x"], f["tip_history_grows"]
    assert x.shape == (len(res.history["load_factor"]), 2)
    np.testing.assert_allclose(x[:, 0], 1.0 - x[:, 1], atol=1e-9)
    assert grows[1:].all() and not grows[0].any()
    np.testing.assert_allclose(f["tip_history_K_I"][:, 0], f["tip_history_K_I"][:, 1], rtol=1e-6)
    left, right = res.crack_polylines
    np.testing.assert_allclose(left[:, 0], 1.0 - right[:, 0], atol=1e-9)
    assert len(left) == 2 + 5  # mouth, initial tip, one point per growth step but the last


def test_toml_array_of_crack_tables() -> None:
    text = """
method = "xfem"
[plate]
width = 20.0
height = 20.0
[[crack]]
kind = "center"
a0 = 1.0
x = 6.0
y = 10.0
[[crack]]
kind = "center"
a0 = 1.0
x = 14.0
y = 10.0
angle = 30.0
"""
    s = rf.Scene.from_toml_str(text)
    assert s.crack.x == 6.0 and s.extra_cracks[0].angle == 30.0
    assert "1 more crack" in s.describe()
    # a single [crack] table still gives one crack
    assert rf.Scene.from_toml_str(text.split("[[crack]]")[0]).extra_cracks == ()


@pytest.mark.parametrize(
    ("cracks", "param"),
    [
        # crossing cracks
        (
            [
                {"kind": "center", "a0": 1.0, "x": 5.0, "y": 10.0},
                {"kind": "center", "a0": 1.0, "x": 5.0, "y": 10.0, "angle": 90.0},
            ],
            "crack[1]",
        ),
        # the second crack's tip outside the plate
        (
            [
                {"kind": "edge", "a0": 1.0, "y": 10.0},
                {"kind": "center", "a0": 2.0, "x": 10.0, "y": 10.0},
            ],
            "crack[1].a0",
        ),
        # a bad key in the second crack
        ([{"kind": "edge"}, {"kind": "edge", "a0": -1.0}], "crack[1].a0"),
        ([{"kind": "edge"}, {"kind": "edge", "side": "middle"}], "crack[1].side"),
    ],
)
def test_bad_crack_sets_name_the_crack(cracks: list[dict[str, object]], param: str) -> None:
    with pytest.raises(InvalidParameterError) as e:
        rf.scenes.edge_crack_plate("xfem", cracks=cracks)
    assert e.value.param == param, str(e.value)


def test_several_cracks_need_xfem_and_core_refusals_name_scene_keys() -> None:
    with pytest.raises(InvalidParameterError) as e:
        rf.scenes.edge_crack_plate("fem", cracks=[{"kind": "seam"}, {"kind": "seam", "y": 5.0}])
    assert e.value.param == "crack"
    # tips of two cracks in one element (44 x 83: elements 0.25 wide): refused by the core
    scene = rf.scenes.edge_crack_plate(
        "xfem",
        cracks=[{"kind": "edge", "a0": 5.3}, {"kind": "edge", "side": "right", "a0": 5.6}],
    )
    with pytest.raises(InvalidParameterError) as e:
        rf.run(scene)
    assert e.value.param == "crack", str(e.value)
    # another crack inside the SIF domain of the primary tip
    scene = rf.scenes.edge_crack_plate(
        "xfem",
        cracks=[{"kind": "edge", "a0": 5.0}, {"kind": "edge", "side": "right", "a0": 5.6}],
    )
    with pytest.raises(InvalidParameterError) as e:
        rf.run(scene)
    assert e.value.param == "xfem.r_I", str(e.value)


def test_tip_tie_tolerance_decides_which_tips_grow() -> None:
    """xfem.tip_tie_tol (a scene key defined only in the core's schema): tips whose critical
    load factor lies within it of the smallest grow together. Two edge cracks of different
    length: with the default 1e-6 only the longer (more critical) one grows in the first step;
    with 0.9 both do. Out-of-range values are refused naming the key."""
    cracks = [
        {"kind": "edge", "a0": 1.5, "y": 10.5},
        {"kind": "edge", "side": "right", "a0": 1.1, "y": 10.5},
    ]
    kw: dict[str, Any] = {"mesh": (22, 42), "growth_steps": 2, "cracks": cracks}
    tight = rf.run(rf.scenes.edge_crack_plate("xfem", **kw))
    loose = rf.run(rf.scenes.edge_crack_plate("xfem", tip_tie_tol=0.9, **kw))
    assert tight.fields["tip_history_grows"][1].tolist() == [1.0, 0.0]
    assert loose.fields["tip_history_grows"][1].tolist() == [1.0, 1.0]
    assert rf.scene.XfemOptions().tip_tie_tol == 1e-6
    with pytest.raises(rf.InvalidParameterError) as e:
        rf.scenes.edge_crack_plate("xfem", tip_tie_tol=1.0)
    assert e.value.param == "xfem.tip_tie_tol"
