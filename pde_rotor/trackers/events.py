"""Inversion events of a run: one row per stop-and-release cycle, in events.csv and events.nc.

:class:`InversionTracker` classifies each cycle m by the one rule of
:mod:`pde_rotor.statistics.inversion`:

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
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from pde.trackers.base import InfoDict
from pde.trackers.interrupts import FixedInterrupts

from ..config import RotorConfig
from ..io.output import AppendOnlyCSV, write_netcdf_atomic
from ..model.pde import RotorFields
from ..model.setup import Setup, as_setup
from ..statistics.inversion import ReleaseWatch, direction
from .base import RotorTracker, sampling_times
from .variables import EVENT_ATTRS, EVENT_COLUMNS

_logger = logging.getLogger(__name__)


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


class InversionTracker(RotorTracker):
    """Detects, per cycle, whether the released rotor inverted its direction.

    Appends one row per cycle to events.csv as soon as it is known (flushed to disk) and
    writes events.nc atomically at the end.
    """

    def __init__(
        self,
        run: Setup | RotorConfig,
        interval: float,
        commit_fraction: float,
        csv_path: str | Path | None = None,
        nc_path: str | Path | None = None,
        *,
        attrs: dict[str, Any] | None = None,
    ):
        """
        Args:
            run: the run's setup (:class:`~pde_rotor.model.setup.Setup`) or configuration.
            interval: time between omega samples after a release (a multiple of dt).
            commit_fraction: commit criterion |omega| >= commit_fraction |omega_before|.
            csv_path: events.csv, appended row by row (None: not written).
            nc_path: events.nc, written at the end (None: not written).
            attrs: global attributes of events.nc.
        """
        setup = as_setup(run)
        schedule = setup.schedule
        super().__init__(
            setup, FixedInterrupts(sampling_times(schedule, interval, setup.config.protocol.t_end))
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

    def initialize(self, field: RotorFields, info: InfoDict | None = None) -> float:
        """Create events.csv with its header."""
        if self.csv_path is not None and self._csv is None:
            self._csv = AppendOnlyCSV(self.csv_path, EVENT_COLUMNS)
        return super().initialize(field, info)

    def release_time(self, event: InversionEvent) -> float:
        """Time at which the stop of `event` ends."""
        return event.t_stop + self.schedule.n_stop * self.schedule.dt

    def handle(self, field: RotorFields, t: float) -> None:
        """Check the open release (:mod:`pde_rotor.statistics.inversion`), open a cycle at its stop.

        The sample at the start of the next stop is the release's last check; the
        release is closed there, committed or not, before the next cycle opens.
        """
        step = self.step_of(t)
        omega = field.rotor.omega
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
