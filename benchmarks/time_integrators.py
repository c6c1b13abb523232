"""Order and cost of the time integrators (numerics.integrator: euler, heun).

A rotor started at omega0 = 100, far from its steady rotation, on the coarse grid
(dx = delta = 0.05), runs to t = 0.4 with dt = 4e-4, 2e-4, 1e-4, 5e-5. For each integrator
the script prints omega(0.4), the ratios of successive differences (2 for first order, 4
for second) and the wall time per step, all measured in the same run; then, for each
run, the error against the Richardson limit of the Heun sequence, and its cost in steps
x stages, so that accuracy per cost can be compared.

Run:  python benchmarks/time_integrators.py [--t-end 0.4]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pde_rotor import RotorConfig, Simulation

DTS = (4e-4, 2e-4, 1e-4, 5e-5)


def omega_at(integrator: str, dt: float, t_end: float) -> tuple[float, float]:
    """omega(t_end) and the wall time per step (after compilation)."""
    cfg = RotorConfig.model_validate(
        {
            "grid": {"dx": 0.05, "dt": dt},
            "geometry": {"smoothing": 0.05},
            "rotor": {"omega0": 100.0},
            "protocol": {"cycles": 0},
            "numerics": {"scheme": "paper", "integrator": integrator},
            "output": {"progress": False},
        }
    )
    Simulation(cfg).run(10 * dt)  # compile
    sim = Simulation(cfg)
    start = time.perf_counter()
    sim.run(t_end)
    return sim.rotor.omega, (time.perf_counter() - start) / round(t_end / dt)


def main() -> None:
    """Print the convergence table of both integrators."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=0.4)
    args = parser.parse_args()
    results = {}
    for integrator in ("euler", "heun"):
        runs = [omega_at(integrator, dt, args.t_end) for dt in DTS]
        omegas = np.array([r[0] for r in runs])
        diffs = np.diff(omegas)
        results[integrator] = omegas
        print(f"{integrator}: omega({args.t_end:g}) at dt = {', '.join(f'{d:g}' for d in DTS)}:")
        print("   ", " ".join(f"{w:.5f}" for w in omegas))
        print("    difference ratios:", " ".join(f"{r:.2f}" for r in diffs[:-1] / diffs[1:]))
        print("    ms/step:", " ".join(f"{1e3 * r[1]:.3f}" for r in runs))
    heun = results["heun"]
    limit = heun[-1] + (heun[-1] - heun[-2]) / 3.0
    print(f"Richardson limit of the Heun sequence: {limit:.5f}")
    for integrator, stages in (("euler", 1), ("heun", 2)):
        for dt, omega in zip(DTS, results[integrator], strict=True):
            cost = stages * round(args.t_end / dt)
            print(f"  {integrator:5s} dt = {dt:g}: error {omega - limit:+.2e}, {cost} stage steps")


if __name__ == "__main__":
    main()
