"""Track bodies and contact: the numbers behind their tests, printed.

CPU: the terminal arc speed of a camphor-free track disk under a tangential force against
d f_t / (mu A) (A = int F dA, both directions, Euler and Heun) and its distance from its
circle; two disks pushed together on one track with contact on: the footprints' gap at rest
and the force balance kappa (ell - g) cos(dtheta / 2) = f_t. With ``--gpu`` (set
NUMBA_ENABLE_CUDASIM=1 on a machine without a GPU) also the largest difference of poses and
fields between the GPU's and the CPU's run of two track boats, without and with contact.
The configurations are the tests' (tests/solver/test_track.py, tests/solver/test_contact.py,
tests/backends/test_gpu_bodies.py).

Run:  PYTHONPATH=. python benchmarks/track_checks.py [--gpu]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from pde_rotor.solver.simulation import Simulation
from tests.solver.test_contact import pushed_rest
from tests.solver.test_track import track_config


def terminal_speed() -> None:
    """w / (d f_t / (mu A)) - 1 and | |X| - R | after 25 relaxation times."""
    mu, force, radius = 1.0, 0.02, 1.5
    for integrator in ("euler", "heun"):
        bodies = [
            {
                "name": name,
                "plate": {"shape": "disk", "radius": 0.3},
                "motion": {"kind": "track", "mass": 2e-3, "friction": mu, "direction": way,
                           "force": force},
                "start": {"x": radius * math.cos(angle), "y": radius * math.sin(angle)},
            }
            for name, way, angle in (("ccw", "counterclockwise", 0.3), ("cw", "clockwise", 3.5))
        ]  # fmt: skip
        numerics = {"scheme": "paper", "integrator": integrator}
        sim = Simulation(track_config(bodies, flow={"enabled": False}, numerics=numerics))
        sim.run(0.2)
        for k, sign in enumerate((1.0, -1.0)):
            area = float(np.sum(sim.pde.F[sim.pde.owner == k]) * sim.pde.domain.cell_area)
            pose = sim.bodies.poses[k]
            theta = math.atan2(pose[1], pose[0])
            speed = -pose[3] * math.sin(theta) + pose[4] * math.cos(theta)
            error = speed / (sign * force / (mu * area)) - 1
            off = abs(math.hypot(pose[0], pose[1]) - radius)
            print(f"{integrator} {bodies[k]['name']}: w / (d f_t / (mu A)) - 1 = {error:.2e}, "
                  f"| |X| - R | = {off:.1e}")  # fmt: skip


def contact_balance() -> None:
    """The gap and the force balance of two disks pushed together at rest."""
    force = 0.1
    gap, along, speed = pushed_rest(force)
    print(f"contact: gap {gap:.5f}, kappa (ell - g) cos(dtheta / 2) / f_t - 1 = "
          f"{along / force - 1:.2e}, largest |w| {speed:.1e}")  # fmt: skip


def gpu_agreement() -> None:
    """GPU against CPU, two track boats, 3 steps, without and with contact."""
    from tests.backends import test_gpu_bodies as gpu_tests

    half = math.asin(3.3 / 2 / 2.25)
    close = [
        {**gpu_tests.TRACK_BOATS[0], "start": {"x": 2.25, "y": 0.0}},
        {**gpu_tests.TRACK_BOATS[1],
         "start": {"x": 2.25 * math.cos(2 * half), "y": 2.25 * math.sin(2 * half)}},
    ]  # fmt: skip
    cases = (
        ("track", gpu_tests.TRACK_BOATS, {}),
        ("contact", close, {"contact": {"enabled": True, "stiffness": 100.0, "range": 0.2}}),
    )
    for integrator in ("euler", "heun"):
        for name, boats, extra in cases:
            grid = {"domain_radius": 4.0, "vessel": gpu_tests.VESSEL}
            numerics = {"scheme": "paper", "integrator": integrator}
            cpu, gpu = gpu_tests.pair(
                gpu_tests.config(boats, grid=grid, numerics=numerics, **extra)
            )
            cpu.run(0.003)
            gpu.run(0.003)
            poses = np.abs(gpu.bodies.poses - cpu.bodies.poses).max()
            fields = np.abs(gpu.state.data - cpu.state.data).max() / np.abs(cpu.state.data).max()
            print(f"gpu {name} {integrator}: poses {poses:.2g}, fields {fields:.2g} relative")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gpu", action="store_true", help="also the GPU against the CPU")
    args = parser.parse_args()
    terminal_speed()
    contact_balance()
    if args.gpu:
        gpu_agreement()


if __name__ == "__main__":
    main()
