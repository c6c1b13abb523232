"""The figure of any sweep report (``pde-rotor plot``): P against the swept axis.

:func:`report_figure` draws a report of :func:`pde_rotor.sweep.report`:

* one axis: P with its 95 % interval, and faintly P(inv | CCW) and P(inv | CW) where the
  report holds them;
* two axes: a heat map of P, one cell per point, in the order of the axis values (cells
  of points not measured yet are blank);
* more axes: one panel per combination of values of the axes beyond the first one
  (curves) or two (heat maps).

An axis with a single value is fixed: the title names it. The footer is the gallery's:
grid, dt, stops per point, estimator, noise and how the intervals were computed.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from ..config import RotorConfig
from ..plotting.figures import (
    add_footer,
    draw_conditionals,
    errorbar_p,
    new_figure,
    probability_axes,
)
from ..units import LENGTH_UNITS, TIME_UNITS
from .stored import SweepData

REPORT_VARIABLES = ("P", "P_low", "P_high", "stops")
"""Variables a report must hold to be drawn."""
P_LABEL = "inversion probability P (dimensionless)"
"""Label of the colour bar of the heat maps."""
PAPER_UNITS = "paper units"
"""Units of a key without its own: the paper's dimensionless units."""
AXES: dict[str, tuple[str, str | None]] = {
    "protocol.t_stop": ("stop duration t_stop", TIME_UNITS),
    "protocol.t_ini": ("free rotation before the first stop t_ini", TIME_UNITS),
    "protocol.t_release": ("release duration t_release", TIME_UNITS),
    "protocol.cycles": ("stop-and-release cycles M", None),
    "geometry.asymmetry": ("asymmetry \u0394", "rad"),
    "geometry.smoothing": ("edge width \u03b4", LENGTH_UNITS),
    "geometry.n_corners": ("corners N", None),
    "noise.sigma": ("noise intensity \u03c3", PAPER_UNITS),
    "grid.dx": ("grid spacing dx", LENGTH_UNITS),
    "grid.dt": ("time step dt", TIME_UNITS),
    "grid.domain_radius": ("domain radius L", LENGTH_UNITS),
    "flow.enabled": ("flow (1: on, 0: off)", None),
}
"""Axis label and units (None: a count or a switch) of the config keys that sweeps
vary; any other key is labelled with the schema's description, in :data:`PAPER_UNITS`."""
MAX_TICKS = 12
"""Most tick labels along a heat-map axis (every k-th value beyond that)."""
MAX_COLUMNS = 3
"""Panels per row."""


class ReportError(ValueError):
    """A dataset that is not a sweep report, or an axis it does not have."""


def report_axes(ds: xr.Dataset) -> list[str]:
    """The swept axes of a report: the dimensions of P, in the report's order.

    Raises:
        ReportError: `ds` lacks one of :data:`REPORT_VARIABLES`.
    """
    if ds.attrs.get("estimator") == "collective":
        msg = (
            "a collective sweep's report (measures against time, not P): draw it with "
            "gallery/bodies_crowd.py (docs/collective.md)"
        )
        raise ReportError(msg)
    missing = [name for name in REPORT_VARIABLES if name not in ds]
    if missing:
        msg = f"not a sweep report (no variable {', '.join(missing)})"
        raise ReportError(msg)
    return list(ds["P"].dims)


def layout(ds: xr.Dataset, x: str | None = None) -> tuple[str, str | None, list[str]]:
    """The roles of a report's axes: (x, y, panels).

    x is `x`, else t_stop if it is swept, else the first axis with several values; y (a
    heat map's vertical axis; None: curves) is the first other axis with several values;
    every further axis with several values gets one panel per value.

    Raises:
        ReportError: `x` is not an axis of the report, or no axis has several values.
    """
    axes = report_axes(ds)
    if x is not None and x not in axes:
        msg = f"the report has no axis {x!r} (its axes: {', '.join(axes) or 'none'})"
        raise ReportError(msg)
    free = [d for d in axes if ds.sizes[d] > 1]
    if x is None:
        if not free:
            msg = "the report has no axis with several values: nothing to draw P against"
            raise ReportError(msg)
        x = "t_stop" if "t_stop" in free else free[0]
    others = [d for d in free if d != x]
    return x, (others[0] if others else None), others[1:]


def axis_label(ds: xr.Dataset, dim: str) -> str:
    """``stop duration t_stop [1/a]``: the label of a report's axis, with its units.

    The axis is the config key in the coordinate's ``config_key`` attribute: labelled
    from :data:`AXES`, else from its description in the schema
    (:class:`pde_rotor.config.RotorConfig`); a dimension without a known key is named as
    it is.
    """
    key = str(ds[dim].attrs.get("config_key", dim))
    if key in AXES:
        label, units = AXES[key]
        return label if units is None else f"{label} [{units}]"
    section, _, name = key.rpartition(".")
    field = RotorConfig.model_fields.get(section)
    fields = getattr(field.annotation, "model_fields", {}) if field is not None else {}
    if name not in fields:
        return dim
    symbol, _, meaning = (fields[name].description or name).partition(": ")
    return f"{meaning or symbol} ({symbol}) [{PAPER_UNITS}]"


