"""The implicit cut cells' clusters of a vessel: how many, how large, what a dense inverse
and the sparse factors cost a step.

For each config given (a run config with ``grid.wall: no_flux`` or ``grid.vessel``) and
for the three vessels of ``benchmarks/vessel_step.py`` (the ring sweep's annulus, the
narrow annulus, the full box, on the ring sweep's grid), it prints the wet and stiff
cells, the clusters (:func:`pde_rotor.model.clusters.cluster_matrices`, coefficient
dt D / dx^2 of the run): their count, the cells in them, the largest, and sum size^2,
the multiply-adds a step of the dense inverses the step applied before; and the sparse
factors' rows (:func:`pde_rotor.model.clusters.implicit_factors`), the later cells a row
(1: every cluster a tree) and the levels, the factors' multiply-adds a step being
2 x rows x later cells.

Run:  python benchmarks/cluster_sizes.py [configs/bodies/disk_in_dish.yaml ...]
"""

from __future__ import annotations

import argparse

import numpy as np
from vessel_step import DT, DX, VESSELS, N

from pde_rotor.config.yaml_io import load_config
from pde_rotor.model.clusters import cluster_matrices, implicit_factors
from pde_rotor.model.surface import SurfacePDE
from pde_rotor.model.vessel import make_vessel_cells
from pde_rotor.model.wall import CutCells


def report(name: str, cells: CutCells, coefficient: float) -> None:
    """One line of the clusters of `cells`."""
    sizes = np.array([m.size for m, _ in cluster_matrices(cells, coefficient)], np.int64)
    index, levels, _ = implicit_factors(cells, coefficient)
    line = f"{name}: {int(cells.mask.sum())} wet cells, {int(cells.stiff.sum())} stiff"
    if sizes.size:
        values, counts = np.unique(sizes, return_counts=True)
        by_size = ", ".join(f"{s}: {c}" for s, c in zip(values, counts, strict=True))
        line += (
            f"; {sizes.size} clusters, {sizes.sum()} cells, largest {sizes.max()}, "
            f"sum size^2 {int((sizes**2).sum())}; factors: {index.shape[0]} rows, "
            f"{index.shape[1] - 1} later cells a row, {levels.size - 1} levels; "
            f"clusters by size {{{by_size}}}"
        )
    print(line)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("configs", nargs="*", help="run configs with cut cells")
    args = parser.parse_args()
    coords = (np.arange(N) - (N - 1) / 2) * DX
    for name, vessel in VESSELS.items():
        report(f"{name} (dx = {DX:g})", make_vessel_cells(coords, vessel), DT / DX**2)
    for path in args.configs:
        config = load_config(path)
        cells = SurfacePDE(config).domain.cut_cells
        if cells is None:
            parser.error(f"{path}: no cut cells (neither grid.wall: no_flux nor grid.vessel)")
        grid = config.grid
        report(f"{path} (dx = {grid.dx:g})", cells, grid.dt * config.camphor.diffusion / grid.dx**2)


if __name__ == "__main__":
    main()
