"""The ``output:`` section: what a run records and how often."""

from __future__ import annotations

from pydantic import Field

from .fields import (
    Fraction,
    Int,
    PositiveFloat,
    _Section,
)


class OutputConfig(_Section):
    """What a run records (trackers of :mod:`pde_rotor.trackers`) and how often."""

    timeseries_interval: PositiveFloat = Field(
        0.01, description="time between rows of timeseries.nc (t, phi, omega, torque, ...)"
    )
    event_interval: PositiveFloat = Field(
        0.01, description="time between omega samples used to detect the commit after a release"
    )
    commit_fraction: Fraction = Field(
        0.5,
        description=(
            "a released rotor has committed to a direction once |omega| >= commit_fraction * "
            "|omega before the stop|"
        ),
    )
    snapshot_interval: PositiveFloat | None = Field(
        10.0, description="time between field snapshots in snapshots.h5 (null: none)"
    )
    movie: bool = Field(True, description="render movie.mp4 while the run goes")
    movie_interval: PositiveFloat = Field(0.05, description="simulated time between movie frames")
    movie_fps: Int = Field(20, ge=1, le=120, description="frames per second of movie.mp4")
    movie_dpi: Int = Field(100, ge=20, le=600, description="resolution of the movie frames")
    movie_view: PositiveFloat = Field(
        1.5, description="half width of the square shown in the movie (paper Fig. 3: 1.5)"
    )
    progress: bool = Field(True, description="show a progress bar (simulated time, ETA, omega)")
    checkpoint_seconds: PositiveFloat = Field(
        60.0, description="wall-clock seconds between rewrites of timeseries.nc during a run"
    )
