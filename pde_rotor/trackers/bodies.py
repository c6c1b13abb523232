"""The record of a run with bodies: every body's motion in bodies.nc, its inversions, a movie.

:class:`BodiesTracker` samples the state of every body (:class:`BodiesState`: position,
angle, velocities, the tension force and torque, the friction and the contact force of
the last step, whether it was held) every ``interval`` and at the start and end of every
stop of every body's own protocol, and writes ``bodies.nc`` (dimensions ``time`` and ``body``).
:meth:`BodiesTracker.events` classifies each stop of each body with a protocol by the
rule of :mod:`pde_rotor.statistics.inversion`, from the same samples the rotor's
:class:`~pde_rotor.trackers.events.InversionTracker` reads (omega just before the stop,
then every sample of the release until the body's next stop). :class:`BodiesMovieTracker`
renders c, v and every body into movie.mp4 as the run goes. :class:`BodiesLogTracker`
writes a line to the log (run.log) at every tenth of the run and warns once per body when
it moves more than :data:`CELL_FRACTION` of a cell per step.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from pde.trackers.base import InfoDict
from pde.trackers.interrupts import FixedInterrupts

from ..config import RotorConfig
from ..io.mp4 import Mp4Writer, figure_frame
from ..io.output import write_netcdf_atomic
from ..model.setup import Setup, as_setup
from ..model.surface import POSE_COLUMNS, SurfaceFields
from ..plotting.bodies import BodiesFrame
from ..statistics.inversion import classify_release
from ..units import OMEGA_UNITS, TIME_UNITS
from .base import RotorTracker, sampling_times

BODY_VARIABLES: dict[str, dict[str, str]] = {
    "x": {"long_name": "x of the body's position X (its axis)", "units": "diffusion length"},
    "y": {"long_name": "y of the body's position X (its axis)", "units": "diffusion length"},
    "phi": {"long_name": "body angle phi", "units": "rad"},
    "u": {"long_name": "velocity U_x", "units": "diffusion length per time unit"},
    "v": {"long_name": "velocity U_y", "units": "diffusion length per time unit"},
    "omega": {"long_name": "angular velocity dphi/dt", "units": OMEGA_UNITS},
    "force_x": {"long_name": "surface tension force s k int F_k d_x c dA (last step)"},
    "force_y": {"long_name": "surface tension force s k int F_k d_y c dA (last step)"},
    "torque": {"long_name": "surface tension torque about X, Eq. (torque) (last step)"},
    "drag_x": {"long_name": "friction force -mu int F_k (u_k - v)_x dA (last step)"},
    "drag_y": {"long_name": "friction force -mu int F_k (u_k - v)_y dA (last step)"},
    "friction": {"long_name": "friction torque about X, Eq. (eq_motion) (last step)"},
    "stopped": {"long_name": "1 if the body was held during the last step", "units": "1"},
    "contact_x": {"long_name": "contact force of contact: on the body, x (last step)"},
    "contact_y": {"long_name": "contact force of contact: on the body, y (last step)"},
}
"""Variables of bodies.nc (dimensions time, body) with their attributes."""

CELL_FRACTION = 0.2
"""A body whose fastest point moves more than this fraction of a cell per step is warned
about: its footprint jumps across the lattice and the force it feels follows the grid."""

_logger = logging.getLogger(__name__)


class BodiesTracker(RotorTracker):
    """Records every body's state; writes bodies.nc (rewritten every checkpoint)."""

    def __init__(
        self,
        run: Setup | RotorConfig,
        interval: float,
        path: str | Path | None = None,
        *,
        checkpoint_seconds: float = 60.0,
        attrs: dict[str, Any] | None = None,
    ):
        """
        Args:
            run: the run's setup (:class:`~pde_rotor.model.setup.Setup`) or configuration
                (with ``bodies``).
            interval: time between samples (a multiple of dt).
            path: NetCDF file to write (None: keep in memory only).
            checkpoint_seconds: wall time between intermediate writes.
            attrs: global attributes of the Dataset.
        """
        setup = as_setup(run)
        t_end = setup.config.protocol.t_end
        self.bodies = setup.bodies
        times = sampling_times(setup.schedule, interval, t_end)
        for schedule in setup.body_schedules:
            if schedule is not None:
                times = np.union1d(times, sampling_times(schedule, interval, t_end))
        super().__init__(setup, FixedInterrupts(times))
        self.path = Path(path) if path is not None else None
        self.checkpoint_seconds = checkpoint_seconds
        self.attrs = dict(attrs or {})
        self.times: list[float] = []
        self.samples: list[np.ndarray] = []
        self._last_write = time.monotonic()

    def handle(self, field: SurfaceFields, t: float) -> None:
        """Append one sample of every body's state."""
        t = self.step_of(t) * self.schedule.dt
        if self.times and t <= self.times[-1]:
            return  # the same time handed twice (py-pde handles t_end once more)
        self.times.append(t)
        self.samples.append(field.bodies.poses.copy())
        if self.path is not None and time.monotonic() - self._last_write > self.checkpoint_seconds:
            self.write({"status": "running", "message": "", "t_final": t})

    def to_dataset(self, status: dict[str, Any] | None = None) -> xr.Dataset:
        """The samples so far as a Dataset over (time, body)."""
        data = np.array(self.samples).reshape(len(self.samples), len(self.bodies), -1)
        data_vars = {
            name: (("time", "body"), data[:, :, POSE_COLUMNS.index(name)], attrs)
            for name, attrs in BODY_VARIABLES.items()
        }
        coords = {
            "time": ("time", np.asarray(self.times), {"units": TIME_UNITS}),
            "body": ("body", [b.name for b in self.bodies]),
            "motion": ("body", [b.motion for b in self.bodies]),
        }
        ds = xr.Dataset(data_vars, coords=coords)
        ds.attrs.update(self.attrs)
        if status is not None:
            ds.attrs.update({k: str(v) for k, v in status.items()})
        return ds

    def events(self, commit_fraction: float) -> xr.Dataset:
        """Each stop of each body with a protocol, classified (see the module docstring).

        Returns:
            A Dataset over (body, cycle) of t_stop, omega_before, direction_before,
            direction_after, inverted, committed (bodies without stops: no entries).
        """
        times = np.asarray(self.times)
        omega = np.array(self.samples).reshape(len(times), len(self.bodies), -1)[:, :, 5]
        rows = []
        for k, (body, schedule) in enumerate(
            zip(self.bodies, self.setup.body_schedules, strict=True)
        ):
            if schedule is None:
                continue
            starts = schedule.stop_steps() * schedule.dt
            for m, start in enumerate(starts):
                before = np.searchsorted(times, start - 1e-12)
                if before >= len(times) or abs(times[before] - start) > 1e-9:
                    continue  # the run ended before this stop
                release = start + schedule.n_stop * schedule.dt
                end = starts[m + 1] if m + 1 < len(starts) else np.inf
                checks = omega[(times > release + 1e-12) & (times <= end + 1e-12), k]
                outcome = classify_release(omega[before, k], checks, commit_fraction)
                rows.append((body.name, m + 1, start, outcome))
        names = [r[0] for r in rows]
        return xr.Dataset(
            {
                "body": ("event", names),
                "cycle": ("event", [r[1] for r in rows]),
                "t_stop": ("event", [r[2] for r in rows], {"units": TIME_UNITS}),
                "omega_before": ("event", [r[3].omega_before for r in rows]),
                "direction_before": ("event", [r[3].direction_before for r in rows]),
                "direction_after": ("event", [r[3].direction_after for r in rows]),
                "inverted": ("event", [r[3].inverted for r in rows]),
                "committed": ("event", [r[3].committed for r in rows]),
            }
        )

    def write(self, status: dict[str, Any]) -> None:
        """Write bodies.nc atomically."""
        if self.path is not None:
            write_netcdf_atomic(self.to_dataset(status), self.path)
            self._last_write = time.monotonic()

    def _finish(self, status: dict[str, Any]) -> None:
        self.write(status)


