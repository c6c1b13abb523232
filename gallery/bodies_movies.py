"""Movies of camphor bodies on one surface: two rotors side by side, and a free camphor disk.

Two scenes of the model with bodies (docs/bodies.md), each written as an mp4 (ffmpeg of
imageio-ffmpeg) and a small GIF for the README (Pillow), with c of Eq. (eqc) in colour, the
flow v of Eq. (eqv) as arrows and every body's outline and pills
(:class:`pde_rotor.plotting.bodies.BodiesFrame`):

* ``bodies_two_rotors``: two of the paper's hexagon rotors 3 apart (configs/bodies/
  two_rotors.yaml, no noise); both spin up from rest in opposite directions, the left one
  is stopped for 0.5 and released while the right one keeps turning;
* ``bodies_free_disk``: one free camphor disk (no plate, configs/bodies/free_disk.yaml) at
  friction mu = 0.15, below its onset of motion mu_c = 0.176, starts from a slow push and
  speeds up on its own until its footprint reaches the dish's edge, where the run ends.

bodies_movies.png/.pdf: three frames of each. Both scenes run on a coarse grid (dx = 0.05,
delta = 0.025 of the configs) with a frame every 0.004 (rotors) and 0.05 (disk) at every
fidelity; the tiny fidelity shortens them.

Run: ``python gallery/bodies_movies.py [--quick | --tiny]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg

from pde_rotor.config import load_config
from pde_rotor.gallery.common import (
    CONFIGS,
    add_footer,
    fidelity_label,
    new_figure,
    parse_args,
    save,
)
from pde_rotor.io.mp4 import Mp4Writer
from pde_rotor.io.output import atomic_path
from pde_rotor.model.setup import Setup
from pde_rotor.plotting.bodies import BodiesFrame
from pde_rotor.solver.bodies import BodyContactError
from pde_rotor.solver.simulation import Simulation

NAME = "bodies_movies"
COARSE = ("grid.dx=0.05", "grid.dt=0.0004", "noise.sigma=0")
"""Every scene's grid: dx = 0.05 (delta = 0.025 of the configs), no noise."""
FPS = 25
GIF_WIDTH = 400
GIF_COLORS = 48


def render(sim: Simulation, times: np.ndarray, title: str) -> tuple[list[np.ndarray], str]:
    """Run `sim` through `times`, one frame at each; stops early where a body touches the
    dish's edge (the message is returned)."""
    x, y = (np.asarray(a) for a in sim.pde.domain.grid.axes_coords)
    frame = BodiesFrame(sim.pde.bodies, x, y)
    canvas = FigureCanvasAgg(frame.fig)
    frames, ended = [], ""
    for t in times:
        try:
            sim.run(float(t))
        except BodyContactError as err:
            ended = str(err)
            break
        poses = sim.bodies.poses
        omegas = ", ".join(f"{b.name} {poses[k, 5]:+.0f}" for k, b in enumerate(sim.pde.bodies))
        speed = np.hypot(poses[:, 3], poses[:, 4]).max()
        frame.update(
            sim.state.data, poses, f"{title}\nt = {sim.t:.2f}, omega: {omegas}, |U| = {speed:.2f}"
        )
        canvas.draw()
        frames.append(np.asarray(canvas.buffer_rgba())[..., :3].copy())
    return frames, ended


def write_movies(frames: list[np.ndarray], out: Path, name: str) -> list[Path]:
    """mp4 and a small GIF (downscaled, 48 colours, 40 ms a frame) of `frames`."""
    from PIL import Image

    mp4 = out / f"{name}.mp4"
    writer = Mp4Writer(mp4, FPS)
    for frame in frames:
        writer.append(frame)
    writer.close()
    images = []
    for frame in frames:
        image = Image.fromarray(frame)
        image = image.resize((GIF_WIDTH, round(image.height * GIF_WIDTH / image.width)))
        images.append(image.quantize(colors=GIF_COLORS, method=Image.Quantize.MEDIANCUT))
    gif = out / f"{name}.gif"
    with atomic_path(gif) as tmp:
        images[0].save(
            tmp, format="GIF", save_all=True, append_images=images[1:], duration=40, loop=0
        )
    return [mp4, gif]


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run both scenes, write their mp4 and GIF, and the storyboard PNG/PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    tiny = args.fidelity.is_tiny
    scale = 0.1 if tiny else 1.0
    t_stop = 6.0 * scale
    rotors = load_config(
        CONFIGS / "bodies" / "two_rotors.yaml",
        [
            *COARSE,
            "output.movie=false",
            f"protocol.t_ini={t_stop + 1.5 * scale!r}",
            "protocol.cycles=0",
            f"bodies[0].protocol.t_ini={t_stop!r}",
            f"bodies[0].protocol.t_stop={0.5 * scale!r}",
            "bodies[0].protocol.cycles=1",
        ],
    )
    disk = load_config(
        CONFIGS / "bodies" / "free_disk.yaml",
        [
            *COARSE,
            f"protocol.t_ini={12.0 * scale!r}",
            "bodies[0].motion.friction=0.15",
            "bodies[0].motion.mass=0.002",
            "bodies[0].start.x=-3.5",
            "bodies[0].start.velocity=[0.3, 0.0]",
        ],
    )
    scenes = {
        "bodies_two_rotors": (
            rotors,
            np.arange(t_stop - 0.1 * scale, rotors.protocol.t_end, 0.004),
            "two rotors: the left one stopped for 0.5, the right one free",
        ),
        "bodies_free_disk": (
            disk,
            np.arange(0.0, disk.protocol.t_end, 0.05),
            "a free camphor disk below its onset friction",
        ),
    }
    written: list[Path] = []
    story = new_figure(12.0, 7.6)
    axes = story.subplots(2, 3)
    for row, (name, (config, times, title)) in enumerate(scenes.items()):
        sim = Simulation(config)
        sim.run(float(times[0]))
        frames, ended = render(sim, times, title)
        print(f"{name}: {len(frames)} frames to t = {sim.t:.3g}" + (f"; {ended}" if ended else ""))
        written += write_movies(frames, args.out, name)
        for ax, k in zip(axes[row], (0, len(frames) // 2, len(frames) - 1), strict=True):
            ax.imshow(frames[k])
            ax.set_axis_off()
        axes[row][0].set_title(f"{name}.gif: first, middle and last frame", loc="left")
    bodies = len(Setup(rotors).bodies) + len(Setup(disk).bodies)
    story.suptitle(f"{bodies} camphor bodies in two scenes (frames of the movies)")
    add_footer(story, fidelity_label(args.fidelity, rotors, "coarse grid in every fidelity"))
    return [*save(story, args.out, NAME), *written]


if __name__ == "__main__":
    main()
