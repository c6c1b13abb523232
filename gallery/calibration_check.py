"""How well the decision model fits every flow ensemble: the calibration of its tails.

By bins of q, the probability the decision model (docs/decision.md) gives the less
likely direction after a release, the stops of every stored flow ensemble that went that
way, against the number the model expects, with the 95 % range of a Poisson count; the
title gives Pearson's X^2 over the conditionals where the model expects at least five
stops each way (:mod:`pde_rotor.decision.goodness`). Points come from the committed
reports and data/decision/dx40.nc only, so every fidelity draws the same page.

Run: ``python gallery/calibration_check.py [--quick | --tiny]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pde_rotor.decision.check import compare
from pde_rotor.decision.goodness import goodness_of_fit
from pde_rotor.decision.map import draw_calibration
from pde_rotor.decision.table import load_table
from pde_rotor.gallery.common import DATA, parse_args
from pde_rotor.sweep.stored import load_report

NAME = "calibration_check"
TABLE = "dx40.nc"
"""The decision table of the paper's grid with flow (data/decision/)."""
REPORTS = ("fig5", "fig7a", "fig7b", "fig7c", "fig9", "science_calibration")
"""The flow ensembles on the table's physics (data/NAME.nc), besides the science_grid_*
and science_one_intensity_* reports."""


def report_paths(data: Path) -> list[Path]:
    """Every stored flow report on the table's physics under `data`."""
    named = [data / f"{name}.nc" for name in REPORTS]
    extra = sorted(data.glob("science_grid_*.nc")) + sorted(data.glob("science_one_intensity_*.nc"))
    return [path for path in [*named, *extra] if path.is_file()]


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw the calibration page as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    paths = report_paths(DATA)
    table = load_table(DATA / "decision" / TABLE)
    fit = goodness_of_fit(compare(table, [load_report(path) for path in paths]))
    for line in fit.describe():
        print(f"{NAME}: {line}")
    footer = (
        f"decision table data/decision/{TABLE}; conditionals of "
        f"{', '.join(p.name for p in paths)}; {fit.conditionals} informative conditionals"
    )
    return draw_calibration(fit, args.out, NAME, footer=footer)


if __name__ == "__main__":
    main()