class BodiesMovieTracker(RotorTracker):
    """Renders a frame of c, v and every body every interval into an mp4 (movie.mp4).

    As the rotor's :class:`~pde_rotor.trackers.movie.MovieTracker`: frames are rendered as
    the run goes and encoded by :class:`~pde_rotor.io.mp4.Mp4Writer` into
    ``movie.mp4.part``, renamed when complete.
    """

    def __init__(self, run: Setup | RotorConfig, path: str | Path, interval: float, *,
                 fps: int = 20, dpi: int = 100):  # fmt: skip
        """
        Args:
            run: the run's setup or configuration (with ``bodies``).
            path: final mp4 file name.
            interval: simulated time between frames (a multiple of dt).
            fps: frames per second; dpi: resolution of the frames.
        """
        setup = as_setup(run)
        dt = setup.dt
        every = max(1, round(interval / dt))
        steps = round(setup.config.protocol.t_end / dt)
        times = np.arange(0, steps + 1, every, dtype=np.int64) * dt
        super().__init__(setup, FixedInterrupts(times))
        self.path = Path(path)
        self.fps = fps
        self.dpi = dpi
        self.bodies = setup.bodies
        self._frame: BodiesFrame | None = None
        self._writer: Mp4Writer | None = None
        self._last_step = -1

    def initialize(self, field: SurfaceFields, info: InfoDict | None = None) -> float:
        """Create the figure and the mp4 writer."""
        x, y = (np.asarray(a) for a in field.grid.axes_coords)
        self._frame = BodiesFrame(self.bodies, x, y)
        self._writer = Mp4Writer(self.path, self.fps)
        return super().initialize(field, info)

    def handle(self, field: SurfaceFields, t: float) -> None:
        """Render and encode one frame."""
        step = self.step_of(t)
        if step == self._last_step or self._frame is None or self._writer is None:
            return
        self._last_step = step
        poses = field.bodies.poses
        moving = ", ".join(
            f"{b.name} {poses[k, 5]:+.0f}" for k, b in enumerate(self.bodies) if b.motion != "fixed"
        )
        title = f"t = {step * self.schedule.dt:.2f}   omega: {moving}"
        self._frame.update(field.data, poses, title)
        self._writer.append(figure_frame(self._frame.fig, self.dpi))

    def _finish(self, status: dict[str, Any]) -> None:
        if self._writer is not None:
            self._writer.close()


