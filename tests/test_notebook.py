"""The notebook experience: plots that are figures (shown inline), units on every axis, crack
paths for every method, clear refusals, HTML views, history tables, progress bars, logging, and
the example notebook examples/fig7.ipynb run end to end."""

from __future__ import annotations

import ast
import inspect
import logging
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

import rustfrac as rf
from rustfrac import plotting

ROOT = Path(__file__).resolve().parents[1]
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def results(seam: rf.Result) -> dict[str, rf.Result]:
    """One small result of every method (FEM: the session's seam run)."""
    return {
        "fem": seam,
        "xfem": rf.run(
            rf.scenes.edge_crack_plate("xfem", mesh=(22, 42), growth_steps=4, crack_angle=20.0)
        ),
        "pd": rf.run(rf.examples.path("pd_coarse.toml")),
        "ccm_pd": rf.run(rf.scenes.edge_crack_plate("ccm_pd", dx=0.2, sla_steps=60)),
    }


# ----------------------------------------------------------------------------------------------
# figures, units


@pytest.mark.parametrize("method", ["fem", "xfem", "pd", "ccm_pd"])
@pytest.mark.parametrize("plot", ["plot_field", "plot_crack_path"])
def test_plots_are_figures_shown_inline_with_units(
    results: dict[str, rf.Result], method: str, plot: str
) -> None:
    fig = getattr(plotting, plot)(results[method])
    assert isinstance(fig, Figure)
    assert fig._repr_png_().startswith(PNG)  # Jupyter's inline view, no pyplot needed
    ax = fig.axes[0]
    assert ax.get_xlabel() == "x1 [length]" and ax.get_ylabel() == "x2 [length]"


def test_every_axis_and_colourbar_has_a_unit(results: dict[str, rf.Result]) -> None:
    u = plotting.PAPER_UNITS
    figs = [
        plotting.plot_field(results["fem"], "s22", units=u),
        plotting.plot_field(results["xfem"], "u2", units=u),
        plotting.plot_field(results["xfem"], "von_mises", units=u),
        plotting.plot_damage(results["ccm_pd"], units=u),
        plotting.plot_tip_deformation(results["xfem"], units=u),
        plotting.plot_load_path(results["xfem"], x="cmod", y="K_I", units=u),
        plotting.plot_load_path(results["pd"], x="crack_length", y="load_factor", units=u),
    ]
    labels = [lab for f in figs for a in f.axes for lab in (a.get_xlabel(), a.get_ylabel()) if lab]
    assert (
        "s22 [MPa]" in labels
        and "u2 [mm]" in labels
        and "von_mises [MPa]" in labels
        and "damage index [-]" in labels
    )
    assert "cmod [mm]" in labels and "K_I [MPa mm^1/2]" in labels
    assert "load_factor [-]" in labels and "crack_length [mm]" in labels
    assert all(lab.endswith("]") for lab in labels), labels
    assert plotting.Units().label("sigma22", "stress") == "sigma22 [force/length^2]"


def test_ax_keyword_draws_into_given_axes(results: dict[str, rf.Result]) -> None:
    ax = Figure().add_subplot()
    fig = plotting.plot_load_path(results["xfem"], x="cmod", ax=ax)
    assert fig is ax.figure and isinstance(ax, Axes)
    assert len(ax.lines[0].get_xdata()) == len(results["xfem"].history["cmod"])


def test_fig6_has_axis_labels(tmp_path: Path) -> None:
    from rustfrac import figures

    xy = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    el = np.array([[0, 1, 2, 3]])
    crack = np.array([[0.0, 0.5], [0.5, 0.5]])
    fig = figures.plot_discretisations(
        {"coords": xy, "elements": el, "heaviside_nodes": [0], "tip_nodes": [1], "crack": crack},
        {"node_xy": xy, "is_pd": [True] * 4, "elements": el, "crack": crack},
        (0.0, 1.0, 0.0, 1.0),
    )
    for ax in fig.axes:
        assert ax.get_xlabel() == "x1 [mm]" and ax.get_ylabel() == "x2 [mm]"


# ----------------------------------------------------------------------------------------------
# plot_field: the component asked for, or a clear refusal


def test_plot_field_colours_by_the_requested_component(results: dict[str, rf.Result]) -> None:
    res = results["fem"]
    el = res.elements
    for k, comp in enumerate(("s11", "s22", "s12")):
        fig = plotting.plot_field(res, comp)
        drawn = np.asarray(fig.axes[0].collections[0].get_array())
        np.testing.assert_allclose(drawn, res.fields["nodal_stress"][:, k][el].mean(axis=1))
        assert comp in fig.axes[0].get_title()


