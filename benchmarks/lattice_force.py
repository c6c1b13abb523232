"""The lattice force on a held, symmetric body: rms over sub-cell positions (paper scheme).

A symmetric body at rest feels no force in the continuum; on the grid, its point-sampled
F and G and the area-form force integral (the ``paper`` scheme, the only one bodies run on)
depend on where its centre sits within a cell, and a spurious force remains. The body is
held (a stop of its own protocol) at `--offsets` x `--offsets` positions spread over one
cell, c and v relax for `--relax` time units, and the tension force s k int F grad c dA is
read. Printed: the rms and the largest |force| over the positions, beside the force on a
camphor boat (the same pill 0.05 off the centre of a strip plate, held at the cell's
corner): the smallest asymmetry force this page compares with.

Run:  python benchmarks/lattice_force.py [--dx 0.025] [--offsets 4] [--relax 4]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation


def held_force(dx: float, dt: float, body: dict, x: float, y: float, relax: float) -> np.ndarray:
    """Tension force (x, y) on `body` held at (x, y) after `relax` time units."""
    config = RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 2.0, "dx": dx, "dt": dt},
            "numerics": {"scheme": "paper"},
            "protocol": {"t_ini": relax, "cycles": 0},
            "bodies": [
                {
                    **body,
                    "motion": {"kind": "free", "mass": 1e-3},
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
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--offsets", type=int, default=4)
    parser.add_argument("--relax", type=float, default=4.0)
    args = parser.parse_args()
    disk = {"name": "disk", "pills": [{"x": 0.0, "y": 0.0}]}
    forces = []
    for i in range(args.offsets):
        for j in range(args.offsets):
            x, y = (i / args.offsets) * args.dx, (j / args.offsets) * args.dx
            forces.append(held_force(args.dx, args.dt, disk, x, y, args.relax))
    magnitude = np.hypot(*np.array(forces).T)
    boat = {
        "name": "boat",
        "plate": {"shape": "strip", "length": 0.6, "width": 0.3},
        "pills": [{"x": 0.05, "y": 0.0}],
    }
    boat_force = held_force(args.dx, args.dt, boat, 0.0, 0.0, args.relax)
    print(
        f"free camphor disk (rho = 0.1) held at {len(forces)} positions over a cell, dx = "
        f"{args.dx:g}, paper scheme, flow on, after {args.relax:g}: lattice force rms "
        f"{math.sqrt(np.mean(magnitude**2)):.3g}, largest {magnitude.max():.3g}"
    )
    print(
        f"camphor boat (pill 0.05 off the centre of a 0.6 x 0.3 strip) held: force "
        f"({boat_force[0]:.3g}, {boat_force[1]:.3g}), |f| = {math.hypot(*boat_force):.3g}"
    )


if __name__ == "__main__":
    main()
