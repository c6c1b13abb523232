"""The two-disk rotor of Koyano et al., PRE 96, 012609 (2017): its onset of rotation.

Two camphor disks at (+-l, 0) on a strip that does not touch the water (F = G = the two
disks' smoothed indicators), no flow (v = 0 in Eq. (eqc)), the torque of the surface
tension T = -k int F r x grad c dA (the sign of ``rotor.torque = "physical"``). The
torque response :func:`rotor_torque_coefficient` comes from a sparse finite-difference
solve of the co-rotating linear problem on a stretched quadrant grid (:func:`rotor_grid`);
with the friction moment :func:`rotor_friction_moment` it gives the critical friction
:func:`rotor_critical_friction`, the growth rate :func:`rotor_growth_rate` and the
critical half-length :func:`rotor_critical_half_length` (docs/bodies.md, section 3).

Units are the config's: lengths in sqrt(D/a) when D = a = 1, times in 1/a.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq
from scipy.sparse.linalg import splu

from .disk import CamphorDisk


def _stretched_axis(fine_lo: float, fine_hi: float, spacing: float, end: float) -> np.ndarray:
    """Nodes on [0, end]: spacing h on [fine_lo, fine_hi], growing by GROWTH per node
    outside it, up to end / 80."""
    coarse = max(spacing, end / 80)
    fine = np.arange(fine_lo, fine_hi + spacing / 2, spacing)

    def grow(start: float, stop: float) -> list[float]:
        nodes, step, x = [], spacing, start
        direction = 1.0 if stop > start else -1.0
        while (stop - x) * direction > 0:
            step = min(step * GROWTH, coarse)
            x += direction * step
            nodes.append(x)
        return nodes

    left = [x for x in grow(fine[0], 0.0) if x > spacing / 2]
    right = grow(fine[-1], end)
    nodes = np.concatenate([[0.0], left[::-1], fine[fine > spacing / 2], right])
    nodes[-1] = max(nodes[-1], end)
    return nodes


GROWTH = 1.08
"""Ratio of neighbouring spacings outside the fine window of the rotor grid."""


def _second_difference(nodes: np.ndarray, parity: int) -> sp.csr_matrix:
    """d2/dx2 on the nodes (the last is a Dirichlet 0), mirrored at 0 with `parity` +-1.

    For parity -1 the node at 0 holds 0 too and is dropped: the matrix acts on the
    nodes strictly inside; for +1 it acts on nodes[:-1].
    """
    h = np.diff(nodes)
    h_left = np.r_[h[0], h[:-1]]
    n = nodes.size - 1
    lower = 2 / (h_left * (h_left + h))
    upper = 2 / (h * (h_left + h))
    main = -lower - upper
    if parity > 0:
        upper[0] += lower[0]  # ghost node -x_1 holds u_1
        return sp.diags([lower[1:n], main[:n], upper[: n - 1]], [-1, 0, 1], format="csr")
    return sp.diags([lower[2:n], main[1:n], upper[1 : n - 1]], [-1, 0, 1], format="csr")


def _first_difference(nodes: np.ndarray) -> sp.csr_matrix:
    """Central d/dx on nodes[1:-1] of values on nodes[:-1], the last node being 0."""
    h = np.diff(nodes)
    hl, hr = h[:-1], h[1:]
    n = nodes.size - 1
    cols = np.arange(1, n)
    rows = np.arange(n - 1)
    data = [-hr / (hl * (hl + hr)), (hr - hl) / (hl * hr), hl / (hr * (hl + hr))]
    matrix = sp.csr_matrix(
        (np.concatenate(data), (np.tile(rows, 3), np.concatenate([cols - 1, cols, cols + 1]))),
        shape=(n - 1, n + 1),
    )
    return matrix[:, :n]


def _trapezoid(nodes: np.ndarray) -> np.ndarray:
    """Trapezoid weights of nodes[:-1] on [0, nodes[-1]] (the last node holds 0)."""
    return np.r_[(nodes[1] - nodes[0]) / 2, (nodes[2:] - nodes[:-2]) / 2]


@dataclass(frozen=True)
class RotorGrid:
    """The quadrant grid of the two-disk rotor and its smoothed indicators.

    Attributes:
        x: node abscissae, 0 first, the Dirichlet boundary last.
        y: node ordinates, likewise.
        indicator: F = G = sum of the two disks' 1/2 [1 + tanh((rho - |r - X_j|)/delta)]
            on the nodes (x[:-1], y[:-1]).
        turning: dF/dtheta = x dF/dy - y dF/dx on the interior nodes (x[1:-1], y[1:-1]),
            from its closed form.
        weights: trapezoid weights of the interior nodes.
    """

    x: np.ndarray
    y: np.ndarray
    indicator: np.ndarray
    turning: np.ndarray
    weights: np.ndarray


def rotor_grid(
    disk: CamphorDisk, half_length: float, smoothing: float, spacing: float, margin: float = 8.0
) -> RotorGrid:
    """The quadrant x, y >= 0 of the two-disk rotor (disks at (+-l, 0)) on a stretched grid.

    Args:
        disk: one of the two disks.
        half_length: l, distance of each disk's centre from the axis.
        smoothing: delta of the tanh indicators.
        spacing: grid spacing within 8 delta + rho / 2 of each rim.
        margin: distance of the boundary (c = 0) from the disks, in diffusion lengths.

    Returns:
        The grid.
    """
    rho, reach = disk.radius, margin / disk.decay
    pad = 8 * smoothing + rho / 2
    lo, hi = half_length - rho - pad, half_length + rho + pad
    x = _stretched_axis(max(0.0, lo), hi, spacing, half_length + rho + reach)
    y = _stretched_axis(0.0, rho + pad, spacing, rho + reach)
    X, Y = np.meshgrid(x[:-1], y[:-1], indexing="ij")
    indicator = np.zeros_like(X)
    turning = np.zeros_like(X)
    for centre in (half_length, -half_length):
        s = np.hypot(X - centre, Y)
        edge = np.tanh((rho - s) / smoothing)
        indicator += 0.5 * (1 + edge)
        # dF/ds = -(1 - tanh^2) / (2 delta), ds/dtheta = centre y / s
        turning -= (1 - edge**2) / (2 * smoothing) * centre * Y / np.maximum(s, spacing)
    weights = np.outer(_trapezoid(x), _trapezoid(y))
    return RotorGrid(x, y, indicator, turning[1:, 1:], weights[1:, 1:])


def _rest_field(disk: CamphorDisk, grid: RotorGrid) -> np.ndarray:
    """c0 of the rotor at rest on the quadrant (even in x and y).

    Solves D lap c0 - a (1 - F) c0 = -S G, Eq. (eqc) at rest.
    """
    lap = sp.kron(_second_difference(grid.x, 1), sp.identity(grid.y.size - 1)) + sp.kron(
        sp.identity(grid.x.size - 1), _second_difference(grid.y, 1)
    )
    sink = disk.evaporation * (1 - grid.indicator.ravel())
    matrix = (disk.diffusion * lap - sp.diags(sink)).tocsc()
    return splu(matrix).solve(-disk.source * grid.indicator.ravel()).reshape(grid.indicator.shape)


def rotor_torque_coefficient(
    disk: CamphorDisk,
    half_length: float,
    lam: float = 0.0,
    smoothing: float = 0.005,
    spacing: float | None = None,
    margin: float = 8.0,
) -> float:
    """K_rot(lambda): torque per unit angular velocity of the two-disk rotor at rest.

    Two disks of radius rho centred at (+-l, 0), F = G = their smoothed indicators (the
    strip does not touch the water). In the frame turning with the rotor at angular
    velocity omega exp(lambda t), the first-order field solves

        D lap c1 - (a (1 - F) + lambda) c1 = -omega dc0/dtheta,

    and the torque is T1 = -k int F dc1/dtheta dA = k int c1 dF/dtheta dA = K_rot omega
    (docs/bodies.md, section 3). c0 is even and c1 odd in x and y, so both are
    solved on the quadrant by sparse LU, with c = 0 `margin` diffusion lengths beyond
    the disks. The result tends to the sharp limit about as delta^2, led by the smoothed
    disks' larger area pi (rho^2 + pi^2 delta^2 / 12).

    Args:
        disk: one of the two disks.
        half_length: l > rho.
        lam: growth rate lambda > -a.
        smoothing: delta of the tanh indicators.
        spacing: grid spacing near the rims (default delta / 2).
        margin: distance of the outer boundary, in diffusion lengths.

    Returns:
        K_rot; the rest state turns unstable where K_rot(0) exceeds the friction moment
        mu int F |r|^2 dA.
    """
    return _rotor_response(disk, half_length, smoothing, spacing or smoothing / 2, margin)(lam)


def _rotor_response(
    disk: CamphorDisk, half_length: float, smoothing: float, spacing: float, margin: float
) -> Callable[[float], float]:
    """lambda -> K_rot(lambda), with the rest state and its dc0/dtheta solved once."""
    grid = rotor_grid(disk, half_length, smoothing, spacing, margin)
    rest = _rest_field(disk, grid)
    slope_x = (_first_difference(grid.x) @ rest)[:, 1:]
    slope_y = (rest @ _first_difference(grid.y).T)[1:, :]
    X, Y = np.meshgrid(grid.x[1:-1], grid.y[1:-1], indexing="ij")
    drive = -(X * slope_y - Y * slope_x).ravel()
    lap = sp.kron(_second_difference(grid.x, -1), sp.identity(grid.y.size - 2)) + sp.kron(
        sp.identity(grid.x.size - 2), _second_difference(grid.y, -1)
    )
    sink = disk.evaporation * (1 - grid.indicator[1:, 1:].ravel())

    def torque(lam: float) -> float:
        matrix = (disk.diffusion * lap - sp.diags(sink + lam)).tocsc()
        response = splu(matrix).solve(drive).reshape(X.shape)
        return float(4 * disk.tension_slope * np.sum(grid.weights * response * grid.turning))

    return torque


def rotor_friction_moment(disk: CamphorDisk, half_length: float) -> float:
    """J = int F |r|^2 dA = 2 (pi rho^2 l^2 + pi rho^4 / 2) for two sharp disks at +-l.

    Args:
        disk: one of the two disks.
        half_length: l.

    Returns:
        J; the friction torque of Eq. (eq_motion) at rest flow is -mu J omega.
    """
    return 2 * disk.area * (half_length**2 + disk.radius**2 / 2)


def _grid_friction_moment(disk: CamphorDisk, half_length: float, smoothing: float) -> float:
    """int F |r|^2 dA with the smoothed F, by the rotor grid's trapezoid rule."""
    grid = rotor_grid(disk, half_length, smoothing, smoothing / 2)
    X, Y = np.meshgrid(grid.x[:-1], grid.y[:-1], indexing="ij")
    weights = np.outer(_trapezoid(grid.x), _trapezoid(grid.y))
    return float(4 * np.sum(weights * grid.indicator * (X**2 + Y**2)))


