"""The no-flux dish wall: cut cells of the circle r = L and their conservative Laplacian.

``grid.wall: no_flux`` holds the camphor in the dish (dc/dr = 0 at r = L, the wall of the
experiments of Koyano, Suematsu & Kitahata, PRE 99, 022211 (2019)). A staircase of whole
cells would put the wall on the grid's lines, so the camphor field instead lives on the
cut cells of the circle (an embedded boundary), finite volumes whose geometry is computed
once per grid (:func:`make_cut_cells`):

* the volume fraction kappa of each cell, the part of the cell inside the circle (exact:
  the area of a rectangle cut by a disk);
* the aperture alpha of each face, the part of the face inside the circle (exact).

Camphor crosses only the open part of a face: the flux of Eq. (eqc) through a face between
cells P and N is D alpha (c_N - c_P) / dx by diffusion and alpha (c v . n)_face by
advection (the mean of the two cells' c v, so that a full cell gives the 5-point
Laplacian and the central divergence of the absorbing wall), and nothing crosses the
circle itself. Each face's flux leaves one cell and enters the other, so the total
sum_P kappa_P c_P dx^2 changes only by the sublimation and the sources: with both off it
is conserved to round-off.

A cut cell can be arbitrarily small (kappa -> 0), and the conservative rate Q / kappa of an
explicit step would then need dt -> 0. The rate of every cut cell is therefore the hybrid of
flux redistribution (Chern & Colella 1987; Pember et al., J. Comput. Phys. 120, 278
(1995)): the cell keeps kappa Q / kappa + (1 - kappa) D_nc, D_nc the volume-weighted mean
of the conservative rates over its 3 x 3 neighbourhood (sum Q / sum kappa), and the camphor
this leaves over, (1 - kappa) (Q - kappa D_nc), goes to its neighbours in proportion to
their volume. Nothing is lost, no rate has a small divisor, and the stiffest rate stays that
of a full cell (the 5-point Laplacian's dt limit holds; ``tests/model/test_wall.py``). On
the circle the discrete Neumann eigenvalues converge at second order in dx.

The flow v keeps the solid wall's no-slip v = 0 on the cells whose centre lies outside
the circle (:mod:`pde_rotor.model.domain`); advection therefore carries no camphor through
the wall, and none through a closed face.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class CutCells:
    """The cut-cell geometry of the circle r = L on a square grid (see the module).

    Attributes:
        volume: (n, n) volume fraction kappa of each cell (1 inside, 0 outside).
        aperture_x: (n, n) open fraction of the face between cells (i, j) and (i + 1, j).
        aperture_y: (n, n) open fraction of the face between cells (i, j) and (i, j + 1).
        cut: flat indices (i n + j) of the cut cells, 0 < kappa < 1.
        near: (n, n) sum of kappa over the 3 x 3 neighbourhood of each cell (itself
            included).
        lo, hi: per row i, the column range [lo, hi) of cells with kappa > 0.
        dx: grid spacing.
    """

    volume: np.ndarray
    aperture_x: np.ndarray
    aperture_y: np.ndarray
    cut: np.ndarray
    near: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    dx: float

    def arrays(self) -> tuple[np.ndarray, ...]:
        """(volume, aperture_x, aperture_y, cut, near, lo, hi), the 2-D arrays flattened:
        the `wall` the compiled step takes (:mod:`pde_rotor.kernels.wall`)."""
        return (
            self.volume.reshape(-1),
            self.aperture_x.reshape(-1),
            self.aperture_y.reshape(-1),
            self.cut,
            self.near.reshape(-1),
            self.lo,
            self.hi,
        )

    @property
    def mask(self) -> np.ndarray:
        """Boolean (n, n): the cells that hold camphor (kappa > 0)."""
        return self.volume > 0

    def total(self, c: np.ndarray) -> float:
        """sum_P kappa_P c_P dx^2: the camphor in the dish."""
        return float(np.sum(self.volume * c)) * self.dx**2


def _quadrant_area(x: np.ndarray, y: np.ndarray, radius: float) -> np.ndarray:
    """Area of {0 < X < x, 0 < Y < y, X^2 + Y^2 < L^2}, odd in x and in y."""
    sx, sy = np.sign(x), np.sign(y)
    a = np.minimum(np.abs(x), radius)
    b = np.minimum(np.abs(y), radius)
    inside = a * a + b * b <= radius * radius
    cross = np.sqrt((radius - b) * (radius + b))  # where Y = b meets the circle

    def primitive(t: np.ndarray) -> np.ndarray:
        """int_0^t sqrt(L^2 - X^2) dX for 0 <= t <= L, without cancellation near L."""
        root = np.sqrt((radius - t) * (radius + t))
        return 0.5 * (t * root + radius**2 * np.arctan2(t, root))

    capped = cross * b + primitive(a) - primitive(np.minimum(cross, a))
    return sx * sy * np.where(inside, a * b, capped)


def _open_length(lo: np.ndarray, hi: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Length of [lo, hi] inside [-half, half]."""
    return np.clip(np.minimum(hi, half) - np.maximum(lo, -half), 0.0, None)


TINY = 1e-10
"""Volume fractions below this are round-off of a cell that touches the circle: 0."""


