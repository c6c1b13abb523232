"""Is one row of the measured Fig. 9 map, taken whole, where the decision model puts it?

A single cell outside its 95 % interval is expected now and then (one in twenty); the
question is whether its row departs from the model. For one Delta this takes the
measured cells of data/fig9.nc with t_stop in [--from, --to] and the cell of
data/fig7c.nc (t_stop = 3) where it has that Delta and fig9 has not measured it, and
compares, for the stops from CCW and from CW separately, the inversions k_i of n_i with
the model's P(inv | direction) p_i of the decision table (data/decision/dx40.nc,
docs/decision.md) at the noise of the reports:

* the sum: z = (sum k - sum n p) / sqrt(sum n p (1 - p)) and its two-sided p-value
  (normal approximation of a sum of binomials), a shift of the whole row; where the
  rarer outcome (inverted or not) is expected fewer than 10 times, also its Poisson
  tail on the side the count lies (P(K >= count) above the expectation, else
  P(K <= count));
* chi2 = sum (k_i - n_i p_i)^2 / (n_i p_i (1 - p_i)) with one degree of freedom per
  cell, which cells above and below the model do not cancel in. Only cells where both
  outcomes are expected at least :data:`CHI2_MIN_EXPECTED` times enter it (the chi2
  law fails for rarer outcomes; the Poisson tail of the sum is the test there).

    python benchmarks/fig9_rows.py --asymmetry 1e-5 [--from 2 --to 3] [--data DIR]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import xarray as xr
from scipy.stats import chi2 as chi2_dist
from scipy.stats import norm, poisson

from pde_rotor.decision.table import diffusion_of, load_table
from pde_rotor.sweep.stored import load_report

ROOT = Path(__file__).resolve().parents[1]
CHI2_MIN_EXPECTED = 5.0
"""Smallest expected count of either outcome for a cell to enter the chi2 sum."""
SIDES = ("ccw", "cw")
"""The report's suffixes of the two directions, in the order of the table's
conditionals (pde_rotor.decision.table.DIRECTIONS: CCW, CW)."""


def row_cells(
    data: Path, asymmetry: float, t_from: float, t_to: float
) -> list[tuple[float, xr.Dataset]]:
    """(t_stop, cell) of every measured cell of the row, sorted by t_stop.

    Raises:
        SystemExit: fig9's design has no row at `asymmetry`.
    """
    fig9 = load_report(data / "fig9.nc")
    rows = fig9["asymmetry"].values
    if not np.isclose(rows, asymmetry, rtol=1e-6, atol=0).any():
        raise SystemExit(f"data/fig9.nc has no row Delta = {asymmetry:g} (rows: {rows})")
    row = fig9.sel(asymmetry=asymmetry, method="nearest")
    cells = {}
    for t in row["t_stop"].values:
        cell = row.sel(t_stop=t)
        if t_from <= t <= t_to and int(cell["runs_done"]) > 0:
            cells[round(float(t), 9)] = cell
    fig7c = load_report(data / "fig7c.nc")
    t_fig7c = round(float(json.loads(fig7c.attrs["base_config"])["protocol"]["t_stop"]), 9)
    at = np.isclose(fig7c["asymmetry"].values, asymmetry, rtol=1e-6, atol=0)
    if t_from <= t_fig7c <= t_to and at.any() and t_fig7c not in cells:
        cell = fig7c.isel(asymmetry=int(np.argmax(at)))
        if int(cell["runs_done"]) > 0:
            cells[t_fig7c] = cell
    return sorted(cells.items())


def rare_tail(count: float, expected: float) -> str:
    """The Poisson tail of `count` rare outcomes on the side it lies from `expected`."""
    if count >= expected:
        return f"P(>= {int(count)} | {expected:.1f}) = {poisson.sf(count - 1, expected):.2f}"
    return f"P(<= {int(count)} | {expected:.1f}) = {poisson.cdf(count, expected):.2f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--asymmetry", type=float, required=True)
    parser.add_argument("--from", dest="t_from", type=float, default=2.0)
    parser.add_argument("--to", dest="t_to", type=float, default=3.0)
    parser.add_argument("--data", type=Path, default=ROOT / "data")
    args = parser.parse_args()
    table = load_table(args.data / "decision" / "dx40.nc")
    fig9 = load_report(args.data / "fig9.nc")
    sigma = json.loads(fig9.attrs["base_config"])["noise"]["sigma"]
    diffusion = diffusion_of(sigma, table.inertia)
    cells = row_cells(args.data, args.asymmetry, args.t_from, args.t_to)
    if not cells:
        raise SystemExit(f"no measured cell at Delta = {args.asymmetry:g} in the range")
    print(f"Delta = {args.asymmetry:g}, sigma = {sigma:g} (Dw = {diffusion:.3g})")
    for index, side in enumerate(SIDES):
        k = n = mean = var = chi2 = 0.0
        cells_in_chi2 = 0
        for t, cell in cells:
            kk, nn = int(cell[f"inversions_{side}"]), int(cell[f"stops_{side}"])
            p = float(table.conditionals(t, args.asymmetry, diffusion)[index])
            print(f"  from {side.upper()}, t_stop = {t:g}: {kk} of {nn} inverted, model {p:.3f}")
            k, n, mean, var = k + kk, n + nn, mean + nn * p, var + nn * p * (1 - p)
            if min(nn * p, nn * (1 - p)) >= CHI2_MIN_EXPECTED:
                chi2 += (kk - nn * p) ** 2 / (nn * p * (1 - p))
                cells_in_chi2 += 1
        line = f"from {side.upper()}: {int(k)} of {int(n)} inverted against {mean:.1f}"
        if var > 0:
            z = (k - mean) / np.sqrt(var)
            line += f" (z = {z:+.2f}, two-sided p = {2 * norm.sf(abs(z)):.2f})"
        inverted_rare = mean < n - mean
        rare, count = (mean, k) if inverted_rare else (n - mean, n - k)
        if rare < 10:
            outcome = "inverted" if inverted_rare else "not inverted"
            line += f"; {outcome}: Poisson {rare_tail(count, rare)}"
        if cells_in_chi2:
            line += (
                f"; per cell chi2 = {chi2:.2f} on {cells_in_chi2} df "
                f"({len(cells) - cells_in_chi2} cells too rare), "
                f"p = {chi2_dist.sf(chi2, cells_in_chi2):.2f}"
            )
        print(line)


if __name__ == "__main__":
    main()
