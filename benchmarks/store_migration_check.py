"""Do the committed sweep stores still give the committed reports?

Every stored report that a sweep directory of the repository produced is regenerated
from that directory (:func:`pde_rotor.sweep.gather`, which reads the store) and compared
with the committed file: every count variable (integers: inversions, stops, runs_done,
...) must be identical and every float variable equal to within :data:`FLOAT_TOLERANCE`
(NaN where the committed one is NaN); the largest float difference is printed, so a
change of the last bit (a Wilson bound now computed by scipy instead of the closed form,
1e-16) shows without failing the check. ``data/NAME.nc`` is the report of
``data/sweeps/NAME`` for the design in ``configs/sweeps/NAME.yaml`` or, where it was
written for a subset of that design, for the design recorded in the directory's
sweep.yaml (the one whose axis values are the report's coordinates);
``data/sweeps/NAME/report.nc`` is the report of the directory's own design. Run it
before and after a change of the store (e.g. ``pde-rotor compact``): one line per
report, exit status 1 if any differs.

    python benchmarks/store_migration_check.py [DATA_DIR]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from pde_rotor.sweep import Sweep, gather

ROOT = Path(__file__).resolve().parents[1]
FLOAT_TOLERANCE = 1e-12
"""Largest absolute difference of a float variable (probabilities and their bounds)."""


def reports(data: Path) -> list[tuple[Path, list[Sweep], Path]]:
    """(committed report, the designs it may be of, its sweep directory) of every stored
    report that a sweep directory under `data`/sweeps produced."""
    found = []
    for sweep_dir in sorted((data / "sweeps").iterdir()):
        if not (sweep_dir / "sweep.yaml").is_file():
            continue
        recorded = Sweep.load(sweep_dir)
        sweep_file = ROOT / "configs" / "sweeps" / f"{sweep_dir.name}.yaml"
        if (data / f"{sweep_dir.name}.nc").is_file() and sweep_file.is_file():
            designs = [Sweep.load(sweep_file), recorded]
            found.append((data / f"{sweep_dir.name}.nc", designs, sweep_dir))
        if (sweep_dir / "report.nc").is_file():
            found.append((sweep_dir / "report.nc", [recorded], sweep_dir))
    return found


def regenerate(committed: xr.Dataset, designs: list[Sweep], sweep_dir: Path) -> xr.Dataset:
    """The report of `sweep_dir` for the first of `designs` with the coordinates of
    `committed` (the last one where none has them)."""
    for design in designs:
        regenerated = gather(design, sweep_dir)
        if regenerated.coords.to_dataset().equals(committed.coords.to_dataset()):
            break
    return regenerated


def compare(committed: xr.Dataset, regenerated: xr.Dataset) -> tuple[list[str], float]:
    """Names of the variables of `committed` that `regenerated` lacks or changes, and the
    largest difference of a float variable."""
    differ, largest = [], 0.0
    for name, variable in committed.data_vars.items():
        if name not in regenerated:
            differ.append(f"{name} (missing)")
            continue
        new = regenerated[name].transpose(*variable.dims).values
        old = variable.values
        if np.issubdtype(old.dtype, np.floating):
            same = old.shape == new.shape and np.array_equal(np.isnan(old), np.isnan(new))
            if same:
                gap = np.abs(np.nan_to_num(new) - np.nan_to_num(old))
                largest = max(largest, float(gap.max(initial=0.0)))
                same = bool((gap <= FLOAT_TOLERANCE).all())
        else:
            same = old.dtype == new.dtype and np.array_equal(old, new)
        if not same:
            differ.append(name)
    return differ, largest


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", type=Path, nargs="?", default=ROOT / "data")
    args = parser.parse_args()
    failed = 0
    for path, designs, sweep_dir in reports(args.data):
        with xr.open_dataset(path, engine="h5netcdf") as stored:
            committed = stored.load()
        regenerated = regenerate(committed, designs, sweep_dir)
        differ, largest = compare(committed, regenerated)
        counts = {
            name: int(committed[name].sum())
            for name in ("runs_done", "runs_expected", "stops", "inversions")
        }
        n_count = sum(not np.issubdtype(v.dtype, np.floating) for v in committed.data_vars.values())
        n_float = len(committed.data_vars) - n_count
        where = f"{path.relative_to(args.data.parent)} <- {sweep_dir.relative_to(args.data.parent)}"
        summary = ", ".join(f"{k} {v}" for k, v in counts.items())
        verdict = (
            f"DIFFER: {', '.join(differ)}" if differ else f"identical (floats within {largest:.1g})"
        )
        print(f"{where}: {summary}; {n_count} count and {n_float} float variables {verdict}")
        failed += bool(differ)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
