"""The collapse of every probability curve of Figs. 5, 7, 8 and 9 onto one master curve.

The reduced decision model (docs/decision.md) predicts that after a release the rotor
turns the +1 way with probability Φ(x), x = β̄ / sqrt(λ Dw): the angle-mean bias of the
stop's end over the noise scale. If it holds, every conditional of every curve, with flow
(Figs. 5, 7 and the measured cells of the map of Fig. 9; table data/decision/dx40.nc)
and without (Fig. 8; dx40_no_flow.nc), whatever its t_stop, Δ and direction, falls on
the one line Φ(x). Each report of the figures' sweeps is placed with the table of its
own physics (:func:`pde_rotor.decision.check.table_for`); the points come from the
committed data only, so every fidelity draws the same page.

Run: ``python gallery/master_curve.py [--quick | --tiny]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scipy.special import ndtr

from pde_rotor.decision.check import master_points, table_for
from pde_rotor.decision.map import draw_master
from pde_rotor.gallery.common import DATA, parse_args
from pde_rotor.sweep.stored import load_report

NAME = "master_curve"
CURVES = ("fig5", "fig7a", "fig7b", "fig7c", "fig8", "fig9")
"""The reports of the paper's probability curves and map (data/NAME.nc;
fig9 may be partial: its unmeasured cells are NaN and give no point)."""


def curve_points(data: Path) -> tuple[list[dict[str, float]], list[str]]:
    """The master-curve points of every stored curve report under `data`, each placed
    with its own decision table of data/decision/, and the names of the tables used."""
    points: list[dict[str, float]] = []
    tables: list[str] = []
    for name in CURVES:
        path = data / f"{name}.nc"
        if not path.is_file():
            continue
        report = load_report(path)
        found = table_for(report, data / "decision")
        if found is None:
            continue
        table_path, table = found
        points += master_points(table, [report])
        if table_path.name not in tables:
            tables.append(table_path.name)
    return points, tables


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw the master curve as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    points, tables = curve_points(DATA)
    if not points:
        msg = f"{DATA}: no curve report ({', '.join(CURVES)}) with a decision table"
        raise FileNotFoundError(msg)
    inside = sum(p["low"] <= ndtr(p["x"]) <= p["high"] for p in points)
    print(f"{NAME}: {len(points)} conditionals, {inside} hold Φ(x) in their 95 % interval")
    footer = (
        f"the conditionals of data/{{{','.join(CURVES)}}}.nc, each placed with its decision "
        f"table ({', '.join(tables)}); {inside} of {len(points)} intervals hold \u03a6(x)"
    )
    return draw_master(points, args.out, NAME, footer=footer)


if __name__ == "__main__":
    main()
