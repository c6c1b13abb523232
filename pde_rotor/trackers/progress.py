"""A tqdm progress bar of a run (rotor or bodies), with an ETA that leaves the compile time out."""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
from pde.trackers.base import InfoDict
from pde.trackers.interrupts import RealtimeInterrupts

with warnings.catch_warnings():
    # in a notebook without ipywidgets tqdm.auto warns, then draws its text bar: the
    # same bar, without a warning in every executed notebook
    warnings.filterwarnings("ignore", message="IProgress not found")
    from tqdm.auto import tqdm

from ..config import RotorConfig
from ..model.pde import RotorFields
from ..model.setup import Setup, as_setup
from ..model.surface import SurfaceFields
from .base import RotorTracker


class ProgressBarTracker(RotorTracker):
    """tqdm progress bar: simulated time, ETA, current omega and protocol phase.

    In a run with bodies it shows the fastest body's speed |U| and |omega| instead.

    Until the first steps have run (the first run compiles the solver, about 10 s) the
    bar says so instead of an ETA. The ETA is then the remaining simulated time over the
    rate measured since the first interrupt after those steps, so the compile time does
    not inflate it (tqdm's own rate would count it).
    """

    COMPILING = "compiling the solver (first run only)"
    """Shown until the first steps have run."""

    def __init__(
        self,
        run: Setup | RotorConfig,
        refresh_seconds: float = 0.5,
        *,
        leave: bool = True,
        clock: Callable[[], float] = time.monotonic,
    ):
        """
        Args:
            run: the run's setup (:class:`~pde_rotor.model.setup.Setup`) or configuration.
            refresh_seconds: wall-clock time between updates.
            leave: keep the bar on screen when the run ends.
            clock: wall clock in seconds (for tests).
        """
        setup = as_setup(run)
        super().__init__(
            setup, RealtimeInterrupts(duration=refresh_seconds, dt_initial=100 * setup.dt)
        )
        self.leave = leave
        self.clock = clock
        self.bar: tqdm | None = None
        self._t_start = 0.0
        self._measured_from: tuple[float, float] | None = None

    def initialize(self, field: RotorFields, info: InfoDict | None = None) -> float:
        """Open the bar over [t_start, t_end] of the controller."""
        t_first = super().initialize(field, info)
        controller = (info or {}).get("controller", {})
        self._t_start = float(controller.get("t_start", 0.0))
        t_end = float(controller.get("t_end", self.config.protocol.t_end))
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

    def handle(self, field: RotorFields | SurfaceFields, t: float) -> None:
        """Advance the bar to t and show the ETA, omega, phase and cycle (bodies: speeds)."""
        if self.bar is None:
            return
        self.bar.n = round(min(t, self.bar.total), 6)
        if isinstance(field, SurfaceFields):
            poses = field.bodies.poses
            speed = float(np.hypot(poses[:, 3], poses[:, 4]).max())
            spin = float(np.abs(poses[:, 5]).max())
            state = f"max |U|={speed:.3g} max |omega|={spin:.3g}"
        else:
            rotor = field.rotor
            cycle = self.schedule.cycle(max(self.step_of(t) - 1, 0))
            phase = "stopped" if rotor.stopped else "running"
            state = f"omega={rotor.omega:+.1f} {phase} cycle {cycle}/{self.schedule.cycles}"
        self.bar.set_postfix_str(f"{self.eta(t)}, {state}", refresh=False)
        self.bar.refresh()

    def _finish(self, status: dict[str, Any]) -> None:
        if self.bar is not None:
            if status["status"] == "completed":
                self.bar.n = self.bar.total
                self.bar.refresh()
            self.bar.close()
