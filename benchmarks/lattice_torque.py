"""Spurious lattice torque on a stopped symmetric plate, and the asymmetry torque.

For each grid spacing, the steady camphor field of a plate held at angle phi (sparse
solve of the discrete Eq. (eqc) with v = 0, :mod:`pde_rotor.model.analysis`) gives the torque
T(phi), Eq. (torque). In the continuum T = 0 for Delta = 0; the Cartesian grid breaks the
hexagon's symmetry and leaves a torque of period pi/6 in phi. The asymmetry torque is
T(Delta) - T(0) at the same angles, for each discretisation scheme
(``numerics.scheme``, :mod:`pde_rotor.model.schemes`). Evidence for docs/model.md.

Run:  python benchmarks/lattice_torque.py [--angles 48] [--asymmetry 2e-5 1e-4]
      [--dx 0.05 0.025] [--schemes paper consistent] [--smoothing 0.025]
      [--plate-filter gaussian|sharpened KAPPA] [--pill-filter gaussian|sharpened KAPPA]

delta is max(dx, 0.025) (the paper's delta = dx down to its own grid) unless --smoothing
fixes it (the convergence check of the asymmetry torque at delta = 0.025).
"""

from __future__ import annotations

import argparse

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.model.analysis import stopped_torque


def stable_dt(dx: float) -> float:
    """1e-4 halved until below the explicit limit (the steady solve does not use it)."""
    dt = 1e-4
    while dt > 0.2 * dx * dx:
        dt /= 2
    return dt


def main() -> None:
    """Print rms and max lattice torque and the asymmetry torque per grid spacing."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--angles", type=int, default=48, help="angles over one period pi/6")
    parser.add_argument("--asymmetry", type=float, nargs="+", default=[2e-5], help="Delta [rad]")
    parser.add_argument("--dx", type=float, nargs="+", default=[0.05, 0.025])
    parser.add_argument("--smoothing", type=float, default=None, help="fixed delta")
    parser.add_argument("--schemes", nargs="+", default=["paper", "consistent"])
    for part in ("plate", "pill"):
        parser.add_argument(
            f"--{part}-filter",
            nargs=2,
            metavar=("KERNEL", "KAPPA"),
            default=None,
            help=f"numerics.{part}_filter_kernel and _width (default: the schema's)",
        )
    args = parser.parse_args()
    filtering = {}
    for part, choice in (("plate", args.plate_filter), ("pill", args.pill_filter)):
        if choice is not None:
            filtering[f"{part}_filter_kernel"] = choice[0]
            filtering[f"{part}_filter_width"] = float(choice[1])
    phis = np.arange(args.angles) * (np.pi / 6) / args.angles
    header = " ".join(f"{'T(D=' + format(a, 'g') + ')-T(0)':>16}" for a in args.asymmetry)
    print(f"{'scheme':>10} {'dx':>7} {'delta':>6} {'rms T(0)':>10} {'max |T(0)|':>11} {header}")
    for scheme in args.schemes:
        for dx in args.dx:
            smoothing = args.smoothing or max(dx, 0.025)
            base = {
                "grid": {"dx": dx, "dt": stable_dt(dx)},
                "numerics": {"scheme": scheme, **(filtering if scheme == "consistent" else {})},
            }
            symmetric = stopped_torque(
                RotorConfig.model_validate({**base, "geometry": {"smoothing": smoothing}}), phis
            )
            cells = []
            for asymmetry in args.asymmetry:
                geometry = {"smoothing": smoothing, "asymmetry": asymmetry}
                shifted = RotorConfig.model_validate({**base, "geometry": geometry})
                cells.append(f"{(stopped_torque(shifted, phis) - symmetric).mean():16.5e}")
            print(
                f"{scheme:>10} {dx:7.4f} {smoothing:6.4f} {np.sqrt(np.mean(symmetric**2)):10.3e}"
                f" {np.abs(symmetric).max():11.3e} {' '.join(cells)}",
                flush=True,
            )


if __name__ == "__main__":
    main()