def rotor_critical_friction(
    disk: CamphorDisk, half_length: float, smoothing: float = 0.005
) -> float:
    """mu_c(l) = K_rot(0) / J: below it the two-disk rotor at rest starts to turn.

    Both K_rot and J = int F |r|^2 dA are taken with the same smoothed F, as in the
    simulation; the leading delta^2 terms (the smoothed disks' larger area) cancel in
    the ratio.

    Args:
        disk: one of the two disks.
        half_length: l > rho.
        smoothing: delta of the tanh indicators.

    Returns:
        mu_c(l).
    """
    torque = rotor_torque_coefficient(disk, half_length, smoothing=smoothing)
    return torque / _grid_friction_moment(disk, half_length, smoothing)


def rotor_growth_rate(
    disk: CamphorDisk,
    half_length: float,
    friction: float,
    inertia: float,
    smoothing: float = 0.005,
) -> float:
    """The real growth rate of rotation of the two-disk rotor at rest.

    Root of I lambda = K_rot(lambda) - mu J (Eq. (eq_motion) linearised, v = 0).

    Args:
        disk: one of the two disks.
        half_length: l > rho.
        friction: mu.
        inertia: I.
        smoothing: delta of the tanh indicators.

    Returns:
        lambda > -a.
    """
    moment = _grid_friction_moment(disk, half_length, smoothing)
    torque = _rotor_response(disk, half_length, smoothing, smoothing / 2, 8.0)

    def balance(lam: float) -> float:
        return torque(lam) - friction * moment - inertia * lam

    low, high = -0.5 * disk.evaporation, 0.5 * disk.evaporation
    while balance(high) > 0:
        high *= 4
    while balance(low) < 0 and low > -disk.evaporation * (1 - 1e-6):
        low = (low - disk.evaporation) / 2
    return float(brentq(balance, low, high, xtol=1e-10, rtol=1e-8))


