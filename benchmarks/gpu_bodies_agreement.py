"""Bodies on the GPU against the CPU in numba's CUDA simulator: the figures behind
tests/backends/test_gpu_bodies.py, printed (docs/gpu.md, docs/results.md).

* Euler and Heun, a free disk and a fixed_axis hexagon (the test's ``TWO_BODIES``: flow, a
  stop, noise), 6 steps from smooth fields, both schemes: the largest pose difference and
  the largest field difference relative to max |c, v|;
* Heun, the same two bodies with external forces and torques and the saturating tension
  law (the test's ``LOADED``, c_sat = 0.5), 4 steps, both schemes: the same differences;
* Euler and Heun, a free disk in an annular channel with two no-flux walls (the test's
  ``vessel_pair``), 3 steps: the same differences;
* Heun, the paper's small rotor as one fixed_axis body on the GPU against the CPU rotor's
  Heun, 9 steps through two stops with noise, both schemes: phi, omega (relative), fields;
* Heun's order: a free disk's pose and velocities at t = 0.008 for dt = 1e-3, 5e-4,
  2.5e-4, the ratio of successive differences (4: second order), with Euler's beside it.

Run:  PYTHONPATH=. python benchmarks/gpu_bodies_agreement.py   (about 3 minutes)
"""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

os.environ["NUMBA_ENABLE_CUDASIM"] = "1"  # before numba-cuda is imported

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    """Print the figures."""
    spec = importlib.util.spec_from_file_location(
        "test_gpu_bodies", ROOT / "tests" / "backends" / "test_gpu_bodies.py"
    )
    assert spec is not None and spec.loader is not None
    t = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(t)
    from pde_rotor.solver.simulation import Simulation

    for scheme in ("paper", "consistent"):
        for integrator in ("euler", "heun"):
            numerics = {"scheme": scheme, "integrator": integrator}
            cpu, gpu = t.pair(t.config(t.TWO_BODIES, numerics=numerics))
            cpu.run(0.006)
            gpu.run(0.006)
            pose = np.abs(cpu.bodies.poses - gpu.bodies.poses).max()
            fields = np.abs(cpu.state.data - gpu.state.data).max() / np.abs(cpu.state.data).max()
            print(
                f"{integrator}, two bodies, {scheme}: poses {pose:.2e}, fields {fields:.2e}",
                flush=True,
            )
        numerics = {"scheme": scheme, "integrator": "heun"}
        cpu, gpu = t.pair(t.config(t.LOADED, numerics=numerics, camphor={"saturation": 0.5}))
        cpu.run(0.004)
        gpu.run(0.004)
        pose = np.abs(cpu.bodies.poses - gpu.bodies.poses).max()
        fields = np.abs(cpu.state.data - gpu.state.data).max() / np.abs(cpu.state.data).max()
        print(
            f"heun, two bodies, external loads, c_sat 0.5, {scheme}: poses {pose:.2e}, "
            f"fields {fields:.2e}",
            flush=True,
        )
        rotor, body = t.rotor_configs("heun", scheme)
        a = Simulation(rotor)
        b = Simulation(body, stepper=t.gpu_bodies_stepper)
        a.run(0.009)
        b.run(0.009)
        phi = abs(a.rotor.phi - b.bodies.poses[0, 2])
        omega = abs(a.rotor.omega - b.bodies.poses[0, 5]) / abs(a.rotor.omega)
        fields = np.abs(a.state.data - b.state.data).max() / np.abs(a.state.data).max()
        print(
            f"heun, rotor as a body against the rotor, {scheme}: phi {phi:.2e}, "
            f"omega {omega:.2e}, fields {fields:.2e}",
            flush=True,
        )
    for integrator in ("euler", "heun"):
        cpu, gpu = t.vessel_pair(integrator)
        cpu.run(0.003)
        gpu.run(0.003)
        pose = np.abs(cpu.bodies.poses - gpu.bodies.poses).max()
        fields = np.abs(cpu.state.data - gpu.state.data).max() / np.abs(cpu.state.data).max()
        print(
            f"{integrator}, disk in an annulus: poses {pose:.2e}, fields {fields:.2e}", flush=True
        )
    for integrator in ("heun", "euler"):
        x1, x2, x4 = (t.free_disk_x(integrator, dt) for dt in (1e-3, 5e-4, 2.5e-4))
        d1, d2 = np.abs(x1 - x2).max(), np.abs(x2 - x4).max()
        print(f"{integrator}: differences {d1:.3e}, {d2:.3e}, ratio {d1 / d2:.3f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