class BodiesLogTracker(RotorTracker):
    """Logs the run's progress as it goes and warns when a body outruns the lattice.

    Every ``interval`` (the time series' sampling) it checks each moving body's fastest
    point, |U| + |omega| R with R the footprint's radius: beyond :data:`CELL_FRACTION`
    dx per step it logs one warning for that body (time, speeds, dx, dt and what to
    change). At every tenth of t_end it logs one line with each body's speed and
    angular velocity, so run.log grows while the run goes.
    """

    def __init__(self, run: Setup | RotorConfig, interval: float):
        """
        Args:
            run: the run's setup or configuration (with ``bodies``).
            interval: simulated time between checks (a multiple of dt).
        """
        setup = as_setup(run)
        dt, t_end = setup.dt, setup.config.protocol.t_end
        every = max(1, round(interval / dt))
        steps = round(t_end / dt)
        marks = np.unique(np.round(np.linspace(0, steps, 11)).astype(np.int64))
        times = np.union1d(np.arange(0, steps + 1, every, dtype=np.int64), marks) * dt
        super().__init__(setup, FixedInterrupts(times))
        self.bodies = setup.bodies
        self.marks = set(int(m) for m in marks[1:])
        self.warned: set[str] = set()

    def handle(self, field: SurfaceFields, t: float) -> None:
        """Warn about fast bodies; log a progress line at every tenth of the run."""
        grid = self.config.grid
        poses = field.bodies.poses
        step = self.step_of(t)
        for k, body in enumerate(self.bodies):
            if body.motion == "fixed" or body.name in self.warned:
                continue
            speed = float(np.hypot(poses[k, 3], poses[k, 4]))
            spin = abs(float(poses[k, 5]))
            cells = (speed + spin * body.shape.reach) * grid.dt / grid.dx
            if cells > CELL_FRACTION:
                self.warned.add(body.name)
                _logger.warning(
                    "body %s moves %.2f of a cell per step at t = %.6g (|U| = %.4g, "
                    "|omega| = %.4g, footprint radius %.3g; dx = %g, dt = %g): above %g, "
                    "its force follows the lattice (lower grid.dt or raise its friction)",
                    body.name, cells, t, speed, spin, body.shape.reach, grid.dx, grid.dt,
                    CELL_FRACTION,
                )  # fmt: skip
        if step in self.marks:
            state = "; ".join(
                f"{b.name} |U| {np.hypot(poses[k, 3], poses[k, 4]):.4g} omega {poses[k, 5]:+.4g}"
                for k, b in enumerate(self.bodies)
                if b.motion != "fixed"
            )
            _logger.info("t = %.6g of %.6g: %s", t, self.config.protocol.t_end, state or "-")