def test_plot_field_refuses_an_unknown_component(results: dict[str, rf.Result]) -> None:
    with pytest.raises(rf.InvalidParameterError, match="s11, s22, s12, von_mises, u1, u2") as e:
        plotting.plot_field(results["fem"], "sxx")
    assert e.value.param == "component"


@pytest.mark.parametrize("method", ["pd", "ccm_pd"])
def test_plot_field_refuses_stresses_a_result_lacks(
    results: dict[str, rf.Result], method: str
) -> None:
    with pytest.raises(rf.InvalidParameterError, match=r"no 's22'.*valid for it: u1, u2") as e:
        plotting.plot_field(results[method], component="s22")
    assert e.value.param == "component"


def _centroids(fig: Figure) -> np.ndarray:
    return np.array([p.vertices[:-1].mean(axis=0) for p in fig.axes[0].collections[0].get_paths()])


def test_xfem_stress_fields_far_from_the_crack_are_the_applied_traction() -> None:
    """XFEM s22 and von Mises from the element and cut-cell stresses: far from the crack of a
    plate under traction t, s22 = t and (plane strain, s33 = nu s22) von Mises =
    t sqrt(1 - nu + nu^2); at the crack faces s22 vanishes (traction-free)."""
    res = rf.run(rf.scenes.edge_crack_plate("xfem", mesh=(44, 83), bc="traction"))
    t, nu = res.sigma22, 0.25
    fig = plotting.plot_field(res, "s22", scale=0.0)
    xy, s22 = _centroids(fig), np.asarray(fig.axes[0].collections[0].get_array())
    assert len(s22) > len(res.elements)  # the cut cells are drawn, not their elements
    far = np.abs(xy[:, 1] - 10.5) > 7.0
    np.testing.assert_allclose(s22[far], t, rtol=0.02)
    faces = (xy[:, 0] < 0.6) & (np.abs(xy[:, 1] - 10.5) < 0.1)
    assert faces.any() and np.all(np.abs(s22[faces]) < 0.05 * t)
    vm = np.asarray(
        plotting.plot_field(res, "von_mises", scale=0.0).axes[0].collections[0].get_array()
    )
    np.testing.assert_allclose(vm[far], t * np.sqrt(1 - nu + nu**2), rtol=0.03)
    np.testing.assert_allclose(
        plotting.von_mises([[1.0, 0.0, 0.0]], 0.3, "stress"), [1.0], rtol=1e-15
    )
    np.testing.assert_allclose(plotting.von_mises([[0.0, 0.0, 1.0]], 0.3, "strain"), [3**0.5])


def test_xfem_plot_field_of_each_growth_state(results: dict[str, rf.Result]) -> None:
    """state=k draws history row k's crack and stresses: the s22 peak sits at that row's tip;
    the default is the last state; a row without a kept state is refused naming ``state``."""
    res = results["xfem"]
    rows = list(res.fields["state_rows"])
    assert rows == [1, 2, 3, 4]
    for row in rows:
        fig = plotting.plot_field(res, "s22", state=row, scale=0.0)
        xy, s22 = _centroids(fig), np.asarray(fig.axes[0].collections[0].get_array())
        tip = np.array([res.history["tip_x"][row], res.history["tip_y"][row]])
        assert np.linalg.norm(xy[np.argmax(s22)] - tip) < 11.0 / 22, row
        assert f"row {row}" in fig.axes[0].get_title()
    last = plotting.plot_field(res, "s22", scale=0.0).axes[0].collections[0].get_array()
    np.testing.assert_array_equal(
        last, plotting.plot_field(res, "s22", state=4, scale=0.0).axes[0].collections[0].get_array()
    )
    origin = plotting.plot_field(res, "s22", state=0).axes[0].collections[0].get_array()
    assert (np.asarray(origin) == 0).all()
    with pytest.raises(rf.InvalidParameterError, match="1, 2, 3, 4") as e:
        plotting.plot_field(res, "s22", state=7)
    assert e.value.param == "state"


def test_plot_field_on_pd_grid_nodes(results: dict[str, rf.Result]) -> None:
    res = results["ccm_pd"]
    fig = plotting.plot_field(res, "u1")
    drawn = np.asarray(fig.axes[0].collections[0].get_array())
    np.testing.assert_array_equal(drawn, res.fields["u"].reshape(-1, 2)[:, 0])
    assert len(drawn) == len(res.fields["node_xy"])


