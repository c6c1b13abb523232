"""Camphor boats on a ring: the 1D limit of Eq. (eqc) and its exact travelling waves.

N point-like boats of length l move along a ring of length L (a channel much narrower than
the camphor's decay length sqrt(D/a), averaged across its width, no flow). Each boat i, centre
X_i(t), releases camphor at one point, its rear end X_i - l/2 (``source="rear"``) or its
centre (``source="centre"``, the symmetric boat), and Eq. (eqc) becomes

    c_t = D c_xx - a c + s0 sum_i delta(x - X_i - sigma),      sigma = -l/2 or 0.

The surface tension gamma = gamma0 - k c, Eq. (surfacetension), pulls a boat's two ends;
overdamped (Eq. (eq_motion) without its inertia) the boat obeys

    mu dX_i/dt = k [c(X_i - l/2) - c(X_i + l/2)].

Only the product k s0 (``drive``) enters. docs/ring.md derives the three results:

* **Travelling state.** N evenly spaced boats moving together at speed V see, in the
  co-moving frame xi = x - V t, the Bloch Green's function of D c'' + V c' - r c = -delta
  (:func:`bloch_green`, a closed form of the sum over images). The N-boat state is the one
  boat state on a ring of length d = L / N, and V solves mu V = F(V) (:func:`drive_force`,
  :func:`travelling_speeds`).
* **Spacing modes.** A perturbation x_i ~ w^i e^{lambda t} with w = e^{2 pi i m / N}
  (m = 0 ... N - 1, the discrete Fourier modes of the spacing) grows or decays with the
  roots of :func:`spacing_dispersion`; :func:`spacing_rates` gives the leading root of each
  mode (m = 0 without the translation root lambda = 0: the speed's relaxation).
* **Onset of the symmetric boat.** At rest (V = 0) a root of the m = 0 mode crosses
  lambda = 0 at mu = -k s0 d/dlambda [G'(-l/2) - G'(l/2)] (:func:`rest_pitchfork_friction`):
  below it the boats start to move together. A pair lambda = +-i omega of mode m crosses at
  :func:`rest_hopf_friction` (oscillating spacings); :func:`rest_critical_friction` is the
  larger of the two, the friction below which the rest state is unstable.

Units are the config's: lengths in sqrt(D/a) when D = a = 1, times in 1/a.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.optimize import brentq


@dataclass(frozen=True)
class RingBoats:
    """N identical camphor boats on a ring of the 1D model.

    Attributes:
        ring_length: L, the ring's circumference.
        boat_length: l, the distance between a boat's rear and front ends.
        count: N, the number of boats.
        friction: mu, the boat's friction coefficient (force per unit speed).
        drive: k s0, tension slope times camphor supply per boat.
        diffusion: D, camphor diffusion coefficient.
        evaporation: a, sublimation rate (everywhere on the ring).
        source: ``"rear"``: camphor from the boat's rear end; ``"centre"``: from its centre.
    """

    ring_length: float
    boat_length: float
    count: int
    friction: float
    drive: float = 1.0
    diffusion: float = 1.0
    evaporation: float = 1.0
    source: Literal["rear", "centre"] = "rear"

    def __post_init__(self) -> None:
        if self.count < 1:
            raise ValueError(f"count = {self.count}: need at least one boat")
        if not 0 < self.boat_length < self.ring_length / self.count:
            raise ValueError(
                f"boat_length = {self.boat_length}: need 0 < l < L / N = "
                f"{self.ring_length / self.count:g} so that the boats do not overlap"
            )
        if self.source not in ("rear", "centre"):
            raise ValueError(f"source = {self.source!r}: use 'rear' or 'centre'")

    @property
    def spacing(self) -> float:
        """d = L / N, the distance between neighbours when evenly spaced."""
        return self.ring_length / self.count

    @property
    def source_offset(self) -> float:
        """sigma, the source's position relative to the boat's centre."""
        return -0.5 * self.boat_length if self.source == "rear" else 0.0

    @property
    def ends(self) -> tuple[float, float]:
        """The rear and front ends relative to the boat's own source."""
        half = 0.5 * self.boat_length
        return -half - self.source_offset, half - self.source_offset


def _exponents(speed: float, rate: complex, diffusion: float) -> tuple[complex, complex, complex]:
    """s+, s- and the amplitude A of the line Green's function of D G'' + V G' - r G = -delta."""
    root = cmath.sqrt(speed * speed + 4.0 * diffusion * rate)
    return (-speed + root) / (2 * diffusion), (-speed - root) / (2 * diffusion), 1.0 / root


