"""The paper's rotor with Heun on the GPU against the CPU, in numba's CUDA simulator.

A rotor run with ``numerics.integrator: heun`` on the GPU steps as the rotor's fixed_axis
body on the bodies' kernel (:func:`pde_rotor.backends.gpu_bodies.run_rotor_ensemble`,
through :func:`pde_rotor.backends.member_stepper` for a single run). The small rotor of
tests/backends/test_gpu.py (omega0 = 50, noise, two stops), 9 steps, both schemes: phi,
omega, the torques (relative) and c, v (relative to their largest value) against the CPU
rotor's Heun (docs/gpu.md, docs/results.md).

Run:  PYTHONPATH=. python benchmarks/gpu_rotor_heun.py   (about 20 s)
"""

from __future__ import annotations

import os

os.environ["NUMBA_ENABLE_CUDASIM"] = "1"  # before numba-cuda is imported

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.backends import backend_for, member_stepper
from pde_rotor.solver.simulation import Simulation


def rotor_config(scheme: str) -> RotorConfig:
    """The test's small rotor with Heun on the GPU backend."""
    return RotorConfig.model_validate(
        {
            "grid": {"dx": 0.1, "dt": 1e-3, "domain_radius": 1.6},
            "geometry": {
                "radius": 0.3,
                "pill_radius": 0.06,
                "pill_inset": 0.03,
                "smoothing": 0.05,
            },
            "numerics": {"scheme": scheme, "integrator": "heun"},
            "rotor": {"omega0": 50.0},
            "noise": {"sigma": 1e-5, "seed": 3},
            "protocol": {"t_ini": 0.003, "t_stop": 0.002, "t_release": 0.001, "cycles": 2},
            "solver": {"backend": "gpu"},
        }
    )


def relative(got: float, want: float) -> float:
    """|got - want| / |want|."""
    return abs(got - want) / abs(want)


def main() -> None:
    for scheme in ("paper", "consistent"):
        cfg = rotor_config(scheme)
        cpu_run = Simulation(cfg)
        gpu_run = Simulation(cfg, stepper=member_stepper(backend_for(cfg)))
        cpu_run.run(0.009)
        gpu_run.run(0.009)
        want, got = cpu_run.rotor, gpu_run.rotor
        fields = np.abs(gpu_run.state.data - cpu_run.state.data).max()
        print(
            f"{scheme}: phi {relative(got.phi, want.phi):.2g}, "
            f"omega {relative(got.omega, want.omega):.2g}, "
            f"torque {relative(got.torque, want.torque):.2g}, "
            f"friction {relative(got.friction, want.friction):.2g} relative; "
            f"c, v {fields / np.abs(cpu_run.state.data).max():.2g} of their largest value"
        )


if __name__ == "__main__":
    main()
