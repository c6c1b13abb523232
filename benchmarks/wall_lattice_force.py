"""The lattice force on a held camphor disk near a straight wall of a rectangular tank.

As :mod:`benchmarks.lattice_force` does at the dish's centre: a free camphor disk (a pill
without plate, rho = 0.1, flow on) is held (a stop of its own protocol) at `--offsets` x
`--offsets` positions over one cell, c and v relax for `--relax` time units, and the
tension force is read. Here the disk sits `--distance` from the wall x = a of the tank
|x|, |y| < a (``grid.vessel: rectangle``, walls on cell faces), on the tank's mirror line
y = 0, and the wall pushes or pulls it: a force smooth in the position, f_wall(x, y) =
(p(x), Psi(x) y) to first order in y, as large as the whole lattice force over a cell. The
lattice force vanishes by symmetry where the disk's centre lies on a cell corner, so
holds at the corners x0 - dx, x0, x0 + dx (x0 = a - distance) fit p as a parabola and a
hold at (x0, dx) gives Psi; the lattice force is f - f_wall. Printed per wall (`--wall`)
and distance: p(x0) (the wall's force, > 0 towards the wall), the rms and largest |f| as
measured and the rms and largest lattice force |f - f_wall| over the positions.

Run:  python benchmarks/wall_lattice_force.py [--wall no_flux absorbing] [--distance 0.75]
      [--half 1.5] [--scheme consistent] [--dx 0.05] [--dt 4e-4] [--offsets 3] [--relax 3]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation

DISK = {"name": "disk", "pills": [{"x": 0.0, "y": 0.0}]}
"""The free camphor disk of benchmarks/lattice_force.py: one paper pill, no plate."""


def held_force(args: argparse.Namespace, wall: str, x: float, y: float) -> np.ndarray:
    """Tension force (x, y) on the disk held at (x, y) in the tank after `relax`."""
    relax = args.relax
    config = RotorConfig.model_validate(
        {
            "grid": {
                "domain_radius": args.half,
                "dx": args.dx,
                "dt": args.dt,
                "vessel": {"shape": "rectangle", "half_widths": [args.half] * 2, "wall": wall},
            },
            "numerics": {"scheme": args.scheme},
            "protocol": {"t_ini": relax, "cycles": 0},
            "bodies": [
                {
                    **DISK,
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
    parser.add_argument("--wall", nargs="+", default=["no_flux", "absorbing"])
    parser.add_argument("--distance", nargs="+", type=float, default=[0.75])
    parser.add_argument("--half", type=float, default=1.5)
    parser.add_argument("--scheme", default="consistent")
    parser.add_argument("--dx", type=float, default=0.05)
    parser.add_argument("--dt", type=float, default=4e-4)
    parser.add_argument("--offsets", type=int, default=3)
    parser.add_argument("--relax", type=float, default=3.0)
    args = parser.parse_args()
    dx = args.dx
    for wall in args.wall:
        for distance in args.distance:
            x0 = args.half - distance
            back, here, ahead = (held_force(args, wall, x0 + m * dx, 0.0)[0] for m in (-1, 0, 1))
            slope, curve = (ahead - back) / (2 * dx), (ahead - 2 * here + back) / (2 * dx**2)
            psi = held_force(args, wall, x0, dx)[1] / dx
            positions, forces = [], []
            for i in range(args.offsets):
                for j in range(args.offsets):
                    sx, sy = (i / args.offsets) * dx, (j / args.offsets) * dx
                    positions.append((sx, sy))
                    forces.append(held_force(args, wall, x0 + sx, sy))
            at = np.array(positions)
            smooth = np.stack([here + slope * at[:, 0] + curve * at[:, 0] ** 2, psi * at[:, 1]])
            measured = np.hypot(*np.array(forces).T)
            lattice = np.hypot(*(np.array(forces) - smooth.T).T)
            print(
                f"{wall} wall, disk held {distance:g} from it ({len(forces)} positions over a "
                f"cell, dx = {dx:g}, {args.scheme} scheme, flow on, after {args.relax:g}): the "
                f"wall's force {here:.4g} (towards it), d/dx {slope:.3g}, Psi = {psi:.3g}; force "
                f"as measured rms {math.sqrt(np.mean(measured**2)):.3g}, largest "
                f"{measured.max():.3g}; lattice force (less the wall's) rms "
                f"{math.sqrt(np.mean(lattice**2)):.3g}, largest {lattice.max():.3g}"
            )


if __name__ == "__main__":
    main()
