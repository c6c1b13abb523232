"""What the paper's noise sigma = 0.1 does when taken literally.

Eq. (eq_motion) with <xi(t) xi(s)> = 2 sigma^2 delta(t - s), Eq. (noiseav), integrated by
Euler-Maruyama (the solver's definition): each step adds sqrt(2 dt) sigma / I N(0, 1) to
omega, i.e. 141 per step for sigma = 0.1, dt = 1e-4, I = 1e-5, against a steady
omega of about 176. This script starts from steady rotation (no noise, t = 6) and runs
one more time unit with several sigma, printing mean omega and its standard deviation.

Run:  python benchmarks/noise_literal.py [--dx 0.05]
"""

from __future__ import annotations

import argparse

import numpy as np

from pde_rotor import RotorConfig, Simulation


def main() -> None:
    """Print omega statistics over one time unit for several noise intensities."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=float, default=0.05, help="grid spacing (smoothing = dx)")
    parser.add_argument("--sigmas", type=float, nargs="+", default=[0.0, 1e-6, 1e-4, 1e-2, 0.1])
    args = parser.parse_args()
    base = {
        "grid": {"dx": args.dx, "dt": 1e-4},
        "geometry": {"smoothing": args.dx},
        "protocol": {"cycles": 0},
    }
    warm = Simulation(RotorConfig.model_validate(base))
    warm.run(6.0)
    print(f"steady omega without noise at t = 6: {warm.rotor.omega:.2f}")
    print(f"{'sigma':>8} {'kick/step':>10} {'mean omega':>11} {'std omega':>10}")
    for sigma in args.sigmas:
        config = RotorConfig.model_validate({**base, "noise": {"sigma": sigma, "seed": 1}})
        sim = warm.branch(config)
        omegas = []
        for n in range(1, 101):
            sim.run(warm.t + 0.01 * n)
            omegas.append(sim.rotor.omega)
        kick = np.sqrt(2 * config.grid.dt) * sigma / config.rotor.inertia
        print(f"{sigma:8.1e} {kick:10.3g} {np.mean(omegas):11.2f} {np.std(omegas):10.2f}")


if __name__ == "__main__":
    main()
