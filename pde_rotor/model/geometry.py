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
|x| >= X_SATURATION (:mod:`pde_rotor.config`) they equal 0 or 1 to within
exp(-2 X_SATURATION) = 4e-18, so the kernels (:mod:`pde_rotor.physics`) evaluate them
only inside the disk of :attr:`GeometryConfig.support_radius` (F) and within
rho + X_SATURATION delta of each pill (G). This module holds the numpy reference
versions (point values; the filtered fields of the ``consistent`` scheme are in
:mod:`pde_rotor.model.filtering`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..config import GeometryConfig


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
        support_radius: radius outside which F = G = 0 exactly
            (:attr:`GeometryConfig.support_radius`).
    """

    n_corners: int
    radius: float
    apothem: float
    pill_radius: float
    pill_distance: float
    asymmetry: float
    smoothing: float
    support_radius: float

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
            support_radius=geometry.support_radius,
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


def support_rows(
    coords: np.ndarray, radius: float, centre: tuple[float, float] = (0.0, 0.0)
) -> tuple[np.ndarray, np.ndarray]:
    """Column range [lo, hi) per row of the cells whose centre lies within `radius`.

    Args:
        coords: cell-centre coordinates along one axis of the square grid.
        radius: radius of the disk.
        centre: centre (x, y) of the disk, in the frame of `coords` (default: their
            origin).

    Returns:
        Two int64 arrays (lo, hi), one entry per row; lo == hi for rows with no cell.
    """
    n = coords.size
    lo = np.zeros(n, dtype=np.int64)
    hi = np.zeros(n, dtype=np.int64)
    cx, cy = centre
    for i, x in enumerate(coords):
        inside = np.nonzero((x - cx) ** 2 + (coords - cy) ** 2 < radius**2)[0]
        if inside.size:
            lo[i], hi[i] = inside[0], inside[-1] + 1
    return lo, hi
