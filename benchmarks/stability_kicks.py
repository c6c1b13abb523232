"""The growth rates the gallery's kicked simulations measured, from the eigenvalues.

``gallery/bodies_onsets.py`` (paper grid, no flow, paper scheme, delta = 0.025) held a free
disk (mass 2e-3, dish radius 4) and the two-disk rotor (l = 0.5, inertia 1e-4, dish radius
3) for 6, kicked them and fitted lambda over [0.5, 1.5]; docs/results.md records the rates
at 0.8, 0.9, 0.95, 1.05, 1.1, 1.2 times the theory's mu_c (0.17635 and 0.13820). This script
prints the leading eigenvalue of the same configs at the same frictions.

Run: ``python benchmarks/stability_kicks.py [--dx 0.025]`` (one thread: OMP_NUM_THREADS=1).
"""

from __future__ import annotations

import argparse
import time

from pde_rotor.config import read_config_data
from pde_rotor.stability.continuation import spectrum_at

KEY = "bodies[0].motion.friction"
FACTORS = (0.8, 0.9, 0.95, 1.05, 1.1, 1.2)
SYSTEMS = {
    "free disk": ("configs/bodies/free_disk.yaml", 4.0, 0.17635, {"mass": 2e-3}),
    "two-disk rotor": ("configs/bodies/two_disk_rotor.yaml", 3.0, 0.13820, {"inertia": 1e-4}),
}


def main() -> None:
    """Print lambda at each friction of each system."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=float, default=0.025)
    args = parser.parse_args()
    for name, (path, radius, mu_c, motion) in SYSTEMS.items():
        data = read_config_data(path)
        data["grid"] = {"domain_radius": radius, "dx": args.dx, "dt": 1e-4}
        data["flow"] = {"enabled": False}
        data["geometry"] = {"smoothing": 0.025}
        data["bodies"][0]["motion"].update(motion)
        for factor in FACTORS:
            start = time.thread_time()
            lam = spectrum_at(data, KEY, factor * mu_c, k=4).leading
            print(
                f"{name}: mu = {factor:g} mu_c = {factor * mu_c:.5f}: lambda = {lam.real:+.4f} "
                f"{lam.imag:+.1e}i (cpu {time.thread_time() - start:.0f}s)",
                flush=True,
            )


if __name__ == "__main__":
    main()