# ----------------------------------------------------------------------------------------------
# crack paths


def test_crack_path_of_xfem_is_the_final_polyline(results: dict[str, rf.Result]) -> None:
    res = results["xfem"]
    ax = plotting.plot_crack_path(res).axes[0]
    final = res.crack_polylines[0]
    assert len(final) > 2  # grew
    assert any(
        len(line.get_xdata()) == len(final) and np.allclose(line.get_xydata(), final)
        for line in ax.lines
    )
    plate = next(p for p in ax.patches if isinstance(p, Rectangle))
    assert (plate.get_width(), plate.get_height()) == (11.0, 21.0)


def test_crack_path_draws_the_layout_of_the_scene() -> None:
    """Holes, notches, supports and loads are drawn where the scene puts them."""
    from matplotlib.patches import Circle, FancyArrow

    scene = {
        "method": "fem",
        "plate": {"width": 20.0, "height": 8.0},
        "crack": {"kind": "none"},
        "hole": [{"shape": "circle", "center": [6.0, 4.0], "radius": 0.5}],
        "notch": [{"side": "bottom", "at": 10.0, "width": 0.2, "depth": 2.0}],
        "support": [
            {"region": "point", "point": [1.0, 0.0]},
            {"region": "edge", "side": "left", "fix": "u1"},
        ],
        "load": [{"region": "point", "point": [10.0, 8.0], "force": [0.0, -1.0]}],
    }
    res = rf.Result("fem", 0.0, 0.0, 0, 0.0, meta={"scene": scene})
    ax = plotting.plot_crack_path(res).axes[0]
    (hole,) = [p for p in ax.patches if isinstance(p, Circle)]
    assert tuple(hole.center) == (6.0, 4.0) and hole.radius == 0.5
    notch = [p for p in ax.patches if isinstance(p, Rectangle)][1]
    assert (notch.get_x(), notch.get_y(), notch.get_width(), notch.get_height()) == (
        9.9,
        0.0,
        0.2,
        2.0,
    )
    supports = [ln for ln in ax.lines if ln.get_color() == "C2"]
    assert any(np.allclose(ln.get_xydata(), [[1.0, 0.0]]) for ln in supports)
    assert any(np.allclose(ln.get_xydata(), [[0.0, 0.0], [0.0, 8.0]]) for ln in supports)
    (arrow,) = [p for p in ax.patches if isinstance(p, FancyArrow)]
    tipx, tipy = arrow.get_xy()[np.argmin(arrow.get_xy()[:, 1])]
    assert (tipx, tipy) == pytest.approx((10.0, 8.0))  # the arrow points down onto the point


def test_damage_ridge_follows_the_pd_crack(results: dict[str, rf.Result]) -> None:
    (ridge,) = plotting.damage_ridge(results["pd"])  # pd_coarse: the crack along x2 = 3.1
    np.testing.assert_allclose(ridge[:, 1], 3.1, atol=0.01)
    assert ridge[0, 0] == 0.0 and ridge[-1, 0] > 1.1  # from the mouth past the pre-crack tip
    lines = plotting.plot_crack_path(results["ccm_pd"]).axes[0].lines
    assert any("damage ridge" in str(line.get_label()) for line in lines)
    with pytest.raises(rf.InvalidParameterError) as e:
        plotting.damage_ridge(results["pd"], threshold=0.0)
    assert e.value.param == "threshold"


def test_fem_crack_path_is_the_seam(results: dict[str, rf.Result]) -> None:
    lines = plotting.plot_crack_path(results["fem"]).axes[0].lines
    (seam,) = [ln for ln in lines if ln.get_label() == "seam crack"]
    # what the mesh cuts: along the grid line nearest x2 = 10.5, to the first node at or beyond
    # a0 = 1.1 (h = 0.25 on 44 x 83)
    y = results["fem"].meta["seam_y"]
    assert abs(y - 10.5) <= 0.5 * 21 / 83 + 1e-12
    np.testing.assert_allclose(seam.get_xydata(), [[0.0, y], [1.25, y]])


def test_plots_refuse_results_without_their_data(results: dict[str, rf.Result]) -> None:
    with pytest.raises(rf.PlotDataError, match="PD and CCM-PD"):
        plotting.plot_damage(results["xfem"])
    with pytest.raises(rf.PlotDataError, match="XFEM"):
        plotting.plot_tip_deformation(results["pd"])
    with pytest.raises(rf.PlotDataError, match="history"):
        plotting.plot_load_path(results["fem"])
    with pytest.raises(rf.InvalidParameterError, match=r"valid: .*sigma22") as e:
        plotting.plot_load_path(results["pd"], x="nope")
    assert e.value.param == "x"


