"""Cost of K bodies: ms per step of the bodies' step with 1, 2, 3 and 4 rotors on one dish.

The paper's hexagon rotor (as a ``fixed_axis`` body, turning at omega = 150) placed 1, 2, 3
or 4 times on a dish of radius 4 at the paper's grid (dx = 0.025, dt = 1e-4), one thread,
each `--scheme` (both by default). Each count is timed alternately with the others
(`--repeats` rounds, minimum kept) over `--steps` steps after a warm-up, in CPU time of the
stepping thread (on a shared machine the wall-clock time also counts other processes);
printed: ms/step, its ratio to one body's step and the goal 1 + 0.3 K for K bodies.

Run:  NUMBA_NUM_THREADS=1 python benchmarks/bench_bodies.py [--steps 400] [--repeats 3]
      [--scheme paper consistent]
"""

from __future__ import annotations

import argparse
import time

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation

PLACES = [(-1.5, -1.5), (1.5, 1.5), (-1.5, 1.5), (1.5, -1.5)]
"""Axes of the rotors: footprints (radius 1.077) apart and inside the dish."""


def config(count: int, scheme: str) -> RotorConfig:
    """`count` paper rotors as bodies on a dish of radius 4, paper grid, `scheme`."""
    rotor = RotorConfig().body_list()[0].model_dump()
    bodies = []
    for k, (x, y) in enumerate(PLACES[:count]):
        body = {**rotor, "name": f"rotor{k}", "protocol": None}
        body["start"] = {**rotor["start"], "x": x, "y": y, "omega": 150.0}
        bodies.append(body)
    return RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 4.0},
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": 100.0, "cycles": 0},
            "bodies": bodies,
        }
    )


def ms_per_step(sim: Simulation, steps: int) -> float:
    """Milliseconds of the thread's CPU time per step, over `steps` steps from the
    simulation's time."""
    dt = sim.config.grid.dt
    start = time.thread_time()
    sim.run(sim.t + steps * dt)
    return 1e3 * (time.thread_time() - start) / steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--scheme", nargs="+", default=["paper", "consistent"])
    args = parser.parse_args()
    for scheme in args.scheme:
        sims = {k: Simulation(config(k, scheme)) for k in (1, 2, 3, 4)}
        for sim in sims.values():
            ms_per_step(sim, 20)  # compile and warm up
        best = {k: float("inf") for k in sims}
        for _ in range(args.repeats):
            for k, sim in sims.items():
                best[k] = min(best[k], ms_per_step(sim, args.steps))
        one = best[1]
        cells = sims[1].pde.domain.coords.size
        print(f"paper grid, dish L = 4 ({cells}^2 cells), {scheme} scheme, thread CPU time")
        for k, ms in best.items():
            print(
                f"K = {k}: {ms:.3f} ms/step, {ms / one:.2f} x one body's step "
                f"(goal 1 + 0.3 K = {1 + 0.3 * k:.1f})"
            )


if __name__ == "__main__":
    main()