def bloch_green(
    y: float,
    spacing: float,
    speed: float,
    rate: complex,
    phase: complex = 1.0,
    diffusion: float = 1.0,
    derivative: bool = False,
) -> complex:
    """The Bloch sum G_w(y) = sum_p w^p G(y - p d) of the co-moving Green's function.

    G solves D G'' + V G' - r G = -delta(y) on the line: G = A e^{s- y} for y > 0 and
    A e^{s+ y} for y < 0, with s+- = (-V +- sqrt(V^2 + 4 D r)) / (2 D) and
    A = 1 / sqrt(V^2 + 4 D r). Summing the geometric series of images, for 0 <= y0 < d

        G_w(y0) = A e^{s- y0} / (1 - e^{s- d} / w) + A w e^{s+ (y0 - d)} / (1 - w e^{-s+ d}),

    and G_w(y0 + n d) = w^n G_w(y0). With w = 1 and real r = a it is the steady field of
    boats spaced d apart, per unit supply, Eq. (eqc) in the co-moving frame.

    Args:
        y: position relative to a source.
        spacing: d, the period of the images.
        speed: V, the speed of the sources (the frame's).
        rate: r, the decay rate (a + lambda for a mode growing as e^{lambda t}); Re r > 0.
        phase: w, the Bloch factor between neighbouring images (|w| = 1).
        diffusion: D.
        derivative: return dG_w/dy instead; at the sources themselves (y a multiple of d)
            the mean of the two one-sided slopes, the value the moving source feels.

    Returns:
        G_w(y) or its derivative.
    """
    s_plus, s_minus, amp = _exponents(speed, rate, diffusion)
    n = math.floor(y / spacing)
    y0 = y - n * spacing
    ahead = amp / (1.0 - cmath.exp(s_minus * spacing) / phase)
    behind = amp * phase / (1.0 - phase * cmath.exp(-s_plus * spacing))
    scale = phase**n
    if not derivative:
        return scale * (
            ahead * cmath.exp(s_minus * y0) + behind * cmath.exp(s_plus * (y0 - spacing))
        )
    right = ahead * s_minus * cmath.exp(s_minus * y0) + behind * s_plus * cmath.exp(
        s_plus * (y0 - spacing)
    )
    if y0 != 0.0:
        return scale * right
    left = (ahead * s_minus * cmath.exp(s_minus * spacing) + behind * s_plus) / phase
    return scale * 0.5 * (right + left)


def drive_force(boats: RingBoats, speed: float) -> float:
    """F(V) = k s0 [G(rear) - G(front)], the pull on each of N boats moving together at V.

    Args:
        boats: the boats.
        speed: their common speed V.

    Returns:
        The force along the direction of motion on each boat in the evenly spaced state.
    """
    rear, front = boats.ends
    args = (boats.spacing, speed, boats.evaporation, 1.0, boats.diffusion)
    return boats.drive * (bloch_green(rear, *args) - bloch_green(front, *args)).real


def travelling_speeds(boats: RingBoats, points: int = 4000) -> tuple[float, ...]:
    """Every speed V > 0 with mu V = F(V): the evenly spaced states moving together.

    F(V) <= k s0 max G <= k s0 (1 / (a d) + 1 / sqrt(4 a D)), so every root lies below
    that bound over mu; the interval is scanned on a geometric grid and each sign change
    refined with Brent's method.

    Args:
        boats: the boats.
        points: scan points.

    Returns:
        The speeds in increasing order (empty if the boats only rest).
    """
    bound = boats.drive * (
        1 / (boats.evaporation * boats.spacing)
        + 1 / math.sqrt(4 * boats.evaporation * boats.diffusion)
    )
    top = 2.0 * bound / boats.friction + 1.0
    grid = np.geomspace(1e-6 * top, top, points)

    def excess(v: float) -> float:
        return drive_force(boats, v) - boats.friction * v

    values = [excess(v) for v in grid]
    roots = [
        brentq(excess, lo, hi, xtol=1e-14, rtol=1e-14)
        for lo, hi, f_lo, f_hi in zip(grid[:-1], grid[1:], values[:-1], values[1:], strict=True)
        if f_lo * f_hi < 0
    ]
    return tuple(roots)


def travelling_speed(boats: RingBoats) -> float:
    """The fastest evenly spaced travelling state (0.0 if there is none).

    Args:
        boats: the boats.

    Returns:
        V.
    """
    speeds = travelling_speeds(boats)
    return speeds[-1] if speeds else 0.0


