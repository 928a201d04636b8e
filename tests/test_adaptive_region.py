"""The adaptive CCM-PD region (``[pd] region = "adaptive"``) from Python and the CLI:
the region grows ahead of the crack, no bond breaks within ``adapt_margin`` horizons of the FEM
part, the switches are reported, and bad options are refused naming the key. The numerics
(against a fixed region covering the path, the oracle, bit-for-bit resume across switches)
are validated in ``crates/rustfrac-core/tests/suite/ccm_pd_adaptive.rs``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import rustfrac as rf
from rustfrac.cli import main
from rustfrac.scenes import edge_crack_plate

#: the coarse paper plate (dx = 0.2, delta = 0.8): the first switch comes at step 303
COARSE = dict(dx=0.2, sla_steps=350, region="adaptive", adapt_margin=1.5, adapt_size=2.5)


@pytest.fixture(scope="module")
def grown() -> rf.Result:
    return rf.run(edge_crack_plate("ccm_pd", **COARSE))


def test_region_grows_and_keeps_the_margin(grown: rf.Result) -> None:
    m = grown.meta
    assert m["pd_region"] == "adaptive"
    start, end = m["pd_regions_initial"], m["pd_regions"]
    assert len(start) == 1 and len(end) > len(start)
    # the start is the square of adapt_size horizons around the tip (1.1, 10.5), snapped to dx
    delta = grown.scalars["delta"]
    x0, y0, x1, y1 = start[0]
    assert x0 == 0.0 and x1 >= 1.1 + 2.5 * delta - 1e-9 and y1 - y0 >= 5 * delta - 1e-9
    sw = m["region_switches"]
    assert [s["step"] for s in sw] == sorted(s["step"] for s in sw) and sw[0]["step"] > 1
    assert sw[-1]["n_pd_nodes"] == m["counts"]["n_pd_nodes"]
    assert m["interface_distance_min"] >= 1.5 - 1e-9
    assert m["timings"]["region_switch_s"] > 0
    assert grown.history["step"][-1] == 350  # row 0 is the unloaded origin


def test_fixed_region_reports_its_closest_approach() -> None:
    r = rf.run(edge_crack_plate("ccm_pd", dx=0.2, sla_steps=30))
    assert r.meta["pd_region"] == "fixed" and r.meta["region_switches"] == []
    assert 0 < r.meta["interface_distance_min"] < 3


@pytest.mark.parametrize(
    ("options", "param"),
    [
        (dict(adapt_margin=3.0, adapt_size=3.5), "pd.adapt_size"),
        (dict(adapt_margin=0.0), "pd.adapt_margin"),
        (dict(region="moving"), "pd.region"),
    ],
)
def test_bad_options_name_the_key(options: dict[str, object], param: str) -> None:
    with pytest.raises(rf.errors.InvalidParameterError) as e:
        rf.run(edge_crack_plate("ccm_pd", dx=0.2, sla_steps=0, **{"region": "adaptive", **options}))
    assert e.value.param == param


def test_cli_runs_an_adaptive_scene(tmp_path: Path) -> None:
    scene = tmp_path / "adaptive.toml"
    text = rf.examples.path("paper_ccm_pd_adaptive.toml").read_text()
    text = (
        text.replace("dx = 0.06666666666666667", "dx = 0.2")
        .replace("sla_steps = 20000", "sla_steps = 320")
        .replace("adapt_margin = 2.0", "adapt_margin = 1.5")
        .replace("adapt_size = 4.0", "adapt_size = 2.5")
    )
    scene.write_text(text)
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "-q"]) == 0
    doc = json.loads((tmp_path / "out" / "result.json").read_text())
    meta = doc["meta"]
    assert meta["pd_region"] == "adaptive" and len(meta["region_switches"]) == 1
