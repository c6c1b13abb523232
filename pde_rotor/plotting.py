"""Figures of a run: movie frames and the summary figure of ``pde-rotor show``.

The movie frame (:class:`RotorFrame`) shows the camphor concentration c of Eq. (eqc) as
a colour map, the surface flow v of Eq. (eqv) as arrows, and the plate (polygon of
paper Fig. 1) with its pills drawn at the current angle phi; the title gives t, omega
and the phase of the stop-and-release protocol. :func:`summary_figure` shows phi(t) and
omega(t) with the stop phases shaded (the paper's Figs. 4 and 6), the table of
inversion events, and a snapshot of c and v (the paper's Fig. 3).

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot state), so they
render without a display.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon

from .config import RotorConfig
from .geometry import RotorShape, pill_centres

SUMMARY_SIZE = (13.0, 8.5)
"""Size of the summary figure in inches."""

ARROWS_ACROSS = 17
"""Number of flow arrows along one side of the field of view."""


def plate_corners(shape: RotorShape, phi: float) -> np.ndarray:
    """Corners of the plate at angle phi, (N, 2): radius R at angles phi + 2 pi j / N.

    They lie between the edge normals e_j = e(phi + 2 pi (j - 1/2) / N), Eq. (ejt0).
    """
    ang = phi + 2 * np.pi * np.arange(1, shape.n_corners + 1) / shape.n_corners
    return shape.radius * np.stack([np.cos(ang), np.sin(ang)], axis=1)


def stop_intervals(config: RotorConfig, t_max: float | None = None) -> list[tuple[float, float]]:
    """(start, end) of every stop phase of the protocol, optionally those before `t_max`."""
    p = config.protocol
    spans = [(p.t_ini + m * p.period, p.t_ini + m * p.period + p.t_stop) for m in range(p.cycles)]
    if t_max is not None:
        spans = [(a, min(b, t_max)) for a, b in spans if a < t_max]
    return [(a, b) for a, b in spans if b > a]


@dataclass
class FieldView:
    """Cells of the square field of view |x|, |y| <= half_width.

    Attributes:
        sel: index slice along either axis.
        coords: coordinates of the selected cells.
        arrows: index array of the cells carrying flow arrows.
    """

    sel: slice
    coords: np.ndarray
    arrows: np.ndarray

    @classmethod
    def make(cls, coords: np.ndarray, half_width: float) -> FieldView:
        """Select the cells within `half_width` of the origin (all if it is wider)."""
        inside = np.nonzero(np.abs(coords) <= half_width + 1e-12)[0]
        if inside.size == 0:
            inside = np.arange(coords.size)
        sel = slice(int(inside[0]), int(inside[-1]) + 1)
        n = inside.size
        stride = max(1, round(n / ARROWS_ACROSS))
        arrows = np.arange(stride // 2, n, stride)
        return cls(sel=sel, coords=coords[sel], arrows=arrows)

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """imshow extent of the selected cells (cell edges)."""
        h = 0.5 * (self.coords[1] - self.coords[0]) if self.coords.size > 1 else 0.5
        lo, hi = self.coords[0] - h, self.coords[-1] + h
        return (lo, hi, lo, hi)


class RotorFrame:
    """A figure showing c, v and the rotor, updated in place (one call per movie frame)."""

    def __init__(
        self,
        shape: RotorShape,
        coords: np.ndarray,
        half_width: float,
        *,
        figsize: tuple[float, float] = (5.6, 5.0),
        ax=None,
        colorbar: bool = True,
    ):
        """
        Args:
            shape: rotor geometry.
            coords: cell-centre coordinates of the grid (either axis).
            half_width: half width of the square shown.
            figsize: figure size in inches (when a new figure is made).
            ax: draw into these axes instead of a new figure.
            colorbar: add a colour bar for c.
        """
        self.shape = shape
        self.view = FieldView.make(coords, half_width)
        if ax is None:
            self.fig = Figure(figsize=figsize)
            ax = self.fig.add_subplot()
        else:
            self.fig = ax.figure
        self.ax = ax
        self.c_max = 0.0
        self.v_max = 0.0
        n = self.view.coords.size
        self.image = ax.imshow(
            np.zeros((n, n)),
            origin="lower",
            extent=self.view.extent,
            cmap="viridis",
            vmin=0.0,
            vmax=1.0,
            interpolation="nearest",
        )
        if colorbar:
            self.fig.colorbar(self.image, ax=ax, label="camphor concentration c", shrink=0.85)
        a = self.view.coords[self.view.arrows]
        ax_x, ax_y = np.meshgrid(a, a, indexing="ij")
        spacing = float(a[1] - a[0]) if a.size > 1 else 1.0
        zeros = np.zeros_like(ax_x)
        self.quiver = ax.quiver(
            ax_x,
            ax_y,
            zeros,
            zeros,
            color="white",
            angles="xy",
            scale_units="xy",
            scale=1.0 / (0.9 * spacing),
            width=0.004,
            alpha=0.85,
        )
        self.plate = Polygon(
            plate_corners(shape, 0.0), closed=True, fill=False, edgecolor="white", linewidth=1.5
        )
        ax.add_patch(self.plate)
        self.pills = [
            Circle((0.0, 0.0), shape.pill_radius, fill=False, edgecolor="orangered", linewidth=1.2)
            for _ in range(shape.n_corners)
        ]
        for pill in self.pills:
            ax.add_patch(pill)
        ax.set_xlim(self.view.extent[:2])
        ax.set_ylim(self.view.extent[2:])
        ax.set_aspect("equal")
        ax.set_xlabel("x")
        ax.set_ylabel("y")

    def update(
        self,
        data: np.ndarray,
        phi: float,
        *,
        title: str = "",
    ) -> None:
        """Draw the state `data` (3, n, n) = (c, v_x, v_y) with the rotor at angle phi.

        The colour scale of c and the arrow scale of v follow the largest values seen so
        far, so that successive frames are comparable; the longest arrow spans 0.9 of the
        arrow spacing.
        """
        sel = self.view.sel
        c = data[0][sel, sel]
        c_now = float(np.max(c)) if c.size else 0.0
        self.c_max = max(self.c_max, c_now)
        self.image.set_data(c.T)
        self.image.set_clim(0.0, self.c_max if self.c_max > 0 else 1.0)
        idx = self.view.arrows
        vx = data[1][sel, sel][np.ix_(idx, idx)]
        vy = data[2][sel, sel][np.ix_(idx, idx)]
        speed = float(np.max(np.hypot(vx, vy))) if vx.size else 0.0
        self.v_max = max(self.v_max, speed)
        norm = self.v_max if self.v_max > 0 else 1.0
        self.quiver.set_UVC(vx / norm, vy / norm)
        self.plate.set_xy(plate_corners(self.shape, phi))
        for pill, centre in zip(self.pills, pill_centres(self.shape, phi), strict=True):
            pill.set_center(tuple(centre))
        self.ax.set_title(title, fontsize=10)


def frame_title(t: float, omega: float, stopped: bool, cycle: int, cycles: int) -> str:
    """Movie title: time, omega and the protocol phase."""
    if cycle == 0:
        phase = "initial rotation" if not stopped else "stopped"
    else:
        phase = f"{'stopped' if stopped else 'released'}, cycle {cycle}/{cycles}"
    return f"t = {t:8.3f}   omega = {omega:+8.2f}   ({phase})"


def _shade_stops(ax, spans: list[tuple[float, float]]) -> None:
    for a, b in spans:
        ax.axvspan(a, b, color="tab:red", alpha=0.18, linewidth=0)


@dataclass
class Snapshot:
    """One stored state of the fields with the rotor angle at that time.

    Attributes:
        t: time.
        data: (3, n, n) = (c, v_x, v_y).
        phi: rotor angle.
        coords: cell-centre coordinates (either axis).
    """

    t: float
    data: np.ndarray
    phi: float
    coords: np.ndarray


def summary_figure(
    config: RotorConfig,
    timeseries: xr.Dataset,
    events: xr.Dataset,
    snapshot: Snapshot | None = None,
    *,
    max_rows: int = 14,
    fig: Figure | None = None,
) -> Figure:
    """Figure of a run: phi(t), omega(t) with stops shaded, the events table, a c/v snapshot.

    Args:
        config: the run's configuration.
        timeseries: the run's time series (dimension ``time``).
        events: the run's events (dimension ``cycle``).
        snapshot: one stored state, or None.
        max_rows: events shown in the table (the first ones, then the last).
        fig: draw into this figure (e.g. one made by pyplot to display it); default: a
            new Figure not attached to pyplot.

    Returns:
        The figure.
    """
    if fig is None:
        fig = Figure(figsize=SUMMARY_SIZE, layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=[1.5, 1])
    ax_phi = fig.add_subplot(grid[0, 0])
    ax_omega = fig.add_subplot(grid[1, 0], sharex=ax_phi)
    ax_table = fig.add_subplot(grid[0, 1])
    ax_snap = fig.add_subplot(grid[1, 1])

    t = timeseries["time"].values
    spans = stop_intervals(config, float(t[-1]) if t.size else None)
    for ax, name, label in (
        (ax_phi, "phi", "angle phi [rad]"),
        (ax_omega, "omega", "angular velocity dphi/dt"),
    ):
        _shade_stops(ax, spans)
        ax.plot(t, timeseries[name].values, color="k", linewidth=0.8)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    ax_omega.set_xlabel("time t")
    delta = config.geometry.asymmetry
    ax_phi.set_title(
        f"Delta = {delta:g}, t_stop = {config.protocol.t_stop:g}, flow "
        f"{'on' if config.flow.enabled else 'off'} (stops shaded)",
        fontsize=10,
    )
    if timeseries.attrs.get("status", "completed") != "completed":
        ax_phi.text(
            0.01,
            0.98,
            f"run {timeseries.attrs['status']}: {timeseries.attrs.get('message', '')}",
            transform=ax_phi.transAxes,
            va="top",
            fontsize=8,
            color="tab:red",
        )

    _events_table(ax_table, events, max_rows)

    if snapshot is None:
        ax_snap.text(0.5, 0.5, "no field snapshot stored", ha="center", va="center")
        ax_snap.set_axis_off()
    else:
        shape = RotorShape.from_config(config.geometry)
        frame = RotorFrame(shape, snapshot.coords, config.output.movie_view, ax=ax_snap)
        t_s = snapshot.t
        omega = float(np.interp(t_s, t, timeseries["omega"].values)) if t.size else math.nan
        frame.update(
            snapshot.data, snapshot.phi, title=f"snapshot t = {t_s:g}, omega = {omega:+.2f}"
        )
    return fig


def _events_table(ax, events: xr.Dataset, max_rows: int) -> None:
    ax.set_axis_off()
    n = events.sizes.get("cycle", 0)
    if n == 0:
        ax.text(0.5, 0.5, "no completed stop-and-release cycle", ha="center", va="center")
        return
    inverted = events["inverted"].values.astype(bool)
    committed = events["committed"].values.astype(bool)
    rows_idx = list(range(n))
    if n > max_rows:
        rows_idx = [*range(max_rows - 1), n - 1]
    cells = []
    for k, i in enumerate(rows_idx):
        if n > max_rows and k == max_rows - 1:
            cells.append(["..."] * 6)
        ttc = float(events["time_to_commit"].values[i])
        cells.append(
            [
                str(int(events["cycle"].values[i])),
                f"{float(events['t_stop'].values[i]):g}",
                f"{float(events['omega_before'].values[i]):+.1f}",
                {1: "+ (ccw)", -1: "- (cw)", 0: "0"}[int(events["direction_after"].values[i])],
                "yes" if inverted[i] else "no",
                f"{ttc:.3g}" if committed[i] else "not committed",
            ]
        )
    table = ax.table(
        cellText=cells,
        colLabels=["m", "stop at", "omega before", "after", "inverted", "t to commit"],
        colWidths=[0.08, 0.14, 0.2, 0.16, 0.14, 0.22],
        loc="upper center",
        cellLoc="center",
    )
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    table.scale(1.0, 1.15)
    frac = events.attrs.get("commit_fraction", math.nan)
    ax.set_title(
        f"inversions {int(inverted.sum())}/{n} = {inverted.mean():.2f}"
        f"  (committed: |omega| >= {frac:g} |omega before|)",
        fontsize=10,
    )
