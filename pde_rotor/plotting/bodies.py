"""Figures of a run with bodies: every body's outline, pills and path; omega and speed.

:func:`draw_body` draws one body at a pose (plate outline, pills), :func:`bodies_summary`
the summary of a run (summary.png): the dish with each body at its last pose and the
path of its position, and each body's angular velocity and speed against time.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon, Rectangle

from ..config import RotorConfig
from ..model.bodies import Body, Pose, pill_centres


def plate_outline(body: Body, pose: Pose) -> np.ndarray | None:
    """The plate's outline as (M, 2) points on the surface (None: no plate or a disk)."""
    shape = body.shape
    c, s = math.cos(pose.phi), math.sin(pose.phi)
    if shape.plate == "polygon":
        angles = pose.phi + 2 * np.pi * np.arange(shape.n_corners) / shape.n_corners
        return np.stack(
            [pose.x + shape.radius * np.cos(angles), pose.y + shape.radius * np.sin(angles)],
            axis=1,
        )
    if shape.plate == "strip":
        a, b = shape.length / 2, shape.width / 2
        corners = np.array([[a, b], [-a, b], [-a, -b], [a, -b]])
        return np.stack(
            [
                pose.x + c * corners[:, 0] - s * corners[:, 1],
                pose.y + s * corners[:, 0] + c * corners[:, 1],
            ],
            axis=1,
        )
    return None


def draw_body(ax: Axes, body: Body, pose: Pose, color: str) -> None:
    """Draw `body` at `pose`: plate outline (polygon, strip or disk) and its pills."""
    outline = plate_outline(body, pose)
    if outline is not None:
        ax.add_patch(Polygon(outline, closed=True, fill=False, edgecolor=color, lw=1.2))
    elif body.shape.plate == "disk":
        ax.add_patch(Circle((pose.x, pose.y), body.shape.radius, fill=False, edgecolor=color))
    for (px, py), rho in zip(pill_centres(body.shape, pose), body.shape.pills[:, 2], strict=True):
        ax.add_patch(Circle((px, py), rho, color=color, alpha=0.6, lw=0))


def draw_vessel(ax: Axes, config: RotorConfig) -> None:
    """The vessel's walls, dashed: the dish's circle, an annulus' two, a tank's sides."""
    grid = config.grid
    cx, cy = grid.domain_centre
    vessel = grid.vessel
    style = {"fill": False, "edgecolor": "0.5", "ls": "--"}
    if vessel is None:
        ax.add_patch(Circle((cx, cy), grid.domain_radius, **style))
    elif vessel.shape == "annulus":
        for radius in (vessel.inner_radius, vessel.outer_radius):
            ax.add_patch(Circle((cx, cy), radius, **style))
    else:
        a, b = vessel.half_widths
        ax.add_patch(Rectangle((cx - a, cy - b), 2 * a, 2 * b, **style))


def bodies_summary(ds: xr.Dataset, config: RotorConfig, bodies: tuple[Body, ...]) -> Figure:
    """The summary figure of a run with bodies (bodies.nc as `ds`)."""
    fig = Figure(figsize=(11, 4.5), layout="constrained")
    dish, omega, speed = fig.subplots(1, 3)
    colors = [f"C{k}" for k in range(len(bodies))]
    cx, cy = config.grid.domain_centre
    radius = config.grid.domain_radius
    draw_vessel(dish, config)
    for k, body in enumerate(bodies):
        x, y = ds["x"].values[:, k], ds["y"].values[:, k]
        dish.plot(x, y, color=colors[k], lw=0.8)
        last = Pose(float(x[-1]), float(y[-1]), float(ds["phi"].values[-1, k]))
        draw_body(dish, body, last, colors[k])
        time = ds["time"].values
        omega.plot(time, ds["omega"].values[:, k], color=colors[k], label=body.name)
        speed.plot(time, np.hypot(ds["u"].values[:, k], ds["v"].values[:, k]), color=colors[k])
    dish.set(xlim=(cx - radius, cx + radius), ylim=(cy - radius, cy + radius), aspect="equal")
    dish.set(title="bodies at the end, paths of X", xlabel="x", ylabel="y")
    omega.set(xlabel="t", ylabel="omega", title="angular velocity")
    omega.legend(fontsize="small")
    speed.set(xlabel="t", ylabel="|U|", title="speed")
    return fig


class BodiesFrame:
    """A movie frame of a run with bodies: c over the dish, the flow v as arrows, every
    body's outline and pills; updated in place, one call per frame."""

    def __init__(self, bodies: tuple[Body, ...], x: np.ndarray, y: np.ndarray, *, arrows: int = 24):
        """
        Args:
            bodies: the run's bodies.
            x, y: the cell-centre coordinates of the grid on the surface (axis 0, axis 1).
            arrows: arrows of v along each axis.
        """
        self.bodies = bodies
        self.fig = Figure(figsize=(5.6, 5.0))  # fixed layout: frames must not jitter
        self.ax = self.fig.add_subplot()
        h = 0.5 * (x[1] - x[0])
        extent = (x[0] - h, x[-1] + h, y[0] - h, y[-1] + h)
        self.image = self.ax.imshow(
            np.zeros((y.size, x.size)),
            origin="lower",
            extent=extent,
            cmap="viridis",
            vmin=0,
            vmax=1,
        )
        self.fig.colorbar(self.image, ax=self.ax, label="camphor concentration c", shrink=0.85)
        step = max(1, x.size // arrows)
        self.sel = slice(step // 2, None, step)
        ax_x, ax_y = np.meshgrid(x[self.sel], y[self.sel], indexing="ij")
        self.quiver = self.ax.quiver(
            ax_x, ax_y, np.zeros_like(ax_x), np.zeros_like(ax_y), color="white", angles="xy",
            scale_units="xy", scale=1.0 / (0.9 * step * (x[1] - x[0])), width=0.004, alpha=0.8,
        )  # fmt: skip
        self.c_max = 0.0
        self.patches: list = []
        self.ax.set_aspect("equal")
        self.ax.set(xlabel="x", ylabel="y")

    def update(self, data: np.ndarray, poses: np.ndarray, title: str = "") -> None:
        """Draw the state `data` (3, n, n) with the bodies at `poses` (K, >= 3: x, y, phi).

        The colour scale of c follows the largest value so far; the arrows are scaled per
        frame so that the largest |v| spans 0.9 of their spacing.
        """
        c = data[0]
        self.c_max = max(self.c_max, float(c.max()))
        self.image.set_data(c.T)
        self.image.set_clim(0.0, self.c_max if self.c_max > 0 else 1.0)
        vx, vy = data[1][self.sel, self.sel], data[2][self.sel, self.sel]
        speed = float(np.hypot(vx, vy).max())
        scale = speed if speed > 0 else 1.0
        self.quiver.set_UVC(vx / scale, vy / scale)
        for patch in self.patches:
            patch.remove()
        before = len(self.ax.patches)
        for k, body in enumerate(self.bodies):
            draw_body(self.ax, body, Pose(*(float(p) for p in poses[k, :3])), "white")
        self.patches = list(self.ax.patches[before:])
        self.ax.set_title(title, fontsize=10)
