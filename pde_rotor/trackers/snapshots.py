"""The fields c and v of a run, with phi and omega, in a py-pde HDF5 FileStorage."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from pde.storage import FileStorage
from pde.storage.base import StorageTracker
from pde.trackers.base import InfoDict
from pde.trackers.interrupts import FixedInterrupts

from ..config import RotorConfig
from ..io.output import commit, part_path
from ..model.pde import RotorFields
from ..model.protocol import StopSchedule
from .base import run_status, sampling_times


class SnapshotTracker(StorageTracker):
    """Stores the fields [c, v] in an HDF5 py-pde FileStorage, with phi and omega.

    Written to ``snapshots.h5.part`` and renamed to its final name when the run ends.
    The rotor angle and velocity of every snapshot are stored as the file attributes
    ``rotor_phi`` and ``rotor_omega`` (lists in snapshot order).
    """

    def __init__(
        self, config: RotorConfig, path: str | Path, interval: float, info: dict | None = None
    ):
        """
        Args:
            config: the run's configuration.
            path: final HDF5 file name.
            interval: time between snapshots (a multiple of dt).
            info: extra attributes of the file (config hash, config YAML, versions).
        """
        self.path = Path(path)
        storage = FileStorage(part_path(self.path), info=dict(info or {}), write_mode="truncate")
        schedule = StopSchedule.from_config(config.protocol, config.grid.dt)
        times = sampling_times(schedule, interval, config.protocol.t_end)
        # multiples of the interval and the final time (no stop times)
        every = round(interval / schedule.dt)
        steps = np.round(times / schedule.dt).astype(np.int64)
        times = times[(steps % every == 0) | (steps == steps[-1])]
        super().__init__(storage, interrupts=FixedInterrupts(times))
        self.config = config
        self.phi: list[float] = []
        self.omega: list[float] = []
        self._finalized = False

    def handle(self, field: RotorFields, t: float) -> None:
        """Store the fields and the rotor angle."""
        super().handle(field, t)
        self.phi.append(field.rotor.phi)
        self.omega.append(field.rotor.omega)

    def finalize(self, info: InfoDict | None = None) -> None:
        """Close the file and give it its final name (once)."""
        if self._finalized:
            return
        self._finalized = True
        status = run_status(info)
        self.storage.info.update(
            rotor_phi=self.phi, rotor_omega=self.omega, status=status["status"]
        )
        super().finalize(info)
        self.storage.close()
        if part_path(self.path).exists():
            commit(part_path(self.path), self.path)
