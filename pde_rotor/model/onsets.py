"""Onsets of motion from linear stability: the theory the body simulations are checked against.

Everything here is the no-flow limit (v = 0) of Eq. (eqc),

    dc/dt = D lap c - a (1 - F) c + s0 / (pi rho^2) G,

with sharp indicators (delta -> 0) unless a function says otherwise, and the force and
torque of the surface tension gamma = gamma0 - k c, Eq. (surfacetension), on the floating
part F of a body: f = -k int F grad c dA, T = -k int F (r - X) x grad c dA (the sign of
``rotor.torque = "physical"``, Eq. (torque) corrected). docs/bodies.md derives each result.

* A free camphor disk (the pill is the object, F = G) on an unbounded surface: the rest
  state :func:`rest_concentration`, the velocity response :func:`free_disk_force_coefficient`
  K(lambda) in closed form (Bessel functions), the critical friction
  :func:`free_disk_critical_friction`, the growth rate :func:`free_disk_growth_rate`,
  and the pitchfork's cubic coefficient :func:`free_disk_cubic_coefficient` with the
  exact drive :func:`free_disk_drive` of a disk translating at any speed (a radial
  Chebyshev solve of the Fourier modes in theta).
* The same disk at the centre of a dish with a no-flux or absorbing wall: the force per
  unit displacement :func:`free_disk_displacement_force`, the Hopf onset
  :func:`dish_hopf_onset` and the Hopf pair's growth rate :func:`dish_hopf_rate`
  (Koyano, Suematsu & Kitahata, PRE 99, 022211 (2019)).
* The two-disk rotor of Koyano et al., PRE 96, 012609 (2017): the torque response
  :func:`rotor_torque_coefficient` from a sparse finite-difference solve of the
  co-rotating linear problem with smoothed indicators, the critical friction
  :func:`rotor_critical_friction` and the critical half-length
  :func:`rotor_critical_half_length`.

Units are the config's: lengths in sqrt(D/a) when D = a = 1, times in 1/a.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from itertools import pairwise
from typing import TYPE_CHECKING, Literal

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq
from scipy.sparse.linalg import splu
from scipy.special import ive, kve

if TYPE_CHECKING:
    from ..config import RotorConfig


@dataclass(frozen=True)
class CamphorDisk:
    """A camphor disk of Eq. (eqc) and the surface it floats on.

    Attributes:
        diffusion: D, camphor diffusion coefficient.
        evaporation: a, sublimation rate on open water.
        supply: s0, camphor supply of the disk.
        tension_slope: k of gamma = gamma0 - k c, Eq. (surfacetension).
        radius: rho, the disk radius.
    """

    diffusion: float
    evaporation: float
    supply: float
    tension_slope: float
    radius: float

    @classmethod
    def from_config(cls, config: RotorConfig) -> CamphorDisk:
        """The disk of a config: its camphor section and its pill radius.

        Args:
            config: a :class:`pde_rotor.config.RotorConfig`.

        Returns:
            The disk with D, a, s0, k of ``config.camphor`` and rho = ``geometry.pill_radius``.
        """
        camphor = config.camphor
        return cls(
            diffusion=camphor.diffusion,
            evaporation=camphor.evaporation,
            supply=camphor.supply,
            tension_slope=camphor.tension_slope,
            radius=config.geometry.pill_radius,
        )

    def __post_init__(self) -> None:
        for name in ("diffusion", "evaporation", "radius"):
            if not getattr(self, name) > 0:
                value = getattr(self, name)
                msg = f"{name} must be > 0 (the rest state needs sublimation), got {value}"
                raise ValueError(msg)

    @property
    def decay(self) -> float:
        """q = sqrt(a/D), the inverse diffusion length."""
        return math.sqrt(self.evaporation / self.diffusion)

    @property
    def area(self) -> float:
        """A = pi rho^2."""
        return math.pi * self.radius**2

    @property
    def source(self) -> float:
        """S = s0 / (pi rho^2), the supply density under the disk."""
        return self.supply / self.area


@dataclass(frozen=True)
class Wall:
    """The circular wall of a dish of radius L centred on the disk.

    Attributes:
        radius: L.
        condition: ``"no_flux"`` (dc/dr = 0 at L) or ``"absorbing"``
            (c = 0 at L, the simulator's domain, docs/model.md).
    """

    radius: float
    condition: Literal["no_flux", "absorbing"]

    def __post_init__(self) -> None:
        if self.condition not in ("no_flux", "absorbing"):
            msg = f"wall condition must be 'no_flux' or 'absorbing', got {self.condition!r}"
            raise ValueError(msg)


# --- Bessel functions of the outer region --------------------------------------------------


def _outer_mode(
    order: int, decay: complex, r: np.ndarray | float, wall: Wall | None
) -> tuple[np.ndarray, np.ndarray]:
    """The outer solution W of (L_m - Q^2) W = 0 that meets the wall, scaled by exp(Q r).

    W = K_m(Q r) - beta I_m(Q r), with beta = 0 on an unbounded surface and beta fixed by
    W(L) = 0 or W'(L) = 0. Returned as (W, dW/dr) times exp(Q r), written with the
    exponentially scaled kve, ive so that neither overflows for Q L up to 1e4.

    Args:
        order: m >= 0.
        decay: Q with Re Q > 0.
        r: radii (rho <= r <= L).
        wall: the dish, or None.

    Returns:
        (W, W') scaled by exp(Q r).
    """
    z = decay * np.asarray(r)
    k = kve(order, z)
    dk = -0.5 * (kve(abs(order - 1), z) + kve(order + 1, z))
    if wall is None:
        return k, decay * dk
    i = ive(order, z)
    di = 0.5 * (ive(abs(order - 1), z) + ive(order + 1, z))
    zl = decay * wall.radius
    if wall.condition == "absorbing":
        beta = kve(order, zl) / ive(order, zl)
    else:
        beta = -0.5 * (kve(abs(order - 1), zl) + kve(order + 1, zl))
        beta /= 0.5 * (ive(abs(order - 1), zl) + ive(order + 1, zl))
    # K_m = kve exp(-z), I_m = ive exp(Re z): beta I_m(Qr) exp(Qr) carries
    # exp((Q + Re Q)(r - L)), at most 1 in modulus inside the dish
    factor = np.exp((decay + np.real(decay)) * (np.asarray(r) - wall.radius))
    return k - beta * factor * i, decay * (dk - beta * factor * di)


def _inner_log_derivative(lam: complex, disk: CamphorDisk) -> complex:
    """u'/u at r = rho for the regular m = 1 solution of (D L_1 - lambda) u = 0 inside.

    u = I_1(p r), p = sqrt(lambda / D), and u = r at lambda = 0 (no sublimation under
    the disk, F = 1 there). The ratio is even in p, so the branch of the root is free.
    """
    if lam == 0:
        return 1.0 / disk.radius
    z = np.sqrt(complex(lam) / disk.diffusion) * disk.radius
    # z I_1'(z) = z I_2(z) + I_1(z): no cancellation against the 1/rho of lambda = 0
    return (1.0 + z * ive(2, z) / ive(1, z)) / disk.radius


def _real_if_real(value: complex, lam: complex) -> complex | float:
    """A real number for a real growth rate, the complex value otherwise."""
    return float(np.real(value)) if np.isreal(lam) else complex(value)


def rest_concentration(
    disk: CamphorDisk, r: np.ndarray | float, wall: Wall | None = None
) -> np.ndarray:
    """The rest state c0(r) of a disk at rest (at the centre of the dish if `wall`).

    Inside (F = G = 1, no sublimation): D lap c0 + S = 0, c0 = A0 - S r^2 / (4 D).
    Outside: D lap c0 - a c0 = 0, c0 = B W_0(r), W_0 = K_0(q r) - beta I_0(q r) meeting the
    wall. c0 and dc0/dr are continuous at rho; the flux through the rim, -2 pi rho D
    dc0/dr = s0, is the whole supply (docs/bodies.md, "Rest state").

    Args:
        disk: the disk.
        r: radii >= 0 (at most L with a wall).
        wall: the dish, or None for an unbounded surface.

    Returns:
        c0 at `r`.
    """
    r = np.asarray(r, dtype=float)
    rho, D, q = disk.radius, disk.diffusion, disk.decay
    slope = -disk.source * rho / (2 * D)  # dc0/dr at rho, from the flux s0
    w_rho, dw_rho = _outer_mode(0, q, rho, wall)
    rim = slope * w_rho / dw_rho
    outer_r = np.maximum(r, rho)
    w, _ = _outer_mode(0, q, outer_r, wall)
    outside = slope * w / dw_rho * np.exp(-q * (outer_r - rho))
    inside = rim + disk.source * (rho**2 - r**2) / (4 * D)
    return np.where(r < rho, inside, np.real(outside))


def free_disk_displacement_force(
    disk: CamphorDisk, lam: complex, wall: Wall | None = None
) -> complex | float:
    """Force per unit displacement, Phi(lambda), of a disk displaced as X exp(lambda t).

    In the lab frame the field is c0 + X h(r) cos(theta) exp(lambda t), h the m = 1
    solution of (D L_1 - a (1 - F) - lambda) h = 0 that is regular at 0, continuous,
    meets the wall, and whose slope jumps at rho by -(a c0(rho) + S) / D (the moving
    source and sink, docs/bodies.md, "Growth rate"). The force on the displaced contour is
    f = -k pi rho (dc0/dr(rho) + h(rho)) X. On an unbounded surface Phi(0) = 0
    (translation invariance) and K(lambda) = Phi(lambda) / lambda; in a dish Phi(0) is minus
    the wall's stiffness.

    Args:
        disk: the disk.
        lam: growth rate lambda (complex allowed), Re(a + lambda) > 0.
        wall: the dish, or None.

    Returns:
        Phi(lambda), real for a real lambda.
    """
    rho, D = disk.radius, disk.diffusion
    slope = -disk.source * rho / (2 * D)  # dc0/dr at rho
    c_rim = float(rest_concentration(disk, rho, wall))
    jump = (disk.evaporation * c_rim + disk.source) / D
    decay = np.sqrt(complex(disk.evaporation + lam) / D)
    w, dw = _outer_mode(1, decay, rho, wall)
    mismatch = dw / w - _inner_log_derivative(lam, disk)
    if wall is None:
        # h = -dc0/dr at lambda = 0, so jump = slope * mismatch(0): subtract in closed form
        w0, dw0 = _outer_mode(1, disk.decay, rho, None)
        rim = slope * (mismatch - (dw0 / w0 - 1.0 / rho)) / mismatch
    else:
        rim = slope - jump / mismatch
    return _real_if_real(-disk.tension_slope * math.pi * rho * rim, lam)


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
        return _real_if_real(free_disk_displacement_force(disk, lam) / lam, lam)
    x = disk.decay * disk.radius
    if lam != 0:
        step = TAYLOR_STEP * disk.evaporation
        at_zero = free_disk_force_coefficient(disk)
        above = float(free_disk_force_coefficient(disk, step))
        below = float(free_disk_force_coefficient(disk, -step))
        slope = (above - below) / (2 * step)
        curvature = (above - 2 * at_zero + below) / step**2
        return _real_if_real(at_zero + lam * slope + lam**2 * curvature / 2, lam)
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


def dish_hopf_onset(disk: CamphorDisk, wall: Wall, mass: float = 0.0) -> tuple[float, float]:
    """Critical friction and frequency of the Hopf onset of a disk at the centre of a dish.

    The displacement X exp(lambda t) obeys m lambda^2 + mu A lambda - Phi(lambda) = 0
    (:func:`free_disk_displacement_force`). A no-flux wall pushes the disk back to the
    centre (Phi(0) < 0), so the rest state loses stability through lambda = +-i omega:
    Re Phi(i omega) = -m omega^2 fixes omega, mu_c = Im Phi(i omega) / (omega A). The m = 1
    mode is twofold (x and y), hence the double Hopf of Koyano, Suematsu & Kitahata.

    Args:
        disk: the disk.
        wall: the dish; its wall must hold the disk (no-flux).
        mass: m of the disk.

    Returns:
        (mu_c, omega_c).

    Raises:
        ValueError: if the wall does not restore (an absorbing wall: the centre is a
            saddle at every friction, its real root is :func:`dish_drift_rate`).
    """
    if free_disk_displacement_force(disk, 0.0, wall) >= 0:
        msg = f"a {wall.condition} wall does not hold the disk at the centre: no Hopf onset"
        raise ValueError(msg)

    def real_part(omega: float) -> float:
        return (
            float(np.real(free_disk_displacement_force(disk, 1j * omega, wall))) + mass * omega**2
        )

    omegas = np.geomspace(1e-8, 1e4, 241) * disk.evaporation
    signs = np.sign([real_part(w) for w in omegas])
    first = int(np.argmax(signs > 0))
    if signs[first] <= 0:
        msg = "no frequency found where the wall's restoring force is balanced"
        raise ValueError(msg)
    omega = brentq(real_part, omegas[first - 1], omegas[first], xtol=1e-15, rtol=1e-13)
    force = free_disk_displacement_force(disk, 1j * omega, wall)
    return float(np.imag(force)) / (omega * disk.area), float(omega)


def dish_hopf_rate(disk: CamphorDisk, wall: Wall, friction: float, mass: float = 0.0) -> complex:
    """The complex growth rate lambda = sigma + i omega of the Hopf pair at friction mu.

    The root of m lambda^2 + mu A lambda - Phi(lambda) = 0 that passes through i omega_c
    at mu_c (:func:`dish_hopf_onset`), followed from there in steps of mu_c / 400 by
    Newton's method (Phi is analytic; its derivative by a central difference): sigma > 0
    below mu_c, < 0 above, and omega the frequency of the linear orbit about the centre.
    Away from mu_c the pair can meet on the real axis and split into two real rates;
    the root followed is then one of them (omega = 0).

    Args:
        disk: the disk.
        wall: the dish (no-flux).
        friction: mu.
        mass: m of the disk.

    Returns:
        lambda.

    Raises:
        ValueError: as :func:`dish_hopf_onset`, or if Newton's method does not converge.
    """
    mu_c, omega_c = dish_hopf_onset(disk, wall, mass)

    def phi(lam: complex) -> complex:
        return complex(free_disk_displacement_force(disk, lam, wall))

    lam = 1j * omega_c
    steps = max(1, math.ceil(abs(friction - mu_c) / mu_c * 400))
    for mu in np.linspace(mu_c, friction, steps + 1)[1:]:
        lam = _newton(lambda z, mu=mu: mass * z**2 + mu * disk.area * z - phi(z), lam)
        if lam is None:
            msg = f"no Hopf root found at friction {mu:g} (mu_c = {mu_c:g})"
            raise ValueError(msg)
    return complex(lam)


def _newton(func: Callable[[complex], complex], start: complex) -> complex | None:
    """A root of the analytic `func` by Newton's method from `start` (None: no convergence)."""
    lam = start
    for _ in range(60):
        step = 1e-6 * max(abs(lam), 1.0)
        slope = (func(lam + step) - func(lam - step)) / (2 * step)
        delta = func(lam) / slope
        lam -= delta
        if abs(delta) < 1e-13 * max(abs(lam), 1.0):
            return lam
    return None


def dish_drift_rate(disk: CamphorDisk, wall: Wall, friction: float, mass: float = 0.0) -> float:
    """Largest real root of m lambda^2 + mu A lambda - Phi(lambda) = 0 (docs/bodies.md, section 2).

    With an absorbing wall (the simulator's Dirichlet circle) Phi(0) > 0: the wall pulls
    the disk off the centre at every friction, slowly when the wall is far. This is the
    rate at which a disk released at the centre drifts away.

    Args:
        disk: the disk.
        wall: the dish.
        friction: mu.
        mass: m of the disk.

    Returns:
        The largest real lambda in (0, infinity), or nan if there is none.
    """

    def chi(lam: float) -> float:
        force = float(free_disk_displacement_force(disk, lam, wall))
        return mass * lam**2 + friction * disk.area * lam - force

    lams = np.geomspace(1e-12, 1e8, 401) * disk.evaporation
    values = np.array([chi(lam) for lam in lams])
    crossings = np.nonzero(np.diff(np.sign(values)) != 0)[0]
    if crossings.size == 0:
        return math.nan
    i = int(crossings[-1])
    return float(brentq(chi, lams[i], lams[i + 1], xtol=1e-16, rtol=1e-12))


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


# --- the two-disk rotor: sparse finite differences on a stretched quadrant grid ----------


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