def make_cut_cells(coords: np.ndarray, radius: float) -> CutCells:
    """The cut cells of the circle of radius `radius` about 0 on the grid of `coords`.

    Args:
        coords: cell-centre coordinates along either axis (uniform, the same along both,
            :attr:`pde_rotor.model.domain.Domain.coords`); the outermost ring of cells
            must lie outside the circle.
        radius: L.

    Returns:
        The :class:`CutCells`.

    Raises:
        ValueError: if the circle reaches the grid's outermost ring of cells.
    """
    n = coords.size
    dx = float(coords[1] - coords[0])
    faces = np.append(coords - dx / 2, coords[-1] + dx / 2)
    x0, x1 = faces[:-1, None], faces[1:, None]
    y0, y1 = faces[None, :-1], faces[None, 1:]
    area = (
        _quadrant_area(x1, y1, radius)
        - _quadrant_area(x0, y1, radius)
        - _quadrant_area(x1, y0, radius)
        + _quadrant_area(x0, y0, radius)
    )
    far = np.maximum(x0**2, x1**2) + np.maximum(y0**2, y1**2)
    volume = np.where(far <= radius**2, 1.0, np.clip(area / dx**2, 0.0, 1.0))
    volume = np.where(volume > TINY, volume, 0.0)
    if volume[[0, -1], :].any() or volume[:, [0, -1]].any():
        msg = f"the circle of radius {radius:g} reaches the grid's outermost cells"
        raise ValueError(msg)
    held = volume > 0
    # the face at x = faces[i + 1] between cells i and i + 1, open where y^2 < L^2 - x^2
    half = np.sqrt(np.clip((radius - faces[1:]) * (radius + faces[1:]), 0.0, None))
    aperture_x = np.where(
        held & np.roll(held, -1, axis=0), _open_length(y0, y1, half[:, None]) / dx, 0.0
    )
    aperture_y = np.where(
        held & np.roll(held, -1, axis=1), _open_length(x0, x1, half[None, :]) / dx, 0.0
    )
    near = sum(np.roll(volume, (di, dj), axis=(0, 1)) for di in (-1, 0, 1) for dj in (-1, 0, 1))
    cols = np.arange(n)
    lo = np.where(held.any(axis=1), np.argmax(held, axis=1), 0).astype(np.int64)
    hi = np.where(held.any(axis=1), n - np.argmax(held[:, ::-1], axis=1), 0).astype(np.int64)
    if not np.array_equal(held, (cols >= lo[:, None]) & (cols < hi[:, None])):
        msg = "the cells inside the circle are not one run per row"
        raise ValueError(msg)
    return CutCells(
        volume=volume,
        aperture_x=aperture_x,
        aperture_y=aperture_y,
        cut=np.flatnonzero(held & (volume < 1.0)).astype(np.int64),
        near=np.where(held, near, 0.0),
        lo=lo,
        hi=hi,
        dx=dx,
    )


def wall_fluxes(
    c: np.ndarray, v: np.ndarray | None, cells: CutCells, diffusion: float
) -> np.ndarray:
    """Net inflow of camphor into each cut cell by Eq. (eqc)'s diffusion and advection.

    Q_P = D / dx^2 sum_f alpha_f (c_N - c_P) - 1 / (2 dx) sum_f alpha_f n_f . (c v_P + c v_N)
    over the four faces f of cell P, N across f, n_f the outward normal: the rate of c of a
    full cell (kappa = 1), the inflow per dx^2 of a cut one.

    Args:
        c: (n, n) the camphor field (0 outside the circle).
        v: (2, n, n) the flow, or None without flow.
        cells: the cut cells.
        diffusion: D.

    Returns:
        (n, n) Q, 0 outside the circle.
    """
    dx = cells.dx
    q = np.zeros_like(c)
    for axis, aperture in ((0, cells.aperture_x), (1, cells.aperture_y)):
        ahead = np.roll(c, -1, axis=axis)
        flux = aperture * diffusion * (ahead - c) / dx**2  # from the next cell into this one
        if v is not None:
            cv = c * v[axis]
            flux -= aperture * (cv + np.roll(cv, -1, axis=axis)) / (2 * dx)
        q += flux
        q -= np.roll(flux, 1, axis=axis)
    return np.where(cells.mask, q, 0.0)


def redistributed_rate(inflow: np.ndarray, cells: CutCells) -> np.ndarray:
    """The rate of c of every cell from its inflow Q, with flux redistribution (the module).

    A full cell gets Q; a cut cell P the hybrid Q_P + (1 - kappa_P) D_nc, D_nc = sum Q /
    sum kappa over its 3 x 3 neighbourhood, and each of its neighbours N the share
    (1 - kappa_P) (Q_P - kappa_P D_nc) / (sum kappa over the neighbours), so that
    sum_P kappa_P rate_P = sum_P Q_P.

    Args:
        inflow: (n, n) Q of :func:`wall_fluxes`.
        cells: the cut cells.

    Returns:
        (n, n) the rate of c by diffusion and advection, 0 outside the circle.
    """
    kappa = cells.volume
    cut = cells.mask & (kappa < 1.0)
    offsets = [(di, dj) for di in (-1, 0, 1) for dj in (-1, 0, 1)]
    mean = sum(np.roll(inflow, o, axis=(0, 1)) for o in offsets) / np.where(cut, cells.near, 1.0)
    mean = np.where(cut, mean, 0.0)
    left = (1.0 - kappa) * (inflow - kappa * mean)
    spread = np.where(cut, left / np.where(cut, cells.near - kappa, 1.0), 0.0)
    shares = sum(np.roll(spread, o, axis=(0, 1)) for o in offsets if o != (0, 0))
    return np.where(cells.mask, inflow + (1.0 - kappa) * mean + shares, 0.0)
