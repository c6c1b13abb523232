"""The free camphor disk's onset of motion: simulation against the linear stability.

A free camphor disk (no plate: the pill is the object, radius rho = 0.1) at the centre of a
dish, no flow (the no-flow limit of the derivation in docs/bodies.md). The disk is held
for `--relax` time units while c relaxes to the rest state, then released with the small
velocity U0 along x; its velocity then grows or decays as e^{lambda t}. The script fits
lambda to log |U| over [`--fit-start`, `--fit-end`] after the release, at each friction
mu, and prints it beside the growth rate of the linear stability,
m lambda = K(lambda) - mu pi rho^2 (:func:`pde_rotor.theory.free_disk.free_disk_growth_rate`),
and the critical friction where the simulated lambda changes sign (linear interpolation
between the two frictions that bracket it) beside the closed form mu_c.

Run:  python benchmarks/free_disk_onset.py [--dx 0.025] [--mu 0.15 0.17 0.18 0.2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.gallery.onsets import free_disk_config, kick_growth_rate
from pde_rotor.theory import (
    CamphorDisk,
    free_disk_critical_friction,
    free_disk_growth_rate,
    free_disk_smoothed_coefficients,
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--dish", type=float, default=4.0, help="dish radius L")
    parser.add_argument("--mass", type=float, default=2e-3)
    parser.add_argument("--mu", type=float, nargs="+", default=[0.16, 0.17, 0.18, 0.19])
    parser.add_argument("--relax", type=float, default=8.0)
    parser.add_argument("--u0", type=float, default=1e-4)
    parser.add_argument("--fit-start", type=float, default=0.5)
    parser.add_argument("--fit-end", type=float, default=2.0)
    args = parser.parse_args()
    disk = CamphorDisk.from_config(RotorConfig())
    smoothing = RotorConfig().geometry.smoothing
    force, area = free_disk_smoothed_coefficients(disk, smoothing)
    mu_sharp = free_disk_critical_friction(disk)
    print(
        f"free disk rho = {disk.radius:g}, m = {args.mass:g}, dx = {args.dx:g}, "
        f"delta = {smoothing:g}, dish L = {args.dish:g}, no flow"
    )
    print(f"theory: mu_c = {mu_sharp:.5f} (sharp), {force / area:.5f} (smoothed delta)")
    rates = []
    for mu in args.mu:
        start = time.perf_counter()
        config = free_disk_config(
            args.dx, args.dt, args.dish, args.mass, mu, args.relax + args.fit_end + 0.1, args.relax
        )
        lam = kick_growth_rate(config, args.relax, args.u0, (args.fit_start, args.fit_end))
        theory = free_disk_growth_rate(disk, mu, args.mass)
        rates.append(lam)
        print(
            f"mu = {mu:.4f}: lambda simulated {lam:+.4f}, linear stability {theory:+.4f} "
            f"({time.perf_counter() - start:.0f} s)",
            flush=True,
        )
    mus, lams = np.array(args.mu), np.array(rates)
    change = np.nonzero(np.diff(np.sign(lams)))[0]
    if change.size:
        i = change[0]
        mu_c = mus[i] - lams[i] * (mus[i + 1] - mus[i]) / (lams[i + 1] - lams[i])
        print(
            f"simulated mu_c = {mu_c:.5f}: {mu_c / mu_sharp - 1:+.2%} from the sharp closed "
            f"form, {mu_c / (force / area) - 1:+.2%} from the smoothed"
        )
    else:
        print("lambda does not change sign over the frictions given")


if __name__ == "__main__":
    main()
