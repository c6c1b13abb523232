"""Do the bank and restart estimators agree? (an estimator is checked before use)

The bank estimator (pde_rotor.sweep, ``kind: bank``) differs from the restart estimator
in ways that should not change the statistics: the few steps before the stop are
noise-free and one stop is shared by all noise intensities (and in the stored bank
reports, written before run-file version 2, the stop angles follow a golden-ratio
sequence instead of uniform random draws). This script compares
two stored reports on their common points: P(inv | CCW) and P(inv | CW) with Fisher's
exact test, Holm-corrected over all tests (pde_rotor.statistics.proportions.two_proportion_test).

Default: the restart pilot data/calibration_pilot.nc (paper resolution, 20 restarts per
direction) against the bank calibration data/calibration.nc (60 per direction), at
their common points (t_stop = 3; sigma = 0, 1e-6). No simulation runs.

    python benchmarks/bank_vs_restart.py [--restart FILE.nc] [--bank FILE.nc]
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path

import numpy as np
import xarray as xr

from pde_rotor.statistics.proportions import Proportion, two_proportion_test

ROOT = Path(__file__).resolve().parents[1]


def common_points(a: xr.Dataset, b: xr.Dataset) -> list[dict[str, float]]:
    """Coordinates (by dimension) present in both reports; both must have the same dims."""
    if set(a.dims) != set(b.dims):
        msg = f"reports have different dimensions: {sorted(a.dims)} and {sorted(b.dims)}"
        raise SystemExit(msg)
    dims = sorted(a.dims)
    shared = {
        d: [v for v in a[d].values if np.isclose(b[d].values, v, rtol=1e-9, atol=0).any()]
        for d in dims
    }
    return [dict(zip(dims, combo, strict=True)) for combo in itertools.product(*shared.values())]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--restart", type=Path, default=ROOT / "data" / "calibration_pilot.nc")
    parser.add_argument("--bank", type=Path, default=ROOT / "data" / "calibration.nc")
    args = parser.parse_args()
    with (
        xr.open_dataset(args.restart, engine="h5netcdf") as restart,
        xr.open_dataset(args.bank, engine="h5netcdf") as bank,
    ):
        tests = []
        for point in common_points(restart, bank):
            r = restart.sel(point, method="nearest")
            b = bank.sel(point, method="nearest")
            for name in ("ccw", "cw"):
                first = Proportion(int(r[f"inversions_{name}"]), int(r[f"stops_{name}"]))
                second = Proportion(int(b[f"inversions_{name}"]), int(b[f"stops_{name}"]))
                if first.n == 0 or second.n == 0:
                    continue  # a partial report: no stops from this direction yet
                tests.append((point, name, two_proportion_test(first, second)))
    order = sorted(range(len(tests)), key=lambda i: tests[i][2].p_value)
    holm = [0.0] * len(tests)
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (len(tests) - rank) * tests[i][2].p_value))
        holm[i] = running
    print(f"restart: {args.restart.name}   bank: {args.bank.name}")
    for (point, name, test), p_holm in zip(tests, holm, strict=True):
        where = ", ".join(f"{k} = {v:g}" for k, v in point.items())
        print(
            f"{where}, P(inv | {name.upper()}): restart {test.first.k}/{test.first.n} = "
            f"{test.first.p:.3f}, bank {test.second.k}/{test.second.n} = {test.second.p:.3f}, "
            f"Fisher p (Holm) = {p_holm:.3f}"
        )
    print(f"agree (alpha = 0.05, Holm over {len(tests)} tests): {min(holm, default=1) >= 0.05}")


if __name__ == "__main__":
    main()
