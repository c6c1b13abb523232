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
from matplotlib.patches import Circle, Polygon

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


def bodies_summary(ds: xr.Dataset, config: RotorConfig, bodies: tuple[Body, ...]) -> Figure:
    """The summary figure of a run with bodies (bodies.nc as `ds`)."""
    fig = Figure(figsize=(11, 4.5), layout="constrained")
    dish, omega, speed = fig.subplots(1, 3)
    colors = [f"C{k}" for k in range(len(bodies))]
    cx, cy = config.grid.domain_centre
    radius = config.grid.domain_radius
    dish.add_patch(Circle((cx, cy), radius, fill=False, edgecolor="0.5", ls="--"))
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
