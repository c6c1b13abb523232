"""The free disk's rate after a kick, fitted over successive windows of one run.

As benchmarks/free_disk_onset.py (paper grid, no flow, m = 2e-3, dish L = 4, held
`--relax`, kicked to U = 1e-4), but |U| is recorded every 0.05 for `--span` time units after
the release and lambda fitted to log |U| over each window of `--windows` (pairs of times
after the release), beside the linear stability's leading root. A fit that starts before
the field's own transients have decayed (they decay at a + D k^2 >= a = 1 and faster)
mixes them in: the fitted rate approaches the leading root as the window moves later.

Run:  python benchmarks/free_disk_fit_windows.py [--mu 0.1852 0.1675] [--span 6]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.gallery.onsets import free_disk_config
from pde_rotor.solver.simulation import Simulation
from pde_rotor.theory import CamphorDisk, free_disk_growth_rate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--dish", type=float, default=4.0)
    parser.add_argument("--mass", type=float, default=2e-3)
    parser.add_argument("--mu", type=float, nargs="+", default=[0.1852, 0.1675])
    parser.add_argument("--relax", type=float, default=8.0)
    parser.add_argument("--span", type=float, default=6.0)
    parser.add_argument("--windows", type=float, nargs="+", default=[0.5, 2, 2, 4, 4, 6])
    args = parser.parse_args()
    disk = CamphorDisk.from_config(RotorConfig())
    windows = list(zip(args.windows[::2], args.windows[1::2], strict=True))
    for mu in args.mu:
        start = time.perf_counter()
        config = free_disk_config(
            args.dx, args.dt, args.dish, args.mass, mu, args.relax + args.span + 0.1, args.relax
        )
        sim = Simulation(config)
        sim.run(args.relax)
        sim.bodies.poses[0, 3] = 1e-4
        times = np.arange(0.0, args.span + 1e-9, 0.05)
        speeds = []
        for t in times:
            sim.run(args.relax + round(t / args.dt) * args.dt)
            speeds.append(np.hypot(*sim.bodies.poses[0, 3:5]))
        logs = np.log(np.array(speeds))
        fits = []
        for lo, hi in windows:
            keep = (times >= lo - 1e-9) & (times <= hi + 1e-9)
            fits.append(f"[{lo:g}, {hi:g}] {np.polyfit(times[keep], logs[keep], 1)[0]:+.4f}")
        theory = free_disk_growth_rate(disk, mu, args.mass)
        print(
            f"mu = {mu:.4f}: lambda fitted over {'; '.join(fits)}; linear stability "
            f"{theory:+.4f} ({time.perf_counter() - start:.0f} s)",
            flush=True,
        )


if __name__ == "__main__":
    main()
