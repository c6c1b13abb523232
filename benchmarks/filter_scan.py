"""The consistent scheme's prefilters against the goals of docs/model.md, one row each.

For each choice of the prefilters of F (plate) and G (pills) (``numerics.plate_filter_*``,
``numerics.pill_filter_*``), the numbers the choice of the default rests on:

* omega(8): the paper's spin-up (omega0 = 0.1, no noise) at its dx = delta = 0.025,
  dt = 1e-4, Eq. (eq_motion); goal: within 1 % of the converged value (the convergence
  table, benchmarks/convergence.py);
* the lattice torque of a stopped symmetric plate over `--angles` angles per pi/6 at
  dx = delta = 0.05 (goal rms <= 1e-6) and at dx = delta = 0.025 (goals rms <= 1e-7,
  max <= 2e-7), sparse steady solves (:func:`pde_rotor.model.analysis.stopped_torque`);
* the asymmetry torque T(Delta = 2e-5) - T(0) at fixed delta = 0.025 on dx = 1/30, 1/40,
  1/60 (12 angles) and its spread (max - min) / |mean| (goal <= 2 %).

Run:  python benchmarks/filter_scan.py [--pill sharpened:0.95 gaussian:0.7 ...]
                                       [--plate gaussian:0.7] [--angles 48]
About 3 minutes per row on one core.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from pde_rotor import RotorConfig, Simulation
from pde_rotor.model.analysis import stopped_torque

SPREAD_GRIDS = (30, 40, 60)
ASYMMETRY = 2e-5


def config(plate: str, pill: str, dx: float, dt: float, **geometry: float) -> RotorConfig:
    """The paper's rotor, no noise, no stops, with prefilters 'kernel:kappa'."""
    numerics: dict[str, Any] = {"scheme": "consistent"}
    for part, choice in (("plate", plate), ("pill", pill)):
        kernel, kappa = choice.split(":")
        numerics[f"{part}_filter_kernel"] = kernel
        numerics[f"{part}_filter_width"] = float(kappa)
    return RotorConfig.model_validate(
        {
            "grid": {"dx": dx, "dt": dt},
            "geometry": geometry,
            "numerics": numerics,
            "protocol": {"cycles": 0},
            "output": {"progress": False},
        }
    )


def row(plate: str, pill: str, angles: int) -> str:
    """One markdown row of the scan."""
    sim = Simulation(config(plate, pill, 0.025, 1e-4, smoothing=0.025))
    sim.run(8.0)
    cells = [plate, pill, f"{sim.rotor.omega:.2f}"]
    phis = np.arange(angles) * (math.pi / 6) / angles
    for dx in (0.05, 0.025):
        torque = stopped_torque(config(plate, pill, dx, 1e-5, smoothing=dx), phis)
        cells += [f"{np.sqrt(np.mean(torque**2)):.3g}", f"{np.abs(torque).max():.3g}"]
    few = np.arange(12) * (math.pi / 6) / 12
    asym = []
    for inv_dx in SPREAD_GRIDS:
        base = stopped_torque(config(plate, pill, 1 / inv_dx, 1e-5, smoothing=0.025), few)
        shifted = config(plate, pill, 1 / inv_dx, 1e-5, smoothing=0.025, asymmetry=ASYMMETRY)
        asym.append(float((stopped_torque(shifted, few) - base).mean()))
    spread = (max(asym) - min(asym)) / abs(float(np.mean(asym)))
    cells += [" / ".join(f"{a * 1e7:.3f}" for a in asym), f"{100 * spread:.2f} %"]
    return "| " + " | ".join(cells) + " |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plate", default="gaussian:0.7", help="kernel:kappa of F")
    parser.add_argument(
        "--pill",
        nargs="+",
        default=["gaussian:0.7", "sharpened:0.9", "sharpened:0.95", "sharpened:1.0"],
        help="kernel:kappa of G, one row each",
    )
    parser.add_argument("--angles", type=int, default=48, help="angles per pi/6, lattice torque")
    args = parser.parse_args()
    print(
        "| plate | pills | ω(8) | rms, dx = 0.05 | max, dx = 0.05 | rms, dx = 0.025 "
        "| max, dx = 0.025 | T(Δ = 2e-5) - T(0) [1e-7] at 1/dx = 30 / 40 / 60 | spread |"
    )
    print("|---" * 9 + "|", flush=True)
    for pill in args.pill:
        print(row(args.plate, pill, args.angles), flush=True)


if __name__ == "__main__":
    main()
