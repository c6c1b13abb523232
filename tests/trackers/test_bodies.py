"""A run with bodies through pde_rotor.run: bodies.nc, the stops of each body, summary.png."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from matplotlib.figure import Figure

from pde_rotor import RotorConfig, run
from pde_rotor.plotting.bodies import draw_vessel

TWO_BODIES = {
    "grid": {"domain_radius": 3.0, "dx": 0.05, "dt": 2e-4},
    "numerics": {"scheme": "paper"},
    "protocol": {"t_ini": 0.1, "t_stop": 0.04, "t_release": 0.06, "cycles": 2},
    "output": {"timeseries_interval": 0.01, "movie_interval": 0.05, "progress": False},
    "bodies": [
        {
            "name": "stopped",
            "plate": {"shape": "polygon", "n_corners": 6, "radius": 0.5},
            "pills": [{"x": 0.3, "y": 0.05}],
            "start": {"x": -1.3, "y": 0.0, "omega": 30.0},
            "protocol": {"t_ini": 0.1, "t_stop": 0.04, "t_release": 0.06, "cycles": 2},
        },
        {
            "name": "boat",
            "pills": [{"x": 0.0, "y": 0.0}],
            "motion": {"kind": "free", "mass": 1e-3, "friction": 1e-4},
            "start": {"x": 1.2, "y": 0.0, "velocity": [0.0, 0.5]},
        },
    ],
}


def test_bodies_run_writes_every_body_and_its_stops(tmp_path: Path) -> None:
    """bodies.nc samples both bodies at the interval and at the stops' ends; the stopped
    body is held (omega = 0) exactly in its stops, the free one moves all along; each of
    the stopped body's two stops is classified; the files of a bodies run are written."""
    config = RotorConfig.model_validate(TWO_BODIES)
    result = run(config, tmp_path / "run")
    assert result.ok, result.message
    names = {"config.yaml", "bodies.nc", "events.nc", "summary.png", "movie.mp4", "run.log"}
    assert set(result.files) == names
    assert (tmp_path / "run" / "movie.mp4").stat().st_size > 0
    with xr.open_dataset(tmp_path / "run" / "bodies.nc", engine="h5netcdf") as ds:
        ds = ds.load()
    assert list(ds["body"].values) == ["stopped", "boat"]
    t = ds["time"].values
    assert t[-1] == pytest.approx(config.protocol.t_end, abs=1e-12)
    held = ds["stopped"].sel(body="stopped").values == 1
    in_stop = ((t > 0.1 + 1e-9) & (t <= 0.14 + 1e-9)) | ((t > 0.2 + 1e-9) & (t <= 0.24 + 1e-9))
    np.testing.assert_array_equal(held, in_stop)
    assert np.all(ds["omega"].sel(body="stopped").values[held] == 0.0)
    boat = ds.sel(body="boat")
    assert np.all(boat["stopped"].values == 0)
    assert boat["y"].values[-1] > 0.0  # it moved off along its start velocity
    events = result.events
    assert list(events["body"].values) == ["stopped", "stopped"]
    assert list(events["cycle"].values) == [1, 2]
    omega = ds["omega"].sel(body="stopped")
    before = [float(omega.sel(time=t_stop, method="nearest")) for t_stop in (0.1, 0.2)]
    np.testing.assert_array_equal(events["direction_before"].values, np.sign(before))
    np.testing.assert_array_equal(events["omega_before"].values, before)


@pytest.mark.parametrize(
    ("vessel", "walls"),
    [
        (None, [("Circle", 3.0)]),
        (
            {"shape": "annulus", "inner_radius": 1.0, "outer_radius": 3.0},
            [("Circle", 1.0), ("Circle", 3.0)],
        ),
        ({"shape": "rectangle", "half_widths": [3.0, 1.5]}, [("Rectangle", (6.0, 3.0))]),
    ],
)
def test_the_summary_draws_the_vessels_walls(vessel: dict | None, walls: list) -> None:
    """The summary's first panel draws the dish's circle, an annulus' two circles or a
    tank's sides, where the walls are."""
    grid = {"vessel": vessel} if vessel else {}
    start = {"x": 2.0} if vessel else {}
    config = RotorConfig.model_validate({"grid": grid, "bodies": [{"pills": [{}], "start": start}]})
    ax = Figure().subplots()
    draw_vessel(ax, config)
    drawn = [
        (type(p).__name__, p.radius if hasattr(p, "radius") else (p.get_width(), p.get_height()))
        for p in ax.patches
    ]
    assert drawn == walls
