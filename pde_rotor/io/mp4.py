"""The one mp4 encoder of the package: H.264 with the ffmpeg binary of imageio-ffmpeg.

Used by the run's :class:`~pde_rotor.trackers.MovieTracker` (frames rendered as the run
goes) and by the gallery's inversion movie. Frames are RGB arrays; the file is written
to ``<name>.part`` and renamed when complete (:func:`pde_rotor.io.output.commit`), so a run
that stops early never leaves a truncated movie under the final name.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .output import commit, part_path


class Mp4Writer:
    """Streams RGB frames into an H.264 mp4, atomically.

    Attributes:
        path: final file name.
        fps: frames per second.
        frames: frames written so far.
    """

    def __init__(self, path: str | Path, fps: int):
        """
        Args:
            path: final mp4 file name.
            fps: frames per second.
        """
        self.path = Path(path)
        self.fps = fps
        self.frames = 0
        self._encoder: Any = None

    def append(self, frame: np.ndarray) -> None:
        """Encode one (height, width, 3) uint8 frame; the first fixes the movie's size.

        Odd sizes lose their last row or column (H.264 in yuv420p needs even sizes).
        """
        frame = frame[: frame.shape[0] // 2 * 2, : frame.shape[1] // 2 * 2, :3]
        if self._encoder is None:
            import imageio_ffmpeg

            height, width = frame.shape[:2]
            self._encoder = imageio_ffmpeg.write_frames(
                str(part_path(self.path)),
                (width, height),
                fps=self.fps,
                codec="libx264",
                output_params=["-f", "mp4"],
                macro_block_size=1,
                quality=7,
            )
            self._encoder.send(None)
        self._encoder.send(np.ascontiguousarray(frame, dtype=np.uint8))
        self.frames += 1

    def close(self) -> Path | None:
        """Finish the file and give it its final name (None: no frame was written)."""
        tmp = part_path(self.path)
        if self._encoder is not None:
            self._encoder.close()
            self._encoder = None
        if self.frames > 0 and tmp.exists():
            commit(tmp, self.path)
            return self.path
        tmp.unlink(missing_ok=True)
        return None


def figure_frame(fig: Any, dpi: int) -> np.ndarray:
    """A matplotlib figure drawn at `dpi` by Agg, as an RGB array (height, width, 3)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    fig.set_dpi(dpi)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3]
