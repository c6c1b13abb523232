"""The base of the rotor trackers: interrupts in whole steps, run status, finalize once.

py-pde's :class:`~pde.solvers.Controller` calls every tracker at the times its
``interrupts`` ask for, before advancing the state further (see pde/trackers/base.py).
The fused solver advances whole steps of dt, so every interrupt time used here is an
integer number of steps (:func:`sampling_times`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pde.trackers.base import InfoDict, TrackerBase

from ..config import RotorConfig
from ..model.protocol import StopSchedule
from ..model.setup import Setup, as_setup


def sampling_times(schedule: StopSchedule, interval: float, t_end: float) -> np.ndarray:
    """Multiples of `interval` in [0, t_end] plus the start and end of every stop.

    Computed in integer steps (:meth:`StopSchedule.sample_steps`) so that every time is
    an exact step time.
    """
    dt = schedule.dt
    return schedule.sample_steps(round(interval / dt), round(t_end / dt)) * dt


class RotorTracker(TrackerBase):
    """Base of the trackers of a rotor run; finalize runs at most once.

    A tracker reads everything it records from the state it is handed: the fields and
    ``state.rotor`` (:class:`~pde_rotor.model.pde.RotorFields`); the run's setup
    (:class:`~pde_rotor.model.setup.Setup`: its configuration and stop schedule) gives it
    its sampling times.

    Attributes:
        setup: the run's objects; config: its configuration; schedule: its stop schedule.
    """

    def __init__(self, run: Setup | RotorConfig, interrupts: Any):
        """
        Args:
            run: the run's setup, or its configuration (made into a setup here).
            interrupts: py-pde's interrupts of the tracker.
        """
        super().__init__(interrupts=interrupts)
        self.setup = as_setup(run)
        self.config = self.setup.config
        self.schedule = self.setup.schedule
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
        self.status = run_status(info)
        self._finish(self.status)

    def _finish(self, status: dict[str, Any]) -> None:
        """Write the results; `status` holds status, message and t_final."""


def run_status(info: InfoDict | None) -> dict[str, Any]:
    """Status of a run from py-pde's diagnostics (or the run driver's equivalent)."""
    controller = (info or {}).get("controller", {})
    if controller.get("successful", False):
        status, message = "completed", controller.get("stop_reason", "")
    else:
        status = controller.get("status", "interrupted")
        message = controller.get("stop_reason", "run did not finish")
    return {"status": status, "message": str(message), "t_final": controller.get("t_final")}
