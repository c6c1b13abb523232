"""A free camphor disk on an unbounded surface: onset, growth and pitchfork of its motion.

The pill is the object (F = G), no flow (v = 0 in Eq. (eqc)), sharp indicators unless a
function says otherwise; the force is the surface tension's, f = -k int F grad c dA
(Eq. (surfacetension)). docs/bodies.md derives each result:

* the velocity response :func:`free_disk_force_coefficient` K(lambda) in closed form
  (Bessel functions), the critical friction :func:`free_disk_critical_friction` and the
  growth rate :func:`free_disk_growth_rate` of the translational mode;
* the same with the simulation's smoothed indicator,
  :func:`free_disk_smoothed_coefficients`;
* the exact drive :func:`free_disk_drive` of a disk translating at any speed (a radial
  Chebyshev solve of the Fourier modes in theta), the pitchfork's cubic coefficient
  :func:`free_disk_cubic_coefficient` and the steady speed
  :func:`free_disk_steady_speed` below the onset.

The disk, its rest state and its displacement response are :mod:`.disk`'s.
"""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq
from scipy.sparse.linalg import splu
from scipy.special import kve

from .disk import CamphorDisk, free_disk_displacement_force, real_if_real

SMALL_RATE = 1e-3
"""|lambda| / a below which K(lambda) is evaluated from its Taylor polynomial."""
TAYLOR_STEP = 1e-2
"""Step / a of the central differences that give K'(0) and K''(0)."""


def _bessel_k(order: int, x: float) -> float:
    return float(kve(order, x) * math.exp(-x))


def free_disk_force_coefficient(disk: CamphorDisk, lam: complex = 0.0) -> complex | float:
    """K(lambda): the propulsive force per unit velocity of a free disk, unbounded surface.

    At lambda = 0 the closed form of docs/bodies.md ("Translation"), with x = q rho,

        K(0) = k s0 rho^2 / (8 D^2) [2 K0 / (x K1) - K1 / (x K0 + 2 K1)],

    K_n = K_n(x); otherwise Phi(lambda) / lambda (:func:`free_disk_displacement_force`).
    That quotient loses about log10(a/|lambda|) digits to cancellation, so for
    |lambda| < 1e-3 a it is replaced by the quadratic through lambda = 0, +-1e-2 a
    (K is analytic there; the Taylor remainder is below 1e-10 K).

    Args:
        disk: the disk.
        lam: growth rate lambda.

    Returns:
        K(lambda); the disk self-propels when K(0) exceeds the friction mu pi rho^2.
    """
    if abs(lam) >= SMALL_RATE * disk.evaporation:
        return real_if_real(free_disk_displacement_force(disk, lam) / lam, lam)
    x = disk.decay * disk.radius
    if lam != 0:
        step = TAYLOR_STEP * disk.evaporation
        at_zero = free_disk_force_coefficient(disk)
        above = float(free_disk_force_coefficient(disk, step))
        below = float(free_disk_force_coefficient(disk, -step))
        slope = (above - below) / (2 * step)
        curvature = (above - 2 * at_zero + below) / step**2
        return real_if_real(at_zero + lam * slope + lam**2 * curvature / 2, lam)
    k0, k1 = _bessel_k(0, x), _bessel_k(1, x)
    prefactor = disk.tension_slope * disk.supply * disk.radius**2 / (8 * disk.diffusion**2)
    return prefactor * (2 * k0 / (x * k1) - k1 / (x * k0 + 2 * k1))


def free_disk_critical_friction(disk: CamphorDisk) -> float:
    """mu_c = K(0) / (pi rho^2): below it the rest state of a free disk is unstable.

    Args:
        disk: the disk.

    Returns:
        The friction constant at the pitchfork (unbounded surface, no flow).
    """
    return float(free_disk_force_coefficient(disk)) / disk.area


