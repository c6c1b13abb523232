"""The time series of a run: phi, omega, torques and total camphor in timeseries.nc."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from pde.trackers.interrupts import FixedInterrupts

from ..config import RotorConfig
from ..io.output import write_netcdf_atomic
from ..model.pde import RotorFields, RotorState
from ..model.setup import Setup, as_setup
from ..units import TIME_UNITS
from .base import RotorTracker, sampling_times
from .variables import TIMESERIES_VARIABLES


class TimeSeriesTracker(RotorTracker):
    """Records t, phi, omega, torque, friction, total camphor; writes timeseries.nc.

    Samples every ``interval`` and at the start and end of every stop phase. The file
    is rewritten atomically every ``checkpoint_seconds`` of wall time and at the end.
    """

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
            run: the run's setup (:class:`~pde_rotor.model.setup.Setup`) or configuration.
            interval: time between samples (a multiple of dt).
            path: NetCDF file to write (None: keep in memory only).
            checkpoint_seconds: wall time between intermediate writes.
            attrs: global attributes of the Dataset (config hash, versions, ...).
        """
        setup = as_setup(run)
        times = sampling_times(setup.schedule, interval, setup.config.protocol.t_end)
        super().__init__(setup, FixedInterrupts(times))
        self.interval = interval
        self.path = Path(path) if path is not None else None
        self.checkpoint_seconds = checkpoint_seconds
        self.attrs = dict(attrs or {})
        self.rows: dict[str, list[float]] = {"time": [], **{k: [] for k in TIMESERIES_VARIABLES}}
        self._last_write = time.monotonic()

    def handle(self, field: RotorFields, t: float) -> None:
        """Append one sample of the state's rotor and the total camphor of its field c."""
        cell_area = float(np.prod(field.grid.discretization))
        self.sample(t, field.rotor, float(field.data[0].sum()) * cell_area)

    def sample(self, t: float, rotor: RotorState, camphor_total: float) -> None:
        """Append one sample: the rotor state at time t and int c dA (from :meth:`handle`)."""
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
