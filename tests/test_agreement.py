"""The sigma22-CMOD agreement of two load paths (rustfrac.agreement), on
saw-tooths built around a known curve (its place in the Fig. 7 summary: tests/test_fig7.py)."""

from __future__ import annotations

import numpy as np
import pytest

from rustfrac import agreement


def _reference() -> tuple[np.ndarray, np.ndarray]:
    """An elastic line to a peak at CMOD 1, then a softening branch (no origin row: the
    comparison adds it)."""
    c = np.linspace(1.0, 3.0, 41)
    return c, 30.0 / c**0.5


def _sigma(c: np.ndarray) -> np.ndarray:
    """The reference curve including its elastic line from the origin."""
    return np.where(c <= 1.0, 30.0 * c, 30.0 / np.maximum(c, 1e-300) ** 0.5)


def test_peaks_and_troughs_of_a_known_saw_tooth() -> None:
    # alternating +6 % and -4 % about the reference at CMODs on its linear pieces' knots: the
    # peaks read +6 %, the troughs -4 %, the running mean of an odd window about +1 %
    rc, rs = _reference()
    c = np.linspace(1.0, 2.9, 40)
    ref = np.interp(c, np.concatenate([[0.0], rc]), np.concatenate([[0.0], rs]))
    s = ref * np.where(np.arange(c.size) % 2 == 0, 1.06, 0.96)
    out = agreement.compare(rc, rs, np.concatenate([[0.0], c]), np.concatenate([[0.0], s]), 3)
    assert out["peaks"]["n"] == 19 and out["lower_envelope"]["n"] == 19
    assert out["peaks"]["mean_rel_diff"] == pytest.approx(0.06, abs=1e-12)
    assert out["lower_envelope"]["max_rel_diff"] == pytest.approx(-0.04, abs=1e-12)
    assert out["running_mean"]["mean_rel_diff"] == pytest.approx(0.01, abs=2e-3)
    assert out["running_mean"]["n"] == 38
    assert out["reference_dropped"] == 0


def test_points_beyond_the_reference_and_on_its_elastic_line() -> None:
    rc, rs = _reference()
    # on the elastic line (below the first critical state) the reference is the line from 0
    c = np.array([0.2, 0.4, 0.3, 3.5, 3.2, 3.6])
    s = _sigma(c) * 1.1
    out = agreement.compare(rc, rs, c, s, 1)
    assert out["peaks"]["n"] == 1 and out["peaks"]["mean_rel_diff"] == pytest.approx(0.1)
    # the points past CMOD 3 are outside the reference curve and counted as such
    assert out["running_mean"]["outside"] == 3 and out["running_mean"]["n"] == 3
    assert out["running_mean"]["max_rel_diff"] == pytest.approx(0.1)


def test_a_reference_whose_cmod_snaps_back_is_cut_there() -> None:
    c, s, dropped = agreement.reference_curve([1.0, 2.0, 1.5, 2.5], [10.0, 8.0, 7.0, 6.0])
    assert dropped == 2 and list(c) == [0.0, 1.0, 2.0] and list(s) == [0.0, 10.0, 8.0]


def test_bad_input_is_refused() -> None:
    rc, rs = _reference()
    with pytest.raises(ValueError, match="window"):
        agreement.compare(rc, rs, rc, rs, 4)
    with pytest.raises(ValueError, match="one length"):
        agreement.compare(rc, rs[:-1], rc, rs)
    with pytest.raises(ValueError, match="finite"):
        agreement.compare(rc, rs, [np.nan], [1.0])
