"""Figure helpers shared by the gallery (pde_rotor.plotting.figures)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from pde_rotor.plotting.figures import errorbar_p, new_figure


def _curve(runs_done: list[int]) -> xr.Dataset:
    p = np.array([1.0, 0.9, 0.4])
    return xr.Dataset(
        {
            "P": ("t_stop", p),
            "P_low": ("t_stop", p - 0.1),
            "P_high": ("t_stop", np.minimum(p + 0.1, 1.0)),
            "runs_done": ("t_stop", runs_done),
            "runs_expected": ("t_stop", [100, 100, 100]),
        },
        coords={"t_stop": [0.5, 1.0, 1.5]},
    )


def test_errorbar_p_marks_partial_points_hollow() -> None:
    """A point whose runs are not all done is drawn, hollow and labelled, so a figure
    made from a sweep in progress shows which points may still move."""
    ax = new_figure(4, 3).add_subplot()
    ds = _curve([100, 3, 100])
    errorbar_p(ax, ds["t_stop"].values, ds, fmt="o-", color="tab:red", label="P")
    (hollow,) = [line for line in ax.get_lines() if line.get_label().startswith("partial")]
    assert hollow.get_xdata().tolist() == [1.0] and hollow.get_ydata().tolist() == [0.9]
    assert hollow.get_markerfacecolor() == "white"
    complete = new_figure(4, 3).add_subplot()
    errorbar_p(complete, ds["t_stop"].values, _curve([100, 100, 100]), fmt="o-", label="P")
    assert not [line for line in complete.get_lines() if line.get_label().startswith("partial")]


def test_errorbar_p_joins_the_measured_points_across_unmeasured_ones() -> None:
    """A design run region by region has NaN at the points still to run: the curve's
    line joins the measured points on either side instead of breaking there."""
    ax = new_figure(4, 3).add_subplot()
    ds = _curve([100, 0, 100])
    ds["P"][1] = np.nan
    errorbar_p(ax, ds["t_stop"].values, ds, fmt="o-", label="P")
    line = ax.containers[0].lines[0]  # the data line of the errorbar
    assert line.get_xdata().tolist() == [0.5, 1.5]
    assert line.get_ydata().tolist() == [1.0, 0.4]
