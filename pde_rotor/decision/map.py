"""The Fig. 9 map from the reduced decision model, with ensemble points drawn on it.

P(t_stop, Δ) of :meth:`pde_rotor.decision.table.DecisionTable.probability` on a fine grid,
in the paper's colours (Fig. 9: red high P, blue the favourable direction, grey-white
near 0.5), the critical stop t_c(Δ) of :meth:`~pde_rotor.decision.table.DecisionTable.
critical_stop` as a line, and the points of stored sweep reports (ensembles) as
markers filled with their own P in the same colours.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from ..plotting.figures import add_footer, new_figure, save_figure
from .check import mismatch, table_points
from .goodness import GoodnessOfFit
from .table import DecisionTable, diffusion_of, sigma_of


def ensemble_points(
    table: DecisionTable, reports: Sequence[xr.Dataset], sigma: float
) -> list[tuple]:
    """(t_stop, Δ, P, P_low, P_high) of every report point on the table's grid at the
    map's noise `sigma` (:func:`pde_rotor.decision.check.table_points`; other noise
    values differ by more than 2 % and are left out). Reports of another smoothing,
    flow setting or scheme (:func:`pde_rotor.decision.check.mismatch`) give none, so
    every stored report can be offered."""
    return [
        (p["t_stop"], p["asymmetry"], p["P"], p["P_low"], p["P_high"])
        for ds in reports
        if mismatch(table, json.loads(ds.attrs.get("base_config", "{}")), list(ds.dims)) is None
        for p in table_points(table, ds)
        if abs(p["sigma"] - sigma) <= 0.02 * max(abs(p["sigma"]), abs(sigma))
    ]


def model_curve(
    table: DecisionTable, x_dim: str, x: np.ndarray, sigma: float, **fixed: float
) -> np.ndarray:
    """The model's P along one curve of the paper's figures (Figs. 5, 7, 8).

    Args:
        table: the decision table.
        x_dim: the curve's variable, "t_stop" or "asymmetry".
        x: its values (t_stop within the table's range).
        sigma: the noise intensity of Eq. (eq_motion) (Dw = (sigma/I)²).
        fixed: the other of t_stop and asymmetry.

    Returns:
        P at every `x` (:meth:`pde_rotor.decision.table.DecisionTable.probability`).
    """
    diffusion = diffusion_of(sigma, table.inertia)
    if x_dim == "t_stop":
        return np.asarray(table.probability(x, fixed["asymmetry"], diffusion), dtype=float)
    if x_dim == "asymmetry":
        return np.array([float(table.probability(fixed["t_stop"], d, diffusion)) for d in x])
    msg = f"x_dim must be 't_stop' or 'asymmetry', not {x_dim!r}"
    raise ValueError(msg)


def draw_map(
    table: DecisionTable,
    diffusion: float,
    out: Path,
    name: str = "fig9_predicted",
    t_range: tuple[float, float] = (0.25, 3.5),
    asymmetry_max: float = 1e-4,
    resolution: tuple[int, int] = (160, 81),
    points: Sequence[tuple] = (),
    footer: str = "",
) -> tuple[list[Path], np.ndarray]:
    """Draw P(t_stop, Δ) at `diffusion` and write out/name.png and .pdf.

    The ensemble `points` (t_stop, Δ, P, ...) inside the drawn range are drawn and
    counted in the title; those outside it are left out of both.

    Returns:
        The written paths and the map (n_asymmetry, n_t_stop).
    """
    points = [
        q for q in points if t_range[0] <= q[0] <= t_range[1] and 0.0 <= q[1] <= asymmetry_max
    ]
    t_stop = np.linspace(*t_range, resolution[0])
    asymmetry = np.linspace(0.0, asymmetry_max, resolution[1])
    p = np.array([table.probability(t_stop, d, diffusion) for d in asymmetry])
    fig = new_figure(8.0, 5.6)
    ax = fig.subplots()
    mesh = ax.pcolormesh(t_stop, asymmetry, p, cmap="coolwarm", vmin=0, vmax=1, shading="auto")
    fig.colorbar(mesh, ax=ax, label="inversion probability P")
    lines = ax.contour(t_stop, asymmetry, p, levels=[0.2, 0.5, 0.75], colors="k", linewidths=0.7)
    ax.clabel(lines, fmt="%.2f", fontsize=7)
    t_c = [table.critical_stop(d, diffusion) for d in asymmetry]
    ax.plot(t_c, asymmetry, "w--", lw=1.5, label="critical stop t_c(\u0394)")
    for t, d, value, _low, _high in points:
        ax.scatter(
            [t], [d], c=[value], cmap="coolwarm", vmin=0, vmax=1, s=70, edgecolors="k", zorder=3
        )
        below = d > 0.9 * asymmetry_max  # at the top edge the label goes under the marker
        ax.annotate(
            f"{value:.2f}", (t, d), textcoords="offset points", xytext=(0, -12 if below else 7),
            fontsize=6, ha="center",
        )  # fmt: skip
    ax.set_xlim(*t_range)
    ax.set_ylim(0, asymmetry_max)
    ax.set_xlabel("t_stop")
    ax.set_ylabel("asymmetry \u0394")
    ax.legend(loc="upper right", fontsize=8)
    sigma = sigma_of(diffusion, table.inertia)
    ax.set_title(
        f"Fig. 9 from the decision model: Dw = {diffusion:.3g} (\u03c3 = {sigma:.3g}), "
        f"\u03bb = {table.growth_rate:.3g}"
        + (f"; {len(points)} ensemble points (markers)" if points else ""),
        fontsize=10,
    )
    if footer:
        add_footer(fig, footer)
    return save_figure(fig, out, name), p


MASTER_SPAN = 4.0
"""|x| drawn on the master curve (Φ(4) = 1 - 3e-5); points beyond sit at the edge."""


def draw_master(
    points: Sequence[dict[str, float]], out: Path, name: str = "master_curve", footer: str = ""
) -> list[Path]:
    """The ensembles' P(direction after = +1) against x = β̄/sqrt(λ Dw), with Φ(x)
    (:func:`pde_rotor.decision.check.master_points`)."""
    from scipy.special import ndtr

    fig = new_figure(7.0, 5.0)
    ax = fig.subplots()
    x = np.array([p["x"] for p in points])
    value = np.array([p["P"] for p in points])
    err = np.array([[p["P"] - p["low"] for p in points], [p["high"] - p["P"] for p in points]])
    inside = np.abs(x) <= MASTER_SPAN
    ax.errorbar(
        x[inside], value[inside], yerr=err[:, inside], fmt="o", ms=4, capsize=2,
        label="ensembles (95 % CI)",
    )  # fmt: skip
    if (~inside).any():
        ax.errorbar(
            np.clip(x[~inside], -MASTER_SPAN, MASTER_SPAN), value[~inside],
            yerr=err[:, ~inside], fmt=">", ms=5, capsize=2, color="tab:gray",
            label=f"|x| > {MASTER_SPAN:g}, drawn at the edge",
        )  # fmt: skip
    grid = np.linspace(-MASTER_SPAN, MASTER_SPAN, 400)
    ax.plot(grid, ndtr(grid), "k-", lw=1, label="\u03a6(x): linear escape")
    ax.set_xlabel("x = \u03b2 / sqrt(\u03bb Dw)  (angle-mean bias at release over the noise scale)")
    ax.set_ylabel("P(direction after the release = +1)")
    ax.set_ylim(-0.02, 1.02)
    ax.legend(fontsize=8)
    ax.set_title("Master curve: every stop of every point on one line if the model holds")
    if footer:
        add_footer(fig, footer)
    return save_figure(fig, out, name)


def draw_calibration(
    fit: GoodnessOfFit, out: Path, name: str = "calibration_check", footer: str = ""
) -> list[Path]:
    """The model's calibration: per bin of the predicted probability q of the less likely
    direction, the stops that went that way against the expected count, with the bin's
    95 % binomial range, and the full test in the title (:mod:`.goodness`)."""
    fig = new_figure(7.0, 5.0)
    ax = fig.subplots()
    bins = [b for b in fit.bins if b.conditionals and b.expected > 0]
    at = np.arange(len(bins))
    expected = np.array([b.expected for b in bins])
    ratio = np.array([b.observed for b in bins]) / expected
    spread = np.array([[1 - b.range[0] / b.expected, b.range[1] / b.expected - 1] for b in bins])
    ax.errorbar(at, np.ones(len(bins)), yerr=spread.T, fmt="none", ecolor="0.6", elinewidth=8,
                label="model: 1, with the 95 % range of its count (sum of binomials)")  # fmt: skip
    colours = ["tab:blue" if b.holds else "tab:red" for b in bins]
    ax.scatter(at, ratio, c=colours, zorder=3, s=40, label="ensembles (red: outside the range)")
    for k, b in enumerate(bins):
        ax.annotate(f"{b.observed} of {b.expected:.1f}", (at[k], ratio[k]),
                    textcoords="offset points", xytext=(10, -3), fontsize=8)  # fmt: skip
    ax.set_xticks(at, [f"[{b.low:g}, {b.high:g})\n{b.conditionals} cond." for b in bins])
    ax.set_xlim(-0.5, len(bins) - 0.5)
    ax.set_ylim(0, max(2.0, 1.3 * float(ratio.max())))  # a near-empty bin's range is clipped
    ax.set_xlabel("predicted probability q of the less likely direction (bins)")
    ax.set_ylabel("stops that went that way: observed / expected")
    ax.legend(fontsize=8, loc="upper right")
    widest = max(fit.bins, key=lambda b: b.scatter)
    ax.set_title(
        f"Decision model, {len(fit.conditionals)} conditionals: X\u00b2 p = "
        f"{fit.pearson_p:.2g}, G\u00b2 p = {fit.g_p:.2g} (simulated null)\n{fit.failing} "
        f"fail the exact test at 5 % ({fit.failing_expected:.1f} expected, p = "
        f"{fit.failing_p:.2g}); x scatters {widest.scatter:.2f} in q \u2208 "
        f"[{widest.low:g}, {widest.high:g})",
        fontsize=9,
    )
    if footer:
        add_footer(fig, footer)
    return save_figure(fig, out, name)
