"""Dynamic probe of the lattice torque: end-of-stop torques of one rotor stopped at 15 angles.

The probe of docs/model.md ("Schemes"): the paper's rotor and grid (dx = delta = 0.025,
dt = 1e-4) with Delta = 2e-5 and no noise spins up from omega0 = 100 to t = 6 and is then
stopped for t_stop = 3 at t_ini = 6 + 2e-4 k, k = 0..14 (stop angles spread over about one
period pi/6 of the lattice torque at omega ~ 176). At the end of each stop the memory
of the flow has decayed, and the torque T, Eq. (torque), is what decides the direction
of the release: in the continuum it is the asymmetry torque alone, the same at every
angle. The probe prints every end-of-stop torque, how many carry the asymmetry torque's
sign (that of T(Delta) - T(0) of the stopped plate, benchmarks/lattice_torque.py) and
their spread std / |mean| (goal: all 15 with that sign, spread <= 0.3).

Run:  python benchmarks/dynamic_probe.py [--schemes consistent paper] [--angles 15]
Cost: about 5.1e5 steps per scheme (a spin-up and 15 stops of 3e4 steps).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pde_rotor import RotorConfig, Simulation
from pde_rotor.model.analysis import stopped_torque

ASYMMETRY = 2e-5
T_SPIN = 6.0
T_STOP = 3.0
SPACING = 2e-4


def probe(scheme: str, n_angles: int) -> tuple[np.ndarray, float]:
    """End-of-stop torques at the n_angles stop times, and the static asymmetry torque."""
    base = {
        "geometry": {"asymmetry": ASYMMETRY},
        "rotor": {"omega0": 100.0},
        "numerics": {"scheme": scheme},
        "output": {"progress": False},
    }
    spin = Simulation(RotorConfig.model_validate({**base, "protocol": {"cycles": 0}}))
    spin.run(T_SPIN)
    torques = np.empty(n_angles)
    for k in range(n_angles):
        protocol = {"t_ini": T_SPIN + SPACING * k, "t_stop": T_STOP, "cycles": 1}
        sim = spin.branch(RotorConfig.model_validate({**base, "protocol": protocol}))
        sim.run(protocol["t_ini"] + T_STOP)
        torques[k] = sim.rotor.torque
    phis = np.arange(12) * (np.pi / 6) / 12
    symmetric = {**base, "geometry": {"asymmetry": 0.0}}
    static = stopped_torque(RotorConfig.model_validate(base), phis) - stopped_torque(
        RotorConfig.model_validate(symmetric), phis
    )
    return torques, float(static.mean())


def main() -> None:
    """Print the end-of-stop torques per scheme and the goal's two figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--schemes", nargs="+", default=["consistent", "paper"])
    parser.add_argument("--angles", type=int, default=15)
    args = parser.parse_args()
    for scheme in args.schemes:
        start = time.perf_counter()
        torques, static = probe(scheme, args.angles)
        right = int(np.sum(np.sign(torques) == np.sign(static)))
        spread = torques.std() / abs(torques.mean())
        print(f"{scheme}: end-of-stop torques [1e-7]:", " ".join(f"{t * 1e7:.2f}" for t in torques))
        print(
            f"{scheme}: static asymmetry torque {static:.3e}; mean {torques.mean():.3e}; "
            f"{right}/{args.angles} with its sign; spread std/|mean| = {spread:.2f} "
            f"({time.perf_counter() - start:.0f} s)",
            flush=True,
        )


if __name__ == "__main__":
    main()
