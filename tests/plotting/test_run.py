"""Figures: the drawn rotor matches the model's geometry; frames and summary draw the data."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.path import Path as MplPath

from pde_rotor.config import RotorConfig, validate_config
from pde_rotor.model.geometry import RotorShape, edge_normal_angles, pill_centres, plate_indicator
from pde_rotor.plotting.run import (
    FieldView,
    RotorFrame,
    Snapshot,
    frame_title,
    nice_ceiling,
    plate_corners,
    stop_intervals,
    summary_figure,
)
from pde_rotor.units import CONCENTRATION_UNITS, OMEGA_UNITS, TIME_UNITS


@pytest.mark.parametrize("phi", [0.0, 1.0, -2.5])
@pytest.mark.parametrize("n_corners", [3, 6, 8])
def test_plate_polygon_is_the_plate_of_the_model(phi, n_corners):
    """Corners at radius R; each edge's midpoint lies at the apothem along e_j, Eq. (ejt0)."""
    shape = RotorShape.from_config(validate_config({"geometry": {"n_corners": n_corners}}).geometry)
    corners = plate_corners(shape, phi)
    np.testing.assert_allclose(np.hypot(*corners.T), shape.radius)
    midpoints = 0.5 * (corners + np.roll(corners, 1, axis=0))
    normals = edge_normal_angles(n_corners, phi)
    expected = shape.apothem * np.stack([np.cos(normals), np.sin(normals)], axis=1)
    np.testing.assert_allclose(midpoints, expected, atol=1e-12)
    # F = 1/2 on the drawn edges (the edge of the smoothed indicator)
    f = plate_indicator(midpoints[:, 0], midpoints[:, 1], shape, phi)
    np.testing.assert_allclose(f, 0.5, atol=1e-12)


def test_pills_are_drawn_inside_the_plate():
    config = validate_config({"geometry": {"asymmetry": 1e-4}})
    shape = RotorShape.from_config(config.geometry)
    polygon = MplPath(plate_corners(shape, 0.7))
    for centre in pill_centres(shape, 0.7):
        assert polygon.contains_point(centre)


def test_stop_intervals_follow_the_protocol():
    config = RotorConfig()
    p = config.protocol
    spans = stop_intervals(config)
    assert len(spans) == p.cycles
    np.testing.assert_allclose([b - a for a, b in spans], p.t_stop)
    np.testing.assert_allclose(np.diff([a for a, _ in spans]), p.period)
    clipped = stop_intervals(config, t_max=p.t_ini + 0.2)
    assert clipped == [(p.t_ini, p.t_ini + 0.2)]


def test_field_view_selects_the_square():
    coords = (np.arange(122) - 60.5) * 0.05
    view = FieldView.make(coords, 1.5)
    assert np.all(np.abs(view.coords) <= 1.5)
    assert view.coords.size == 60
    lo, hi, _, _ = view.extent
    assert lo == pytest.approx(-1.5) and hi == pytest.approx(1.5)
    assert view.arrows.max() < view.coords.size


def test_frame_draws_the_state_at_the_rotor_angle():
    config = RotorConfig()
    shape = RotorShape.from_config(config.geometry)
    coords = (np.arange(80) - 39.5) * 0.05
    frame = RotorFrame(shape, coords, 1.5)
    rng = np.random.default_rng(1)
    data = rng.random((3, 80, 80))
    frame.update(data, 0.3, title="t = 1")
    sel = frame.view.sel
    np.testing.assert_array_equal(frame.image.get_array(), data[0][sel, sel].T)
    assert frame.image.get_clim() == (0.0, data[0][sel, sel].max())
    np.testing.assert_allclose(frame.plate.get_xy()[:-1], plate_corners(shape, 0.3))
    np.testing.assert_allclose(
        [p.center for p in frame.pills], pill_centres(shape, 0.3), atol=1e-12
    )
    speeds = np.hypot(frame.quiver.U, frame.quiver.V)
    # the fastest arrow is at most the key's arrow (0.9 of the spacing), at least half of it
    assert 0.5 < speeds.max() <= 1.0
    # colour scale never shrinks: frames stay comparable
    frame.update(0.5 * data, 0.4)
    assert frame.image.get_clim()[1] == data[0][sel, sel].max()
    assert frame.ax.get_title() == ""