# ----------------------------------------------------------------------------------------------
# HTML, history tables, progress, logging


def test_html_views(results: dict[str, rf.Result]) -> None:
    scene = rf.scenes.edge_crack_plate("fem", name="<i>mine</i>")
    html = scene._repr_html_()
    assert "&lt;i&gt;mine&lt;/i&gt;" in html and "<i>" not in html
    assert "<th style='text-align:left'>nu</th>" in html
    html = results["pd"]._repr_html_()
    assert html.startswith("<table>") and "sla_steps_done" in html and "201 rows" in html


def test_history_frame(results: dict[str, rf.Result]) -> None:
    pd = pytest.importorskip("pandas")
    res = results["xfem"]
    df = res.history_frame()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == list(res.history)
    np.testing.assert_array_equal(df["sigma22"].to_numpy(), res.history["sigma22"])
    assert results["fem"].history_frame().empty


def test_history_frame_without_pandas(
    results: dict[str, rf.Result], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas -> ImportError
    with pytest.raises(ImportError, match="pip install pandas"):
        results["xfem"].history_frame()


def test_progress_true_draws_a_tqdm_bar(capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("tqdm")
    rf.run(rf.examples.path("pd_coarse.toml"), progress=True)
    err = capsys.readouterr().err
    assert "rustfrac pd" in err and "200/200" in err


def test_progress_true_without_tqdm_falls_back_to_text(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    rf.run(rf.examples.path("pd_coarse.toml"), progress=True)
    err = capsys.readouterr().err
    assert "100.0%" in err and "sla" in err and "it/s" not in err


def test_progress_callback_and_bad_values() -> None:
    calls: list[tuple[int, int, str]] = []
    rf.run(rf.scenes.edge_crack_plate("fem"), progress=lambda *a: calls.append(a))
    assert calls and calls[-1][0] == calls[-1][1]
    with pytest.raises(rf.InvalidTypeError) as e:
        rf.run(rf.scenes.edge_crack_plate("fem"), progress=3)  # type: ignore[arg-type]
    assert e.value.param == "progress"


def test_library_logs_and_never_prints(caplog: pytest.LogCaptureFixture) -> None:
    from rustfrac.fig7 import fig7

    assert inspect.signature(fig7).parameters["log"].default == logging.getLogger("rustfrac").info
    with caplog.at_level(logging.DEBUG, logger="rustfrac"):
        rf.run(rf.scenes.edge_crack_plate("fem"))
    assert any(r.name == "rustfrac" and "run method fem" in r.message for r in caplog.records)
    offenders = []
    package = Path(rf.__file__).parent
    for f in sorted(package.rglob("*.py")):
        rel = f.relative_to(package)
        if rel.parts[0] == "cli" or f.name == "__main__.py":  # the command line prints its own
            continue
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Name) and node.id == "print":
                offenders.append(f"{rel.as_posix()}:{node.lineno}")
    assert not offenders, offenders


def test_plotting_is_reachable_from_rustfrac_without_slowing_its_import() -> None:
    """``rf.plotting`` works after ``import rustfrac``; matplotlib (half a second) is imported
    at its first use, not by ``import rustfrac``."""
    code = (
        "import sys, rustfrac as rf; assert 'matplotlib' not in sys.modules; "
        "rf.plotting.plot_field; assert 'rustfrac.plotting' in sys.modules; "
        "from rustfrac import plotting; plotting.plot_load_path"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


# ----------------------------------------------------------------------------------------------
# the example notebook


def test_example_notebook_reproduces_fig7(
    tmp_path: Path, child_env: dict[str, str], monkeypatch: pytest.MonkeyPatch
) -> None:
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    # the kernel runs in tmp_path: it imports the rustfrac this suite imports
    monkeypatch.setenv("PYTHONPATH", child_env["PYTHONPATH"])
    nb = nbformat.read(ROOT / "examples" / "fig7.ipynb", as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    client.execute()  # raises CellExecutionError on any failing cell
    kinds = [
        set(o.get("data", {}))
        for c in nb.cells
        if c.cell_type == "code"
        for o in c.outputs
        if o.output_type == "execute_result"
    ]
    assert sum("image/png" in k for k in kinds) >= 6  # fig7.png and five inline figures
    assert sum("text/html" in k for k in kinds) >= 4  # results, history table, scene
    errors = [o for c in nb.cells for o in c.get("outputs", []) if o.output_type == "error"]
    assert not errors
