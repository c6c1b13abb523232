"""The implicit cut cells' clusters: their matrices and the sparse factors the step solves.

Behind a no-flux wall the diffusion through every face of a stiff cut cell is taken by
backward Euler (:mod:`pde_rotor.model.wall`). The faces join the cells into clusters,
connected sets of cells; cluster b's matrix

    A = diag(kappa) + coefficient * sum_{implicit f} alpha_f (e_P - e_N)(e_P - e_N)^T,

coefficient = dt D / dx^2, is symmetric and positive definite (kappa > 0 on every wet
cell, the faces' part a graph Laplacian, positive semi-definite), and the step solves
A c' = kappa c'_explicit on each cluster. Since 1^T A = kappa^T, the solve keeps
sum kappa c' to round-off: it moves camphor only through the faces.

The clusters lie along the walls, chains and rings of cells one to three wide, so that a
dense inverse (O(size^2) a step) grows with the walls' length times the cluster's size.
:func:`implicit_factors` orders each cluster by reverse Cuthill-McKee and factors
A = L D L^T once per run, L unit lower triangular: its nonzeros lie inside A's envelope
(no fill outside it). A cluster that is a tree of cells has no fill at all in this
order (the reverse of a breadth-first search eliminates each cell after its children),
so that each column of L holds one entry below the diagonal, the cell's parent; where
the cells close a loop a column holds a few. Forward substitution (each row's y taken
off its later rows) and back substitution (each row's c' from its later rows) read L by
columns and cost the cluster's size times the entries a column, 2 multiply-adds a cell
for a tree, a step (:func:`pde_rotor.kernels.wall.implicit_clusters`).

The rows of all clusters are interleaved level by level, row t of every cluster before
row t + 1 of any (level t), so that consecutive rows belong to different clusters and
do not wait on each other, and the CUDA step can take one level's rows in parallel
(:mod:`pde_rotor.kernels.cuda_bodies`). The numpy step
(:func:`pde_rotor.model.wall.make_wall_step`) instead applies each cluster's dense
inverse (:func:`cluster_matrices`): the independent check of the factors.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, reverse_cuthill_mckee


class CutCells(Protocol):
    """What the clusters read of :class:`pde_rotor.model.wall.CutCells`."""

    volume: np.ndarray
    aperture_x: np.ndarray
    aperture_y: np.ndarray
    implicit_x: np.ndarray
    implicit_y: np.ndarray


def implicit_faces(cells: CutCells) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(cell P, cell N, alpha) of every implicit face, flat indices."""
    n = cells.volume.shape[0]
    i, j = np.nonzero(cells.implicit_x)
    k, m = np.nonzero(cells.implicit_y)
    near = np.concatenate([i * n + j, k * n + m])
    far = np.concatenate([(i + 1) * n + j, k * n + m + 1])
    alpha = np.concatenate([cells.aperture_x[i, j], cells.aperture_y[k, m]])
    return near, far, alpha


def cluster_matrices(cells: CutCells, coefficient: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """The clusters of cells joined by implicit faces and their backward-Euler matrices.

    Args:
        cells: the cut cells.
        coefficient: dt D / dx^2.

    Returns:
        (members, A) per cluster: the flat indices of its cells (ascending) and its
        matrix A (see the module), row and column u for members[u].
    """
    near, far, alpha = implicit_faces(cells)
    size = cells.volume.size
    graph = sp.coo_matrix((np.ones(near.size), (near, far)), shape=(size, size))
    _, label = connected_components(graph, directed=False)
    nodes = np.unique(np.concatenate([near, far]))
    kappa = cells.volume.reshape(-1)
    clusters = []
    for group in np.unique(label[nodes]):
        members = nodes[label[nodes] == group]
        local = np.full(size, -1)
        local[members] = np.arange(members.size)
        inside = local[near] >= 0
        u, w, a = local[near[inside]], local[far[inside]], coefficient * alpha[inside]
        matrix = np.diag(kappa[members])
        np.add.at(matrix, (u, u), a)
        np.add.at(matrix, (w, w), a)
        np.add.at(matrix, (u, w), -a)
        np.add.at(matrix, (w, u), -a)
        clusters.append((members, matrix))
    return clusters


def _ordered_factor(matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(order, L, d) of one cluster: its reverse Cuthill-McKee order and the unit lower
    triangular L and diagonal d with A[order][:, order] = L diag(d) L^T."""
    order = reverse_cuthill_mckee(sp.csr_matrix(matrix), symmetric_mode=True)
    root = np.linalg.cholesky(matrix[np.ix_(order, order)])
    diagonal = np.diag(root)
    return order.astype(np.int64), root / diagonal, diagonal**2


def implicit_factors(
    cells: CutCells, coefficient: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The clusters' L D L^T factors, column by column, their rows interleaved by level.

    Row g of the solve is cell index[g, 0]; index[g, 1:] are the cells of its cluster's
    later rows that column g of L couples it to, nearest first (the first its parent in
    the elimination tree), padded at the end with the row's own cell; factor[g, 0] is
    1 / d and factor[g, 1:] those entries of L (0 for the padding). The rows
    levels[t]:levels[t + 1] are row t of each cluster that has one, the clusters largest
    first. A tree's rows hold one later cell (index and factor of 2 columns).

    Args:
        cells: the cut cells.
        coefficient: dt D / dx^2.

    Returns:
        (index, levels, factor).
    """
    clusters = sorted(cluster_matrices(cells, coefficient), key=lambda c: -c[0].size)
    factored = []
    width = 1
    for members, matrix in clusters:
        order, lower, d = _ordered_factor(matrix)
        coupled = np.tril(lower != 0, -1)
        width = max(width, int(coupled.sum(axis=0).max()))
        factored.append((members[order], lower, d, coupled))
    sizes = np.array([c[0].size for c in clusters], dtype=np.int64)
    counts = np.array([np.sum(sizes > t) for t in range(sizes.max(initial=0))], np.int64)
    levels = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    index = np.zeros((levels[-1], 1 + width), dtype=np.int64)
    factor = np.zeros((levels[-1], 1 + width))
    for b, (cells_in_order, lower, d, coupled) in enumerate(factored):
        for t, cell in enumerate(cells_in_order):
            g = levels[t] + b  # the clusters are sorted: b is its rank in level t
            later = np.nonzero(coupled[:, t])[0]  # ascending: nearest first
            index[g] = cell
            index[g, 1 : 1 + later.size] = cells_in_order[later]
            factor[g, 0] = 1.0 / d[t]
            factor[g, 1 : 1 + later.size] = lower[later, t]
    return index, levels, factor
