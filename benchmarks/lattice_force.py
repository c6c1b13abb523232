"""The lattice force on a held, symmetric body: rms over sub-cell positions, per scheme.

A symmetric body at rest at the dish centre feels no force in the continuum; on the grid,
its sampled F and G and the force integral depend on where its centre sits within a
cell, and a spurious force remains. The ``paper`` scheme samples F and G at the cell
centres and takes the area-form force with central differences; ``consistent``
prefilters them and takes the force in contour form (docs/bodies.md, "The
rotation-consistent scheme"). The body is
held (a stop of its own protocol) at `--offsets` x `--offsets` positions spread over one
cell, c and v relax for `--relax` time units, and the tension force is read.

A body off the dish centre also feels the dish's absorbing edge, which pulls it
outwards (docs/bodies.md, "A disk in a circular dish": Phi(0) = 3.5e-4 per unit
displacement at L = 2), a force as large as the lattice force over a cell. It is smooth
in the displacement X and, for small X, f_wall = (Phi + Phi3 |X|^2) X; the lattice
force is periodic in X with period dx and vanishes by symmetry where X lies on a cell
corner (the dish centre is one). So two more runs, held at (dx, 0) and (2 dx, 0), give
Phi and Phi3 of each scheme, and the lattice force is f - f_wall. Printed per scheme:
Phi, the rms and largest |f| as measured, and the rms and largest lattice force
|f - f_wall| over the positions. Beside them, two reference
forces: the force on the kicked disk of gallery/bodies_onsets.py, K(0) U at its kick
U = 1e-4 (the linear response of docs/bodies.md, the smallest asymmetry of a body the
gallery resolves), and the force on a camphor boat (the same pill 0.05 off the centre of
a strip plate, held at the cell's corner, on each scheme).

Run:  python benchmarks/lattice_force.py [--scheme paper consistent] [--dx 0.025]
      [--offsets 4] [--relax 4]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation
from pde_rotor.theory import (
    CamphorDisk,
    Wall,
    free_disk_displacement_force,
    free_disk_force_coefficient,
)

GALLERY_KICK = 1e-4
"""The velocity gallery/bodies_onsets.py kicks the free disk to."""


def held_force(
    dx: float, dt: float, scheme: str, body: dict, x: float, y: float, relax: float
) -> np.ndarray:
    """Tension force (x, y) on `body` held at (x, y) after `relax` time units."""
    config = RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 2.0, "dx": dx, "dt": dt},
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": relax, "cycles": 0},
            "bodies": [
                {
                    **body,
                    "motion": {"kind": "free", "mass": 1e-3, "friction": 1e-4},
                    "start": {"x": x, "y": y},
                    "protocol": {"t_ini": 0.0, "t_stop": relax, "t_release": 1.0, "cycles": 1},
                }
            ],
        }
    )
    sim = Simulation(config)
    sim.run(relax)
    return sim.bodies.poses[0, 6:8].copy()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scheme", nargs="+", default=["paper", "consistent"])
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--offsets", type=int, default=4)
    parser.add_argument("--relax", type=float, default=4.0)
    args = parser.parse_args()
    disk = {"name": "disk", "pills": [{"x": 0.0, "y": 0.0}]}
    dx = args.dx
    for scheme in args.scheme:
        one, two = (
            held_force(dx, args.dt, scheme, disk, m * dx, 0.0, args.relax)[0] for m in (1, 2)
        )
        phi = (8.0 * one - two) / (6.0 * dx)
        phi3 = (two - 2.0 * one) / (6.0 * dx**3)
        positions, forces = [], []
        for i in range(args.offsets):
            for j in range(args.offsets):
                x, y = (i / args.offsets) * dx, (j / args.offsets) * dx
                positions.append((x, y))
                forces.append(held_force(dx, args.dt, scheme, disk, x, y, args.relax))
        at = np.array(positions)
        wall = (phi + phi3 * np.sum(at**2, axis=1))[:, None] * at
        measured = np.hypot(*np.array(forces).T)
        lattice = np.hypot(*(np.array(forces) - wall).T)
        print(
            f"free camphor disk (rho = 0.1) held at {len(forces)} positions over a cell, dx = "
            f"{dx:g}, {scheme} scheme, flow on, after {args.relax:g}: the dish's pull Phi = "
            f"{phi:.4g} (Phi3 = {phi3:.3g}); force as measured rms "
            f"{math.sqrt(np.mean(measured**2)):.3g}, largest {measured.max():.3g}; lattice "
            f"force (less the dish's pull) rms {math.sqrt(np.mean(lattice**2)):.3g}, largest "
            f"{lattice.max():.3g}"
        )
    camphor = CamphorDisk.from_config(RotorConfig())
    pull = free_disk_displacement_force(camphor, 0.0, Wall(2.0, "absorbing"))
    print(f"the dish's pull of linear stability (sharp disk, L = 2): Phi(0) = {pull:.4g}")
    coefficient = free_disk_force_coefficient(camphor)
    print(
        f"kicked free disk of gallery/bodies_onsets.py: K(0) U = {coefficient:.4g} x "
        f"{GALLERY_KICK:g} = {coefficient * GALLERY_KICK:.3g}"
    )
    boat = {
        "name": "boat",
        "plate": {"shape": "strip", "length": 0.6, "width": 0.3},
        "pills": [{"x": 0.05, "y": 0.0}],
    }
    for scheme in args.scheme:
        boat_force = held_force(args.dx, args.dt, scheme, boat, 0.0, 0.0, args.relax)
        print(
            f"camphor boat (pill 0.05 off the centre of a 0.6 x 0.3 strip, {scheme} scheme) "
            f"held: force ({boat_force[0]:.3g}, {boat_force[1]:.3g}), "
            f"|f| = {math.hypot(*boat_force):.3g}"
        )


if __name__ == "__main__":
    main()