def free_disk_growth_rate(disk: CamphorDisk, friction: float, mass: float = 0.0) -> float:
    """The real growth rate lambda of the translational mode of a free disk at rest.

    Root of m lambda = K(lambda) - mu pi rho^2 (the linearised m dU/dt = f - mu A U with
    the field's response at the same lambda): positive below the critical friction,
    negative above, 0 at it. K decreases with lambda, so the root is unique.

    Args:
        disk: the disk.
        friction: mu.
        mass: m of the disk (0: overdamped).

    Returns:
        lambda, in (-a, infinity).

    Raises:
        ValueError: if the mode decays as fast as the sublimation (no root above -a):
            its decay then is the continuous spectrum's, not one rate.
    """

    def balance(lam: float) -> float:
        return float(free_disk_force_coefficient(disk, lam)) - friction * disk.area - mass * lam

    low = -disk.evaporation * (1 - 1e-9)
    high = 1.0
    while balance(high) > 0:
        high *= 4
    if balance(low) < 0:
        msg = (
            f"friction {friction:g} damps the translation faster than the sublimation rate "
            f"a = {disk.evaporation:g}: no isolated growth rate"
        )
        raise ValueError(msg)
    return float(brentq(balance, low, high, xtol=1e-14, rtol=1e-12))


def free_disk_smoothed_coefficients(
    disk: CamphorDisk,
    smoothing: float,
    lam: float = 0.0,
    spacing: float | None = None,
    reach: float = 25.0,
) -> tuple[float, float]:
    """K(lambda) and the friction area int F dA with the simulation's smoothed indicator.

    F = G = 1/2 [1 + tanh((rho - r)/delta)], radial finite volumes of width `spacing`
    out to rho + `reach` diffusion lengths (c = 0 there). In the co-moving frame
    (D L_1 - a (1 - F) - lambda) g = -dc0/dr, and the force -k int F grad c1 dA =
    k int c1 grad F dA gives K = k pi int g F' r dr. K / A is the critical friction the
    simulation should find at this delta; it tends to :func:`free_disk_critical_friction`
    as delta -> 0 (docs/bodies.md, "Smoothed indicators").

    Args:
        disk: the disk.
        smoothing: delta.
        lam: growth rate lambda > -a.
        spacing: cell width (default delta / 8).
        reach: outer radius beyond rho, in diffusion lengths.

    Returns:
        (K_delta(lambda), A_delta = int F dA).
    """
    h = spacing or smoothing / 8
    n = math.ceil((disk.radius + reach / disk.decay) / h)
    r = (np.arange(n) + 0.5) * h
    edge = np.tanh((disk.radius - r) / smoothing)
    indicator, slope = 0.5 * (1 + edge), -(1 - edge**2) / (2 * smoothing)
    inner, outer = np.arange(n) * h / (r * h * h), np.arange(1, n + 1) * h / (r * h * h)

    def operator(order: int, rate: float) -> sp.csc_matrix:
        main = -inner - outer - order**2 / r**2  # the cell beyond the last holds c = 0
        lap = sp.diags([inner[1:], main, outer[:-1]], [-1, 0, 1])
        sink = disk.evaporation * (1 - indicator) + rate
        return (disk.diffusion * lap - sp.diags(sink)).tocsc()

    rest = splu(operator(0, 0.0)).solve(-disk.source * indicator)
    response = splu(operator(1, lam)).solve(-np.gradient(rest, h))
    force = disk.tension_slope * math.pi * float(np.sum(response * slope * r)) * h
    return force, 2 * math.pi * float(np.sum(indicator * r)) * h


# --- the translating disk: Fourier modes in theta on radial Chebyshev panels ------------


