"""Collective measures of free bodies in a circular dish: pair correlation, speed, order.

* :func:`pair_correlation`: g(r) of the bodies' centres with the dish's finite-size
  normalisation. In a dish the pair distances of uncorrelated centres are not those of an
  infinite plane: two points uniform in a disk of radius R are r apart with the density
  (:func:`disk_pair_density`)

      p(r) = 4 r / (pi R^2) [arccos(s) - s sqrt(1 - s^2)],   s = r / (2 R),  0 <= r <= 2 R,

  so g(r) = (pairs counted in a bin) / (pairs x records x the integral of p over the bin):
  1 at every r for centres uniform in the disk, whatever R, and no 1/r^2 fall at large r.
  R is the radius the centres may occupy (the dish's radius less a body's footprint);
* :func:`mean_speed`: <|U_k|> over the bodies;
* :func:`polar_order`: |sum_k U_k / |U_k|| / K, 1 when all move the same way;
* :func:`rotational_order`: <(r_k x U_k) / (|r_k| |U_k|)> about the dish's centre, signed:
  +1 for bodies circling counter-clockwise round the centre (milling), -1 clockwise.
"""

from __future__ import annotations

import math

import numpy as np

DENSITY_NODES = 64
"""Gauss-Legendre nodes of the integral of p(r) over one bin of g(r)."""


def disk_pair_density(r: np.ndarray, radius: float) -> np.ndarray:
    """p(r): density of the distance of two points uniform in a disk of `radius`."""
    s = np.clip(np.asarray(r, dtype=float) / (2 * radius), 0.0, 1.0)
    return 4 * np.asarray(r) / (math.pi * radius**2) * (np.arccos(s) - s * np.sqrt(1 - s * s))


def bin_probabilities(edges: np.ndarray, radius: float) -> np.ndarray:
    """Probability that two points uniform in the disk are a bin of `edges` apart."""
    nodes, weights = np.polynomial.legendre.leggauss(DENSITY_NODES)
    lo, hi = edges[:-1, None], edges[1:, None]
    r = 0.5 * (hi - lo) * nodes + 0.5 * (hi + lo)
    return (0.5 * (hi - lo) * weights * disk_pair_density(r, radius)).sum(axis=1)


def pair_counts(positions: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Pair distances counted in the bins `edges`, over every record.

    Args:
        positions: (T, K, 2) centres relative to the dish's centre; records with NaN are
            left out.
        edges: bin edges of r.
    """
    counts = np.zeros(len(edges) - 1)
    k = positions.shape[1]
    i, j = np.triu_indices(k, 1)
    for frame in positions:
        if np.isnan(frame).any():
            continue
        d = np.hypot(*(frame[i] - frame[j]).T)
        counts += np.histogram(d, edges)[0]
    return counts


def pair_correlation(positions: np.ndarray, radius: float, edges: np.ndarray) -> np.ndarray:
    """g(r) in the bins `edges`, normalised by the pair distances of uniform centres in
    the disk of `radius` (module docstring); NaN where no pair can be.

    Args:
        positions: (T, K, 2) centres relative to the dish's centre (K >= 2).
        radius: radius of the disk the centres may occupy.
        edges: bin edges of r.
    """
    frames = int((~np.isnan(positions).any(axis=(1, 2))).sum())
    k = positions.shape[1]
    expected = frames * k * (k - 1) / 2 * bin_probabilities(edges, radius)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(expected > 0, pair_counts(positions, edges) / expected, np.nan)


def _unit(vectors: np.ndarray) -> np.ndarray:
    norm = np.hypot(vectors[..., 0], vectors[..., 1])[..., None]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norm > 0, vectors / norm, 0.0)


def mean_speed(velocities: np.ndarray) -> np.ndarray:
    """<|U_k|> over the bodies at each record; velocities (..., K, 2)."""
    return np.hypot(velocities[..., 0], velocities[..., 1]).mean(axis=-1)


def polar_order(velocities: np.ndarray) -> np.ndarray:
    """|sum_k U_k / |U_k|| / K at each record (a body at rest counts as 0)."""
    return np.hypot(*np.moveaxis(_unit(velocities).mean(axis=-2), -1, 0))


def rotational_order(positions: np.ndarray, velocities: np.ndarray) -> np.ndarray:
    """<r_k x U_k / (|r_k| |U_k|)> at each record, positions about the dish's centre."""
    r, u = _unit(positions), _unit(velocities)
    return (r[..., 0] * u[..., 1] - r[..., 1] * u[..., 0]).mean(axis=-1)