def test_flow_arrows_keep_their_size_after_a_stop_and_the_key_says_how_large():
    """The flow left over after a stop is 1/20 of a turning plate's: per-frame arrows with
    a key that names the speed of its arrow keep it visible (a running maximum shrank it
    to nothing); the key turns orange and says by how much the arrows are enlarged."""
    shape = RotorShape.from_config(RotorConfig().geometry)
    coords = (np.arange(80) - 39.5) * 0.05
    frame = RotorFrame(shape, coords, 1.5)
    x, y = np.meshgrid(coords, coords, indexing="ij")
    swirl = np.stack([np.exp(-(x**2) - y**2), -y, x])  # |v| up to about 2.7 in view
    lengths, colours, labels = {}, {}, {}
    for name, factor in (("turning", 1.0), ("stopped", 0.05)):
        data = swirl * np.array([1.0, factor, factor])[:, None, None]
        frame.update(data, 0.0)
        speed = np.hypot(data[1], data[2])[frame.view.sel, frame.view.sel]
        in_view = float(speed[np.ix_(frame.view.arrows, frame.view.arrows)].max())
        label = frame.key.text.get_text()
        assert label.startswith(f"|v| = {nice_ceiling(in_view):.2g}")
        lengths[name] = float(np.hypot(frame.quiver.U, frame.quiver.V).max())
        colours[name] = frame.key.text.get_bbox_patch().get_facecolor()
        labels[name] = label
    assert lengths["stopped"] > 0.5 * lengths["turning"]
    assert "arrows" not in labels["turning"]
    assert labels["stopped"].endswith("(arrows \u00d725)")  # keys 5 and 0.2 (nice ceilings)
    assert colours["stopped"] != colours["turning"]
    frame.update(swirl, 0.0)  # released again: the movie's own scale, a black key
    assert frame.key.text.get_bbox_patch().get_facecolor() == colours["turning"]
    assert frame.key.U == 1.0  # the key's arrow is the arrow of its speed


@pytest.mark.parametrize(
    ("value", "nice"), [(0.078, 0.1), (1.93, 2.0), (2.0, 2.0), (3.1, 5.0), (7e-4, 1e-3)]
)
def test_nice_ceiling(value, nice):
    assert nice_ceiling(value) == pytest.approx(nice)


def test_frame_title_has_symbols_and_units():
    title = frame_title(12.5, -171.96, False, 2, 3)
    assert f"t = 12.50 [{TIME_UNITS}]" in title
    assert f"\u03c9 = -172.0 [{OMEGA_UNITS}]" in title
    assert "omega" not in title and "released, cycle 2/3" in title


def synthetic_run(config: RotorConfig) -> tuple[xr.Dataset, xr.Dataset]:
    t = np.linspace(0.0, config.protocol.t_end, 200)
    ts = xr.Dataset(
        {"phi": ("time", np.sin(t)), "omega": ("time", np.cos(t))},
        coords={"time": t},
        attrs={"status": "completed"},
    )
    m = np.arange(1, config.protocol.cycles + 1)
    ev = xr.Dataset(
        {
            "t_stop": ("cycle", config.protocol.t_ini + (m - 1) * config.protocol.period),
            "omega_before": ("cycle", np.where(m % 2, 170.0, -170.0)),
            "direction_after": ("cycle", np.where(m % 2, -1, 1)),
            "inverted": ("cycle", m % 3 != 0),
            "committed": ("cycle", np.ones(m.size, dtype=bool)),
            "time_to_commit": ("cycle", np.full(m.size, 0.7)),
        },
        coords={"cycle": m},
        attrs={"commit_fraction": 0.5},
    )
    return ts, ev


def test_summary_figure_has_series_table_and_snapshot():
    config = validate_config({"protocol": {"cycles": 20}})
    ts, ev = synthetic_run(config)
    coords = (np.arange(40) - 19.5) * 0.1
    snap = Snapshot(t=5.0, data=np.ones((3, 40, 40)), phi=0.2, coords=coords)
    fig = summary_figure(config, ts, ev, snap, max_rows=8)
    axes = fig.get_axes()
    assert len(axes) >= 4
    ax_phi, ax_omega, ax_table = axes[:3]
    np.testing.assert_array_equal(ax_phi.lines[0].get_ydata(), ts["phi"].values)
    assert len(ax_omega.patches) == config.protocol.cycles  # one shaded span per stop
    inversions = int(ev["inverted"].sum())
    assert ax_table.get_title().startswith(f"inversions {inversions}/20")
    table = ax_table.tables[0]
    rows = {key[0] for key in table.get_celld()}
    assert len(rows) == 8 + 2  # header, 7 first rows, "...", the last row
    fig.canvas.draw()


