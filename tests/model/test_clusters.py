"""The implicit cut cells' clusters: their matrices are symmetric positive definite and
conserve camphor, and the sparse L D L^T factors the compiled step solves with are those
matrices, level by level, to round-off."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor.config.vessel import AnnulusVessel, RectangleVessel
from pde_rotor.model.clusters import cluster_matrices, implicit_factors
from pde_rotor.model.vessel import make_vessel_cells
from pde_rotor.model.wall import CutCells, make_cut_cells

COEFFICIENT = 0.2
"""dt D / dx^2 of the tests (the 5-point limit is 0.25)."""


def grid_coords(dx: float, radius: float = 1.0) -> np.ndarray:
    """Cell centres of the square grid of :func:`pde_rotor.model.domain.make_domain`."""
    n = 2 * math.ceil(radius / dx - 1e-9) + 2
    return (np.arange(n) + 0.5) * dx - n * dx / 2


VESSELS = {
    "dish": lambda c: make_cut_cells(c, 0.97),
    "annulus": lambda c: make_vessel_cells(
        c, AnnulusVessel(shape="annulus", inner_radius=0.43, outer_radius=0.97)
    ),
    "narrow annulus": lambda c: make_vessel_cells(
        c, AnnulusVessel(shape="annulus", inner_radius=0.8, outer_radius=0.97)
    ),
    "tank": lambda c: make_vessel_cells(
        c, RectangleVessel(shape="rectangle", half_widths=(0.93, 0.61))
    ),
}
"""Vessels whose walls cut the cells (the tank's at dx = 0.1 close one ring of cells)."""


def cells_of(vessel: str, dx: float) -> CutCells:
    return VESSELS[vessel](grid_coords(dx))


@pytest.mark.parametrize("vessel", list(VESSELS))
@pytest.mark.parametrize("dx", [0.1, 0.037])
def test_cluster_matrices_are_spd_and_keep_the_camphor(vessel: str, dx: float) -> None:
    """Each cluster's matrix is symmetric with a Cholesky factor (positive definite), its
    columns add up to the cells' kappa (1^T A = kappa^T: the solve keeps sum kappa c'),
    and the clusters are disjoint sets of the cells with kappa > 0 that hold every
    stiff cell."""
    cells = cells_of(vessel, dx)
    kappa = cells.volume.reshape(-1)
    clusters = cluster_matrices(cells, COEFFICIENT)
    assert clusters
    seen = np.concatenate([members for members, _ in clusters])
    assert np.unique(seen).size == seen.size
    assert np.all(kappa[seen] > 0)
    assert set(np.flatnonzero(cells.stiff)) <= set(seen)
    for members, matrix in clusters:
        assert np.array_equal(matrix, matrix.T)
        np.linalg.cholesky(matrix)
        scale = np.abs(matrix).max()
        assert np.abs(matrix.sum(axis=0) - kappa[members]).max() <= 1e-15 * scale


def dense_factor(index: np.ndarray, factor: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """L D L^T on the cells index[rows, 0], from the factor rows `rows` (one cluster)."""
    cells = index[rows, 0]
    where = {int(cell): u for u, cell in enumerate(cells)}
    lower = np.eye(rows.size)
    for u, g in enumerate(rows):
        for cell, weight in zip(index[g, 1:], factor[g, 1:], strict=True):
            if weight != 0.0:
                lower[where[int(cell)], u] = weight
    return lower @ np.diag(1.0 / factor[rows, 0]) @ lower.T


@pytest.mark.parametrize("vessel", list(VESSELS))
@pytest.mark.parametrize("dx", [0.1, 0.037])
def test_factors_are_the_cluster_matrices_level_by_level(vessel: str, dx: float) -> None:
    """Gathered cluster by cluster (row t of cluster b at levels[t] + b, the clusters
    largest first), L D L^T is the cluster's matrix to round-off; each row's later cells
    are its own cluster's at later levels (so that a level's rows are independent), and
    the padding is the row's own cell with weight 0."""
    cells = cells_of(vessel, dx)
    clusters = sorted(cluster_matrices(cells, COEFFICIENT), key=lambda c: -c[0].size)
    index, levels, factor = implicit_factors(cells, COEFFICIENT)
    assert index.shape == factor.shape
    assert levels[-1] == index.shape[0] == sum(m.size for m, _ in clusters)
    level_of = np.zeros(cells.volume.size, dtype=np.int64)
    for t in range(levels.size - 1):
        level_of[index[levels[t] : levels[t + 1], 0]] = t
    for b, (members, matrix) in enumerate(clusters):
        rows = np.array([levels[t] + b for t in range(members.size)])
        assert np.array_equal(np.sort(index[rows, 0]), members)
        order = np.searchsorted(members, index[rows, 0])
        product = dense_factor(index, factor, rows)
        expected = matrix[np.ix_(order, order)]
        assert np.abs(product - expected).max() <= 1e-14 * np.abs(matrix).max()
        later = index[rows, 1:]
        padded = factor[rows, 1:] == 0.0
        assert np.all(later[padded] == np.broadcast_to(index[rows, :1], later.shape)[padded])
        assert np.all(level_of[later[~padded]] > np.nonzero(~padded)[0])
        assert np.all(np.isin(later, members))


def test_trees_have_no_fill_and_a_ring_of_cells_some() -> None:
    """Clusters that are trees of cells (the dish's, the annulus') keep one later cell a
    row, their parent; the tank at dx = 0.1, whose stiff cells join into one ring round
    its walls, needs more (the ring's fill)."""
    for vessel in ("dish", "annulus", "narrow annulus"):
        index, _, _ = implicit_factors(cells_of(vessel, 0.037), COEFFICIENT)
        assert index.shape[1] == 2
    index, levels, _ = implicit_factors(cells_of("tank", 0.1), COEFFICIENT)
    assert levels.size == index.shape[0] + 1  # one cluster
    assert index.shape[1] > 2
