"""Paper Fig. 9 from the reduced decision model: P(t_stop, Delta) at the calibrated noise.

The model (docs/decision.md, :mod:`pde_rotor.decision.table`) turns a table of noise-free
stop curves and the release growth rate into P at any point; this page draws it on a
fine grid, at the calibrated noise (pde_rotor.config.CALIBRATED_SIGMA, from the ensemble
of configs/sweeps/science_calibration.yaml; the table's own Delta = 2e-5 plateau crosses
the paper's 0.2 within 2 % of it). The table is the committed data/decision/dx40.nc
(the paper's grid, the default scheme; ``pde-rotor predict measure`` rebuilds it in
about 10 minutes), so every fidelity reads it; the fidelities differ in the map's
resolution. The markers are the points of the stored ensembles (data/*.nc: the
science sweeps and the figures' sweeps) on the table's grid, scheme and flow at the
same noise, filled with their own P: where they sit on their background colour, the
model and the ensembles agree.

Run: ``python gallery/fig9_predicted.py [--quick | --tiny]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pde_rotor.cli.predict import table_footer
from pde_rotor.config import CALIBRATED_SIGMA
from pde_rotor.decision.map import draw_map, ensemble_points
from pde_rotor.decision.table import diffusion_of, load_table
from pde_rotor.gallery.common import DATA, parse_args
from pde_rotor.paper import PLATEAU, PLATEAU_ASYMMETRY, PLATEAU_STOP
from pde_rotor.sweep.stored import load_report

NAME = "fig9_predicted"
TABLE = DATA / "decision" / "dx40.nc"
RESOLUTION = {"full": 200, "quick": 100, "tiny": 12}
"""Map points along t_stop (half as many along Delta)."""


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw the predicted Fig. 9 as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    if not TABLE.is_file():
        msg = f"{TABLE}: no decision table (pde-rotor predict measure paper ... -o {TABLE})"
        raise FileNotFoundError(msg)
    table = load_table(TABLE)
    target, t_stop, asymmetry = PLATEAU, PLATEAU_STOP, PLATEAU_ASYMMETRY
    own = table.calibrate(target, t_stop, asymmetry, (1e-9, 1e2))
    sigma = CALIBRATED_SIGMA
    diffusion = diffusion_of(sigma, table.inertia)
    reports = [load_report(path) for path in sorted(DATA.glob("*.nc"))]
    points = ensemble_points(table, reports, sigma)
    n = RESOLUTION[args.fidelity.name]
    footer = (
        f"{table_footer(table, TABLE)}; the calibrated noise \u03c3 = {sigma:.3g}, "
        f"Dw = {diffusion:.3g} (the table's own P({t_stop:g}, {asymmetry:g}) = {target:g} "
        f"at Dw = {own:.3g}); "
        f"{len(points)} ensemble points from data/*.nc; {n} x {n // 2} map points"
    )
    paths, _ = draw_map(
        table, diffusion, args.out, NAME, resolution=(n, n // 2), points=points, footer=footer
    )
    for d in (0.0, 2e-5, 5e-5, 1e-4):
        print(f"{NAME}: Delta = {d:g}: critical stop t_c = {table.critical_stop(d, diffusion):.3f}")
    return paths


if __name__ == "__main__":
    main()
