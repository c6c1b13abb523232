"""Spurious lattice torque on a stopped symmetric plate, and the asymmetry torque.

For each grid spacing, the steady camphor field of a plate held at angle phi (sparse
solve of the discrete Eq. (eqc) with v = 0, :mod:`pde_rotor.analysis`) gives the torque
T(phi), Eq. (torque). In the continuum T = 0 for Delta = 0; the Cartesian grid breaks the
hexagon's symmetry and leaves a torque of period pi/6 in phi. The asymmetry torque is
T(Delta) - T(0) at the same angles, for each discretisation scheme
(``numerics.scheme``, :mod:`pde_rotor.schemes`). Evidence for docs/model.md.

Run:  python benchmarks/lattice_torque.py [--angles 48] [--asymmetry 2e-5]
      [--dx 0.05 0.025] [--schemes paper consistent]
"""

from __future__ import annotations

import argparse

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.analysis import stopped_torque


def main() -> None:
    """Print rms and max lattice torque and the asymmetry torque per grid spacing."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--angles", type=int, default=48, help="angles over one period pi/6")
    parser.add_argument("--asymmetry", type=float, default=2e-5, help="Delta [rad]")
    parser.add_argument("--dx", type=float, nargs="+", default=[0.05, 0.025])
    parser.add_argument("--schemes", nargs="+", default=["paper", "consistent"])
    args = parser.parse_args()
    phis = np.arange(args.angles) * (np.pi / 6) / args.angles
    print(
        f"{'scheme':>10} {'dx':>7} {'rms T(0)':>10} {'max |T(0)|':>11} {'T(D)-T(0)':>11}"
        f" {'spread':>9}"
    )
    for scheme in args.schemes:
        for dx in args.dx:
            # delta = max(dx, 0.025): the paper's delta = dx down to its own grid
            base = {"grid": {"dx": dx}, "numerics": {"scheme": scheme}}
            geometry = {"smoothing": max(dx, 0.025)}
            symmetric = stopped_torque(
                RotorConfig.model_validate({**base, "geometry": geometry}), phis
            )
            shifted = {**base, "geometry": {**geometry, "asymmetry": args.asymmetry}}
            asymmetric = stopped_torque(RotorConfig.model_validate(shifted), phis) - symmetric
            print(
                f"{scheme:>10} {dx:7.4f} {np.sqrt(np.mean(symmetric**2)):10.3e}"
                f" {np.abs(symmetric).max():11.3e} {asymmetric.mean():11.3e}"
                f" {asymmetric.std():9.1e}",
                flush=True,
            )


if __name__ == "__main__":
    main()
