"""Camphor boats in a straight channel of finite width: the 2D steady state, exactly.

The 1D theory of :mod:`.ring` pulls a boat by k [c(rear) - c(front)] with c the
width-averaged concentration, as if the boat spanned the channel. A boat of width b in a
channel of width w > b feels, besides, the part of c that varies across the channel,
largest at its own pill. This module solves Eq. (eqc) without flow for N evenly spaced
boats moving together at speed V in a straight channel, periodic along x with period
P = L / N and no-flux across (0 < y < w), exactly: in the co-moving frame

    D lap c + V c_x - a c + S g = 0

is diagonal in the modes e^{i k x} cos(q y), k = 2 pi n / P, q = m pi / w, with g the
uniform disk of the pill (radius rho, supply S, centred on the channel's middle line at
x = sigma from the boat's centre):

    c_nm = S g_nm / (D (k^2 + q^2) + a - i V k),
    g_nm = e^{-i k sigma} cos(q w / 2) 2 J1(kappa rho) / (kappa rho) (2 - [m = 0]) / (P w),

kappa = sqrt(k^2 + q^2) (odd m vanish: cos(q w / 2) = 0). The boat is a sharp strip
l x b centred on the middle line; the tension on its rear and front edges,
Eq. (surfacetension),

    f(V) = k int_{|y - w/2| < b/2} [c(-l/2, y) - c(l/2, y)] dy
         = k sum_nm c_nm (-2 i sin(k l / 2)) Y_m,   Y_m = int cos(q y) dy over the strip,

balances the friction mu_2D l b V of Eq. (eq_motion) (overdamped). The 1D theory's
parameters map as there: k s0 = k S / w (width-averaged supply), mu = mu_2D l. With
b = w only m = 0 is left and f is the 1D theory's force with the disk as source, whatever
w: the width average is exact for a boat that spans the channel. Evaporation goes on
under the plate here (as in the 1D theory; the 2D model stops it there, Eq. (eqc)'s
a (1 - F) c, which couples the modes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special
from scipy.optimize import brentq


@dataclass(frozen=True)
class ChannelBoats:
    """N identical strip boats, evenly spaced, in a straight no-flux channel.

    Attributes:
        ring_length: L, the channel's length (periodic).
        count: N.
        channel_width: w.
        boat_length: l, the strip's length along the channel.
        boat_width: b <= w, the strip's width.
        pill_radius: rho of the pill, a uniform disk on the middle line.
        source: sigma, the pill's centre along the boat from its centre.
        friction: mu of the 1D theory, mu_2D l (force per speed per unit width).
        drive: k s0 of the 1D theory, k S / w.
        diffusion: D.
        evaporation: a (everywhere, also under the plate).
    """

    ring_length: float
    count: int
    channel_width: float
    boat_length: float
    boat_width: float
    pill_radius: float
    source: float
    friction: float
    drive: float = 1.0
    diffusion: float = 1.0
    evaporation: float = 1.0

    def __post_init__(self) -> None:
        if not 0 < self.boat_width <= self.channel_width:
            raise ValueError(
                f"boat_width = {self.boat_width}: need 0 < b <= channel_width = "
                f"{self.channel_width}"
            )
        if not 0 < self.boat_length < self.ring_length / self.count:
            raise ValueError(
                f"boat_length = {self.boat_length}: need 0 < l < L / N = "
                f"{self.ring_length / self.count:g}"
            )


def channel_force(boats: ChannelBoats, speed: float, cutoff: float = 30.0) -> float:
    """f(V) / b: the tension on each boat moving at `speed`, per unit boat width.

    Args:
        boats: the boats.
        speed: V.
        cutoff: the modes are kept for kappa rho < cutoff (the pill's transform falls as
            (kappa rho)^(-3/2); 15 and 30 differ by 1.3e-4 relative at w = 1.9).

    Returns:
        f / b, comparable with the 1D theory's force per unit width k s0 [G(rear) - G(front)].
    """
    w, b = boats.channel_width, boats.boat_width
    period = boats.ring_length / boats.count
    top = cutoff / boats.pill_radius
    n = np.arange(1, math.ceil(top * period / (2 * math.pi)) + 1)
    k = 2 * math.pi * n / period  # k > 0; the conjugate modes -k double the real part
    q = np.arange(0, math.ceil(top * w / math.pi) + 1, 2) * math.pi / w
    kk, qq = np.meshgrid(k, q, indexing="ij")
    kappa = np.hypot(kk, qq) * boats.pill_radius
    disk = 2 * special.j1(kappa) / kappa
    across = np.cos(q * w / 2)
    weight = np.where(q == 0, 1.0, 2.0) * across / (period * w)
    field = (
        np.exp(-1j * kk * boats.source)
        * disk
        * weight
        / (boats.diffusion * (kk**2 + qq**2) + boats.evaporation - 1j * speed * kk)
    )
    safe = np.where(q == 0, 1.0, q)
    strip = np.where(q == 0, b, 2 * across * np.sin(q * b / 2) / safe)
    edges = -2j * np.sin(kk * boats.boat_length / 2)
    supply = boats.drive * w  # k S
    return 2 * supply * float(np.real(np.sum(field * edges * strip))) / b


def channel_speed(boats: ChannelBoats, low: float, high: float, points: int = 14) -> float:
    """The fastest steady speed in (low, high): mu V = f(V) / b.

    Args:
        boats: the boats.
        low, high: the interval scanned (geometrically) for sign changes.
        points: scan points.

    Returns:
        V (0.0 if no root lies in the interval).
    """

    def excess(v: float) -> float:
        return channel_force(boats, v) - boats.friction * v

    grid = np.geomspace(low, high, points)
    values = [excess(v) for v in grid]
    roots = [
        brentq(excess, lo, hi, xtol=1e-10, rtol=1e-10)
        for lo, hi, f_lo, f_hi in zip(grid[:-1], grid[1:], values[:-1], values[1:], strict=True)
        if f_lo * f_hi < 0
    ]
    return roots[-1] if roots else 0.0
