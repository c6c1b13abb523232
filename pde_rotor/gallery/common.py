"""Shared helpers of the gallery scripts: fidelities, configs, sweeps, saving and captions.

Every gallery script reproduces one figure of Koyano, Kitahata, Nakata & Gorecki, Chaos 30
(2020) (or adds a page the paper does not have) at one of three fidelities:

* ``full`` (default): the paper's resolution from configs/ (dx = delta = 0.025,
  dt = 1e-4, domain radius 3) and the paper's protocol (t_ini = t_release = 10, M = 100);
* ``quick`` (``--quick``): the coarse grid of configs/quickstart.yaml (dx = delta = 0.05,
  dt = 4e-4) and short protocols, so that all figures together run in minutes;
* ``tiny`` (``--tiny``): the coarse grid on a small domain (radius 1.75) with very short
  times, only to prove in CI that a script runs end to end; its images mean nothing.

Figures are written as PNG and PDF to gallery/output/ (or ``--out``); every figure carries
a footer that states the fidelity it was computed at (dx, dt, delta, samples, backend).
The sweeps and probability curves of Figs. 5, 7, 8 and 9 are read and drawn by
:mod:`.sweeps`.
"""

from __future__ import annotations

import argparse
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from pde_rotor.config import RotorConfig, load_config, read_config_data
from pde_rotor.plotting.figures import (
    FOOTER_FONTSIZE,
    add_footer,
    count_range,
    grid_label,
    new_figure,
    wilson_text,
)
from pde_rotor.plotting.figures import save_figure as save

__all__ = [
    "FOOTER_FONTSIZE",
    "add_footer",
    "count_range",
    "fidelity_label",
    "grid_label",
    "new_figure",
    "parse_args",
    "save",
    "wilson_text",
]

GALLERY = Path(__file__).resolve().parents[2] / "gallery"
"""The gallery directory (scripts, committed PNGs, README)."""
ROOT = GALLERY.parent
"""Repository root."""
CONFIGS = ROOT / "configs"
"""Run configurations read by the scripts."""
SWEEPS = CONFIGS / "sweeps"
"""Sweep specifications of the probability figures (``pde-rotor sweep``)."""
DATA = ROOT / "data"
"""Stored sweep reports (NetCDF written by :func:`pde_rotor.sweep.report`)."""
SWEEP_RUNS = ROOT / "data" / "sweeps"
"""Where sweeps run by the gallery keep their results (the CLI's default: resumable, and
committed results travel with the repository)."""
OUTPUT = GALLERY / "output"
"""Default output directory (gitignored)."""
SCHEDULER: str | None = None
"""Dask scheduler address for the sweeps (``--scheduler``); None: a LocalCluster per sweep."""

PAPER_CONFIG = CONFIGS / "paper_fig4a.yaml"
"""Paper-resolution config of the symmetric rotor (Delta = 0): base of Fig. 3 and the movie."""
QUICK_CONFIG = CONFIGS / "quickstart.yaml"
"""Source of the coarse grid used by the quick and tiny fidelities."""

QUICK_SWEEP_SAMPLES = 10
"""Restarts per direction and point of the sweeps the quick gallery runs itself (20 stops
per point): all six probability sweeps then take about 10 minutes on 2 cores."""
TINY_DOMAIN_RADIUS = 1.75
"""Domain radius of the tiny fidelity: the support of F and G (radius 1.655 at delta = 0.05)
stays inside the disk (the config rejects smaller domains)."""

_logger = logging.getLogger("gallery")


@dataclass(frozen=True)
class Fidelity:
    """How a gallery figure is computed.

    Attributes:
        name: "full", "quick" or "tiny".
        grid: ``key.path=value`` overrides of grid and smoothing (empty: the config's own).
        protocol: overrides of the stop-and-release protocol for the time-series figures
            (Figs. 4 and 6; empty: the config's own, the paper's t_ini = t_release = 10 and
            M = 100).
        spinup: time of free rotation before a steady state is used (Fig. 3, movie).
        sweep_variant: which variant of a figure's sweep to run when no stored report
            exists ("" for the full sweep file, "_quick" for the quick one).
        sweep_samples: at most this many restarts per direction and point when the
            gallery runs a sweep itself (None: the sweep file's ``samples``). The runs are
            the first ones of the sweep file's (same seeds, same stored runs), so a later
            ``pde-rotor sweep`` of the file into the same directory reuses them.
    """

    name: str
    grid: tuple[str, ...] = ()
    protocol: tuple[str, ...] = ()
    spinup: float = 10.0
    sweep_variant: str = ""
    sweep_samples: int | None = None

    @property
    def is_tiny(self) -> bool:
        """Whether this is the CI smoke-test size."""
        return self.name == "tiny"

    def config(self, path: str | Path = PAPER_CONFIG, *overrides: str) -> RotorConfig:
        """Load a config from configs/ with this fidelity's grid and the given overrides.

        Output trackers that write files (movie, snapshots) and the progress bar are off:
        the gallery runs in memory.
        """
        return load_config(
            path,
            [
                *self.grid,
                *overrides,
                "output.progress=false",
                "output.movie=false",
                "output.snapshot_interval=null",
            ],
        )


