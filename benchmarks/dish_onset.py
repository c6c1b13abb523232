"""A free camphor disk at the centre of a no-flux dish: the Hopf onset, simulated against
the linear stability (Koyano, Suematsu & Kitahata, PRE 99, 022211 (2019)).

The disk (no plate: the pill is the object, radius rho = 0.1, mass m) sits at the centre
of a dish of radius L whose wall holds the camphor in (``grid.wall: no_flux``), no flow
(the no-flow limit of the derivation in docs/bodies.md). It is held for `--relax` time
units while c relaxes to the rest state, then released with the small velocity U0 along
x. Its position then moves as a pair of modes e^{lambda t}, lambda = sigma + i omega; the
script fits lambda to (x, y) over [`--fit-start`, `--fit-end`] after the release
(:func:`pde_rotor.gallery.onsets.hopf_rate`) at each friction mu (given as multiples of
the theory's mu_c), prints it beside the linear stability's
(:func:`pde_rotor.theory.dish.dish_hopf_rate`), and the friction where the simulated
sigma changes sign (linear interpolation between the two frictions that bracket it) with
the frequency there, beside mu_c and omega_c (:func:`~pde_rotor.theory.dish.dish_hopf_onset`).

Run:  python benchmarks/dish_onset.py [--dx 0.025 --dt 1e-4] [--factors 0.98 1.0 1.02]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.gallery.onsets import disk_in_dish_config, kick_hopf_rate
from pde_rotor.theory import CamphorDisk, Wall, dish_hopf_onset, dish_hopf_rate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--dish", type=float, default=3.0, help="dish radius L")
    parser.add_argument("--mass", type=float, default=1e-4)
    parser.add_argument("--factors", type=float, nargs="+", default=[0.97, 0.99, 1.01, 1.03])
    parser.add_argument("--relax", type=float, default=6.0)
    parser.add_argument("--u0", type=float, default=1e-4)
    parser.add_argument("--fit-start", type=float, default=4.0)
    parser.add_argument("--fit-end", type=float, default=28.0)
    args = parser.parse_args()
    disk = CamphorDisk.from_config(RotorConfig())
    wall = Wall(args.dish, "no_flux")
    mu_c, omega_c = dish_hopf_onset(disk, wall, args.mass)
    print(
        f"free disk rho = {disk.radius:g}, m = {args.mass:g} in a no-flux dish L = "
        f"{args.dish:g}; dx = {args.dx:g}, dt = {args.dt:g}, no flow"
    )
    print(f"theory: mu_c = {mu_c:.5f}, omega_c = {omega_c:.5f}")
    mus = mu_c * np.array(args.factors)
    rates = []
    for mu in mus:
        start = time.perf_counter()
        end = args.relax + args.fit_end + 0.1
        config = disk_in_dish_config(args.dx, args.dt, args.dish, args.mass, mu, end, args.relax)
        lam = kick_hopf_rate(config, args.relax, args.u0, (args.fit_start, args.fit_end))
        theory = dish_hopf_rate(disk, wall, mu, args.mass)
        rates.append(lam)
        print(
            f"mu = {mu:.5f} ({mu / mu_c:.3f} mu_c): sigma {lam.real:+.4f}, omega "
            f"{lam.imag:.4f}; linear stability {theory.real:+.4f}, {theory.imag:.4f} "
            f"({time.perf_counter() - start:.0f} s)",
            flush=True,
        )
    lams = np.array(rates)
    change = np.nonzero(np.diff(np.sign(lams.real)))[0]
    if change.size:
        i = change[0]
        weight = lams[i].real / (lams[i].real - lams[i + 1].real)
        found = mus[i] + weight * (mus[i + 1] - mus[i])
        omega = lams[i].imag + weight * (lams[i + 1].imag - lams[i].imag)
        print(
            f"simulated mu_c = {found:.5f} ({found / mu_c - 1:+.2%}), omega_c = {omega:.4f} "
            f"({omega / omega_c - 1:+.2%})"
        )
    else:
        print("sigma does not change sign over the frictions given")


if __name__ == "__main__":
    main()