def _chebyshev(lo: float, hi: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """n + 1 Chebyshev-Lobatto nodes on [lo, hi], ascending, and their d/dr matrix."""
    j = np.arange(n + 1)
    nodes = lo + (hi - lo) * (1 - np.cos(np.pi * j / n)) / 2
    weights = (-1.0) ** j
    weights[[0, -1]] *= 0.5
    diff = nodes[:, None] - nodes[None, :]
    np.fill_diagonal(diff, 1.0)
    matrix = (weights[None, :] / weights[:, None]) / diff
    np.fill_diagonal(matrix, 0.0)
    np.fill_diagonal(matrix, -matrix.sum(axis=1))
    return nodes, matrix


class _RadialModes:
    """The co-moving steady problem of a disk translating at speed U along x.

    0 = D lap c - a (1 - F) c + U dc/dx + S G with c = sum_m c_m(r) cos(m theta),
    m = 0..modes, collocated on Chebyshev panels: [0, rho] (the disk, no sublimation),
    panels doubling in length from rho to the diffusion length, then panels of two
    diffusion lengths out to R, where c = 0. Sharp F = G: adjacent panels share their
    end radius, with c and dc/dr continuous there. Regularity at r = 0: dc_0/dr = 0 and
    c_m = 0 for m >= 1. U d/dx couples m to m +- 1:

        [dc/dx]_n = (1 + [n = 1]) (c_{n-1}' - (n-1) c_{n-1} / r) / 2
                    + (c_{n+1}' + (n+1) c_{n+1} / r) / 2.
    """

    def __init__(self, disk: CamphorDisk, modes: int, outer_radius: float, nodes: int) -> None:
        self.disk, self.modes = disk, modes
        rho, length = disk.radius, 1.0 / disk.decay
        breaks = [0.0, rho]
        while breaks[-1] < rho + length:
            breaks.append(min(2 * breaks[-1], rho + length))
        while breaks[-1] < outer_radius:
            breaks.append(breaks[-1] + 2 * length)
        radii, blocks = zip(
            *(_chebyshev(lo, hi, nodes) for lo, hi in pairwise(breaks)), strict=True
        )
        self.r = np.concatenate(radii)
        self.deriv = sp.block_diag(blocks, format="csr")
        ends = np.cumsum([block.shape[0] for block in blocks])
        self.rim = int(ends[0] - 1)
        self.inside = np.arange(self.r.size) <= self.rim
        self.left, self.right = np.r_[0, ends[:-1]], ends - 1
        self.pde = np.ones(self.r.size, dtype=bool)
        self.pde[self.left] = self.pde[self.right] = False
        self.keep = sp.diags(self.pde.astype(float))
        self.inv_r = sp.diags(1.0 / np.where(self.r > 0, self.r, 1.0))
        rows = sp.lil_matrix((self.size, self.size))
        for lo, hi in zip(self.right[:-1], self.left[1:], strict=True):
            rows[lo, lo], rows[lo, hi] = 1.0, -1.0
            rows[hi] = self.deriv[lo] - self.deriv[hi]
        rows[self.size - 1, self.size - 1] = 1.0
        self.matching = rows.tocsr()  # panel ends: c and dc/dr continuous, c = 0 at R

    @property
    def size(self) -> int:
        """Nodes per mode."""
        return self.r.size

    def _rows(self, matrix: sp.spmatrix, order: int) -> sp.csr_matrix:
        """Replace the panel-end rows of a mode's PDE matrix by the matching conditions."""
        centre = self.deriv[0] if order == 0 else sp.csr_matrix(([1.0], ([0], [0])), (1, self.size))
        first = sp.vstack([centre, sp.csr_matrix((self.size - 1, self.size))])
        return (self.keep @ matrix + self.matching + first).tocsr()

    def mode_operator(self, order: int) -> sp.csr_matrix:
        """D (d2 + d/r - m^2/r^2) - a (1 - F) on one mode, with the matching rows."""
        disk, inv_r = self.disk, self.inv_r
        sink = np.where(self.inside, 0.0, disk.evaporation)
        lap = self.deriv @ self.deriv + inv_r @ self.deriv - order**2 * inv_r @ inv_r
        return self._rows(disk.diffusion * lap - sp.diags(sink), order)

    def _coupling(self, order: int, to: int) -> sp.csr_matrix:
        """The block of [d/dx] taking mode `order` to mode `to` (PDE rows only)."""
        if to == order + 1:
            block = (1 + (to == 1)) * (self.deriv - order * self.inv_r) / 2
        else:
            block = (self.deriv + order * self.inv_r) / 2
        return (self.keep @ block).tocsr()

    def x_derivative(self, fields: dict[int, np.ndarray]) -> dict[int, np.ndarray]:
        """[dc/dx]_n on the PDE rows for the modes in `fields` (mode -> values)."""
        out: dict[int, np.ndarray] = {}
        for order, values in fields.items():
            for to in (order - 1, order + 1):
                if to >= 0:
                    out[to] = out.get(to, 0.0) + self._coupling(order, to) @ values
        return out

    def coupled_operator(self, speed: float) -> sp.csc_matrix:
        """The whole co-moving operator on modes 0..modes."""
        count = self.modes + 1
        grid = [[None] * count for _ in range(count)]
        for m in range(count):
            grid[m][m] = self.mode_operator(m)
            for to in (m - 1, m + 1):
                if 0 <= to < count:
                    grid[to][m] = speed * self._coupling(m, to)
        return sp.bmat(grid, format="csc")

    def source(self) -> np.ndarray:
        """-S G on the PDE rows of mode 0 (the right-hand side of the rest problem)."""
        return np.where(self.inside & self.pde, -self.disk.source, 0.0)

    def force(self, first_mode: np.ndarray) -> float:
        """-k pi rho c_1(rho): the force along x from the cos(theta) mode."""
        return float(-self.disk.tension_slope * math.pi * self.disk.radius * first_mode[self.rim])


def _modes_for(disk: CamphorDisk, speed: float, modes: int, nodes: int) -> _RadialModes:
    """A radial grid long enough for the wake: R - rho = 40 / (slowest decay rate)."""
    drift = speed / (2 * disk.diffusion)
    slowest = math.sqrt(drift**2 + disk.decay**2) - drift
    return _RadialModes(disk, modes, disk.radius + 40.0 / slowest, nodes)


def free_disk_drive(disk: CamphorDisk, speed: float, modes: int = 16, nodes: int = 16) -> float:
    """The exact propulsive force f(U) on a disk translating steadily at speed U.

    In the frame of the disk the steady field solves the linear problem
    D lap c - a (1 - F) c + U dc/dx + S G = 0; its cos(theta) mode at the rim gives
    f = -k pi rho c_1(rho). The steady speeds at friction mu are the roots of
    f(U) = mu pi rho^2 U (docs/bodies.md, "Pitchfork").

    Args:
        disk: the disk.
        speed: U >= 0.
        modes: highest Fourier mode kept.
        nodes: Chebyshev intervals per radial panel.

    Returns:
        f(U), along the motion.
    """
    grid = _modes_for(disk, speed, modes, nodes)
    rhs = np.zeros((modes + 1, grid.size))
    rhs[0] = grid.source()
    values = splu(grid.coupled_operator(speed)).solve(rhs.ravel())
    return grid.force(values[grid.size : 2 * grid.size])


def free_disk_cubic_coefficient(disk: CamphorDisk, nodes: int = 24) -> float:
    """K3 of the drive f(U) = K(0) U + K3 U^3 + O(U^5): the pitchfork's normal form.

    The expansion c = c0 + U c1 + U^2 c2 + U^3 c3 of the co-moving problem gives one
    radial problem per order and mode: L_1 g = -c0', L_0 h0 = -(g' + g/r)/2,
    L_2 h2 = -(g' - g/r)/2, L_1 j = -(h0' + h2'/2 + h2/r), and K3 = -k pi rho j(rho)
    (docs/bodies.md, "Pitchfork"). K3 < 0 makes the pitchfork supercritical:
    U^2 = pi rho^2 (mu_c - mu) / |K3| just below mu_c.

    Args:
        disk: the disk.
        nodes: Chebyshev intervals per radial panel.

    Returns:
        K3.
    """
    grid = _modes_for(disk, 0.0, 3, nodes)

    def solve(rhs: dict[int, np.ndarray]) -> dict[int, np.ndarray]:
        return {m: splu(grid.mode_operator(m).tocsc()).solve(-v) for m, v in rhs.items()}

    rest = splu(grid.mode_operator(0).tocsc()).solve(grid.source())
    first = solve({1: grid.x_derivative({0: rest})[1]})
    second = solve(grid.x_derivative(first))
    third = solve({1: grid.x_derivative(second)[1]})
    return grid.force(third[1])


def free_disk_steady_speed(disk: CamphorDisk, friction: float) -> float:
    """The steady speed U of a free disk at friction mu: the root of f(U) = mu pi rho^2 U.

    Args:
        disk: the disk.
        friction: mu, below :func:`free_disk_critical_friction`.

    Returns:
        U > 0 (0 at or above the critical friction).
    """
    drag = friction * disk.area
    if float(free_disk_force_coefficient(disk)) <= drag:
        return 0.0

    def excess(speed: float) -> float:
        return free_disk_drive(disk, speed) - drag * speed

    high = math.sqrt(disk.evaporation * disk.diffusion)
    while excess(high) > 0:
        high *= 2
    low = high / 2
    while excess(low) < 0:
        low /= 2
    return float(brentq(excess, low, high, xtol=1e-12, rtol=1e-10))