def _response(boats: RingBoats, speed: float, phase: complex, growth: complex) -> complex:
    """k s0 [G_w'(rear) - G_w'(front)] at decay rate a + lambda."""
    rear, front = boats.ends
    args = (boats.spacing, speed, boats.evaporation + growth, phase, boats.diffusion, True)
    return boats.drive * (bloch_green(rear, *args) - bloch_green(front, *args))


def spacing_dispersion(boats: RingBoats, speed: float, mode: int, growth: complex) -> complex:
    """f_m(lambda) = mu lambda - R_m(lambda): zero at the growth rates of spacing mode m.

    Linearising the boats' motion about the evenly spaced state at speed V, with
    x_j(t) = w^j e^{lambda t} and w = e^{2 pi i m / N}: the field a source left at time t - tau
    is the heat kernel K(y, tau), its position error is x_j(t - tau), and the force on boat i
    changes by k s0 sum_j int dtau [K_y(rear) - K_y(front)] (x_i(t) - x_j(t - tau)). The
    tau-integrals are Laplace transforms, i.e. Green's functions at decay rate a + lambda:

        R_m(lambda) = k s0 {[G_1'(e_r) - G_1'(e_f)]_{r = a}
                            - [G_w'(e_r) - G_w'(e_f)]_{r = a + lambda}}

    with e_r, e_f the ends relative to the source (:func:`bloch_green`). R_0(0) = 0 (a shift
    of every boat) and R_0'(0) = F'(V) (a slow change of speed).

    Args:
        boats: the boats.
        speed: V of the state (0 for boats at rest).
        mode: m, 0 ... N - 1.
        growth: lambda, Re lambda > -a.

    Returns:
        f_m(lambda).
    """
    phase = cmath.exp(2j * math.pi * mode / boats.count)
    static = _response(boats, speed, 1.0, 0.0)
    return boats.friction * growth - (static - _response(boats, speed, phase, growth))


def _reduced(boats: RingBoats, speed: float, mode: int, growth: complex) -> complex:
    """f_m, divided by lambda for m = 0 to remove the translation root."""
    value = spacing_dispersion(boats, speed, mode, growth)
    return value / growth if mode == 0 else value


def _newton(func, start: complex, tol: float = 1e-12, steps: int = 60) -> complex | None:
    """Newton's method with a centred complex difference; None when it does not converge."""
    z = start
    for _ in range(steps):
        h = 1e-6 * max(1.0, abs(z))
        try:
            f = func(z)
            slope = (func(z + h) - func(z - h)) / (2 * h)
        except (ZeroDivisionError, OverflowError):
            return None
        if slope == 0 or not cmath.isfinite(f):
            return None
        step = f / slope
        z -= step
        if abs(step) < tol * max(1.0, abs(z)):
            return z
    return None


def spacing_roots(
    boats: RingBoats, speed: float, mode: int, floor: float = 0.98, reach: float = 3.0
) -> list[complex]:
    """The roots of f_m with Re lambda > -floor a, by Newton from a grid of starts.

    The region holds no pole of f_m (the field's own modes decay at a + D k^2 or faster), so
    :func:`winding_number` counts its roots independently (tests/theory/test_ring.py).

    Args:
        boats: the boats.
        speed: V.
        mode: m.
        floor: roots below Re lambda = -floor a are left out.
        reach: the starts cover Re lambda up to `reach` and |Im lambda| up to
            V k_max + reach, k_max = 2 pi (m + N) / L.

    Returns:
        The distinct roots, largest real part first (m = 0: without lambda = 0).
    """
    a = boats.evaporation
    top = speed * 2 * math.pi * (mode + boats.count) / boats.ring_length + reach
    roots: list[complex] = []
    for re in np.linspace(-floor * a, reach, 9):
        for im in np.linspace(-top, top, 13):
            z = _newton(lambda g: _reduced(boats, speed, mode, g), complex(re, im))
            if z is None or z.real <= -floor * a or (mode == 0 and abs(z) < 1e-9):
                continue
            if all(abs(z - r) > 1e-7 * max(1.0, abs(z)) for r in roots):
                roots.append(z)
    return sorted(roots, key=lambda z: -z.real)


def spacing_rates(boats: RingBoats, speed: float | None = None) -> list[complex | None]:
    """The leading growth rate of each spacing mode m = 0 ... N - 1.

    Args:
        boats: the boats.
        speed: V (default: :func:`travelling_speed`).

    Returns:
        One lambda per mode, None where no root lies above -0.98 a (the mode then decays at
        least as fast as the field, at a or faster). m = 0 is the speed's relaxation;
        modes m and N - m are complex conjugates.
    """
    v = travelling_speed(boats) if speed is None else speed
    out: list[complex | None] = []
    for m in range(boats.count):
        roots = spacing_roots(boats, v, m)
        out.append(roots[0] if roots else None)
    return out


