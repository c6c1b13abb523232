"""Paper Fig. 6: phi(t) and omega(t) of the asymmetric rotor (Delta = 1e-4), t_stop = 0.5 and 2.

Runs configs/paper_fig6a.yaml (t_stop = 0.5) and configs/paper_fig6b.yaml (t_stop = 2)
through :func:`pde_rotor.api.run` (full fidelity: as written, M = 100 cycles at the
paper's resolution; quick/tiny: coarse grid and a few cycles) and plots (1) the angle
phi(t) and (2) the angular velocity dphi/dt of Eq. (eq_motion), stop phases shaded. The
paper: perfect inversion for t_stop = 0.5; for t_stop = 2 no inversion, the rotor always
turns in its preferred direction (clockwise for Delta > 0).

Run: ``python gallery/fig6_timeseries.py [--quick | --tiny] [--cycles M] [--runs DIR]``
(``--runs``: read the two runs from run directories, :mod:`_timeseries`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from _common import CONFIGS
from _timeseries import timeseries_main

NAME = "fig6_timeseries"
PANELS = (("a", CONFIGS / "paper_fig6a.yaml"), ("b", CONFIGS / "paper_fig6b.yaml"))
TITLE = "Fig. 6: asymmetric rotor (\u0394 = 1e-4), (a) t_stop = 0.5, (b) t_stop = 2"


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run both configs and write Fig. 6 as PNG and PDF."""
    return timeseries_main(NAME, TITLE, PANELS, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    main()
