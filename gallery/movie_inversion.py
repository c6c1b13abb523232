"""Movie of one inversion: steady rotation, a stop of 0.5, release in the other direction.

The symmetric rotor of configs/paper_fig4a.yaml (Delta = 0) spins up freely, is stopped
once for t_stop = 0.5 and released. The movie shows the camphor concentration c of
Eq. (eqc) with the surface flow v of Eq. (eqv) as arrows
(:class:`pde_rotor.plotting.run.RotorFrame`) next to omega(t), Eq. (eq_motion). While the
plate turns, frames are 0.002 (before the stop) and 0.0025 (after the release) time units
apart: at omega = 176 the hexagon turns at most 0.44 rad per frame, below half its symmetry
angle pi/3, so the eye sees the true direction; during the stop, 0.01 apart. Written:
movie_inversion.mp4 (ffmpeg of imageio-ffmpeg),
movie_inversion.gif (small, for the README; Pillow) and movie_inversion.png/.pdf: three
frames (steady rotation, a fifth into the stop, the last frame) with omega(t).

Run: ``python gallery/movie_inversion.py [--quick | --tiny]``.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from pde_rotor.gallery.common import (
    PAPER_CONFIG,
    add_footer,
    fidelity_label,
    new_figure,
    parse_args,
    save,
)
from pde_rotor.io.mp4 import Mp4Writer
from pde_rotor.io.output import atomic_path
from pde_rotor.model.geometry import RotorShape
from pde_rotor.plotting.run import RotorFrame
from pde_rotor.solver.simulation import Simulation
from pde_rotor.units import OMEGA_UNITS, TIME_UNITS

NAME = "movie_inversion"
T_STOP = 0.5
"""Duration of the stop (the paper's Fig. 4(a))."""
ROTATING_FRAME_DT = 0.002
"""Time between frames of the steady rotation (see module docstring)."""
RELEASED_FRAME_DT = 0.0025
"""Time between frames after the release."""
STOPPED_FRAME_DT = 0.01
"""Time between frames during the stop."""
BEFORE = 0.06
"""Steady rotation shown before the stop."""
AFTER = 0.6
"""Time shown after the release."""
FPS = 25
GIF_WIDTH = 448
"""Width of the GIF in pixels (the mp4 is 960 x 480)."""
GIF_COLORS = 48


@dataclass
class Segment:
    """Frames every `dt` from `start` (inclusive) to `end` (exclusive)."""

    start: float
    end: float
    dt: float


def frame_times(config, fid_tiny: bool) -> np.ndarray:
    """Frame times, integer multiples of grid.dt (see module docstring)."""
    dt = config.grid.dt
    p = config.protocol
    scale = 10.0 if fid_tiny else 1.0
    t_stop, t_release = p.t_ini, p.t_ini + p.t_stop
    after = 2 * p.t_stop if fid_tiny else AFTER
    segments = [
        Segment(t_stop - BEFORE, t_stop, ROTATING_FRAME_DT * scale),
        Segment(t_stop, t_release, STOPPED_FRAME_DT * scale),
        Segment(t_release, t_release + after, RELEASED_FRAME_DT * scale),
    ]
    steps: list[int] = []
    for seg in segments:
        every = max(1, round(seg.dt / dt))
        steps.extend(range(round(seg.start / dt), round(seg.end / dt), every))
    steps.append(round(segments[-1].end / dt))
    return np.unique(np.asarray(steps)) * dt


class MovieFigure:
    """c and v on the left, omega(t) on the right; :meth:`draw` renders one frame."""

    def __init__(self, config, coords: np.ndarray, t_range: tuple[float, float], w_max: float):
        self.fig = Figure(figsize=(8.0, 4.0), dpi=120, layout="constrained")
        self.fig.get_layout_engine().set(wspace=0.06)
        self.canvas = FigureCanvasAgg(self.fig)
        ax_f, self.ax_w = self.fig.subplots(1, 2, width_ratios=[1.15, 1])
        self.frame = RotorFrame(RotorShape.from_config(config.geometry), coords, 1.5, ax=ax_f)
        p = config.protocol
        self.ax_w.axvspan(p.t_ini, p.t_ini + p.t_stop, color="tab:red", alpha=0.2, lw=0)
        self.ax_w.axhline(0, color="0.5", lw=0.7)
        (self.line,) = self.ax_w.plot([], [], color="k", lw=1.2)
        (self.dot,) = self.ax_w.plot([], [], "o", color="tab:blue", ms=5)
        self.ax_w.set_xlim(*t_range)
        self.ax_w.set_ylim(-1.15 * w_max, 1.15 * w_max)
        self.ax_w.set_xlabel(f"time t [{TIME_UNITS}] (stop shaded)")
        self.ax_w.set_ylabel(f"angular velocity \u03c9 [{OMEGA_UNITS}]")
        self.ax_w.grid(alpha=0.3)
        self.ax_w.set_title("+: counter-clockwise, \u2212: clockwise", fontsize=9)

    def draw(self, data: np.ndarray, phi: float, title: str, ts: list, ws: list) -> np.ndarray:
        """Update and render; returns the RGB image (480, 960, 3)."""
        self.frame.update(data, phi, title=title)
        self.line.set_data(ts, ws)
        self.dot.set_data(ts[-1:], ws[-1:])
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()


def phase(t: float, config) -> str:
    """'rotating', 'stopped' or 'released' at time t."""
    p = config.protocol
    if t <= p.t_ini + 1e-12:
        return "steady rotation"
    if t <= p.t_ini + p.t_stop + 1e-12:
        return "stopped"
    return "released"


def write_gif(frames: list[np.ndarray], times: np.ndarray, path: Path) -> None:
    """Small GIF: downscaled, 48-colour palette, every frame 40 ms (stopped frames kept)."""
    from PIL import Image

    images = []
    for frame in frames:
        image = Image.fromarray(frame)
        height = round(image.height * GIF_WIDTH / image.width)
        image = image.resize((GIF_WIDTH, height), Image.LANCZOS)
        images.append(image.quantize(colors=GIF_COLORS, method=Image.Quantize.MEDIANCUT))
    with atomic_path(path) as tmp:
        images[0].save(
            tmp,
            format="GIF",
            save_all=True,
            append_images=images[1:],
            duration=1000 // FPS,
            loop=0,
            optimize=True,
        )


def write_mp4(frames: list[np.ndarray], path: Path) -> None:
    """H.264 mp4 by the package's one encoder (:class:`pde_rotor.io.mp4.Mp4Writer`)."""
    writer = Mp4Writer(path, FPS)
    for frame in frames:
        writer.append(frame)
    writer.close()


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run the inversion, render the movie, write mp4, GIF, and the storyboard PNG/PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    t_stop = 2 * T_STOP / 5 if fid.is_tiny else T_STOP
    config = fid.config(
        PAPER_CONFIG,
        f"protocol.t_ini={fid.spinup!r}",
        f"protocol.t_stop={t_stop!r}",
        f"protocol.t_release={10 * t_stop!r}",
        "protocol.cycles=1",
    )
    times = frame_times(config, fid.is_tiny)
    start = time.perf_counter()
    sim = Simulation(config)
    sim.run(float(times[0]))
    w_max = max(abs(sim.rotor.omega), 1e-9)
    movie = MovieFigure(config, sim.pde.domain.coords, (float(times[0]), float(times[-1])), w_max)
    frames, ts, ws = [], [], []
    story: dict[str, tuple[float, np.ndarray, float, float]] = {}
    p = config.protocol
    marks = {
        "steady rotation": p.t_ini - 0.02 * (10 if fid.is_tiny else 1),
        "during the stop": p.t_ini + p.t_stop / 5,
        "released": float(times[-1]),
    }
    for t in times:
        sim.run(float(t))
        ts.append(sim.t)
        ws.append(sim.rotor.omega)
        title = (
            f"t = {sim.t:.3f} [{TIME_UNITS}],  \u03c9 = {sim.rotor.omega:+.1f} [{OMEGA_UNITS}]\n"
            f"{phase(sim.t, config)}"
        )
        frames.append(movie.draw(sim.state.data, sim.rotor.phi, title, ts, ws))
        for label, t_mark in marks.items():
            if label not in story and sim.t >= t_mark - 1e-9:
                story[label] = (sim.t, sim.state.data.copy(), sim.rotor.phi, sim.rotor.omega)
    wall = time.perf_counter() - start
    omega_before = ws[int(np.searchsorted(ts, p.t_ini))]
    omega_after = ws[-1]
    inverted = np.sign(omega_after) == -np.sign(omega_before)
    print(
        f"{NAME}: omega before the stop {omega_before:+.2f}, {ts[-1] - p.t_ini - p.t_stop:.3g} "
        f"after the release {omega_after:+.2f} ({'inverted' if inverted else 'not inverted'}); "
        f"{len(frames)} frames, {wall:.0f} s"
    )
    written = []
    mp4 = args.out / f"{NAME}.mp4"
    write_mp4(frames, mp4)
    gif = args.out / f"{NAME}.gif"
    write_gif(frames, times, gif)
    written += [mp4, gif]

    fig = new_figure(13.0, 4.4)
    axes = fig.subplots(1, 4, width_ratios=[1, 1, 1, 1.2])
    coords = sim.pde.domain.coords
    # one colour scale for the three panels; arrows scaled per panel (key: |v|), so that
    # the flow left over during the stop shows
    c_max = max(float(d[0].max()) for _, d, _, _ in story.values())
    for ax, (label, (t, data, phi, omega)) in zip(axes[:3], story.items(), strict=False):
        frame = RotorFrame(
            RotorShape.from_config(config.geometry), coords, 1.5, ax=ax, colorbar=None
        )
        frame.c_max = c_max
        frame.update(
            data,
            phi,
            title=f"{label}\nt = {t:.2f} [{TIME_UNITS}], \u03c9 = {omega:+.1f} [{OMEGA_UNITS}]",
        )
        ax.title.set_fontsize(9)
    ax_w = axes[3]
    ax_w.axvspan(p.t_ini, p.t_ini + p.t_stop, color="tab:red", alpha=0.2, lw=0)
    ax_w.plot(ts, ws, color="k", lw=1.2)
    ax_w.axhline(0, color="0.5", lw=0.7)
    ax_w.set_xlabel(f"time t [{TIME_UNITS}] (stop shaded)")
    ax_w.set_ylabel(f"\u03c9 [{OMEGA_UNITS}]")
    ax_w.grid(alpha=0.3)
    ax_w.set_title(
        f"\u03c9: {omega_before:+.1f} before, {omega_after:+.1f} after "
        f"({'inverted' if inverted else 'not inverted'})",
        fontsize=9,
    )
    fig.suptitle(
        f"One inversion: steady rotation, a stop of t_stop = {p.t_stop:g}, release "
        f"(frames of {NAME}.mp4 / .gif)\nc from 0 to {c_max:.2f} in all three panels; "
        "arrows scaled per panel, the key gives |v|",
        fontsize=11,
    )
    add_footer(
        fig,
        fidelity_label(
            fid,
            config,
            f"{PAPER_CONFIG.name}, free rotation to t = {p.t_ini:g}, one stop; {len(frames)} "
            f"frames",
        ),
    )
    return [*save(fig, args.out, NAME), *written]


if __name__ == "__main__":
    main()
