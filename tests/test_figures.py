"""``figures.save_figure`` draws a figure once and crops it to its tight box: the PNG shows what
matplotlib's own ``savefig(bbox_inches="tight")`` (which lays the figure out twice) shows."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")
from matplotlib.figure import Figure
from PIL import Image

from rustfrac import figures


def _ink(path: Path) -> np.ndarray:
    """The RGB pixels of a PNG inside the bounding box of everything not white."""
    a = np.asarray(Image.open(path).convert("RGB")).astype(float)
    rows, cols = np.nonzero((a < 250).any(axis=2))
    return a[rows.min() : rows.max() + 1, cols.min() : cols.max() + 1]


def _curves_figure() -> Figure:
    c = np.linspace(0.0, 0.05, 50)
    curves = [("a", c, 600 * c, {"marker": "."}), ("b", c, 500 * c, {"ls": "--"})]
    rel = (c, 0.1 * np.sin(40 * c))
    return figures.plot_fig7(
        curves, title="title", published=[("p", 0.01, 6.0)], agreement={"peaks": rel}
    )


def _patches_figure() -> Figure:
    # a suptitle near the top edge: the padded tight box leaves the canvas there
    cells = np.array([[[0, 0], [1, 0], [1, 1], [0, 1]]], dtype=float)
    return figures.plot_deformed_patches(
        [(cells, 0.01 * cells, "one"), (cells, -0.01 * cells, "two")]
    )


@pytest.mark.parametrize("make", [_curves_figure, _patches_figure])
def test_saved_png_shows_what_savefig_tight_shows(make, tmp_path: Path) -> None:
    ours, ref = tmp_path / "ours.png", tmp_path / "ref.png"
    figures.save_figure(make(), ours)
    make().savefig(ref, format="png", dpi=150, bbox_inches="tight")
    a, b = _ink(ours), _ink(ref)
    # the same ink box (within the sub-pixel offset of the two crops) ...
    assert abs(a.shape[0] - b.shape[0]) <= 1 and abs(a.shape[1] - b.shape[1]) <= 1
    # ... and the same picture in it, at the best alignment within a pixel (antialiased edges
    # still differ by the sub-pixel offset of the crops)
    h, w = min(a.shape[0], b.shape[0]) - 2, min(a.shape[1], b.shape[1]) - 2
    diff = min(
        np.abs(a[1 : 1 + h, 1 : 1 + w] - b[1 + i : 1 + i + h, 1 + j : 1 + j + w]).mean()
        for i in (-1, 0, 1)
        for j in (-1, 0, 1)
    )
    print(f"mean |difference| {diff:.2f} / 255")
    assert diff < 3.0, diff
    assert Image.open(ours).info["dpi"] == pytest.approx((150, 150), abs=0.05)


def test_ink_outside_the_canvas_is_kept(tmp_path: Path) -> None:
    fig = Figure(figsize=(3.0, 2.0))
    fig.add_subplot().plot([0, 1], [0, 1])
    fig.text(1.3, 0.5, "outside the canvas")
    out = figures.save_figure(fig, tmp_path / "f.png", dpi=100)
    # savefig's own tight box: wider than the 300-pixel canvas, with the text in it
    assert Image.open(out).size[0] > 300 + 100


def test_fig7_axis_ends_at_x_max_and_readings_are_points() -> None:
    c = np.linspace(0.0, 0.05, 50)
    back_and_forth = (np.array([0.02, 0.018, 0.021, 0.019]), np.array([0.1, 0.0, 0.12, 0.05]))
    curves = [("computed", c, 600 * c, {}), ("reference", 2 * c, 300 * c, {"ls": "--"})]
    # the readings of rustfrac.agreement.compare, in its order
    panel = {k: back_and_forth for k in ("peaks", "lower_envelope", "running_mean")}
    whole = figures.plot_fig7(curves, agreement=panel)
    assert whole.axes[0].get_xlim()[1] >= 0.1  # every curve whole by default
    cut = figures.plot_fig7(curves, agreement=panel, x_max=0.054)
    assert cut.axes[0].get_xlim() == pytest.approx((0.0, 0.054))
    # a reading along the SLA steps goes back and forth in CMOD: points, no zigzag line
    lines = cut.axes[1].get_lines()[:3]
    assert [ln.get_linestyle() for ln in lines] == ["None"] * 3
    assert [ln.get_marker() for ln in lines] == ["^", "v", "."]