def _quick_grid() -> tuple[str, ...]:
    """The coarse grid of configs/quickstart.yaml as overrides (one home for the numbers)."""
    data = read_config_data(QUICK_CONFIG)
    grid, geometry = data.get("grid", {}), data.get("geometry", {})
    return (
        f"grid.dx={grid['dx']!r}",
        f"grid.dt={grid['dt']!r}",
        f"geometry.smoothing={geometry['smoothing']!r}",
    )


def fidelity(name: str) -> Fidelity:
    """The :class:`Fidelity` called `name` ("full", "quick" or "tiny")."""
    if name == "full":
        return Fidelity("full")
    quick = _quick_grid()
    if name == "quick":
        return Fidelity(
            "quick",
            grid=quick,
            protocol=("protocol.t_ini=6.0", "protocol.t_release=6.0", "protocol.cycles=6"),
            spinup=8.0,
            sweep_variant="_quick",
            sweep_samples=QUICK_SWEEP_SAMPLES,
        )
    if name == "tiny":
        return Fidelity(
            "tiny",
            grid=(*quick, f"grid.domain_radius={TINY_DOMAIN_RADIUS}"),
            protocol=("protocol.t_ini=1.0", "protocol.t_release=1.0", "protocol.cycles=2"),
            spinup=1.0,
            sweep_variant="_quick",
        )
    msg = f"unknown fidelity {name!r} (allowed: full, quick, tiny)"
    raise ValueError(msg)


def parse_args(
    description: str,
    argv: Sequence[str] | None = None,
    extra: Callable[[argparse.ArgumentParser], None] | None = None,
) -> argparse.Namespace:
    """Command line shared by the scripts: ``[--quick | --tiny] [--out DIR]``.

    The namespace gets ``fidelity`` (a :class:`Fidelity`) and ``out`` (a Path, created).
    """
    parser = argparse.ArgumentParser(description=description)
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument(
        "--quick", action="store_true", help="coarse grid, short protocol, few samples"
    )
    mode.add_argument(
        "--tiny", action="store_true", help="smoke-test size (CI): tiny domain, seconds"
    )
    parser.add_argument(
        "--out", type=Path, default=OUTPUT, help=f"output directory [default: {OUTPUT}]"
    )
    parser.add_argument(
        "--scheduler",
        default=None,
        help="address of a running dask scheduler for the sweeps [default: a LocalCluster]",
    )
    if extra is not None:
        extra(parser)
    args = parser.parse_args(argv)
    args.fidelity = fidelity("tiny" if args.tiny else "quick" if args.quick else "full")
    global SCHEDULER
    SCHEDULER = args.scheduler
    args.out.mkdir(parents=True, exist_ok=True)
    logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")
    for name in ("pde", "distributed"):  # py-pde's per-run and dask's cluster INFO lines
        logging.getLogger(name).setLevel(logging.WARNING)
    return args


# ---------------------------------------------------------------------------------------
# captions and saving
# ---------------------------------------------------------------------------------------


CPU_BACKEND = "cpu (numba fused kernel)"
"""Backend label of everything the gallery computes (single runs and sweeps run on CPU)."""


def fidelity_label(
    fid: Fidelity, config: RotorConfig | None, detail: str = "", backend: str | None = CPU_BACKEND
) -> str:
    """Footer text: fidelity, grid, noise, backend and any detail (samples, M)."""
    parts = [f"pde_rotor, {fid.name} fidelity"]
    if config is not None:
        parts.append(grid_label(config))
        parts.append(f"scheme {config.numerics.scheme}, \u03c3 = {config.noise.sigma:g}")
    if detail:
        parts.append(detail)
    if backend:
        parts.append(f"backend {backend}")
    return "; ".join(parts)