def winding_number(
    boats: RingBoats, speed: float, mode: int, box: tuple[float, float, float], points: int = 4000
) -> int:
    """The number of roots of f_m (m = 0: of f_0 / lambda) inside a rectangle.

    Args:
        boats: the boats.
        speed: V.
        mode: m.
        box: (Re low, Re high, |Im| high) of the rectangle.
        points: samples per side.

    Returns:
        The winding number of the function's values about 0 along the rectangle's edge.
    """
    lo, hi, im = box
    corners = [complex(lo, -im), complex(hi, -im), complex(hi, im), complex(lo, im)]
    path = np.concatenate(
        [
            np.linspace(p, q, points, endpoint=False)
            for p, q in zip(corners, corners[1:] + corners[:1], strict=True)
        ]
    )
    values = np.array([_reduced(boats, speed, mode, complex(z)) for z in path])
    turns = np.angle(np.roll(values, -1) / values)
    return round(turns.sum() / (2 * math.pi))


def rest_pitchfork_friction(boats: RingBoats) -> float:
    """The friction below which N symmetric boats at rest start to move together.

    At V = 0, f_0(lambda) / lambda = mu - R_0(lambda) / lambda changes sign at lambda = 0
    when mu = R_0'(0) = -k s0 d/dr [G_1'(e_r) - G_1'(e_f)] at r = a. For the symmetric boat
    G_1 is even, so a real root of the m = 0 mode crosses zero there (a pitchfork: the boats
    choose a direction). The derivative is a centred difference in r.

    Args:
        boats: boats with ``source="centre"`` (for a rear source the boats never rest).

    Returns:
        The pitchfork's friction.
    """
    _require_rest(boats)
    h = 1e-5 * boats.evaporation
    up = _response(boats, 0.0, 1.0, h)
    down = _response(boats, 0.0, 1.0, -h)
    return (-(up - down) / (2 * h)).real


def rest_hopf_friction(
    boats: RingBoats, mode: int, top: float = 40.0, points: int = 8000
) -> tuple[float, float]:
    """The largest friction at which spacing mode m of boats at rest has a root lambda = i omega.

    f_m(i omega) = 0 splits into Re R_m(i omega) = 0, which fixes omega, and
    mu = Im R_m(i omega) / omega. omega is scanned on (0, `top`] and refined with Brent's
    method. Below that friction the mode oscillates with growing amplitude: the boats'
    spacings oscillate (m != 0) or the boats rock back and forth together (m = 0).

    Args:
        boats: boats with ``source="centre"``.
        mode: m.
        top: the largest omega scanned.
        points: scan points.

    Returns:
        (mu, omega) of the crossing with the largest mu > 0, or (0.0, nan) if there is none.
    """
    _require_rest(boats)
    phase = cmath.exp(2j * math.pi * mode / boats.count)

    def response(omega: float) -> complex:
        return _response(boats, 0.0, 1.0, 0.0) - _response(boats, 0.0, phase, 1j * omega)

    grid = np.linspace(top / points, top, points)
    values = [response(w).real for w in grid]
    best = (0.0, math.nan)
    for lo, hi, f_lo, f_hi in zip(grid[:-1], grid[1:], values[:-1], values[1:], strict=True):
        if f_lo * f_hi < 0:
            omega = brentq(lambda w: response(w).real, lo, hi, xtol=1e-13, rtol=1e-13)
            mu = response(omega).imag / omega
            if mu > best[0]:
                best = (mu, omega)
    return best


def rest_critical_friction(boats: RingBoats) -> float:
    """mu_c(N): below it the evenly spaced symmetric boats at rest do not stay at rest.

    The largest of the pitchfork's friction (:func:`rest_pitchfork_friction`) and every
    mode's Hopf friction (:func:`rest_hopf_friction`).

    Args:
        boats: boats with ``source="centre"``.

    Returns:
        mu_c.
    """
    hopf = [rest_hopf_friction(boats, m)[0] for m in range(boats.count)]
    return max([rest_pitchfork_friction(boats), *hopf])


def _require_rest(boats: RingBoats) -> None:
    if boats.source != "centre":
        raise ValueError("boats rest only with source='centre' (a rear source always drives them)")