def report_footer(ds: xr.Dataset, source: str | Path | None = None) -> str:
    """The gallery's footer for a report: its fidelity, source and interval rule."""
    data = SweepData(ds, Path(source or ""), computed=False)
    where = f"; report: {source}" if source is not None else ""
    return f"pde_rotor; {data.label()}{where}; 95 % interval: {data.interval()}"


def _value(ds: xr.Dataset, dim: str, value: Any) -> str:
    units = AXES.get(str(ds[dim].attrs.get("config_key", "")), ("", None))[1]
    return f"{dim} = {value:g}" + (f" {units}" if units and units != PAPER_UNITS else "")


def _panels(ds: xr.Dataset, dims: list[str]) -> list[tuple[str, xr.Dataset]]:
    """(title, sub-report) for every combination of values of `dims`."""
    panels = []
    for combo in itertools.product(*(ds[d].values.tolist() for d in dims)):
        where = dict(zip(dims, combo, strict=True))
        panels.append((", ".join(_value(ds, d, v) for d, v in where.items()), ds.sel(where)))
    return panels


def _ticks(values: np.ndarray) -> tuple[np.ndarray, list[str]]:
    step = max(1, math.ceil(len(values) / MAX_TICKS))
    at = np.arange(0, len(values), step)
    return at, [f"{values[i]:g}" for i in at]


def draw_curve(ax: Any, ds: xr.Dataset, x: str) -> None:
    """P with its 95 % interval against `x`, and the faint conditionals, on `ax`."""
    ds = ds.sortby(x)
    xv = ds[x].values
    draw_conditionals(ax, xv, ds)
    errorbar_p(ax, xv, ds, fmt="o-", color="tab:blue", label="P (95 % interval)")
    probability_axes(ax, axis_label(ds, x))
    ax.legend(fontsize=8, loc="best")


def draw_heat_map(ax: Any, ds: xr.Dataset, x: str, y: str) -> Any:
    """A heat map of P over `x` (horizontal) and `y`: one cell per point, NaN blank.

    Returns:
        The :class:`matplotlib.collections.QuadMesh` (for the colour bar).
    """
    ds = ds.sortby([x, y])
    xv, yv = ds[x].values, ds[y].values
    mesh = ax.pcolormesh(  # masks the NaN cells: drawn blank
        np.arange(len(xv) + 1) - 0.5,
        np.arange(len(yv) + 1) - 0.5,
        ds["P"].transpose(y, x).values.astype(float),
        cmap="viridis",
        vmin=0.0,
        vmax=1.0,
    )
    ax.set_xticks(*_ticks(xv), fontsize=8, rotation=45)
    ax.set_yticks(*_ticks(yv), fontsize=8)
    ax.set_xlabel(f"{axis_label(ds, x)}, one cell per value")
    ax.set_ylabel(axis_label(ds, y))
    return mesh


def report_figure(ds: xr.Dataset, x: str | None = None, source: str | Path | None = None) -> Figure:
    """The figure of a sweep report: P against `x`, or heat maps of P (see the module).

    Args:
        ds: the report (:func:`pde_rotor.sweep.report`, or a stored one read with
            :func:`pde_rotor.sweep.stored.load_report`).
        x: the axis to draw P against (horizontal); default t_stop if swept, else the
            first axis with several values.
        source: where the report came from, named in the footer.

    Returns:
        A pyplot-free figure (save it with ``fig.savefig``).

    Raises:
        ReportError: `ds` is not a report, has no axis `x`, no axis with several values
            or no measured point.
    """
    x, y, extra = layout(ds, x)
    if not np.isfinite(np.asarray(ds["P"].values, dtype=float)).any():
        msg = "the report holds no measured point yet (P is NaN everywhere)"
        raise ReportError(msg)
    fixed = [d for d in report_axes(ds) if ds.sizes[d] == 1 and d != x]
    ds = ds.squeeze(fixed) if fixed else ds
    panels = _panels(ds, extra)
    ncols = min(MAX_COLUMNS, len(panels))
    nrows = math.ceil(len(panels) / ncols)
    fig = new_figure((6.0 if y else 4.6) * ncols, 3.8 * nrows + 1.0)
    axes = fig.subplots(nrows, ncols, squeeze=False, sharex=True, sharey=True)
    mesh = None
    for ax, (title, panel) in zip(axes.flat, panels, strict=False):
        if y is None:
            draw_curve(ax, panel, x)
        else:
            mesh = draw_heat_map(ax, panel, x, y)
        ax.set_title(title, fontsize=10)
    for ax in axes.flat[len(panels) :]:
        ax.set_visible(False)
    if mesh is not None:
        fig.colorbar(mesh, ax=axes, label=P_LABEL, shrink=0.9)
    name = ds.attrs.get("sweep", "")
    setting = ", ".join(_value(ds, d, float(ds[d])) for d in fixed)
    fig.suptitle(f"sweep {name}" + (f" at {setting}" if setting else ""), fontsize=11)
    add_footer(fig, report_footer(ds, source))
    return fig
