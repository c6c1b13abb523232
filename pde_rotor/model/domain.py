"""Computational domain: a py-pde CartesianGrid covering the disk of radius L.

The paper integrates on "a circular region with a radius of 3" with c = 0 and v = 0 at
the boundary (section "Numerical results"). We use a square CartesianGrid with one
extra ring of cells beyond the disk, so that every cell on the border of the square
lies outside the disk: interior cells (centre radius < L) are updated, all others hold
0 at all times (Dirichlet data on and outside the circle). py-pde's own boundary
conditions on the square therefore never influence an interior cell.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from pde import CartesianGrid

from ..config import GridConfig
from .geometry import RotorShape, support_rows


@dataclass(frozen=True)
class Domain:
    """The grid and the index ranges the compiled kernels loop over.

    Attributes:
        grid: square py-pde CartesianGrid, n x n cells of side dx.
        coords: cell-centre coordinates along either axis (x for axis 0, y for axis 1).
        dx: grid spacing.
        radius: L, radius of the circular domain.
        interior_lo, interior_hi: per row i, the column range [lo, hi) of cells with
            centre radius < L.
        support_lo, support_hi: per row i, the column range of cells within
            :attr:`RotorShape.support_radius`, the only cells where F or G can be nonzero.
    """

    grid: CartesianGrid
    coords: np.ndarray
    dx: float
    radius: float
    interior_lo: np.ndarray
    interior_hi: np.ndarray
    support_lo: np.ndarray
    support_hi: np.ndarray

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(coords, interior_lo, interior_hi, support_lo, support_hi): the `domain` the
        compiled kernels take (:func:`pde_rotor.kernels.cpu.advance`)."""
        return self.coords, self.interior_lo, self.interior_hi, self.support_lo, self.support_hi

    @property
    def interior_mask(self) -> np.ndarray:
        """Boolean (n, n) array, True on cells with centre radius < L."""
        x, y = np.meshgrid(self.coords, self.coords, indexing="ij")
        return x**2 + y**2 < self.radius**2

    @property
    def support_mask(self) -> np.ndarray:
        """Boolean (n, n) array, True on the cells where F or G may be nonzero."""
        columns = np.arange(self.coords.size)
        return (columns >= self.support_lo[:, None]) & (columns < self.support_hi[:, None])

    @property
    def cell_area(self) -> float:
        """Area of one cell, dx^2."""
        return self.dx**2


def make_domain(grid_config: GridConfig, shape: RotorShape) -> Domain:
    """Build the square grid around the disk of radius L and the kernels' loop ranges.

    Args:
        grid_config: the grid section of the run configuration.
        shape: the rotor shape (fixes the support of F and G).

    Returns:
        The :class:`Domain`. With L = 3 and dx = 0.025 the grid has 242 x 242 cells.

    Raises:
        ValueError: if the support of F and G reaches the circle (the kernels read the
            neighbours of every support cell, which must be interior).
    """
    dx = grid_config.dx
    radius = grid_config.domain_radius
    if shape.support_radius + dx >= radius:
        msg = (
            f"grid.domain_radius = {radius:g} must exceed the support of F and G plus one "
            f"cell, {shape.support_radius + dx:.4g}"
        )
        raise ValueError(msg)
    n = 2 * math.ceil(radius / dx - 1e-9) + 2
    half = n * dx / 2
    grid = CartesianGrid([[-half, half], [-half, half]], [n, n])
    coords = np.asarray(grid.axes_coords[0], dtype=float)
    interior_lo, interior_hi = support_rows(coords, radius)
    support_lo, support_hi = support_rows(coords, shape.support_radius)
    return Domain(
        grid=grid,
        coords=coords,
        dx=dx,
        radius=radius,
        interior_lo=interior_lo,
        interior_hi=interior_hi,
        support_lo=support_lo,
        support_hi=support_hi,
    )