def rotor_critical_half_length(
    disk: CamphorDisk, friction: float, smoothing: float = 0.005, longest: float = 20.0
) -> float:
    """l_c(mu): the two-disk rotor turns for l > l_c and rests for l < l_c.

    mu_c(l) (:func:`rotor_critical_friction`) grows from its value at contact (l = rho)
    to the free disk's mu_c for l >> sqrt(D/a); l_c is its inverse.

    Args:
        disk: one of the two disks.
        friction: mu, between mu_c(rho) and the free disk's mu_c.
        smoothing: delta of the tanh indicators.
        longest: the largest l searched.

    Returns:
        l_c.

    Raises:
        ValueError: if mu lies outside that range: then the rotor turns at every l
            (mu < mu_c(rho)) or at none.
    """
    contact = disk.radius * (1 + 1e-3)

    def excess(length: float) -> float:
        return rotor_critical_friction(disk, length, smoothing) - friction

    at_contact, far = excess(contact), excess(longest)
    if at_contact >= 0 or far <= 0:
        msg = (
            f"friction {friction:g} has no critical size: mu_c(l) runs from "
            f"{at_contact + friction:.4g} at contact to {far + friction:.4g} at l = {longest:g}"
        )
        raise ValueError(msg)
    return float(brentq(excess, contact, longest, xtol=1e-6, rtol=1e-6))
