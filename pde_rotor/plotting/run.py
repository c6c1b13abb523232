"""Figures of a run: movie frames and the summary figure of ``pde-rotor show``.

The movie frame (:class:`RotorFrame`) shows the camphor concentration c of Eq. (eqc) as
a colour map, the surface flow v of Eq. (eqv) as arrows with a scale key, and the plate
(polygon of paper Fig. 1) with its pills drawn at the current angle phi; the title gives
t, omega and the phase of the stop-and-release protocol. :func:`summary_figure` shows
phi(t) and omega(t) with the stop phases shaded (the paper's Figs. 4 and 6), the table
of inversion events, and a snapshot of c and v (the paper's Fig. 3).

Labels use the symbols of the paper (φ, ω, Δ) and the units of the output files
(:data:`pde_rotor.units.TIME_UNITS` and its companions; a time series read from
timeseries.nc brings its own ``units`` attributes).

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot state), so they
render without a display.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon

from ..config import RotorConfig
from ..model.geometry import RotorShape, pill_centres
from ..model.setup import Setup
from ..units import CONCENTRATION_UNITS, LENGTH_UNITS, OMEGA_UNITS, TIME_UNITS

SUMMARY_SIZE = (13.0, 8.5)
"""Size of the summary figure in inches."""

ARROWS_ACROSS = 17
"""Number of flow arrows along one side of the field of view."""

ARROW_FILL = 0.9
"""Length of the arrow of the key's speed, in units of the arrow spacing."""


