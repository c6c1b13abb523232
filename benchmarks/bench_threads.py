"""Benchmark of one run on several threads (``solver.threads``): ms/step and equal states.

The same run (the paper's grid, dx = 0.025, dt = 1e-4: 242 x 242 cells; the plate
turning, no stops) is set up once per thread count, 1 and 2 .. the usable cores (or
--threads), and the runs are advanced side by side: each --chunk steps in turn, the
order turned round every round, for --rounds rounds, so that a change of the machine's
speed during the benchmark hits every thread count alike. Printed per thread count: the
median ms/step over the rounds (wall clock), the median of the per-round ratios to one
thread, and the largest difference of the state (c, v_x, v_y, phi, omega) from the
one-thread run's after the same steps: 0 when the threads give the same bits.

Run:  python benchmarks/bench_threads.py [--scheme consistent] [--rounds 10] [--chunk 2000]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from pde_rotor import RotorConfig, Simulation


def main() -> None:
    """Run the benchmark and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scheme", choices=["consistent", "paper"], default="consistent")
    parser.add_argument("--rounds", type=int, default=10, help="turns of every thread count")
    parser.add_argument("--chunk", type=int, default=2000, help="steps per turn")
    parser.add_argument("--threads", type=int, nargs="*", help="thread counts after 1")
    args = parser.parse_args()
    cores = len(os.sched_getaffinity(0))
    counts = [1, *(args.threads or range(2, cores + 1))]
    sims = {}
    for threads in counts:
        config = RotorConfig.model_validate(
            {
                "protocol": {"cycles": 0},
                "numerics": {"scheme": args.scheme},
                "solver": {"threads": threads},
            }
        )
        sims[threads] = Simulation(config)
    dt = sims[1].config.grid.dt
    for sim in sims.values():  # compile and warm up
        sim.run(sim.t + 20 * dt)
    seconds: dict[int, list[float]] = {threads: [] for threads in counts}
    for r in range(args.rounds):
        order = counts[r % len(counts) :] + counts[: r % len(counts)]
        for threads in order:
            sim = sims[threads]
            start = time.perf_counter()
            sim.run(sim.t + args.chunk * dt)
            seconds[threads].append((time.perf_counter() - start) / args.chunk)
    load = os.getloadavg()
    print(
        f"scheme {args.scheme}, grid {sims[1].pde.domain.grid.shape[0]}^2, {args.rounds} rounds "
        f"x {args.chunk} steps per thread count, {cores} usable cores, load average "
        f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f} (after)"
    )
    reference = sims[1]
    for threads in counts:
        sim = sims[threads]
        median = statistics.median(seconds[threads]) * 1e3
        ratio = statistics.median(
            one / many for one, many in zip(seconds[1], seconds[threads], strict=True)
        )
        fields = np.max(np.abs(sim.state.data - reference.state.data))
        rotor = np.max(np.abs(sim.rotor.as_array()[:2] - reference.rotor.as_array()[:2]))
        print(
            f"threads {threads:2d}: {median:8.4f} ms/step, speed-up {ratio:5.2f}x, "
            f"max |state - 1 thread| {max(fields, rotor):.1e} after {sim.t / dt:.0f} steps"
        )


if __name__ == "__main__":
    main()
