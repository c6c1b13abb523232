"""How well the decision model fits every flow ensemble: the calibration of its tails.

Every stored restart or bank ensemble with the flow on (data/*.nc: discovered, not
listed) against the decision table of its own physics (data/decision/: grid, scheme,
flow; :func:`pde_rotor.decision.check.stored_matches`), the way ``pde-rotor predict
check`` does without a table. By bins of q, the probability the model gives the less
likely direction after a release, the stops that went that way against the number the
model expects, with the 95 % range of that count under the model (a sum of binomials);
the title gives the full test over every conditional (:mod:`pde_rotor.decision.goodness`:
X^2 and G^2 on a parametric-bootstrap null, the exact tests' failing count) and the
scatter of the model's x in the bin where it is largest. Every fidelity draws the
committed data, so every fidelity draws the same page.

Run: ``python gallery/calibration_check.py [--quick | --tiny]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pde_rotor.decision.check import (
    Comparison,
    compare,
    is_ensemble,
    report_config,
    stored_matches,
)
from pde_rotor.decision.goodness import goodness_of_fit
from pde_rotor.decision.map import draw_calibration
from pde_rotor.gallery.common import DATA, parse_args
from pde_rotor.sweep.stored import load_report

NAME = "calibration_check"


def flow_ensembles(data: Path) -> list:
    """(report path, report, table path, table) of every stored flow ensemble under
    `data` that a table under data/decision predicts, and the lines of those none does."""
    reports = [(path, load_report(path)) for path in sorted(data.glob("*.nc"))]
    reports = [
        (path, ds)
        for path, ds in reports
        if is_ensemble(ds) and report_config(ds).get("flow", {}).get("enabled", True)
    ]
    return stored_matches(reports, data / "decision")


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw the calibration page as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    pairs, left_out = flow_ensembles(DATA)
    rows = [row for _, ds, _, table in pairs for row in compare(table, [ds]).rows]
    fit = goodness_of_fit(Comparison(rows))
    for line in left_out:
        print(f"{NAME}: left out: {line}")
    for line in fit.describe():
        print(f"{NAME}: {line}")
    tables = sorted({table_path.name for _, _, table_path, _ in pairs})
    reports = sorted({path.name for path, _, _, _ in pairs})
    footer = (
        f"every stored flow ensemble with a decision table: {', '.join(reports)}; tables "
        f"data/decision/{', '.join(tables)}; {len(fit.conditionals)} conditionals, "
        f"{fit.draws} bootstrap draws (seed {fit.seed})"
    )
    return draw_calibration(fit, args.out, NAME, footer=footer)


if __name__ == "__main__":
    main()
