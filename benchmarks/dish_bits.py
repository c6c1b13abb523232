"""The dish before and after a change, bit for bit: run it in two trees and compare.

Saves the state and poses after 0.05 of the no-flux dish of tests/kernels/test_wall.py
(a turning hexagon and a drifting free strip, flow on and off) and of the same bodies in
the default absorbing dish, and the config hashes of the default config and of that run.

Run (once per tree, then compare):
      PYTHONPATH=/path/to/tree python benchmarks/dish_bits.py save OUT.npz
      python benchmarks/dish_bits.py compare A.npz B.npz
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np


def save(out: str) -> None:
    """Run the dishes and write their states, poses and hashes to `out`."""
    from pde_rotor import RotorConfig
    from pde_rotor.solver.simulation import Simulation

    sys.path.insert(0, str(Path(__file__).parents[1] / "tests" / "kernels"))
    from test_wall import BODIES, walled

    bodies = [dict(b) for b in BODIES]
    bodies[1]["motion"] = {"kind": "free", "mass": 1e-2}  # stays clear of the rim
    arrays = {}
    for flow in (True, False):
        sim = walled(bodies, flow={"enabled": flow})
        sim.run(0.05)
        arrays[f"no_flux_flow_{flow}"] = sim.state.data.copy()
        arrays[f"no_flux_poses_flow_{flow}"] = sim.bodies.poses.copy()
    config = RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 4.0, "dx": 0.1, "dt": 1e-3},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": "paper"},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "bodies": bodies,
        }
    )
    sim = Simulation(config)
    sim.run(0.05)
    arrays["absorbing"] = sim.state.data.copy()
    arrays["absorbing_poses"] = sim.bodies.poses.copy()
    arrays["hashes"] = np.array([RotorConfig().config_hash(), config.config_hash()])
    np.savez(out, **arrays)


def compare(first: str, second: str) -> None:
    """Print, per saved array, whether the two files hold it bit for bit."""
    a, b = np.load(first), np.load(second)
    for key in a.files:
        print(f"{key}: {'identical' if np.array_equal(a[key], b[key]) else 'DIFFERENT'}")


if __name__ == "__main__":
    if sys.argv[1] == "save":
        save(sys.argv[2])
    else:
        compare(sys.argv[2], sys.argv[3])
