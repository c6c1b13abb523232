"""The fields c and v of a run, with phi and omega, in a py-pde HDF5 FileStorage."""

from __future__ import annotations

import errno
import os
from pathlib import Path

import numpy as np
from pde.storage import FileStorage
from pde.storage.base import StorageTracker
from pde.trackers.base import InfoDict
from pde.trackers.interrupts import FixedInterrupts

from ..config import RotorConfig
from ..io.output import commit, part_path
from ..model.pde import RotorFields
from ..model.setup import Setup, as_setup
from .base import run_status, sampling_times
from .budget import free_disk, snapshot_reserve


class SnapshotTracker(StorageTracker):
    """Stores the fields [c, v] in an HDF5 py-pde FileStorage, with phi and omega.

    Written to ``snapshots.h5.part`` and renamed to its final name when the run ends.
    The rotor angle and velocity of every snapshot are stored as the file attributes
    ``rotor_phi`` and ``rotor_omega`` (lists in snapshot order).

    A full disk: HDF5 cannot close a file whose write failed, and the process then
    crashes (segmentation fault). So no snapshot is written unless the disk has room
    for it, and the tracker holds :func:`~.budget.snapshot_reserve` bytes of disk in
    ``.snapshots.h5.reserve`` from its start, freed just before the file is closed:
    when another file fills the disk, snapshots.h5 still closes with every snapshot
    written so far.
    """

    def __init__(
        self, run: Setup | RotorConfig, path: str | Path, interval: float, info: dict | None = None
    ):
        """
        Args:
            run: the run's setup (:class:`~pde_rotor.model.setup.Setup`) or configuration.
            path: final HDF5 file name.
            interval: time between snapshots (a multiple of dt).
            info: extra attributes of the file (config hash, config YAML, versions).
        """
        setup = as_setup(run)
        config = setup.config
        self.path = Path(path)
        self.reserve = self.path.with_name(f".{self.path.name}.reserve")
        try:
            with self.reserve.open("wb") as fh:  # written, not sparse: the blocks are taken
                fh.write(bytes(snapshot_reserve(config)))
        except OSError:
            self.reserve.unlink(missing_ok=True)
            raise
        storage = FileStorage(part_path(self.path), info=dict(info or {}), write_mode="truncate")
        schedule = setup.schedule
        times = sampling_times(schedule, interval, config.protocol.t_end)
        # multiples of the interval and the final time (no stop times)
        every = round(interval / schedule.dt)
        steps = np.round(times / schedule.dt).astype(np.int64)
        times = times[(steps % every == 0) | (steps == steps[-1])]
        super().__init__(storage, interrupts=FixedInterrupts(times))
        self.setup = setup
        self.config = config
        self.phi: list[float] = []
        self.omega: list[float] = []
        self._finalized = False

    def handle(self, field: RotorFields, t: float) -> None:
        """Store the fields and the rotor angle.

        Raises:
            OSError: ``ENOSPC`` where the disk has no room for the snapshot (nothing is
                written; :meth:`finalize` then closes the file with the earlier ones).
        """
        room = free_disk(self.path.parent)
        if room < 2 * field.data.nbytes:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(part_path(self.path)))
        super().handle(field, t)
        self.phi.append(field.rotor.phi)
        self.omega.append(field.rotor.omega)

    def finalize(self, info: InfoDict | None = None) -> None:
        """Close the file and give it its final name (once)."""
        if self._finalized:
            return
        self._finalized = True
        self.reserve.unlink(missing_ok=True)
        status = run_status(info)
        self.storage.info.update(
            rotor_phi=self.phi, rotor_omega=self.omega, status=status["status"]
        )
        super().finalize(info)
        self.storage.close()
        if part_path(self.path).exists():
            commit(part_path(self.path), self.path)
