"""The handbook formulas against the table in shared/reference/closed-forms.md (independent of
our numerics) and against each other."""

import numpy as np
import pytest

from rustfrac import handbook

TABLE = [  # a/b, F Tada, F Brown-Srawley, V
    (0.1, 1.1957, 1.1837, 1.5398),
    (0.2, 1.3667, 1.3707, 1.7992),
    (0.3, 1.6551, 1.6599, 2.3086),
    (0.4, 2.1080, 2.1035, 3.2286),
    (0.5, 2.8266, 2.8264, 4.9234),
    (0.6, 4.0432, 4.0264, 8.3064),
    (0.7, 6.3755, 5.9745, 16.1438),
]


@pytest.mark.parametrize("x, f_tada, f_bs, v", TABLE)
def test_factors_match_the_handbook_table(x: float, f_tada: float, f_bs: float, v: float) -> None:
    assert handbook.tada_F(x) == pytest.approx(f_tada, abs=6e-5)
    assert handbook.brown_srawley_F(x) == pytest.approx(f_bs, abs=6e-5)
    assert handbook.tada_V(x) == pytest.approx(v, abs=6e-5)
    if x <= 0.6:  # the two fits agree within their stated accuracy
        assert handbook.tada_F(x) == pytest.approx(handbook.brown_srawley_F(x), rel=0.011)


def test_growth_curve_is_critical_and_softening() -> None:
    E, nu, G0, W = 10000.0, 0.25, 0.367, 11.0
    a = np.linspace(1.1, 7.7, 30)
    cmod, sigma = handbook.edge_crack_curve(a, W, E, nu, G0)
    ep = handbook.e_prime(E, nu)
    k = sigma * np.sqrt(np.pi * a) * handbook.tada_F(a / W)
    np.testing.assert_allclose(k, np.sqrt(G0 * ep), rtol=1e-12)  # K = K_Ic on the whole curve
    assert np.all(np.diff(sigma) < 0)  # the critical stress falls as the crack grows
    assert cmod[0] == pytest.approx(4 * sigma[0] * 1.1 * handbook.tada_V(0.1) / ep)
