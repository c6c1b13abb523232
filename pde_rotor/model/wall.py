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

The cut-cell operator is symmetric (each face couples its two cells with the same weight
D alpha / dx^2) and negative semi-definite in the volume-weighted inner product, and its
discrete Neumann eigenvalues converge at second order in dx. But a cut cell can be
arbitrarily small (kappa -> 0): where the open apertures of a cell exceed 4 kappa (a
*stiff* cell, :attr:`CutCells.stiff`), a forward Euler step would need a smaller dt than
the 5-point Laplacian's. The diffusion through every face of a stiff cell is therefore
taken implicitly (backward Euler), the rest explicitly:

    kappa (c' - c) = dt [Q_E(c) + kappa r(c)] + dt D / dx^2 sum_{implicit f} alpha_f (c'_N - c'_P),

Q_E the explicit faces' diffusion and every face's advection, r the local terms of Eq.
(eqc). The implicit faces join a stiff cell to its neighbours in small clusters along the
rim (tens of cells), each solved exactly (:mod:`pde_rotor.model.clusters`: this numpy
step applies each cluster's inverse, the compiled step its sparse L D L^T factors, both
computed once per run). Both parts are sums of face fluxes, so nothing is lost; the
explicit part obeys the 5-point Laplacian's dt limit cell by cell (Gershgorin), the
implicit part is unconditionally stable, and the symmetric splitting is then stable as a
whole (:func:`make_wall_step`; the compiled step is :mod:`pde_rotor.kernels.wall`).

The flow v keeps the solid wall's no-slip v = 0 on the cells whose centre lies outside
the circle (:mod:`pde_rotor.model.domain`); advection therefore carries no camphor through
the wall, and none through a closed face.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from .clusters import cluster_matrices, implicit_factors


@dataclass(frozen=True)
class CutCells:
    """The cut-cell geometry of the circle r = L on a square grid (see the module).

    Attributes:
        volume: (n, n) volume fraction kappa of each cell (1 inside, 0 outside).
        aperture_x: (n, n) open fraction of the face between cells (i, j) and (i + 1, j).
        aperture_y: (n, n) open fraction of the face between cells (i, j) and (i, j + 1).
        stiff: (n, n) True on the cells whose open apertures add up to more than 4 kappa.
        implicit_x, implicit_y: (n, n) True on the open faces (as ``aperture_x``,
            ``aperture_y``) of a stiff cell, where the diffusion is implicit.
        row_start, span_lo, span_hi: the runs of cells with kappa > 0, row by row: the
            runs of row i are [span_lo[s], span_hi[s]) for row_start[i] <= s <
            row_start[i + 1] (one per row in a dish, two across an annulus' hole).
        flowing: (n, n) True on the cells where v evolves (centre inside the vessel; v = 0,
            the wall's no-slip, on the others).
        dx: grid spacing.
        _factors: the implicit clusters' factors by dt D / dx^2 (:meth:`arrays`), kept:
            every ``run`` builds its stepper anew.
    """

    volume: np.ndarray
    aperture_x: np.ndarray
    aperture_y: np.ndarray
    stiff: np.ndarray
    implicit_x: np.ndarray
    implicit_y: np.ndarray
    row_start: np.ndarray
    span_lo: np.ndarray
    span_hi: np.ndarray
    flowing: np.ndarray
    dx: float
    _factors: dict[float, tuple[np.ndarray, ...]] = field(
        default_factory=dict, init=False, compare=False, repr=False
    )

    def arrays(self, coefficient: float) -> tuple[np.ndarray, ...]:
        """The `wall` the compiled step takes (:mod:`pde_rotor.kernels.wall`), 2-D arrays
        flattened: (volume, aperture_x, aperture_y, explicit diffusion apertures along x
        and y, row_start, span_lo, span_hi, flowing as 0/1, and the implicit clusters'
        index, levels and factor, :func:`pde_rotor.model.clusters.implicit_factors`).

        Args:
            coefficient: dt D / dx^2 of the run.
        """
        if coefficient not in self._factors:  # once per geometry and dt: each run() asks
            self._factors[coefficient] = implicit_factors(self, coefficient)
        index, levels, factor = self._factors[coefficient]
        return (
            self.volume.reshape(-1),
            self.aperture_x.reshape(-1),
            self.aperture_y.reshape(-1),
            np.where(self.implicit_x, 0.0, self.aperture_x).reshape(-1),
            np.where(self.implicit_y, 0.0, self.aperture_y).reshape(-1),
            self.row_start,
            self.span_lo,
            self.span_hi,
            self.flowing.reshape(-1).astype(np.uint8),
            index,
            levels,
            factor,
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


def cell_faces(coords: np.ndarray) -> tuple[np.ndarray, float]:
    """The n + 1 face positions of the cells of `coords` along either axis, and dx."""
    dx = float(coords[1] - coords[0])
    return np.append(coords - dx / 2, coords[-1] + dx / 2), dx


def disk_fractions(coords: np.ndarray, radius: float) -> tuple[np.ndarray, ...]:
    """The exact volume and face fractions of the disk r < `radius` about 0 on the grid.

    Args:
        coords: cell-centre coordinates along either axis (uniform, the same along both).
        radius: the disk's radius.

    Returns:
        (volume, open_x, open_y): the part of each cell inside the disk, of the face
        between cells (i, j) and (i + 1, j), and of the face between (i, j) and (i, j + 1),
        each in units of dx^2 or dx (before the faces of dry cells are closed).
    """
    faces, dx = cell_faces(coords)
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
    # the face at x = faces[i + 1] between cells i and i + 1, open where y^2 < L^2 - x^2
    half = np.sqrt(np.clip((radius - faces[1:]) * (radius + faces[1:]), 0.0, None))
    open_x = np.minimum(_open_length(y0, y1, half[:, None]) / dx, 1.0)
    open_y = np.minimum(_open_length(x0, x1, half[None, :]) / dx, 1.0)
    return volume, open_x, open_y


def assemble_cut_cells(
    volume: np.ndarray,
    open_x: np.ndarray,
    open_y: np.ndarray,
    flowing: np.ndarray,
    dx: float,
    sink: np.ndarray | None = None,
) -> CutCells:
    """The :class:`CutCells` of a vessel from its cells' volume and face fractions.

    A face is open by its fraction between two cells that hold camphor; a face between a
    cell that holds camphor and a `sink` cell (a dry cell beyond an absorbing wall, where
    c = 0) is fully open, so that camphor leaves through it as through the absorbing dish
    wall; every other face is closed (no flux).

    Args:
        volume: (n, n) the part of each cell inside the vessel (:func:`disk_fractions`).
        open_x: (n, n) the open part of each face along x (:func:`disk_fractions`).
        open_y: (n, n) the same along y.
        flowing: (n, n) the cells where v evolves.
        dx: grid spacing.
        sink: (n, n) the dry cells beyond an absorbing wall (None: no absorbing wall).

    Returns:
        The :class:`CutCells`.

    Raises:
        ValueError: if the vessel reaches the grid's outermost ring of cells.
    """
    n = volume.shape[0]
    volume = np.where(volume > TINY, volume, 0.0)
    if volume[[0, -1], :].any() or volume[:, [0, -1]].any():
        msg = "the vessel reaches the grid's outermost cells"
        raise ValueError(msg)
    held = volume > 0
    apertures = []
    for axis, fraction in ((0, open_x), (1, open_y)):
        ahead = np.roll(held, -1, axis=axis)
        aperture = np.where(held & ahead, fraction, 0.0)
        if sink is not None:
            across = (held & np.roll(sink, -1, axis=axis)) | (ahead & sink)
            aperture = np.where(across, 1.0, aperture)
        apertures.append(aperture)
    aperture_x, aperture_y = apertures
    open_sum = aperture_x + np.roll(aperture_x, 1, axis=0) + aperture_y
    open_sum = open_sum + np.roll(aperture_y, 1, axis=1)
    stiff = held & (open_sum > 4.0 * volume * (1.0 + 1e-9))
    starts = np.diff(held.astype(np.int8), axis=1, prepend=0, append=0)
    rows, span_lo = np.nonzero(starts == 1)
    _, span_hi = np.nonzero(starts == -1)
    row_start = np.searchsorted(rows, np.arange(n + 1)).astype(np.int64)
    return CutCells(
        volume=volume,
        aperture_x=aperture_x,
        aperture_y=aperture_y,
        stiff=stiff,
        implicit_x=(aperture_x > 0) & (stiff | np.roll(stiff, -1, axis=0)),
        implicit_y=(aperture_y > 0) & (stiff | np.roll(stiff, -1, axis=1)),
        row_start=row_start,
        span_lo=span_lo.astype(np.int64),
        span_hi=span_hi.astype(np.int64),
        flowing=flowing & held,
        dx=dx,
    )


def make_cut_cells(coords: np.ndarray, radius: float) -> CutCells:
    """The cut cells of the circle of radius `radius` about 0 on the grid of `coords`.

    Args:
        coords: cell-centre coordinates along either axis (uniform, the same along both,
            :attr:`pde_rotor.model.domain.Domain.coords`); the outermost ring of cells
            must lie outside the circle.
        radius: L.

    Returns:
        The :class:`CutCells` (v evolves on the cells whose centre lies inside).

    Raises:
        ValueError: if the circle reaches the grid's outermost ring of cells.
    """
    volume, open_x, open_y = disk_fractions(coords, radius)
    x, y = np.meshgrid(coords, coords, indexing="ij")
    _, dx = cell_faces(coords)
    return assemble_cut_cells(volume, open_x, open_y, x**2 + y**2 < radius**2, dx)


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


def wall_rate(inflow: np.ndarray, cells: CutCells) -> np.ndarray:
    """The semi-discrete rate of c by transport behind the wall: Q / kappa (0 outside)."""
    return np.where(cells.mask, inflow / np.where(cells.mask, cells.volume, 1.0), 0.0)


def make_wall_step(
    cells: CutCells, diffusion: float, dt: float
) -> Callable[[np.ndarray, np.ndarray | None, np.ndarray], np.ndarray]:
    """One step of Eq. (eqc) behind the no-flux wall (see the module), as a function.

    Args:
        cells: the cut cells.
        diffusion: D.
        dt: time step.

    Returns:
        step(c, v, local): c (n, n) after the step from c, the flow v (2, n, n; None
        without flow) and the local rate r of Eq. (eqc) (n, n; -a (1 - F) c + sources):
        forward Euler of the explicit faces' diffusion, of the advection and of r,
        backward Euler of the diffusion through the implicit faces, each cluster's
        matrix (:func:`pde_rotor.model.clusters.cluster_matrices`) inverted once.
    """
    explicit = replace(
        cells,
        aperture_x=np.where(cells.implicit_x, 0.0, cells.aperture_x),
        aperture_y=np.where(cells.implicit_y, 0.0, cells.aperture_y),
    )
    kappa = cells.volume.reshape(-1)
    divisor = np.where(kappa > 0, kappa, 1.0)
    clusters = [
        (members, np.linalg.inv(matrix))
        for members, matrix in cluster_matrices(cells, dt * diffusion / cells.dx**2)
    ]

    def step(c: np.ndarray, v: np.ndarray | None, local: np.ndarray) -> np.ndarray:
        inflow = wall_fluxes(c, None, explicit, diffusion)
        if v is not None:
            inflow = inflow + wall_fluxes(c, v, cells, 0.0)
        rhs = (cells.volume * c + dt * (inflow + cells.volume * local)).reshape(-1)
        out = np.where(kappa > 0, rhs / divisor, 0.0)
        for cluster, inverse in clusters:
            out[cluster] = inverse @ rhs[cluster]
        return out.reshape(c.shape)

    return step
