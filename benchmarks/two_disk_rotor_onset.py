"""The two-disk rotor's onset of rotation: simulation against the linear stability.

Two camphor disks of radius 0.1 at (+-l, 0) on a strip that does not touch the water
(Koyano et al., PRE 96, 012609, 2017), turning about the dish centre, no flow. The rotor
is held while c relaxes, released with omega = 1e-3, and the growth rate lambda of |omega|
is fitted over [0.5, 1.5] after the release at 0.9 and 1.05 times the critical friction
mu_c(l) of the linear stability (:func:`pde_rotor.theory.two_disk_rotor.rotor_critical_friction`),
beside its growth rate I lambda = K_rot(lambda) - mu J; the sign change of the simulated
lambda, interpolated linearly, is the simulated mu_c.

Run:  python benchmarks/two_disk_rotor_onset.py [--dx 0.025] [--half-length 0.5]
"""

from __future__ import annotations

import argparse

from pde_rotor import RotorConfig
from pde_rotor.gallery.onsets import kick_rotation_rate, two_disk_rotor_config
from pde_rotor.theory import CamphorDisk, rotor_critical_friction, rotor_growth_rate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--half-length", type=float, default=0.5)
    parser.add_argument("--inertia", type=float, default=1e-4)
    parser.add_argument("--relax", type=float, default=6.0)
    args = parser.parse_args()
    disk = CamphorDisk.from_config(RotorConfig())
    smoothing = RotorConfig().geometry.smoothing
    mu_c = rotor_critical_friction(disk, args.half_length, smoothing)
    print(
        f"two-disk rotor l = {args.half_length:g}, rho = {disk.radius:g}, I = {args.inertia:g}, "
        f"dx = {args.dx:g}, delta = {smoothing:g}, no flow: theory mu_c = {mu_c:.5f}"
    )
    factors, rates = (0.9, 1.05), []
    for factor in factors:
        mu = factor * mu_c
        config = two_disk_rotor_config(
            args.dx, args.dt, 3.0, args.half_length, args.inertia, mu, args.relax + 2.0, args.relax
        )
        lam = kick_rotation_rate(config, args.relax, 1e-3, (0.5, 1.5))
        theory = rotor_growth_rate(disk, args.half_length, mu, args.inertia, smoothing)
        rates.append(lam)
        print(f"mu = {mu:.5f}: lambda simulated {lam:+.4f}, linear stability {theory:+.4f}")
    low, high = factors[0] * mu_c, factors[1] * mu_c
    simulated = low - rates[0] * (high - low) / (rates[1] - rates[0])
    print(f"simulated mu_c = {simulated:.5f}: {simulated / mu_c - 1:+.2%} from the theory")


if __name__ == "__main__":
    main()