def all_text(fig) -> str:
    """Every text of a figure: titles, labels, table cells, texts."""
    found = []
    for ax in fig.get_axes():
        found += [ax.get_title(), ax.get_xlabel(), ax.get_ylabel()]
        found += [t.get_text() for t in ax.texts]
        for table in ax.tables:
            found += [cell.get_text().get_text() for cell in table.get_celld().values()]
    return "\n".join(found)


def test_summary_figure_speaks_in_symbols_and_units():
    """phi, omega, Delta as symbols; time and omega in the units the files carry."""
    config = validate_config({"protocol": {"cycles": 3}, "geometry": {"asymmetry": 1e-4}})
    ts, ev = synthetic_run(config)
    ts["time"].attrs["units"] = TIME_UNITS
    ts["omega"].attrs["units"] = OMEGA_UNITS
    snap = Snapshot(t=5.0, data=np.ones((3, 40, 40)), phi=0.2, coords=(np.arange(40) - 19.5) / 10)
    text = all_text(summary_figure(config, ts, ev, snap))
    for expected in (
        f"time t [{TIME_UNITS}]",
        f"angular velocity \u03c9 [{OMEGA_UNITS}]",
        "angle \u03c6 [rad]",
        "\u0394 = 0.0001",
        "\u03c9 before",
    ):
        assert expected in text
    for ascii_name in ("omega", "Delta", "phi", "dphi"):
        assert ascii_name not in text


def test_summary_table_leaves_no_empty_panel():
    """The table takes the height of its rows (or the room the snapshot leaves) and the
    snapshot follows right under it: no empty panel in between."""
    config = validate_config({"protocol": {"cycles": 3}})
    ts, ev = synthetic_run(config)
    snap = Snapshot(t=5.0, data=np.ones((3, 40, 40)), phi=0.2, coords=(np.arange(40) - 19.5) / 10)
    fig = summary_figure(config, ts, ev, snap)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    ax_table = next(ax for ax in fig.get_axes() if ax.tables)
    ax_snap = next(ax for ax in fig.get_axes() if ax.images)
    renderer = canvas.get_renderer()
    table_box = ax_table.tables[0].get_window_extent(renderer)
    axes_box = ax_table.get_window_extent(renderer)
    assert table_box.height == pytest.approx(axes_box.height, rel=0.02)  # cells fill it
    snap_top = ax_snap.get_tightbbox(renderer).y1  # the snapshot's title included
    gap_inches = (table_box.y0 - snap_top) / fig.dpi
    assert 0 <= gap_inches < 0.6


def test_summary_figure_without_snapshot_or_events():
    config = RotorConfig()
    ts, ev = synthetic_run(config)
    fig = summary_figure(config, ts, ev.isel(cycle=slice(0, 0)), None)
    texts = [t.get_text() for ax in fig.get_axes() for t in ax.texts]
    assert any("no field snapshot" in t for t in texts)
    assert any("no completed" in t for t in texts)


def test_summary_of_a_diverged_run_keeps_its_panels_and_wraps_the_message():
    """A long error message goes above the panels, wrapped: the panels keep their width and
    the title stays inside the figure."""
    config = validate_config({"protocol": {"cycles": 3}})
    ts, ev = synthetic_run(config)
    message = "simulation diverged at t = 0.0084: non-finite c (likely cause: " + "x " * 120
    ts.attrs.update(status="diverged", message=message)
    fig = summary_figure(config, ts, ev, None)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    ax_phi = fig.get_axes()[0]
    assert ax_phi.get_position().width > 0.35  # of the figure's width, as without a message
    title = ax_phi.title.get_window_extent(renderer)
    assert title.x0 >= 0 and title.x1 <= fig.bbox.width
    heading = fig._suptitle
    assert heading is not None and heading.get_text().replace("\n", " ").startswith("run diverged")
    box = heading.get_window_extent(renderer)
    assert box.x0 >= 0 and box.x1 <= fig.bbox.width and box.y1 <= fig.bbox.height


def test_colour_bar_names_the_unit_of_c():
    shape = RotorShape.from_config(RotorConfig().geometry)
    frame = RotorFrame(shape, (np.arange(40) - 19.5) * 0.1, 1.5)
    labels = [ax.get_ylabel() for ax in frame.fig.get_axes()]
    assert f"camphor concentration c [{CONCENTRATION_UNITS}]" in labels
