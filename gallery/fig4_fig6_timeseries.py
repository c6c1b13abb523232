"""Paper Figs. 4 and 6: phi(t) and omega(t), t_stop = 0.5 and 2, for Delta = 0 and 1e-4.

Runs configs/paper_fig4a.yaml, paper_fig4b.yaml (the symmetric rotor, Fig. 4) and
paper_fig6a.yaml, paper_fig6b.yaml (the asymmetric rotor, Delta = 1e-4, Fig. 6) through
:func:`pde_rotor.api.run` (full fidelity: as written, M = 100 cycles at the paper's
resolution; quick/tiny: coarse grid and a few cycles) and plots (1) the angle phi(t)
and (2) the angular velocity dphi/dt of Eq. (eq_motion), stop phases shaded. The paper:
for Delta = 0 the direction is inverted after every stop for t_stop = 0.5 and random
for t_stop = 2; for Delta = 1e-4 perfect inversion for t_stop = 0.5 and none for
t_stop = 2, where the rotor always turns in its preferred direction (clockwise for
Delta > 0).

Run: ``python gallery/fig4_fig6_timeseries.py [--quick | --tiny] [--cycles M] [--runs DIR]``
(``--runs``: read the four runs from run directories, :mod:`pde_rotor.gallery.timeseries`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pde_rotor.gallery.common import CONFIGS
from pde_rotor.gallery.timeseries import TimeseriesFigure, timeseries_main

FIGURES = (
    TimeseriesFigure(
        "fig4_timeseries",
        "Fig. 4: symmetric rotor (\u0394 = 0), (a) t_stop = 0.5, (b) t_stop = 2",
        (("a", CONFIGS / "paper_fig4a.yaml"), ("b", CONFIGS / "paper_fig4b.yaml")),
    ),
    TimeseriesFigure(
        "fig6_timeseries",
        "Fig. 6: asymmetric rotor (\u0394 = 1e-4), (a) t_stop = 0.5, (b) t_stop = 2",
        (("a", CONFIGS / "paper_fig6a.yaml"), ("b", CONFIGS / "paper_fig6b.yaml")),
    ),
)


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run the four configs and write Figs. 4 and 6 as PNG and PDF."""
    return timeseries_main(FIGURES, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    main()
