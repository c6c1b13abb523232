"""Computational domain: a py-pde CartesianGrid covering the disk of radius L.

The paper integrates on "a circular region with a radius of 3" with c = 0 and v = 0 at
the boundary (section "Numerical results"). We use a square CartesianGrid with one
extra ring of cells beyond the disk, so that every cell on the border of the square
lies outside the disk: interior cells (centre radius < L) are updated, all others hold
0 at all times (Dirichlet data on and outside the circle). py-pde's own boundary
conditions on the square therefore never influence an interior cell.

The dish may sit anywhere (``grid.domain_centre``, for several bodies on one surface):
the grid covers the square about its centre, and the coordinates the kernels loop over
(:attr:`Domain.coords`) are measured from that centre, the same along both axes; a body
at X lies at X - centre in that frame (:meth:`Domain.dish_frame`).

With ``grid.wall: no_flux`` the camphor field c lives on the cut cells of the circle
instead (:mod:`pde_rotor.model.wall`, :attr:`Domain.cut_cells`): every cell the circle
covers in part holds c, with its volume fraction and its faces' apertures, while v keeps
v = 0 on the cells whose centre lies outside (the solid wall's no-slip).

With ``grid.vessel`` (an annular channel or a rectangular tank about the centre) c lives
on the vessel's cut cells (:mod:`pde_rotor.model.vessel`) and v on the cells whose centre
lies inside it; :attr:`Domain.radius` is then ``grid.domain_radius``, the half side of
the square that holds the vessel, and the rows' interior ranges span the vessel's cells of
each row (an annulus' hole included: :attr:`Domain.interior_mask` leaves it out).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from pde import CartesianGrid

from ..config import GridConfig
from .geometry import RotorShape, support_rows
from .vessel import make_vessel_cells
from .wall import CutCells, make_cut_cells


@dataclass(frozen=True)
class Domain:
    """The grid and the index ranges the compiled kernels loop over.

    Attributes:
        grid: square py-pde CartesianGrid, n x n cells of side dx, about the dish centre.
        coords: cell-centre coordinates along either axis (x for axis 0, y for axis 1),
            measured from the dish centre (the frame of the kernels).
        dx: grid spacing.
        radius: L, radius of the circular domain.
        interior_lo, interior_hi: per row i, the column range [lo, hi) of cells with
            centre radius < L.
        support_lo, support_hi: per row i, the column range of cells within
            :attr:`RotorShape.support_radius` of the rotor's axis (the origin), the only
            cells where F or G can be nonzero.
        centre: (x, y) of the dish centre (``grid.domain_centre``).
        cut_cells: the cut cells of the circle that hold c behind a no-flux wall
            (``grid.wall: no_flux``) or of the vessel (``grid.vessel``); None with the
            absorbing dish wall.
    """

    grid: CartesianGrid
    coords: np.ndarray
    dx: float
    radius: float
    interior_lo: np.ndarray
    interior_hi: np.ndarray
    support_lo: np.ndarray
    support_hi: np.ndarray
    centre: tuple[float, float] = (0.0, 0.0)
    cut_cells: CutCells | None = None

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(coords, interior_lo, interior_hi, support_lo, support_hi): the `domain` the
        compiled kernels take (:func:`pde_rotor.kernels.cpu.advance`)."""
        return self.coords, self.interior_lo, self.interior_hi, self.support_lo, self.support_hi

    @property
    def x_coords(self) -> np.ndarray:
        """x of the cell centres along axis 0: centre x + :attr:`coords`."""
        return self.centre[0] + self.coords

    @property
    def y_coords(self) -> np.ndarray:
        """y of the cell centres along axis 1: centre y + :attr:`coords`."""
        return self.centre[1] + self.coords

    def dish_frame(self, x: float, y: float) -> tuple[float, float]:
        """A point (x, y) in the frame of :attr:`coords`: (x, y) - centre."""
        return x - self.centre[0], y - self.centre[1]

    @property
    def interior_mask(self) -> np.ndarray:
        """Boolean (n, n) array, True on cells with centre radius < L (in a vessel: on
        the cells whose centre lies inside it, where v evolves)."""
        if self.cut_cells is not None:
            return self.cut_cells.flowing
        x, y = np.meshgrid(self.coords, self.coords, indexing="ij")
        return x**2 + y**2 < self.radius**2

    @property
    def camphor_mask(self) -> np.ndarray:
        """Boolean (n, n) array, True on the cells that hold c: :attr:`interior_mask`
        with the absorbing wall, every cell the circle covers in part with the no-flux
        wall."""
        return self.interior_mask if self.cut_cells is None else self.cut_cells.mask

    def camphor_total(self, c: np.ndarray) -> float:
        """The camphor in the dish: sum of c dA over the cells that hold it (each cut
        cell's part inside the circle with the no-flux wall)."""
        if self.cut_cells is None:
            return float(np.sum(c * self.interior_mask)) * self.cell_area
        return self.cut_cells.total(c)

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
        grid_config: the grid section of the run configuration (its domain_centre
            places the dish).
        shape: the rotor shape (fixes the support of F and G about the origin).

    Returns:
        The :class:`Domain`. With L = 3 and dx = 0.025 the grid has 242 x 242 cells.

    Raises:
        ValueError: if the support of F and G reaches the circle (the kernels read the
            neighbours of every support cell, which must be interior).
    """
    dx = grid_config.dx
    radius = grid_config.domain_radius
    cx, cy = grid_config.domain_centre
    if math.hypot(cx, cy) + shape.support_radius + dx >= radius:
        msg = (
            f"grid.domain_radius = {radius:g} must exceed the support of F and G plus one "
            f"cell, {shape.support_radius + dx:.4g}, beyond the rotor's distance from the "
            f"dish centre, {math.hypot(cx, cy):.4g}"
        )
        raise ValueError(msg)
    n = 2 * math.ceil(radius / dx - 1e-9) + 2
    half = n * dx / 2
    coords = np.asarray(CartesianGrid([[-half, half]], [n]).axes_coords[0], dtype=float)
    grid = CartesianGrid([[cx - half, cx + half], [cy - half, cy + half]], [n, n])
    interior_lo, interior_hi = support_rows(coords, radius)
    cut_cells = make_cut_cells(coords, radius) if grid_config.wall == "no_flux" else None
    if grid_config.vessel is not None:
        cut_cells = make_vessel_cells(coords, grid_config.vessel)
        wet = cut_cells.flowing
        rows = wet.any(axis=1)
        interior_lo = np.where(rows, np.argmax(wet, axis=1), 0).astype(np.int64)
        interior_hi = np.where(rows, n - np.argmax(wet[:, ::-1], axis=1), 0).astype(np.int64)
    support_lo, support_hi = support_rows(coords, shape.support_radius, centre=(-cx, -cy))
    return Domain(
        grid=grid,
        coords=coords,
        dx=dx,
        radius=radius,
        interior_lo=interior_lo,
        interior_hi=interior_hi,
        support_lo=support_lo,
        support_hi=support_hi,
        centre=(cx, cy),
        cut_cells=cut_cells,
    )