def nice_ceiling(value: float) -> float:
    """The smallest of 1, 2, 5 times a power of ten that is >= `value` (> 0)."""
    exponent = math.floor(math.log10(value))
    for step in (1.0, 2.0, 5.0, 10.0):
        nice = step * 10.0**exponent
        if nice >= value * (1 - 1e-12):
            return nice
    return 10.0 ** (exponent + 1)


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
        colorbar: str | None = "right",
    ):
        """
        Args:
            shape: rotor geometry.
            coords: cell-centre coordinates of the grid (either axis).
            half_width: half width of the square shown.
            figsize: figure size in inches (when a new figure is made).
            ax: draw into these axes instead of a new figure.
            colorbar: where to add a colour bar for c ("right", "bottom"; None: none).
        """
        self.shape = shape
        self.view = FieldView.make(coords, half_width)
        if ax is None:
            self.fig = Figure(figsize=figsize)  # fixed layout: frames must not jitter
            ax = self.fig.add_subplot()
        else:
            self.fig = ax.figure
        self.ax = ax
        self.c_max = 0.0
        self.v_key = 1.0
        self.v_reference = 0.0
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
        if colorbar is not None:
            self.fig.colorbar(
                self.image,
                ax=ax,
                label=f"camphor concentration c [{CONCENTRATION_UNITS}]",
                shrink=0.85,
                location=colorbar,
            )
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
            scale=1.0 / (ARROW_FILL * spacing),
            width=0.004,
            alpha=0.85,
        )
        self.key = ax.quiverkey(
            self.quiver,
            0.05,
            0.05,
            1.0,
            self._key_label(),
            labelpos="E",
            coordinates="axes",
            color="white",
            labelcolor="white",
            fontproperties={"size": 9},
        )
        self.key.text.set_bbox({"facecolor": "black", "alpha": 0.85, "edgecolor": "none"})
        self.key.set_zorder(10)  # above the field's arrows
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
        ax.set_xlabel(f"x [{LENGTH_UNITS}]")
        ax.set_ylabel(f"y [{LENGTH_UNITS}]")

    def _key_label(self) -> str:
        if self.v_key < self.v_reference:
            return f"|v| = {self.v_key:.2g}  (arrows \u00d7{self.v_reference / self.v_key:.3g})"
        return f"|v| = {self.v_key:.2g}"

    def update(
        self,
        data: np.ndarray,
        phi: float,
        *,
        title: str = "",
    ) -> None:
        """Draw the state `data` (3, n, n) = (c, v_x, v_y) with the rotor at angle phi.

        The colour scale of c follows the largest value seen so far. The arrows of v are
        scaled per frame: the key's speed, the frame's largest |v| rounded up to 1, 2 or
        5 times a power of ten, spans :data:`ARROW_FILL` of the arrow spacing. The flow
        left over during a stop, a twentieth of the flow of a turning plate, so stays
        visible. The change of scale is made obvious: while the arrows are enlarged
        against the largest key of the movie so far, the key turns orange and says by
        how much.
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
        self.v_key = nice_ceiling(speed) if speed > 0 else 1.0
        self.v_reference = max(self.v_reference, self.v_key)
        self.quiver.set_UVC(vx / self.v_key, vy / self.v_key)
        self.key.text.set_text(self._key_label())
        enlarged = self.v_key < self.v_reference
        self.key.text.get_bbox_patch().set_facecolor("tab:orange" if enlarged else "black")
        self.plate.set_xy(plate_corners(self.shape, phi))
        for pill, centre in zip(self.pills, pill_centres(self.shape, phi), strict=True):
            pill.set_center(tuple(centre))
        self.ax.set_title(title, fontsize=10)


def frame_title(t: float, omega: float, stopped: bool, cycle: int, cycles: int) -> str:
    """Movie title: time and omega with their units, and the protocol phase."""
    if cycle == 0:
        phase = "initial rotation" if not stopped else "stopped"
    else:
        phase = f"{'stopped' if stopped else 'released'}, cycle {cycle}/{cycles}"
    return f"t = {t:.2f} [{TIME_UNITS}],  \u03c9 = {omega:+.1f} [{OMEGA_UNITS}]\n{phase}"


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


def _units(ds: xr.Dataset, name: str, default: str) -> str:
    """The ``units`` attribute of ``ds[name]`` (files written by older versions: `default`)."""
    return str(ds[name].attrs.get("units", default)) if name in ds.variables else default


TABLE_ROW_INCHES = 0.24
"""Height of one row of the events table in the summary figure (at least)."""
SNAPSHOT_INCHES = 6.0
"""Height the snapshot needs under the table in the summary figure (square, title, colour
bar); the table takes the rest of the column, and at least its rows."""


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

    The right column gives the table the height of its rows and the snapshot the rest.

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
    # subfigures lay out independently: the snapshot's colour bar does not narrow the table
    left, right = fig.subfigures(1, 2, width_ratios=[1.5, 1])
    ax_phi, ax_omega = left.subplots(2, 1, sharex=True)
    n_events = events.sizes.get("cycle", 0)
    n_rows = min(n_events, max_rows) + (2 if n_events > max_rows else 1)  # header, "..."
    table_height = max(TABLE_ROW_INCHES * n_rows + 0.7, fig.get_figheight() - SNAPSHOT_INCHES)
    top, bottom = right.subfigures(
        2, 1, height_ratios=[table_height, fig.get_figheight() - table_height]
    )
    ax_table = top.subplots()
    ax_snap = bottom.subplots()

    t = timeseries["time"].values
    time_units = _units(timeseries, "time", TIME_UNITS)
    spans = stop_intervals(config, float(t[-1]) if t.size else None)
    for ax, name, label, units in (
        (ax_phi, "phi", "angle \u03c6", "rad"),
        (ax_omega, "omega", "angular velocity \u03c9", OMEGA_UNITS),
    ):
        _shade_stops(ax, spans)
        ax.plot(t, timeseries[name].values, color="k", linewidth=0.8)
        ax.set_ylabel(f"{label} [{_units(timeseries, name, units)}]")
        ax.grid(alpha=0.3)
    ax_omega.set_xlabel(f"time t [{time_units}]")
    ax_phi.set_title(
        f"\u0394 = {config.geometry.asymmetry:g}, t_stop = {config.protocol.t_stop:g}, flow "
        f"{'on' if config.flow.enabled else 'off'} (stops shaded)",
        fontsize=10,
    )
    if timeseries.attrs.get("status", "completed") != "completed":
        # a figure-wide title, wrapped: the layout makes room for it above the panels
        status = f"run {timeseries.attrs['status']}: {timeseries.attrs.get('message', '')}"
        width = int(fig.get_figwidth() * 13)  # characters of 9 pt per line
        fig.suptitle(textwrap.fill(status, width), fontsize=9, color="tab:red")

    _events_table(ax_table, events, max_rows)

    if snapshot is None:
        ax_snap.text(0.5, 0.5, "no field snapshot stored", ha="center", va="center")
        ax_snap.set_axis_off()
    else:
        shape = Setup(config).shape
        ax_snap.set_anchor("N")  # the room the square leaves goes below it
        frame = RotorFrame(
            shape, snapshot.coords, config.output.movie_view, ax=ax_snap, colorbar="bottom"
        )
        t_s = snapshot.t
        omega = float(np.interp(t_s, t, timeseries["omega"].values)) if t.size else math.nan
        frame.update(snapshot.data, snapshot.phi, title=frame_title_short(t_s, omega))
    return fig


def frame_title_short(t: float, omega: float) -> str:
    """Title of the summary's snapshot: time and omega with their units."""
    return f"snapshot at t = {t:g} [{TIME_UNITS}], \u03c9 = {omega:+.1f} [{OMEGA_UNITS}]"


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
                {1: "+ (ccw)", -1: "\u2212 (cw)", 0: "0"}[int(events["direction_after"].values[i])],
                "yes" if inverted[i] else "no",
                f"{ttc:.3g}" if committed[i] else "not committed",
            ]
        )
    table = ax.table(
        cellText=cells,
        colLabels=["m", "stop at t", "\u03c9 before", "after", "inverted", "t to commit"],
        colWidths=[0.07, 0.16, 0.17, 0.16, 0.15, 0.29],
        bbox=(0.0, 0.0, 1.0, 1.0),
        cellLoc="center",
    )
    table.auto_set_font_size(False)
    table.set_fontsize(9)
    frac = events.attrs.get("commit_fraction", math.nan)
    time_units = _units(events, "t_stop", TIME_UNITS)
    omega_units = _units(events, "omega_before", OMEGA_UNITS)
    ax.set_title(
        f"inversions {int(inverted.sum())}/{n} = {inverted.mean():.2f}; committed: "
        f"|\u03c9| \u2265 {frac:g} |\u03c9 before|\nt in {time_units}, \u03c9 in {omega_units}",
        fontsize=10,
    )
