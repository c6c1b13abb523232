"""Can one noise intensity give both the paper's decay at 1.4 and its 0.2 plateau?

This is asked of the model on the paper's grid (dx = delta = 0.025, dt = 1e-4,
default scheme), with data. Four readings of stored reports (no runs), each a level
crossing with its 95 % interval (:mod:`pde_rotor.statistics.crossing`: straight lines between the
points and between their Wilson bounds):

    1. sigma_cal: where the Fig. 7(b) plateau P(t_stop = 3, Delta = 2e-5) rises through
       0.2 (data/science_calibration.nc, P against sigma);
    2. the Delta = 0 decay point at sigma_cal: where P(t_stop) of Fig. 5 falls through
       0.75 (data/fig5.nc);
    3. sigma_1.4: where P(t_stop = 1.4, Delta = 0) falls through 0.75, the sigma that
       puts the decay at the paper's 1.4 (data/science_one_intensity_decay.nc);
    4. the plateau at sigma_1.4: P(3, 2e-5) against sigma from science_calibration and
       science_one_intensity_plateau together, read at sigma_1.4 (its lower bound at
       the lower end of sigma_1.4's interval, its upper bound at the upper end; P rises
       with sigma). Where P(1.4) stays above 0.75 at every measured sigma, sigma_1.4 is
       only bounded from below, and so is the plateau there.

One intensity gives both numbers only if the plateau at sigma_1.4 can be 0.2, that
is, if the plateau's lower bound at the lower end of sigma_1.4's interval is <= 0.2.

    python benchmarks/one_intensity.py [--data DIR]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import xarray as xr

from pde_rotor.paper import DECAY_STOP, PLATEAU, PLATEAU_ASYMMETRY, PLATEAU_STOP
from pde_rotor.statistics.crossing import DECAY_LEVEL, report_crossing

ROOT = Path(__file__).resolve().parents[1]


def load(data: Path, name: str) -> xr.Dataset | None:
    """A stored report, or None (printed) where it is not there yet."""
    path = data / f"{name}.nc"
    if not path.is_file():
        print(f"missing: {path}")
        return None
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


def along_sigma(reports: list[xr.Dataset]) -> xr.Dataset:
    """P, P_low, P_high against sigma of the plateau point, from one or more reports."""
    curves = []
    for ds in reports:
        at = {"t_stop": PLATEAU_STOP, "asymmetry": PLATEAU_ASYMMETRY}
        sel = {k: v for k, v in at.items() if k in ds.dims}
        values = ds[["P", "P_low", "P_high", "stops"]].sel(sel, method="nearest")
        curves.append(values.reset_coords(drop=True))
    joined = xr.concat(curves, dim="sigma").sortby("sigma")
    return joined.where(joined["stops"] > 0, drop=True)


def measured(ds: xr.Dataset) -> xr.Dataset:
    """A one-curve report without its unmeasured points."""
    ds = ds.squeeze(drop=True)
    return ds.where(ds["stops"] > 0, drop=True)


def print_points(label: str, curve: xr.Dataset) -> None:
    names = ("sigma", "P", "P_low", "P_high", "stops")
    for s, p, lo, hi, n in zip(*(curve[k].values for k in names), strict=True):
        print(f"   {label} at sigma = {s:.3g}: {p:.3f} [{lo:.3f}, {hi:.3f}] ({int(n)} stops)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT / "data")
    args = parser.parse_args()
    calibration = load(args.data, "science_calibration")
    fig5 = load(args.data, "fig5")
    decay = load(args.data, "science_one_intensity_decay")
    plateau = load(args.data, "science_one_intensity_plateau")
    if calibration is not None:
        cal = report_crossing(along_sigma([calibration]), PLATEAU, "sigma", falling=False)
        print(f"1. plateau P(3, 2e-5) = 0.2: {cal.describe('sigma')}")
    if fig5 is not None:
        found = report_crossing(fig5.squeeze(drop=True), DECAY_LEVEL)
        print(f"2. decay at the calibrated sigma, Delta = 0: {found.describe()}")
        if found.value is not None:
            inside = (found.low or -np.inf) <= DECAY_STOP <= (found.high or np.inf)
            print(f"   the paper's 1.4 {'lies' if inside else 'does not lie'} in it")
    if decay is None:
        return
    curve = measured(decay)
    print_points("P(1.4, Delta = 0)", curve)
    s14 = report_crossing(curve, DECAY_LEVEL, x_dim="sigma")
    print(f"3. decay at 1.4, P(1.4, Delta = 0) = 0.75: {s14.describe('sigma')}")
    if s14.low is None or calibration is None:
        print("4. sigma_1.4 is not bounded from below by these points")
        return
    reports = [calibration] + ([plateau] if plateau is not None else [])
    curve = along_sigma(reports)
    s = curve["sigma"].values
    print_points("P(3, 2e-5)", curve)
    # P(3, 2e-5) rises with sigma: at sigma_1.4 it is at least its lower bound at the
    # lower end of sigma_1.4's interval, at most its upper bound at the upper end; past
    # the last plateau point np.interp holds that point's bound, which still bounds it
    low = float(np.interp(s14.low, s, curve["P_low"].values))
    text = f"4. plateau at sigma_1.4: P(3, 2e-5) >= {low:.3f}"
    if s14.value is not None and s14.value <= s.max():
        value = float(np.interp(s14.value, s, curve["P"].values))
        text += f", estimate {value:.3f}"
    if s14.high is not None and s14.high <= s.max():
        text += f", <= {float(np.interp(s14.high, s, curve['P_high'].values)):.3f}"
    print(f"{text} (95 %)")
    verdict = "cannot give both" if low > PLATEAU else "may give both"
    print(
        f"answer: one intensity {verdict}: where the decay sits at 1.4 (sigma >= "
        f"{s14.low:.3g}) the plateau is at least {low:.2f}, against the paper's {PLATEAU:g}"
    )


if __name__ == "__main__":
    main()
