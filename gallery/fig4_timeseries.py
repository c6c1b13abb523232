"""Paper Fig. 4: phi(t) and omega(t) of the symmetric rotor (Delta = 0), t_stop = 0.5 and 2.

Runs configs/paper_fig4a.yaml (t_stop = 0.5) and configs/paper_fig4b.yaml (t_stop = 2)
through :func:`pde_rotor.api.run` (full fidelity: as written, M = 100 cycles at the
paper's resolution; quick/tiny: coarse grid and a few cycles) and plots (1) the angle
phi(t) and (2) the angular velocity dphi/dt of Eq. (eq_motion), stop phases shaded. The
paper: the direction is inverted after every stop for t_stop = 0.5 and random for
t_stop = 2.

Run: ``python gallery/fig4_timeseries.py [--quick | --tiny] [--cycles M] [--runs DIR]``
(``--runs``: read the two runs from run directories, :mod:`_timeseries`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from _common import CONFIGS
from _timeseries import timeseries_main

NAME = "fig4_timeseries"
PANELS = (("a", CONFIGS / "paper_fig4a.yaml"), ("b", CONFIGS / "paper_fig4b.yaml"))
TITLE = "Fig. 4: symmetric rotor (\u0394 = 0), (a) t_stop = 0.5, (b) t_stop = 2"


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run both configs and write Fig. 4 as PNG and PDF."""
    return timeseries_main(NAME, TITLE, PANELS, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    main()
