"""The linear peridynamic solid (``pd.model = "lps"``) from Python, end to end: a pre-cracked
pure-PD plate with nu = 0.3 runs the SLA to a peak and beyond, its critical stretch is the
closed form of docs/design.md ("The linear peridynamic solid"), and bond-based PD refuses
nu != 1/4 naming ``pd.model``."""

from __future__ import annotations

import math

import pytest

import rustfrac as rf


def lps_scene(**pd: object) -> rf.Scene:
    return rf.Scene.from_dict(
        {
            "method": "pd",
            "plate": {"width": 1.2, "height": 2.2},
            "material": {"nu": 0.3},
            "crack": {"a0": 0.5, "y": 1.1},
            "pd": {"dx": 0.2, "m": 2, "sla_steps": 2000, "model": "lps", **pd},
        }
    )


def test_lps_scene_runs_past_the_peak_with_the_closed_form_critical_stretch() -> None:
    res = rf.run(lps_scene(influence="conical"))
    e, nu, g0 = 1e4, 0.3, 0.367  # the paper's material (rf.Scene's defaults but nu)
    mu = e / (2 * (1 + nu))
    delta = res.scalars["delta"]
    assert delta == pytest.approx(0.4, rel=1e-12)
    # conical omega: s_c = sqrt(3 pi G0 / (16 mu delta))
    assert res.scalars["s0"] == pytest.approx(math.sqrt(3 * math.pi * g0 / (16 * mu * delta)))
    s22 = list(res.history["sigma22"])
    k = max(range(len(s22)), key=lambda i: s22[i])
    assert 0 < k < len(s22) - 1
    assert s22[-1] < 0.5 * s22[k]


def test_bond_based_refuses_nu_other_than_a_quarter_naming_pd_model() -> None:
    with pytest.raises(rf.InvalidParameterError, match=r"pd\.model") as e:
        rf.run(lps_scene(model="bond"))
    assert e.value.param == "material.nu"
    with pytest.raises(rf.InvalidParameterError, match="influence") as e:
        rf.run(lps_scene(influence="parabolic"))
    assert e.value.param == "pd.influence"
