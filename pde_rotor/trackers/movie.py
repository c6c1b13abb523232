"""The movie of a run: one frame of c, v, plate and omega every interval, into an mp4."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from pde.trackers.base import InfoDict
from pde.trackers.interrupts import FixedInterrupts

from ..config import RotorConfig
from ..io.mp4 import Mp4Writer, figure_frame
from ..model.pde import RotorFields
from ..model.setup import Setup, as_setup
from ..plotting.run import RotorFrame, frame_title
from .base import RotorTracker


class MovieTracker(RotorTracker):
    """Renders a frame (c, v, plate and pills, omega, phase) every interval into an mp4.

    Frames are rendered as the run goes, so no field history is kept in memory. The
    mp4 is encoded by the package's :class:`~pde_rotor.io.mp4.Mp4Writer` (ffmpeg of the
    imageio-ffmpeg wheel), written to ``movie.mp4.part`` and renamed when complete.
    """

    def __init__(
        self,
        run: Setup | RotorConfig,
        path: str | Path,
        interval: float,
        *,
        fps: int = 20,
        dpi: int = 100,
        half_width: float = 1.5,
    ):
        """
        Args:
            run: the run's setup (:class:`~pde_rotor.model.setup.Setup`) or configuration.
            path: final mp4 file name.
            interval: simulated time between frames (a multiple of dt).
            fps: frames per second of the movie.
            dpi: resolution of the frames.
            half_width: half width of the square shown.
        """
        setup = as_setup(run)
        dt = setup.dt
        every = max(1, round(interval / dt))
        n_end = round(setup.config.protocol.t_end / dt)
        times = np.arange(0, n_end + 1, every, dtype=np.int64) * dt
        super().__init__(setup, FixedInterrupts(times))
        self.path = Path(path)
        self.fps = fps
        self.dpi = dpi
        self.half_width = half_width
        self.frames = 0
        self._writer = None
        self._frame = None
        self._last_step = -1

    def initialize(self, field: RotorFields, info: InfoDict | None = None) -> float:
        """Create the figure and the mp4 writer."""
        self._frame = RotorFrame(self.setup.shape, field.grid.axes_coords[0], self.half_width)
        self._writer = Mp4Writer(self.path, self.fps)
        return super().initialize(field, info)

    def handle(self, field: RotorFields, t: float) -> None:
        """Render and encode one frame."""
        step = self.step_of(t)
        if step == self._last_step or self._frame is None:
            return
        self._last_step = step
        rotor = field.rotor
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
