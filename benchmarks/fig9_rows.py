"""Is one row of the measured Fig. 9 map, taken whole, where the decision model puts it?

A single cell outside its 95 % interval is expected now and then (one in twenty); the
question is whether its row shows a trend the model lacks. For one Delta this sums,
over the measured cells of data/fig9.nc with t_stop in [--from, --to] and the cell of
data/fig7c.nc (t_stop = 3) where it has that Delta, the inversions after CCW and after
CW stops and compares each sum with the model's expectation, sum n p, where p is
P(inv | direction) of the decision table (data/decision/dx40.nc, docs/decision.md) at
the noise of the reports. z = (k - sum n p) / sqrt(sum n p (1 - p)) and its two-sided
p-value (normal approximation of a sum of binomials); where the rarer outcome (inverted
or not) is expected fewer than 10 times, also its Poisson tail P(K >= count).

    python benchmarks/fig9_rows.py --asymmetry 1e-5 [--from 2 --to 3] [--data DIR]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import xarray as xr
from scipy.stats import norm, poisson

from pde_rotor.decision import diffusion_of, load_table
from pde_rotor.sweep.stored import load_report

ROOT = Path(__file__).resolve().parents[1]
SIDES = ("ccw", "cw")
"""The report's suffixes of the two directions, in the order of the table's
conditionals (pde_rotor.decision.DIRECTIONS: CCW, CW)."""


def row_cells(
    data: Path, asymmetry: float, t_from: float, t_to: float
) -> list[tuple[float, xr.Dataset]]:
    """(t_stop, cell) of every measured cell of the row, fig9 first, then fig7c's."""
    cells = []
    fig9 = load_report(data / "fig9.nc").sel(asymmetry=asymmetry, method="nearest")
    for t in fig9["t_stop"].values:
        cell = fig9.sel(t_stop=t)
        if t_from <= t <= t_to and int(cell["runs_done"]) > 0:
            cells.append((float(t), cell))
    fig7c = load_report(data / "fig7c.nc")
    t_fig7c = json.loads(fig7c.attrs["base_config"])["protocol"]["t_stop"]
    if t_from <= t_fig7c <= t_to and np.isclose(fig7c["asymmetry"].values, asymmetry).any():
        cells.append((t_fig7c, fig7c.sel(asymmetry=asymmetry, method="nearest")))
    return cells


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
        k = n = mean = var = 0.0
        for t, cell in cells:
            kk, nn = int(cell[f"inversions_{side}"]), int(cell[f"stops_{side}"])
            p = float(table.conditionals(t, args.asymmetry, diffusion)[index])
            print(f"  from {side.upper()}, t_stop = {t:g}: {kk} of {nn} inverted, model {p:.3f}")
            k, n, mean, var = k + kk, n + nn, mean + nn * p, var + nn * p * (1 - p)
        z = (k - mean) / np.sqrt(var)
        line = (
            f"from {side.upper()}: {int(k)} of {int(n)} inverted against {mean:.1f} "
            f"(z = {z:+.2f}, two-sided p = {2 * norm.sf(abs(z)):.2f}"
        )
        inverted_rare = mean < n - mean
        rare, count = (mean, k) if inverted_rare else (n - mean, n - k)
        if rare < 10:
            outcome = "inverted" if inverted_rare else "not inverted"
            tail = poisson.sf(count - 1, rare)
            line += f"; {outcome}: Poisson P(>= {int(count)} | {rare:.1f}) = {tail:.2f}"
        print(line + ")")


if __name__ == "__main__":
    main()
