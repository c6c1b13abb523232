"""The figure of a sweep report: what is drawn, on synthetic reports and the stored ones."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from matplotlib.collections import QuadMesh
from matplotlib.container import ErrorbarContainer

from pde_rotor.statistics.proportions import CCW, CW
from pde_rotor.sweep import gather
from pde_rotor.sweep.plot import ReportError, axis_label, layout, report_figure
from pde_rotor.sweep.stored import load_report
from tests.sweep.test_sweep import fake_restarts, tiny_sweep

DATA = Path(__file__).resolve().parents[2] / "data"


def synthetic(tmp_path: Path, axes: dict[str, list[float]], samples: int = 4) -> xr.Dataset:
    """The report of a restart sweep over `axes` whose run files are faked: at every
    point 3 of `samples` inversions from CCW, none from CW."""
    sweep = tiny_sweep(samples=samples, axes=axes)
    fake_restarts(tmp_path, sweep, {CCW: 3, CW: 0})
    return gather(sweep, tmp_path)


def p_line(ax) -> np.ndarray:
    """The (x, P) points of the P curve of `ax` (its error-bar line)."""
    (container,) = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
    return np.asarray(container.lines[0].get_xydata())


def footer(fig) -> str:
    return fig.texts[-1].get_text().replace("\n", " ")


def test_a_curve_draws_every_measured_point_of_fig5_with_labels_and_footer() -> None:
    ds = load_report(DATA / "fig5.nc")
    fig = report_figure(ds, source="data/fig5.nc")
    (ax,) = fig.axes
    points = p_line(ax)
    assert len(points) == 16
    np.testing.assert_allclose(points[:, 0], ds["t_stop"].values)
    np.testing.assert_allclose(points[:, 1], ds["P"].values)
    faint = {line.get_label(): line.get_ydata() for line in ax.lines if line.get_alpha()}
    assert set(faint) == {"P(inv | from CCW)", "P(inv | from CW)"}
    np.testing.assert_allclose(faint["P(inv | from CCW)"], ds["P_ccw"].values)
    assert ax.get_xlabel() == "stop duration t_stop [1/a]"
    assert ax.get_ylabel() == "inversion probability P"
    text = footer(fig)
    for part in ("restart estimator", "200 stops per point", "dx = 0.025", "dt = 0.0001"):
        assert part in text
    assert "\u03c3 = 1.5e-07" in text and "data/fig5.nc" in text
    assert "Wilson score" in text


def test_unmeasured_points_are_left_out_and_the_curve_follows_the_axis_order(tmp_path) -> None:
    ds = synthetic(tmp_path, {"protocol.t_stop": [1.2, 0.2, 0.6]})
    ds["P"][1] = np.nan  # t_stop = 0.2 not measured yet
    (ax,) = report_figure(ds).axes
    points = p_line(ax)
    np.testing.assert_allclose(points[:, 0], [0.6, 1.2])
    np.testing.assert_allclose(points[:, 1], ds["P"].values[[2, 0]])


def test_a_heat_map_of_fig9_blanks_the_unmeasured_cells() -> None:
    ds = load_report(DATA / "fig9.nc")
    fig = report_figure(ds, source="data/fig9.nc")
    ax, colorbar = fig.axes
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    cells = mesh.get_array()
    assert cells.shape == (11, 16)  # asymmetry vertical, t_stop horizontal
    p = ds["P"].transpose("asymmetry", "t_stop").values
    assert int(np.ma.count_masked(cells)) == int(np.isnan(p).sum()) == 176 - 32
    np.testing.assert_allclose(cells.compressed(), p[np.isfinite(p)])
    assert ax.get_xlabel().startswith("stop duration t_stop [1/a]")
    assert ax.get_ylabel() == "asymmetry \u0394 [rad]"
    assert colorbar.get_ylabel() == "inversion probability P (dimensionless)"
    assert "32 of 176 points measured" in footer(fig)


def test_x_chooses_the_horizontal_axis_of_a_heat_map() -> None:
    ds = load_report(DATA / "fig9.nc")
    ax = report_figure(ds, x="asymmetry").axes[0]
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    assert mesh.get_array().shape == (16, 11)
    assert ax.get_xlabel().startswith("asymmetry \u0394 [rad]")
    ticks = [t.get_text() for t in ax.get_xticklabels()]
    assert ticks == [f"{v:g}" for v in ds["asymmetry"].values]


def test_heat_map_cells_follow_the_axis_order_and_t_stop_goes_across(tmp_path) -> None:
    axes = {"geometry.asymmetry": [1e-4, 0.0], "protocol.t_stop": [1.2, 0.2]}
    ds = synthetic(tmp_path, axes)
    ds["P"][0, 1] = np.nan  # asymmetry = 1e-4, t_stop = 0.2
    ax = report_figure(ds).axes[0]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["0.2", "1.2"]
    assert [t.get_text() for t in ax.get_yticklabels()] == ["0", "0.0001"]
    (mesh,) = ax.collections
    expected = ds["P"].sortby(["asymmetry", "t_stop"]).values
    np.testing.assert_array_equal(np.ma.getmaskarray(mesh.get_array()), np.isnan(expected))
    np.testing.assert_allclose(mesh.get_array().compressed(), expected[np.isfinite(expected)])


def test_every_value_of_a_third_axis_gets_a_panel(tmp_path) -> None:
    axes = {"protocol.t_stop": [0.2, 1.2], "geometry.asymmetry": [0.0, 1e-4]}
    ds = synthetic(tmp_path, {**axes, "noise.sigma": [0.0, 1e-6, 2e-6]})
    fig = report_figure(ds)
    *panels, colorbar = fig.axes
    assert colorbar.get_ylabel() == "inversion probability P (dimensionless)"
    assert [ax.get_title() for ax in panels] == ["sigma = 0", "sigma = 1e-06", "sigma = 2e-06"]
    for ax, sigma in zip(panels, ds["sigma"].values, strict=True):
        (mesh,) = ax.collections
        expected = ds["P"].sel(sigma=sigma).transpose("asymmetry", "t_stop").values
        np.testing.assert_allclose(mesh.get_array(), expected)


def test_an_axis_of_one_value_is_named_in_the_title(tmp_path) -> None:
    ds = synthetic(tmp_path, {"protocol.t_stop": [3.0], "noise.sigma": [0.0, 1e-6]})
    fig = report_figure(ds)
    (ax,) = fig.axes
    assert len(p_line(ax)) == 2
    assert ax.get_xlabel() == "noise intensity \u03c3 [paper units]"
    assert fig.get_suptitle() == "sweep tiny at t_stop = 3 1/a"
    assert "dx = 0.05, dt = 0.0004, \u03b4 = 0.05, L = 1.75, \u03c3 swept" in footer(fig)
    (mesh,) = report_figure(ds, x="t_stop").axes[0].collections  # asked for: drawn
    assert mesh.get_array().shape == (2, 1)


def test_labels_of_other_keys_come_from_the_schema() -> None:
    ds = xr.Dataset(coords={"supply": ("supply", [1.0], {"config_key": "camphor.supply"})})
    ds = ds.assign_coords(n=[1, 2])
    assert axis_label(ds, "supply") == "camphor supply rate of one pill (s0) [paper units]"
    assert axis_label(ds, "n") == "n"


def test_what_cannot_be_drawn_is_a_report_error(tmp_path) -> None:
    ds = synthetic(tmp_path, {"protocol.t_stop": [0.2, 1.2]})
    with pytest.raises(ReportError, match=r"no axis 'sigma' \(its axes: t_stop\)"):
        layout(ds, "sigma")
    with pytest.raises(ReportError, match="not a sweep report"):
        report_figure(ds.drop_vars("P_low"))
    collective = ds.assign_attrs(estimator="collective")
    with pytest.raises(ReportError, match=r"collective sweep's report .*bodies_crowd\.py"):
        report_figure(collective)
    with pytest.raises(ReportError, match="no measured point"):
        report_figure(ds.assign(P=ds["P"] * np.nan))
    with pytest.raises(ReportError, match="no axis with several values"):
        report_figure(ds.isel(t_stop=[0]))
