"""Cost of bodies runs: the estimate of `pde-rotor check` against the measured step.

Each shipped bodies config (or those named) is built as a Simulation, stepped `--warm`
steps (compiling the kernel the first time), then `--steps` steps timed in the stepping
thread's CPU time (on a shared machine the wall-clock time also counts other processes).
Printed per config: the measured ms/step, the estimate's ms/step
(:func:`pde_rotor.sweep.cost.estimate_run` over its steps, the movie left out) and their
ratio. `check`'s estimates are for one idle core: run with NUMBA_NUM_THREADS=1.

Run:  NUMBA_NUM_THREADS=1 python benchmarks/bodies_cost.py [--steps 400] [CONFIG ...]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pde_rotor.config import load_config
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.cost import estimate_run

CONFIGS = ["two_rotors", "free_disk", "rotor_and_source", "disk_in_dish", "two_disk_rotor"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("configs", nargs="*", default=CONFIGS)
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--warm", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    root = Path(__file__).resolve().parents[1] / "configs" / "bodies"
    print("| config | measured ms/step | estimate ms/step | estimate / measured |")
    print("|---|---|---|---|")
    for name in args.configs:
        cfg = load_config(root / f"{name}.yaml")
        estimate = estimate_run(cfg, movie=False)
        per_step = 1e3 * estimate.seconds / estimate.steps
        sim = Simulation(cfg)
        dt = cfg.grid.dt
        sim.run(args.warm * dt)
        best = float("inf")
        for _ in range(args.repeats):
            start = time.thread_time()
            sim.run(sim.t + args.steps * dt)
            best = min(best, 1e3 * (time.thread_time() - start) / args.steps)
        print(f"| {name} | {best:.3f} | {per_step:.3f} | {per_step / best:.2f} |", flush=True)


if __name__ == "__main__":
    main()
