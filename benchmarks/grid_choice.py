"""Which grid for the figure sweeps? dx = 1/30 against the paper's 0.025.

At three probe points, at one noise intensity (sigma = 1.5e-7, near the
calibration), compare P at dx = 1/30 and dx = 0.025 (delta = 0.025, dt = 1e-4, default
scheme) with >= 100 independent stops each; take the cheaper grid where they agree
(Fisher p > 0.05 and |dP| < 0.1 at every probe), else 0.025.

    probe 1: Delta = 0,    t_stop = 1.5   data/science_grid_symmetric.nc (axis dx)
    probe 2: Delta = 2e-5, t_stop = 3     data/science_calibration.nc (dx = 0.025) and
                                          data/science_calibration_dx30.nc (dx = 1/30)
    probe 3: Delta = 1e-4, t_stop = 1.25  data/science_grid_onset.nc (axis dx)

At Delta = 0 P is one proportion (pooled over both directions) and Fisher's exact test
compares it directly. At Delta != 0 P is the chain value 2ab/(a+b) of the two
conditionals, so each conditional is compared (Fisher, Holm-corrected over the two) and
|dP| is taken on the chain value. No simulation runs.

    python benchmarks/grid_choice.py [--data DIR]
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from pde_rotor.statistics.proportions import Proportion, two_proportion_test

ROOT = Path(__file__).resolve().parents[1]
SIGMA = 1.5e-7
FINE, COARSE = 0.025, 1 / 30
P_LIMIT, DP_LIMIT = 0.05, 0.1


@dataclass(frozen=True)
class Probe:
    """One probe point and where its two grids' values are stored."""

    label: str
    fine: tuple[str, dict[str, float]]
    coarse: tuple[str, dict[str, float]]
    pooled: bool


PROBES = (
    Probe(
        "Delta = 0, t_stop = 1.5",
        ("science_grid_symmetric.nc", {"dx": FINE}),
        ("science_grid_symmetric.nc", {"dx": COARSE}),
        pooled=True,
    ),
    Probe(
        "Delta = 2e-5, t_stop = 3",
        ("science_calibration.nc", {"sigma": SIGMA, "t_stop": 3.0}),
        ("science_calibration_dx30.nc", {"sigma": SIGMA, "t_stop": 3.0}),
        pooled=False,
    ),
    Probe(
        "Delta = 1e-4, t_stop = 1.25",
        ("science_grid_onset.nc", {"dx": FINE}),
        ("science_grid_onset.nc", {"dx": COARSE}),
        pooled=False,
    ),
)


def point(data: Path, where: tuple[str, dict[str, float]]) -> xr.Dataset | None:
    """The report values at one point (None if the report is not there yet)."""
    path = data / where[0]
    if not path.is_file():
        return None
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        sel = {k: v for k, v in where[1].items() if k in ds.dims}
        return ds.sel(sel, method="nearest").load()


def proportion(ds: xr.Dataset, suffix: str) -> Proportion:
    return Proportion(int(ds[f"inversions{suffix}"]), int(ds[f"stops{suffix}"]))


def compare(probe: Probe, fine: xr.Dataset, coarse: xr.Dataset) -> tuple[float, float, str]:
    """(|dP|, the smallest (Holm-adjusted) Fisher p, the counts compared)."""
    dp = abs(float(fine["P"]) - float(coarse["P"]))
    if probe.pooled:
        a, b = proportion(fine, ""), proportion(coarse, "")
        p_value = two_proportion_test(a, b).p_value
        return dp, p_value, f"{a.k}/{a.n} vs {b.k}/{b.n}"
    tests, counts = [], []
    for suffix, name in (("_ccw", "CCW"), ("_cw", "CW")):
        a, b = proportion(fine, suffix), proportion(coarse, suffix)
        tests.append(two_proportion_test(a, b).p_value)
        counts.append(f"{name} {a.k}/{a.n} vs {b.k}/{b.n}")
    # Holm over two tests: the smallest adjusted p-value is twice the smallest raw one
    return dp, min(1.0, 2 * min(tests)), ", ".join(counts)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT / "data")
    args = parser.parse_args()
    agree_all = True
    print(f"sigma = {SIGMA:g}; P [95 %] at dx = 0.025 and dx = 1/30 (inversions/stops)")
    for probe in PROBES:
        fine, coarse = point(args.data, probe.fine), point(args.data, probe.coarse)
        if fine is None or coarse is None:
            print(f"{probe.label}: missing report ({probe.fine[0]} / {probe.coarse[0]})")
            agree_all = False
            continue
        dp, p_value, counts = compare(probe, fine, coarse)
        agree = p_value > P_LIMIT and dp < DP_LIMIT
        agree_all &= agree
        print(
            f"{probe.label}: P = {float(fine['P']):.3f} [{float(fine['P_low']):.3f}, "
            f"{float(fine['P_high']):.3f}] (0.025) vs {float(coarse['P']):.3f} "
            f"[{float(coarse['P_low']):.3f}, {float(coarse['P_high']):.3f}] (1/30); "
            f"|dP| = {dp:.3f}, Fisher p = {p_value:.3g} ({counts}): "
            f"{'agree' if agree else 'DIFFER'}"
        )
    print(
        "choice: dx = 1/30 (the grids agree at every probe)"
        if agree_all
        else "choice: dx = 0.025 (a probe differs or is missing)"
    )


if __name__ == "__main__":
    main()
