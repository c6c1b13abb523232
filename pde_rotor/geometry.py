"""Rotor geometry: plate indicator F, pill indicator G and the pill positions.

Implements the geometric part of the paper's section "Model":

* edge normals e_j(t) = e(phi + 2 pi (j - 1/2) / N), Eq. (ejt0) rotated by phi;
* pill distance R_c = R - rho / cos(pi/N) - p, Eq. (rc);
* pill centres R_j = R_c e(phi + 2 pi j / N + Delta).

Erratum: Eq. (rj) as printed reads e(phi + 2 pi (j - 1/2) / N + Delta), which puts the
pills at the *edge midpoints*. Fig. 1, its caption ("slightly rotated from the line
connecting the center and the polygon corner") and Eq. (rc) (the distance of a pill
touching both sides of a *corner*) put them at the corners; we follow the corners.
See docs/model.md.

F and G are the smoothed indicators of the paper (the two unnumbered equations after
Eq. (rj)). Both are 1/2 (1 + tanh(x)) of a signed distance x in units of delta. For
|x| >= X_SATURATION they equal 0 or 1 to within exp(-2 X_SATURATION) = 4e-18, so
:func:`update_indicators` evaluates them only inside the disk of radius
R + X_SATURATION delta / cos(pi/N) (F) and within rho + X_SATURATION delta of each pill
(G), and agrees with the full evaluation to round-off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from .config import GeometryConfig

X_SATURATION = 20.0
"""|x| beyond which float64 tanh(x) is exactly +-1 (1 - tanh(20) = 8.5e-18 < 2^-54)."""


@dataclass(frozen=True)
class RotorShape:
    """Numbers describing the rotor, derived once from :class:`GeometryConfig`.

    Attributes:
        n_corners: N.
        radius: R, circumradius.
        apothem: R cos(pi/N), distance of the edges from the centre.
        pill_radius: rho.
        pill_distance: R_c, Eq. (rc).
        asymmetry: Delta [rad].
        smoothing: delta.
    """

    n_corners: int
    radius: float
    apothem: float
    pill_radius: float
    pill_distance: float
    asymmetry: float
    smoothing: float

    @classmethod
    def from_config(cls, geometry: GeometryConfig) -> RotorShape:
        """Derive the shape from the geometry section of a run configuration."""
        n = geometry.n_corners
        return cls(
            n_corners=n,
            radius=geometry.radius,
            apothem=geometry.radius * math.cos(math.pi / n),
            pill_radius=geometry.pill_radius,
            pill_distance=geometry.pill_distance,
            asymmetry=geometry.asymmetry,
            smoothing=geometry.smoothing,
        )

    @property
    def support_radius(self) -> float:
        """Radius outside which F = G = 0 exactly (see module docstring)."""
        return self.radius + X_SATURATION * self.smoothing / math.cos(math.pi / self.n_corners)

    def as_array(self) -> np.ndarray:
        """Pack the shape for the compiled kernels: [N, apothem, rho, R_c, Delta, delta]."""
        return np.array(
            [
                self.n_corners,
                self.apothem,
                self.pill_radius,
                self.pill_distance,
                self.asymmetry,
                self.smoothing,
            ]
        )


def edge_normal_angles(n_corners: int, phi: float) -> np.ndarray:
    """Angles of the edge normals e_j, Eq. (ejt0) rotated by phi (j = 1..N)."""
    return phi + 2 * np.pi * (np.arange(1, n_corners + 1) - 0.5) / n_corners


def pill_angles(n_corners: int, phi: float, asymmetry: float) -> np.ndarray:
    """Angles of the pill centres: corners phi + 2 pi j / N shifted by Delta (j = 1..N)."""
    return phi + 2 * np.pi * np.arange(1, n_corners + 1) / n_corners + asymmetry


def pill_centres(shape: RotorShape, phi: float) -> np.ndarray:
    """Pill centres R_j as an (N, 2) array."""
    ang = pill_angles(shape.n_corners, phi, shape.asymmetry)
    return shape.pill_distance * np.stack([np.cos(ang), np.sin(ang)], axis=1)


def plate_indicator(x: np.ndarray, y: np.ndarray, shape: RotorShape, phi: float) -> np.ndarray:
    """Smoothed plate indicator F(r, phi) evaluated everywhere (numpy reference).

    F = 1/2 [1 + tanh(min_j (R cos(pi/N) - r . e_j) / delta)].
    """
    ang = edge_normal_angles(shape.n_corners, phi)
    proj = np.max(
        [x * math.cos(a) + y * math.sin(a) for a in ang],
        axis=0,
    )
    return 0.5 * (1.0 + np.tanh((shape.apothem - proj) / shape.smoothing))


def pill_indicator(x: np.ndarray, y: np.ndarray, shape: RotorShape, phi: float) -> np.ndarray:
    """Smoothed pill indicator G(r, phi) evaluated everywhere (numpy reference).

    G = sum_j 1/2 [1 + tanh((rho - |r - R_j|) / delta)].
    """
    out = np.zeros(np.broadcast(x, y).shape)
    for px, py in pill_centres(shape, phi):
        dist = np.hypot(x - px, y - py)
        out += 0.5 * (1.0 + np.tanh((shape.pill_radius - dist) / shape.smoothing))
    return out


@nb.njit(cache=True, nogil=True, inline="always")
def _logistic(arg: float) -> float:
    """1/2 (1 + tanh(arg)) written as 1 / (1 + exp(-2 arg)): 3x cheaper than libm tanh."""
    return 1.0 / (1.0 + math.exp(-2.0 * arg))


@nb.njit(cache=True, nogil=True)
def update_indicators(
    F: np.ndarray,
    G: np.ndarray,
    coords: np.ndarray,
    box_lo: np.ndarray,
    box_hi: np.ndarray,
    shape: np.ndarray,
    phi: float,
) -> None:
    """Recompute F and G in place where they can differ from 0 (compiled).

    Uses 1/2 (1 + tanh(x)) = 1 / (1 + exp(-2x)); cells beyond the support keep the value
    0, which differs from the formula by less than exp(-2 X_SATURATION) = 4e-18.

    Args:
        F: plate indicator on the grid, shape (n, n); cells outside the support are
            left untouched and must hold 0.
        G: pill indicator on the grid, shape (n, n), same convention.
        coords: cell-centre coordinates along one axis (the grid is square, uniform).
        box_lo: for each row i, first column j inside the support disk.
        box_hi: for each row i, one past the last such column (box_lo == box_hi: none).
        shape: :meth:`RotorShape.as_array`.
        phi: rotor angle.
    """
    n_corners = int(shape[0])
    apothem, rho, r_c, asym, delta = shape[1], shape[2], shape[3], shape[4], shape[5]
    inv_delta = 1.0 / delta
    normal_c = np.empty(n_corners)
    normal_s = np.empty(n_corners)
    for k in range(n_corners):
        a_edge = phi + 2.0 * math.pi * (k + 0.5) / n_corners
        normal_c[k] = math.cos(a_edge)
        normal_s[k] = math.sin(a_edge)
    for i in range(coords.size):
        x = coords[i]
        for j in range(box_lo[i], box_hi[i]):
            y = coords[j]
            proj = x * normal_c[0] + y * normal_s[0]
            for k in range(1, n_corners):
                proj = max(proj, x * normal_c[k] + y * normal_s[k])
            F[i, j] = _logistic((apothem - proj) * inv_delta)
            G[i, j] = 0.0
    # each pill only touches the cells within rho + X_SATURATION delta of its centre
    x0 = coords[0]
    spacing = coords[1] - coords[0]
    reach = rho + X_SATURATION * delta
    last = coords.size - 1
    for k in range(n_corners):
        a_pill = phi + 2.0 * math.pi * (k + 1) / n_corners + asym
        px = r_c * math.cos(a_pill)
        py = r_c * math.sin(a_pill)
        i0 = max(0, math.floor((px - reach - x0) / spacing))
        i1 = min(last, math.ceil((px + reach - x0) / spacing))
        j0 = max(0, math.floor((py - reach - x0) / spacing))
        j1 = min(last, math.ceil((py + reach - x0) / spacing))
        for i in range(i0, i1 + 1):
            dx2 = (coords[i] - px) ** 2
            for j in range(j0, j1 + 1):
                d2 = dx2 + (coords[j] - py) ** 2
                if d2 < reach * reach:
                    G[i, j] += _logistic((rho - math.sqrt(d2)) * inv_delta)


def support_rows(coords: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """Column range [lo, hi) per row of the cells whose centre lies within `radius`.

    Args:
        coords: cell-centre coordinates along one axis of the square grid.
        radius: radius of the disk centred at the origin.

    Returns:
        Two int64 arrays (lo, hi), one entry per row; lo == hi for rows with no cell.
    """
    n = coords.size
    lo = np.zeros(n, dtype=np.int64)
    hi = np.zeros(n, dtype=np.int64)
    for i, x in enumerate(coords):
        inside = np.nonzero(x**2 + coords**2 < radius**2)[0]
        if inside.size:
            lo[i], hi[i] = inside[0], inside[-1] + 1
    return lo, hi
