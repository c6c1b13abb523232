"""The camphor disk of the onset theory, its dish wall, its rest state and its response.

What the free disk (:mod:`.free_disk`) and the disk in a dish (:mod:`.dish`) share: the
disk (:class:`CamphorDisk`), the circular wall (:class:`Wall`), the rest state
:func:`rest_concentration` and the force per unit displacement
:func:`free_disk_displacement_force` Phi(lambda) of the m = 1 mode, in closed form from
Bessel functions, on an unbounded surface or inside the wall. Everything is the no-flow
limit (v = 0) of Eq. (eqc) with sharp indicators, and the force is that of the surface
tension gamma = gamma0 - k c, Eq. (surfacetension), on the floating part of the disk
(docs/bodies.md, "Rest state" and "Growth rate").

Units are the config's: lengths in sqrt(D/a) when D = a = 1, times in 1/a.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np
from scipy.special import ive, kve

from ..config import ConfigError

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

        Raises:
            ConfigError: the config's surface tension is not the linear law of Eq.
                (surfacetension), which every onset of this package assumes.
        """
        camphor = config.camphor
        if camphor.saturation is not None:
            msg = (
                f"camphor.saturation = {camphor.saturation:g}: the exact onsets assume the "
                "linear law gamma0 - k c (allowed here: null)"
            )
            raise ConfigError(msg)
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


def real_if_real(value: complex, lam: complex) -> complex | float:
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
    return real_if_real(-disk.tension_slope * math.pi * rho * rim, lam)
