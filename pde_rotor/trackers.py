"""py-pde trackers that watch a rotor run: progress, time series, inversion events, fields, movie.

py-pde's :class:`~pde.solvers.Controller` calls every tracker at the times its
``interrupts`` ask for, before advancing the state further (see pde/trackers/base.py).
The fused solver advances whole steps of dt, so every interrupt time used here is an
integer number of steps; the trackers that record the rotor ask in addition for the
start and the end of every stop phase (:meth:`StopSchedule.stop_times`), so that the
angular velocity just before each stop is sampled exactly.

The rotor state is not part of py-pde's FieldCollection; trackers read it from the
:class:`~pde_rotor.simulation.Simulation` given to their constructor: ``sim.rotor``
holds phi, omega (Eq. (eq_motion)) and the torque T (Eq. (torque)) and friction torque
of the last step.

Inversion events (:class:`InversionTracker`), one row per stop-and-release cycle m,
classified by the one rule of :mod:`pde_rotor.inversion`:

* ``omega_before``: omega at the start of stop m (the last step before the stop);
* ``direction_after``: the sign of omega when the released rotor has *committed*, i.e.
  at the first sample (every ``output.event_interval``, from the release to the start
  of the next stop or the end of the run) at which
  ``omega != 0 and |omega| >= commit_fraction * |omega_before|``; 0 and
  ``committed = false`` if that never happens;
* ``inverted``: committed and ``direction_after == -sign(omega_before)`` (a release that
  never commits is not an inversion);
* ``time_to_commit``: commit time minus release time (NaN if not committed);
* ``omega_after``: omega at commit (or at the last sample of the release).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr
from pde import FieldCollection
from pde.storage import FileStorage
from pde.storage.base import StorageTracker
from pde.trackers.base import InfoDict, TrackerBase
from pde.trackers.interrupts import FixedInterrupts, RealtimeInterrupts
from tqdm.auto import tqdm

from .inversion import ReleaseWatch, direction
from .mp4 import Mp4Writer, figure_frame
from .output import AppendOnlyCSV, commit, part_path, write_netcdf_atomic
from .protocol import StopSchedule

if TYPE_CHECKING:
    from .simulation import Simulation

_logger = logging.getLogger(__name__)

TIME_UNITS = "1/a"
"""Unit of every time in the outputs: the paper's dimensionless time, in units of 1/a
(a: the evaporation rate of camphor)."""
OMEGA_UNITS = f"rad per {TIME_UNITS}"
"""Unit of the angular velocity omega."""
LENGTH_UNITS = "sqrt(D/a)"
"""Unit of every length: the diffusion length of camphor."""

TIMESERIES_VARIABLES: dict[str, dict[str, str]] = {
    "phi": {
        "long_name": "rotor angle phi",
        "units": "rad",
        "equation": "Eq. (eq_motion): dphi/dt = omega",
    },
    "omega": {
        "long_name": "angular velocity dphi/dt",
        "units": OMEGA_UNITS,
        "equation": "Eq. (eq_motion)",
    },
    "torque": {
        "long_name": "surface tension torque T (of the last step)",
        "units": "model units (k, D, a = 1)",
        "equation": "Eq. (torque)",
    },
    "friction": {
        "long_name": "friction torque -mu int F (|r|^2 omega - r x v) dA (of the last step)",
        "units": "model units (k, D, a = 1)",
        "equation": "Eq. (eq_motion)",
    },
    "camphor_total": {
        "long_name": "total camphor int c dA over the domain",
        "units": "model units",
        "equation": "Eq. (eqc)",
    },
    "stopped": {
        "long_name": "1 if the last step was in a stop phase (phi frozen, omega = 0)",
        "units": "1",
        "equation": "protocol (section Model)",
    },
    "cycle": {
        "long_name": "stop-and-release cycle m of the last step (0: before the first stop)",
        "units": "1",
        "equation": "protocol (section Model)",
    },
}
"""Variables of timeseries.nc with their attributes."""

EVENT_COLUMNS = (
    "cycle",
    "t_stop",
    "omega_before",
    "direction_before",
    "direction_after",
    "inverted",
    "committed",
    "time_to_commit",
    "omega_after",
)
"""Columns of events.csv / variables of events.nc (see module docstring)."""

EVENT_ATTRS: dict[str, dict[str, str]] = {
    "t_stop": {"long_name": "start time of the stop", "units": TIME_UNITS},
    "omega_before": {"long_name": "omega just before the stop", "units": OMEGA_UNITS},
    "direction_before": {"long_name": "sign of omega_before (+1: counterclockwise)"},
    "direction_after": {"long_name": "sign of omega at commit (0: not committed)"},
    "inverted": {"long_name": "committed and direction_after == -direction_before"},
    "committed": {"long_name": "|omega| reached commit_fraction |omega_before| after release"},
    "time_to_commit": {"long_name": "commit time minus release time", "units": TIME_UNITS},
    "omega_after": {
        "long_name": "omega at commit (or at the last sample of the release)",
        "units": OMEGA_UNITS,
    },
}


def _sampling_times(schedule: StopSchedule, interval: float, t_end: float) -> np.ndarray:
    """Multiples of `interval` in [0, t_end] plus the start and end of every stop.

    Computed in integer steps (:meth:`StopSchedule.sample_steps`) so that every time is
    an exact step time.
    """
    dt = schedule.dt
    return schedule.sample_steps(round(interval / dt), round(t_end / dt)) * dt


class _RotorTracker(TrackerBase):
    """Base of the trackers that read ``sim.rotor``; finalize runs at most once."""

    def __init__(self, sim: Simulation, interrupts: Any):
        super().__init__(interrupts=interrupts)
        self.sim = sim
        self.schedule = StopSchedule.from_config(sim.config.protocol, sim.config.grid.dt)
        self.status: dict[str, Any] | None = None
        self._finalized = False

    def step_of(self, t: float) -> int:
        """Index of the step that starts at time t."""
        return round(t / self.schedule.dt)

    def finalize(self, info: InfoDict | None = None) -> None:
        """Finish once (the run driver may call it again after an error)."""
        if self._finalized:
            return
        self._finalized = True
        self.status = _run_status(info)
        self._finish(self.status)

    def _finish(self, status: dict[str, Any]) -> None:
        """Write the results; `status` holds status, message and t_final."""


def _run_status(info: InfoDict | None) -> dict[str, Any]:
    """Status of a run from py-pde's diagnostics (or the run driver's equivalent)."""
    controller = (info or {}).get("controller", {})
    if controller.get("successful", False):
        status, message = "completed", controller.get("stop_reason", "")
    else:
        status = controller.get("status", "interrupted")
        message = controller.get("stop_reason", "run did not finish")
    return {"status": status, "message": str(message), "t_final": controller.get("t_final")}


class ProgressBarTracker(_RotorTracker):
    """tqdm progress bar: simulated time, ETA, current omega and protocol phase.

    Until the first steps have run (the first run compiles the solver, about 10 s) the
    bar says so instead of an ETA. The ETA is then the remaining simulated time over the
    rate measured since the first interrupt after those steps, so the compile time does
    not inflate it (tqdm's own rate would count it).
    """

    COMPILING = "compiling the solver (first run only)"
    """Shown until the first steps have run."""

    def __init__(
        self,
        sim: Simulation,
        refresh_seconds: float = 0.5,
        *,
        leave: bool = True,
        clock: Callable[[], float] = time.monotonic,
    ):
        """
        Args:
            sim: the simulation.
            refresh_seconds: wall-clock time between updates.
            leave: keep the bar on screen when the run ends.
            clock: wall clock in seconds (for tests).
        """
        super().__init__(
            sim, RealtimeInterrupts(duration=refresh_seconds, dt_initial=100 * sim.config.grid.dt)
        )
        self.leave = leave
        self.clock = clock
        self.bar: tqdm | None = None
        self._t_start = 0.0
        self._measured_from: tuple[float, float] | None = None

    def initialize(self, field: FieldCollection, info: InfoDict | None = None) -> float:
        """Open the bar over [t_start, t_end] of the controller."""
        t_first = super().initialize(field, info)
        controller = (info or {}).get("controller", {})
        self._t_start = float(controller.get("t_start", 0.0))
        t_end = float(controller.get("t_end", self.sim.config.protocol.t_end))
        self._measured_from = None
        self.bar = tqdm(
            total=round(t_end, 6),
            initial=round(self._t_start, 6),
            unit="t",
            leave=self.leave,
            dynamic_ncols=True,
            bar_format="{l_bar}{bar}| t={n:.2f}/{total:.2f} [{elapsed}{postfix}]",
            postfix=self.COMPILING,
        )
        return t_first

    def eta(self, t: float) -> str:
        """The postfix's first part: compiling, measuring, or ``ETA 12:34``."""
        now = self.clock()
        if t <= self._t_start:
            return self.COMPILING
        if self._measured_from is None:
            self._measured_from = (t, now)
        t0, wall0 = self._measured_from
        if t <= t0 or now <= wall0:
            return "ETA measuring"
        remaining = (self.bar.total - t) * (now - wall0) / (t - t0) if self.bar else math.nan
        return f"ETA {tqdm.format_interval(max(remaining, 0.0))}"

    def handle(self, field: FieldCollection, t: float) -> None:
        """Advance the bar to t and show the ETA, omega, phase and cycle."""
        if self.bar is None:
            return
        rotor = self.sim.rotor
        cycle = self.schedule.cycle(max(self.step_of(t) - 1, 0))
        self.bar.n = round(min(t, self.bar.total), 6)
        self.bar.set_postfix_str(
            f"{self.eta(t)}, omega={rotor.omega:+.1f} "
            f"{'stopped' if rotor.stopped else 'running'} cycle {cycle}/{self.schedule.cycles}",
            refresh=False,
        )
        self.bar.refresh()

    def _finish(self, status: dict[str, Any]) -> None:
        if self.bar is not None:
            if status["status"] == "completed":
                self.bar.n = self.bar.total
                self.bar.refresh()
            self.bar.close()


class TimeSeriesTracker(_RotorTracker):
    """Records t, phi, omega, torque, friction, total camphor; writes timeseries.nc.

    Samples every ``interval`` and at the start and end of every stop phase. The file
    is rewritten atomically every ``checkpoint_seconds`` of wall time and at the end.
    """

    def __init__(
        self,
        sim: Simulation,
        interval: float,
        path: str | Path | None = None,
        *,
        checkpoint_seconds: float = 60.0,
        attrs: dict[str, Any] | None = None,
    ):
        """
        Args:
            sim: the simulation.
            interval: time between samples (a multiple of dt).
            path: NetCDF file to write (None: keep in memory only).
            checkpoint_seconds: wall time between intermediate writes.
            attrs: global attributes of the Dataset (config hash, versions, ...).
        """
        times = _sampling_times(
            StopSchedule.from_config(sim.config.protocol, sim.config.grid.dt),
            interval,
            sim.config.protocol.t_end,
        )
        super().__init__(sim, FixedInterrupts(times))
        self.interval = interval
        self.path = Path(path) if path is not None else None
        self.checkpoint_seconds = checkpoint_seconds
        self.attrs = dict(attrs or {})
        self.rows: dict[str, list[float]] = {"time": [], **{k: [] for k in TIMESERIES_VARIABLES}}
        self._cell_area = sim.pde.domain.cell_area
        self._last_write = time.monotonic()

    def handle(self, field: FieldCollection, t: float) -> None:
        """Append one sample of the rotor state and the total camphor of `field`."""
        self.sample(t, float(field.data[0].sum()) * self._cell_area)

    def sample(self, t: float, camphor_total: float) -> None:
        """Append one sample: the rotor state ``sim.rotor`` at time t and int c dA.

        Called by :meth:`handle`, and directly when the samples come from an ensemble
        backend's records (:mod:`pde_rotor.single_run`).
        """
        rotor = self.sim.rotor
        step = self.step_of(t)
        values = {
            "time": step * self.schedule.dt,
            "phi": rotor.phi,
            "omega": rotor.omega,
            "torque": rotor.torque,
            "friction": rotor.friction,
            "camphor_total": camphor_total,
            "stopped": int(rotor.stopped),
            "cycle": self.schedule.cycle(max(step - 1, 0)),
        }
        if self.rows["time"] and values["time"] <= self.rows["time"][-1]:
            return  # the same time handed twice (py-pde handles t_end once more)
        for key, value in values.items():
            self.rows[key].append(value)
        if self.path is not None and time.monotonic() - self._last_write > self.checkpoint_seconds:
            self.write({"status": "running", "message": "", "t_final": values["time"]})

    def to_dataset(self, status: dict[str, Any] | None = None) -> xr.Dataset:
        """The samples so far as an xarray Dataset over ``time``."""
        data_vars = {}
        for name, attrs in TIMESERIES_VARIABLES.items():
            dtype = np.int64 if name in ("stopped", "cycle") else np.float64
            data_vars[name] = ("time", np.asarray(self.rows[name], dtype=dtype), attrs)
        coords = {"time": ("time", np.asarray(self.rows["time"]), {"units": TIME_UNITS})}
        ds = xr.Dataset(data_vars, coords=coords)
        ds.attrs.update(self.attrs)
        ds.attrs["sample_interval"] = self.interval
        ds.attrs["sampling"] = "every sample_interval and at the start and end of every stop"
        if status is not None:
            ds.attrs["status"] = status["status"]
            ds.attrs["message"] = status["message"]
        return ds

    def write(self, status: dict[str, Any]) -> None:
        """Write timeseries.nc atomically (no-op without a path)."""
        if self.path is None:
            return
        write_netcdf_atomic(self.to_dataset(status), self.path)
        self._last_write = time.monotonic()

    def _finish(self, status: dict[str, Any]) -> None:
        self.write(status)


@dataclass
class InversionEvent:
    """Outcome of one stop-and-release cycle (see module docstring)."""

    cycle: int
    t_stop: float
    omega_before: float
    direction_before: int
    direction_after: int = 0
    inverted: bool = False
    committed: bool = False
    time_to_commit: float = math.nan
    omega_after: float = math.nan


class InversionTracker(_RotorTracker):
    """Detects, per cycle, whether the released rotor inverted its direction.

    Appends one row per cycle to events.csv as soon as it is known (flushed to disk) and
    writes events.nc atomically at the end.
    """

    def __init__(
        self,
        sim: Simulation,
        interval: float,
        commit_fraction: float,
        csv_path: str | Path | None = None,
        nc_path: str | Path | None = None,
        *,
        attrs: dict[str, Any] | None = None,
    ):
        """
        Args:
            sim: the simulation.
            interval: time between omega samples after a release (a multiple of dt).
            commit_fraction: commit criterion |omega| >= commit_fraction |omega_before|.
            csv_path: events.csv, appended row by row (None: not written).
            nc_path: events.nc, written at the end (None: not written).
            attrs: global attributes of events.nc.
        """
        cfg = sim.config
        schedule = StopSchedule.from_config(cfg.protocol, cfg.grid.dt)
        super().__init__(
            sim, FixedInterrupts(_sampling_times(schedule, interval, cfg.protocol.t_end))
        )
        self.interval = interval
        self.commit_fraction = commit_fraction
        self.csv_path = Path(csv_path) if csv_path is not None else None
        self.nc_path = Path(nc_path) if nc_path is not None else None
        self.attrs = dict(attrs or {})
        self._stop_steps = {int(s): m + 1 for m, s in enumerate(schedule.stop_steps())}
        self.events: list[InversionEvent] = []
        self._open: InversionEvent | None = None
        self._watch: ReleaseWatch | None = None
        self._last_t = math.nan
        self._csv: AppendOnlyCSV | None = None

    def initialize(self, field: FieldCollection, info: InfoDict | None = None) -> float:
        """Create events.csv with its header."""
        if self.csv_path is not None and self._csv is None:
            self._csv = AppendOnlyCSV(self.csv_path, EVENT_COLUMNS)
        return super().initialize(field, info)

    def release_time(self, event: InversionEvent) -> float:
        """Time at which the stop of `event` ends."""
        return event.t_stop + self.schedule.n_stop * self.schedule.dt

    def handle(self, field: FieldCollection, t: float) -> None:
        """Check the open release (rule of :mod:`pde_rotor.inversion`), open a cycle at its stop.

        The sample at the start of the next stop is the release's last check; the
        release is closed there, committed or not, before the next cycle opens.
        """
        step = self.step_of(t)
        omega = self.sim.rotor.omega
        event, watch = self._open, self._watch
        released = event is not None and t >= self.release_time(event)
        if released and watch is not None and watch.check(omega):
            self._close(event, watch, t=step * self.schedule.dt)
        cycle = self._stop_steps.get(step)
        if cycle is not None:
            if self._open is not None and self._watch is not None:
                self._close(self._open, self._watch, t=step * self.schedule.dt)
            self._open = InversionEvent(
                cycle=cycle,
                t_stop=step * self.schedule.dt,
                omega_before=omega,
                direction_before=direction(omega),
            )
            self._watch = ReleaseWatch(omega, self.commit_fraction)
        self._last_t = t

    def _close(self, event: InversionEvent, watch: ReleaseWatch, *, t: float) -> None:
        outcome = watch.outcome
        event.direction_after = outcome.direction_after
        event.inverted = outcome.inverted
        event.committed = outcome.committed
        event.omega_after = outcome.omega_after
        if outcome.committed:
            steps = self.step_of(t) - self.step_of(self.release_time(event))
            event.time_to_commit = round(steps * self.schedule.dt, 12)
        self.events.append(event)
        self._open = self._watch = None
        if self._csv is not None:
            self._csv.append(asdict(event))
        _logger.info(
            "cycle %d: omega %+.2f -> %+.2f, %s%s",
            event.cycle,
            event.omega_before,
            outcome.omega_after,
            "inverted" if event.inverted else "kept direction",
            "" if outcome.committed else " (not committed: not an inversion)",
        )

    @property
    def inversion_probability(self) -> float:
        """Fraction of the recorded cycles that inverted (NaN if none)."""
        if not self.events:
            return math.nan
        return sum(e.inverted for e in self.events) / len(self.events)

    def to_dataset(self, status: dict[str, Any] | None = None) -> xr.Dataset:
        """The events so far as an xarray Dataset over ``cycle``."""
        columns = {name: [getattr(e, name) for e in self.events] for name in EVENT_COLUMNS}
        dtypes = {
            "cycle": np.int64,
            "direction_before": np.int64,
            "direction_after": np.int64,
            "inverted": bool,
            "committed": bool,
        }
        data_vars = {
            name: ("cycle", np.asarray(columns[name], dtype=dtypes.get(name, np.float64)), attrs)
            for name, attrs in EVENT_ATTRS.items()
        }
        ds = xr.Dataset(data_vars, coords={"cycle": np.asarray(columns["cycle"], dtype=np.int64)})
        ds.attrs.update(self.attrs)
        ds.attrs["commit_fraction"] = self.commit_fraction
        ds.attrs["sample_interval"] = self.interval
        ds.attrs["commit_criterion"] = (
            "after the release, the first sample with omega != 0 and |omega| >= "
            "commit_fraction * |omega_before|; direction_after is the sign of omega there; "
            "a release that never commits has direction_after 0 and is not an inversion"
        )
        ds.attrs["inversion_probability"] = self.inversion_probability
        ds.attrs["inversions"] = int(sum(e.inverted for e in self.events))
        if status is not None:
            ds.attrs["status"] = status["status"]
            ds.attrs["message"] = status["message"]
        return ds

    def _finish(self, status: dict[str, Any]) -> None:
        event, watch = self._open, self._watch
        if event is not None and watch is not None and self._last_t >= self.release_time(event):
            # released but not committed when the run ended
            self._close(event, watch, t=self._last_t)
        if self._csv is not None:
            self._csv.close()
        if self.nc_path is not None:
            write_netcdf_atomic(self.to_dataset(status), self.nc_path)


class SnapshotTracker(StorageTracker):
    """Stores the fields [c, v] in an HDF5 py-pde FileStorage, with phi and omega.

    Written to ``snapshots.h5.part`` and renamed to its final name when the run ends.
    The rotor angle and velocity of every snapshot are stored as the file attributes
    ``rotor_phi`` and ``rotor_omega`` (lists in snapshot order).
    """

    def __init__(
        self, sim: Simulation, path: str | Path, interval: float, info: dict | None = None
    ):
        """
        Args:
            sim: the simulation.
            path: final HDF5 file name.
            interval: time between snapshots (a multiple of dt).
            info: extra attributes of the file (config hash, config YAML, versions).
        """
        self.path = Path(path)
        storage = FileStorage(part_path(self.path), info=dict(info or {}), write_mode="truncate")
        schedule = StopSchedule.from_config(sim.config.protocol, sim.config.grid.dt)
        times = _sampling_times(schedule, interval, sim.config.protocol.t_end)
        # multiples of the interval and the final time (no stop times)
        every = round(interval / schedule.dt)
        steps = np.round(times / schedule.dt).astype(np.int64)
        times = times[(steps % every == 0) | (steps == steps[-1])]
        super().__init__(storage, interrupts=FixedInterrupts(times))
        self.sim = sim
        self.phi: list[float] = []
        self.omega: list[float] = []
        self._finalized = False

    def handle(self, field: FieldCollection, t: float) -> None:
        """Store the fields and the rotor angle."""
        super().handle(field, t)
        self.phi.append(self.sim.rotor.phi)
        self.omega.append(self.sim.rotor.omega)

    def finalize(self, info: InfoDict | None = None) -> None:
        """Close the file and give it its final name (once)."""
        if self._finalized:
            return
        self._finalized = True
        status = _run_status(info)
        self.storage.info.update(
            rotor_phi=self.phi, rotor_omega=self.omega, status=status["status"]
        )
        super().finalize(info)
        self.storage.close()
        if part_path(self.path).exists():
            commit(part_path(self.path), self.path)


class MovieTracker(_RotorTracker):
    """Renders a frame (c, v, plate and pills, omega, phase) every interval into an mp4.

    Frames are rendered as the run goes, so no field history is kept in memory. The
    mp4 is encoded by the package's :class:`~pde_rotor.mp4.Mp4Writer` (ffmpeg of the
    imageio-ffmpeg wheel), written to ``movie.mp4.part`` and renamed when complete.
    """

    def __init__(
        self,
        sim: Simulation,
        path: str | Path,
        interval: float,
        *,
        fps: int = 20,
        dpi: int = 100,
        half_width: float = 1.5,
    ):
        """
        Args:
            sim: the simulation.
            path: final mp4 file name.
            interval: simulated time between frames (a multiple of dt).
            fps: frames per second of the movie.
            dpi: resolution of the frames.
            half_width: half width of the square shown.
        """
        dt = sim.config.grid.dt
        every = max(1, round(interval / dt))
        n_end = round(sim.config.protocol.t_end / dt)
        times = np.arange(0, n_end + 1, every, dtype=np.int64) * dt
        super().__init__(sim, FixedInterrupts(times))
        self.path = Path(path)
        self.fps = fps
        self.dpi = dpi
        self.half_width = half_width
        self.frames = 0
        self._writer = None
        self._frame = None
        self._last_step = -1

    def initialize(self, field: FieldCollection, info: InfoDict | None = None) -> float:
        """Create the figure and the mp4 writer."""
        from .plotting import RotorFrame

        sim = self.sim
        self._frame = RotorFrame(sim.pde.shape, sim.pde.domain.coords, self.half_width)
        self._writer = Mp4Writer(self.path, self.fps)
        return super().initialize(field, info)

    def handle(self, field: FieldCollection, t: float) -> None:
        """Render and encode one frame."""
        from .plotting import frame_title

        step = self.step_of(t)
        if step == self._last_step or self._frame is None:
            return
        self._last_step = step
        rotor = self.sim.rotor
        cycle = self.schedule.cycle(max(step - 1, 0))
        title = frame_title(
            step * self.schedule.dt, rotor.omega, rotor.stopped, cycle, self.schedule.cycles
        )
        self._frame.update(field.data, rotor.phi, title=title)
        self._writer.append(figure_frame(self._frame.fig, self.dpi))
        self.frames += 1

    def _finish(self, status: dict[str, Any]) -> None:
        if self._writer is None:
            return
        self._writer.close()
        self._writer = None
