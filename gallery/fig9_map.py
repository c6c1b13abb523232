"""Paper Fig. 9: the inversion probability P(t_stop, Delta) as a map.

At full fidelity the map is the measured one: every ensemble point of the stored reports
(data/*.nc) on the paper's grid and the default scheme at the calibrated noise (the
points :func:`pde_rotor.decision.map.ensemble_points` finds for the table
data/decision/dx40.nc: the curves of Figs. 5 and 7, the grid probes, the one-intensity
sweep and the measured cells of the fig9 sweep itself, data/fig9.nc), on the union of
their t_stop and Delta, blank where nothing was measured; the model's full map is
gallery/fig9_predicted.py.
``--quick`` reads the coarse report of configs/sweeps/fig9_quick.yaml (stored in data/,
else run through :mod:`pde_rotor.sweep`), ``--tiny`` a shrunken copy of it. (a) P with
the paper's colours (red: high, blue: low, grey-white near 0.5), each cell labelled with
P; (b) the width of the 95 % interval of each cell. The paper: high P (red) for short
stops, the favourable direction (blue) for long stops and large Delta, random (grey) for
long stops and small Delta.

Run: ``python gallery/fig9_map.py [--quick | --tiny]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from pde_rotor.config import CALIBRATED_SIGMA, RotorConfig
from pde_rotor.decision.map import ensemble_points
from pde_rotor.decision.table import load_table
from pde_rotor.gallery.common import (
    DATA,
    add_footer,
    grid_label,
    new_figure,
    parse_args,
    save,
)
from pde_rotor.gallery.sweeps import (
    ASYMMETRY_LABEL,
    STOP_LABEL,
    probability_footer,
    sweep_data,
)
from pde_rotor.sweep.stored import load_report

NAME = "fig9_map"
SWEEP = "fig9"
TABLE = DATA / "decision" / "dx40.nc"
"""The decision table whose grid, scheme and flow select the measured map's reports."""


def measured_map(points: Sequence[tuple]) -> xr.Dataset:
    """P, P_low, P_high on the union of the points' Delta and t_stop (NaN where none).

    Args:
        points: (t_stop, Delta, P, P_low, P_high) of ensemble points; where several
            share a cell, the one with the narrowest interval is kept.
    """
    t_stop = np.unique([p[0] for p in points])
    delta = np.unique([p[1] for p in points])
    values = np.full((3, delta.size, t_stop.size), np.nan)
    for t, d, *estimate in sorted(points, key=lambda p: p[4] - p[3], reverse=True):
        values[:, np.searchsorted(delta, d), np.searchsorted(t_stop, t)] = estimate
    dims = ("asymmetry", "t_stop")
    return xr.Dataset(
        {name: (dims, v) for name, v in zip(("P", "P_low", "P_high"), values, strict=True)},
        coords={"asymmetry": delta, "t_stop": t_stop},
    )


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Load or run the sweep, write Fig. 9 as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    if args.fidelity.name == "full":
        table = load_table(TABLE)
        reports = [load_report(path) for path in sorted(DATA.glob("*.nc"))]
        points = ensemble_points(table, reports, CALIBRATED_SIGMA)
        ds = measured_map(points)
        config = RotorConfig.model_validate_json(table.attrs["config"])
        footer = (
            f"measured: the {len(points)} ensemble points of data/*.nc at "
            f"{grid_label(config)}, scheme {config.numerics.scheme} (as {TABLE.name}), "
            f"\u03c3 = {CALIBRATED_SIGMA:g}; 95 % Wilson intervals; blank: not measured "
            "(the decision model's whole map: fig9_predicted)"
        )
    else:
        data = sweep_data(SWEEP, args.fidelity, args.out)
        ds = data.report.transpose("asymmetry", "t_stop", ...)
        extra = [d for d in ds.dims if d not in ("asymmetry", "t_stop")]
        if extra:
            ds = ds.isel(dict.fromkeys(extra, 0))
        footer = probability_footer(args.fidelity, data)
    t_stop = ds["t_stop"].values
    delta = ds["asymmetry"].values
    # Delta and t_stop are drawn on evenly spaced rows and columns (the measured map's
    # values are not evenly spaced, and its cells stay wide enough to carry their labels)
    rows = np.arange(delta.size)
    cols = np.arange(t_stop.size)
    row_edges, col_edges = np.arange(delta.size + 1) - 0.5, np.arange(t_stop.size + 1) - 0.5
    fig = new_figure(12.5, 5.2)
    ax_p, ax_w = fig.subplots(1, 2)
    p = ds["P"].values
    width = ds["P_high"].values - ds["P_low"].values
    mesh = ax_p.pcolormesh(col_edges, row_edges, p, cmap="coolwarm", vmin=0, vmax=1)
    fig.colorbar(mesh, ax=ax_p, label="inversion probability P")
    for i in rows:
        for j, t in enumerate(t_stop):
            if np.isfinite(p[i, j]):
                ax_p.text(j, i, f"{p[i, j]:.2f}", ha="center", va="center", fontsize=7)
                print(
                    f"{NAME}: Delta = {delta[i]:g}, t_stop = {t:g}: P = {p[i, j]:.3f} "
                    f"[{float(ds['P_low'].values[i, j]):.3f}, "
                    f"{float(ds['P_high'].values[i, j]):.3f}]"
                )
    mesh_w = ax_w.pcolormesh(col_edges, row_edges, width, cmap="Greys", vmin=0, vmax=1)
    fig.colorbar(mesh_w, ax=ax_w, label="width of the 95 % interval of P")
    for ax, title in (
        (ax_p, "(a) P(t_stop, \u0394); paper: red short stops, blue long stops and large \u0394"),
        (ax_w, "(b) uncertainty: P_high \u2212 P_low"),
    ):
        ax.set_yticks(rows, [f"{d:g}" for d in delta])
        ax.set_xticks(cols, [f"{t:g}" for t in t_stop], fontsize=8)
        ax.set_xlabel(STOP_LABEL)
        ax.set_ylabel(ASYMMETRY_LABEL)
        ax.set_title(title, fontsize=10)
    fig.suptitle("Fig. 9: inversion probability against t_stop and \u0394", fontsize=11)
    add_footer(fig, footer)
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
