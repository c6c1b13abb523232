"""The cut cells of a vessel (``grid.vessel``): an annular channel or a rectangular tank.

Each wall is a circle arc or a straight line, so the part of a cell inside the vessel
(kappa) and the open part of a face (alpha) are exact (:mod:`pde_rotor.model.wall` for
the circle; products and intersections of intervals for the tank's sides). An annulus is
the outer disk less the inner one: kappa = kappa_out - kappa_in and alpha = alpha_out -
alpha_in, exact where the channel is wider than a cell (the schema asks for four).

A ``no_flux`` wall is its cut cells: camphor crosses only the open part of each face, so
the total sum kappa c dx^2 changes only by sublimation and the sources. An ``absorbing``
wall is the paper's dish wall on a staircase: the cells whose centre lies inside hold c
(kappa = 1), those beyond hold c = 0, and the face between the two is fully open, so
that camphor leaves through it (:func:`pde_rotor.model.wall.assemble_cut_cells`).

The flow v evolves on the cells whose centre lies inside the vessel and is 0 on all
others: the no-slip wall (docs/numerics.md, "Vessels"). One cut-cell step serves every
vessel (:func:`pde_rotor.model.wall.make_wall_step`, compiled in
:mod:`pde_rotor.kernels.wall`), walking only the runs of wet cells of each row.
"""

from __future__ import annotations

import numpy as np

from ..config.vessel import AnnulusVessel, RectangleVessel
from .wall import CutCells, assemble_cut_cells, cell_faces, disk_fractions


def _staircase(inside: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fractions of the absorbing wall: a cell is in by its centre, a face between two."""
    volume = inside.astype(float)
    open_x = (inside & np.roll(inside, -1, axis=0)).astype(float)
    open_y = (inside & np.roll(inside, -1, axis=1)).astype(float)
    return volume, open_x, open_y


def _interval(lo: np.ndarray, hi: np.ndarray, half: float) -> np.ndarray:
    """Length of [lo, hi] inside [-half, half]."""
    return np.clip(np.minimum(hi, half) - np.maximum(lo, -half), 0.0, None)


def rectangle_fractions(
    coords: np.ndarray, half_widths: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact volume and face fractions of the rectangle |x| < a, |y| < b on the grid
    (as :func:`pde_rotor.model.wall.disk_fractions` returns them)."""
    a, b = half_widths
    faces, dx = cell_faces(coords)
    along_x = _interval(faces[:-1], faces[1:], a) / dx
    along_y = _interval(faces[:-1], faces[1:], b) / dx
    volume = along_x[:, None] * along_y[None, :]
    open_x = (np.abs(faces[1:]) < a)[:, None] * along_y[None, :]
    open_y = along_x[:, None] * (np.abs(faces[1:]) < b)[None, :]
    return volume, open_x, open_y


def make_vessel_cells(coords: np.ndarray, vessel: AnnulusVessel | RectangleVessel) -> CutCells:
    """The cut cells of `vessel` about 0 on the square grid of `coords` (see the module).

    Args:
        coords: cell-centre coordinates along either axis, from the vessel's centre.
        vessel: the annulus or rectangle of ``grid.vessel``.

    Returns:
        The :class:`~pde_rotor.model.wall.CutCells`; v evolves where the cell centre
        lies inside.

    Raises:
        ValueError: if the vessel reaches the grid's outermost ring of cells.
    """
    x, y = np.meshgrid(coords, coords, indexing="ij")
    _, dx = cell_faces(coords)
    if isinstance(vessel, RectangleVessel):
        a, b = vessel.half_widths
        inside = (np.abs(x) < a) & (np.abs(y) < b)
        if vessel.wall == "absorbing":
            return assemble_cut_cells(*_staircase(inside), inside, dx, sink=~inside)
        return assemble_cut_cells(*rectangle_fractions(coords, (a, b)), inside, dx)
    r2 = x**2 + y**2
    outer = r2 < vessel.outer_radius**2
    hole = r2 <= vessel.inner_radius**2
    sink = np.zeros_like(outer)
    if vessel.outer_wall == "absorbing":
        out = _staircase(outer)
        sink |= ~outer
    else:
        out = disk_fractions(coords, vessel.outer_radius)
    if vessel.inner_wall == "absorbing":
        inner = _staircase(hole)
        sink |= hole
    else:
        inner = disk_fractions(coords, vessel.inner_radius)
    volume, open_x, open_y = (np.clip(o - i, 0.0, 1.0) for o, i in zip(out, inner, strict=True))
    return assemble_cut_cells(volume, open_x, open_y, outer & ~hole, dx, sink=sink)
