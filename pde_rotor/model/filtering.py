"""Isotropic prefilter of F and G for the ``consistent`` scheme (tables built once per run).

Sampling F and G (the equations after Eq. (rj)) at the cell centres aliases the part of
their spectrum beyond the grid's Nyquist wavenumber pi/dx, and the 5-point Laplacian
treats what remains near it anisotropically: at the paper's dx = delta the pills' and the
plate's tanh edges are one cell wide, and the steady c of a stopped plate inherits a
pattern of the lattice that exerts a torque (docs/model.md, "Schemes"). The remedy of
sampling theory is to low-pass filter before sampling; a Gaussian filter of width
eps = kappa dx is the isotropic choice, so the filtered fields still turn rigidly with
the plate:

    F_eps = F * N_eps,   G_eps = G * N_eps,   N_eps(r) = exp(-|r|^2 / (2 eps^2)) / (2 pi eps^2).

The filter keeps every integral of F and G (their masses) and adds 2 eps^2 to their second
moments about any point, a change of the model of order dx^2 that vanishes with the grid:
both schemes converge to the same continuum. The other kernel is sharpened, a sum of two
Gaussians (:data:`KERNELS`),

    K_eps = 2 N_eps - N_(sqrt2 eps),   Fourier transform 1 - (k eps)^4 / 4 + O(k^6),

which keeps the masses and the second moments (it changes the model at order dx^4) at
the price of a small ringing: the filtered field leaves its range by a few % of its
height. F and G each have their own kernel and width (``numerics.plate_filter_*``,
``numerics.pill_filter_*``): by default the Gaussian at kappa = 0.7 for F and the
sharpened kernel at kappa = 0.95 for G, whose second moment the asymmetry torque feels
(docs/model.md, "Which kernel", has the measurements behind the choice). Every table
below is linear in its kernel and is built as the same sum of Gaussian filterings.

* The plate: F = f(a - h(r)), f(u) = 1/2 (1 + tanh(u / delta)), a = R cos(pi/N). More
  than CREASE_WIDTHS eps from the corner bisectors (the crease of h) the filter sees a
  single straight edge, so there F_eps = f_eps(a - h) with the 1-D profile
  f_eps = f * N_eps, tabulated with spacing dx / 1024 and interpolated linearly. Near
  the bisectors F_eps is taken from a 2-D table in the frame of edge 0 (its normal
  along +x), spacing dx / ``numerics.table_refinement``, filtered by
  :func:`scipy.ndimage.gaussian_filter` and stored as cubic B-spline coefficients. The
  kernels write each cell centre in the frame of its nearest edge
  (:mod:`pde_rotor.physics`, ``filtered_plate``), so F_eps has the hexagon's rotation and
  mirror symmetries exactly.
  Beyond the corners, where F_eps and the table's difference to the edge profile have
  fallen below CORNER_CUTOFF (from h = ``corner_end`` on, about a + 15 delta), the edge
  profile serves near the bisectors too.
* A strip plate of the bodies (:func:`strip_table`): F = f(-max(|x'| - L/2, |y'| - W/2))
  in its frame, filtered as one 2-D table over the quadrant x', y' >= 0 (mirrored about
  the axes), read at (|x'|, |y'|).
* The pills: G is a sum of radial profiles g(|r - R_j|), so G_eps = sum_j g_eps(|r - R_j|)
  with the radial convolution

      g_eps(d) = int_0^inf g(s) (s / eps^2) exp(-(d - s)^2 / (2 eps^2)) I0e(d s / eps^2) ds,

  tabulated on d with spacing dx / 256 and interpolated linearly
  (:mod:`pde_rotor.physics`, ``filtered_pills``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.ndimage import gaussian_filter, gaussian_filter1d, map_coordinates, spline_filter
from scipy.special import i0e

from ..config import X_SATURATION
from .geometry import RotorShape, edge_normal_angles, pill_centres, plate_indicator

PROFILE_REFINEMENT = 256
"""Points of the pill profile table per dx (linear interpolation error < 1e-5 of G)."""

GAUSS_TRUNCATE = 8.0
"""Gaussian kernels are cut at this many widths (relative weight exp(-32) = 1.3e-14)."""

CREASE_WIDTHS = GAUSS_TRUNCATE
"""Cells closer than this many eps to a corner bisector use the 2-D plate table."""

CORNER_CUTOFF = 1e-13
"""Beyond the plate's corners F_eps falls below this (of its height 1), and so does the
difference of the 2-D table and the edge profile: from there on (:func:`corner_end`) the
cells near a bisector take the edge profile too, which changes F by less than 2e-13
(tests/kernels/test_indicators.py) and spares the table a sixth of its cells."""

PILL_CUTOFF = 1e-14
"""The pill profile ends where |g_eps| falls below this (of its height 1): each cell then
adds only the pills within about rho + 16 delta instead of all of them (most of the cost
of G_eps), and c changes by a part in 1e14."""

EDGE_REFINEMENT = 1024
"""Points of the 1-D edge profile per dx (linear interpolation error < 1e-7 of F)."""

EDGE_OVERSAMPLING = 4
"""The edge profile is filtered on nodes this many times coarser, then interpolated."""

KERNELS: dict[str, tuple[tuple[float, float], ...]] = {
    "gaussian": ((1.0, 1.0),),
    "sharpened": ((2.0, 1.0), (-1.0, math.sqrt(2.0))),
}
"""Prefilter kernels (``numerics.plate_filter_kernel``, ``pill_filter_kernel``) as sums
of Gaussians: (weight, width in units of eps). ``sharpened`` = 2 N_eps - N_(sqrt2 eps)
keeps the mass and has a zero second moment: its Fourier transform is
1 - (k eps)^4 / 4 + ..., against the Gaussian's 1 - (k eps)^2 / 2 + ..., so it changes
the model at fourth order in dx."""


def components(kernel: str, width: float) -> list[tuple[float, float]]:
    """The (weight, width) of each Gaussian of `kernel` for eps = `width`."""
    return [(weight, factor * width) for weight, factor in KERNELS[kernel]]


def widest(kernel: str, width: float) -> float:
    """Width of the widest Gaussian of `kernel` for eps = `width` (the filter's reach)."""
    return max(factor for _, factor in KERNELS[kernel]) * width


@dataclass(frozen=True)
class FilterTables:
    """The filtered F and G of one rotor shape, as the kernels read them.

    Attributes:
        plate_values: (n, n) F_eps at the table's nodes (for the numpy reference).
        plate: (n * n,) cubic B-spline coefficients of F_eps in the plate frame, on the
            square table of cell centres x0 + k step (k = 0 .. n - 1) along both axes.
        plate_n: n.
        plate_x0: coordinate of the table's first node.
        plate_step: table spacing.
        pill: g_eps(k pill_step), k = 0, 1, ...; 0 beyond its end.
        pill_step: spacing of the pill profile.
        edge: f_eps(edge_u0 + k edge_step); 0 below its start, 1 beyond its end.
        edge_u0: first node of the edge profile.
        edge_step: spacing of the edge profile.
        plate_reach: the widest Gaussian of the plate's kernel (how far from the
            corner bisectors its crease is felt).
        corner_end: the gauge h (frame of the nearest edge) beyond which the cells near
            a bisector take the edge profile (:func:`corner_end`).
    """

    plate_values: np.ndarray
    plate: np.ndarray
    plate_n: int
    plate_x0: float
    plate_step: float
    pill: np.ndarray
    pill_step: float
    edge: np.ndarray
    edge_u0: float
    edge_step: float
    plate_reach: float
    corner_end: float


def filtered_plate(
    shape: RotorShape, width: float, step: float, kernel: str = "gaussian"
) -> tuple[np.ndarray, float]:
    """F_eps = F * K_eps, edge 0's normal along +x, on a square table of spacing `step`.

    The table covers the support disk of F (:attr:`RotorShape.support_radius`) plus the
    spline's taps; F is sampled on the table's nodes and filtered there (the sampled
    Gaussian, normalised, is the trapezoidal rule of the convolution: with eps >= 4 step
    it is exact to far below the tolerances of the scheme).

    Args:
        shape: the rotor (its asymmetry plays no part: F has none).
        width: eps.
        step: table spacing.
        kernel: name in :data:`KERNELS`.

    Returns:
        (values (n, n), x0): F_eps at the nodes x0 + k step along both axes.
    """
    half = shape.support_radius + 4.0 * step
    count = math.ceil(half / step)
    axis = step * np.arange(-count, count + 1)
    parts = components(kernel, width)
    pad = math.ceil(GAUSS_TRUNCATE * widest(kernel, width) / step)
    padded = step * np.arange(-count - pad, count + pad + 1)
    x, y = np.meshgrid(padded, padded, indexing="ij")
    sharp = plate_indicator(x, y, shape, -math.pi / shape.n_corners)
    values = sum(
        weight * gaussian_filter(sharp, sigma=w / step, mode="constant", truncate=GAUSS_TRUNCATE)
        for weight, w in parts
    )
    return np.ascontiguousarray(values[pad:-pad, pad:-pad]), float(axis[0])


def corner_end(
    values: np.ndarray,
    x0: float,
    step: float,
    edge: tuple[np.ndarray, float, float],
    shape: RotorShape,
    crease: float,
) -> float:
    """The gauge h beyond which the plate table (`values` on the nodes x0 + k step, edge
    0's normal along +x) and the edge profile `edge` (profile, first node, spacing) differ
    by less than CORNER_CUTOFF at every node within `crease` of a corner bisector (and
    in edge 0's sector), plus the two nodes the table's cubic spline reaches.

    Returns:
        h of the last node row where they differ by CORNER_CUTOFF or more, plus 2 step.
    """
    axis = x0 + step * np.arange(values.shape[0])
    profile, u0, u_step = edge
    nodes = u0 + u_step * np.arange(profile.size)
    flat = np.interp(shape.apothem - axis, nodes, profile, left=0.0, right=1.0)
    h, q = axis[:, None], np.abs(axis[None, :])
    half = math.pi / shape.n_corners
    distance = (h * math.tan(half) - q) * math.cos(half)  # from the bisector, inside
    near = (distance >= -step) & (distance <= crease)
    far = near & (np.abs(values - flat[:, None]) >= CORNER_CUTOFF)
    rows = np.nonzero(far.any(axis=1))[0]
    return float(axis[rows[-1]] + 2.0 * step)


def filtered_edge_profile(
    shape: RotorShape, width: float, step: float, kernel: str = "gaussian"
) -> tuple[np.ndarray, float]:
    """f_eps = f * K_eps, f(u) = 1/2 (1 + tanh(u / delta)), on u = u0 + k step.

    The nodes span |u| <= X_SATURATION delta + GAUSS_TRUNCATE eps (eps of the widest
    Gaussian of the kernel), beyond which f_eps is
    0 or 1 to 1e-14. The convolution is the direct sum of the sampled kernel (the
    trapezoidal rule, exact to round-off for the smooth f, and relative-accurate in the
    exponential tails) on nodes EDGE_OVERSAMPLING times coarser, brought to `step` by
    cubic spline interpolation (error ~ (step / eps)^4, far below 1e-10).

    Returns:
        (profile, u0).
    """
    coarse = step * EDGE_OVERSAMPLING
    parts = components(kernel, width)
    reach = GAUSS_TRUNCATE * widest(kernel, width)
    count = math.ceil((X_SATURATION * shape.smoothing + reach) / coarse)
    u = coarse * np.arange(-count, count + 1)
    f = 0.5 * (1.0 + np.tanh(u / shape.smoothing))
    blurred = sum(
        weight * gaussian_filter1d(f, sigma=w / coarse, mode="nearest", truncate=GAUSS_TRUNCATE)
        for weight, w in parts
    )
    fine = np.arange((u.size - 1) * EDGE_OVERSAMPLING + 1) / EDGE_OVERSAMPLING
    profile = map_coordinates(blurred, fine[None], order=3, mode="nearest")
    return np.ascontiguousarray(profile), float(u[0])


def filtered_pill_profile(
    shape: RotorShape, width: float, step: float, kernel: str = "gaussian"
) -> np.ndarray:
    """g_eps(k step), k = 0, 1, ...: one pill's profile convolved with K_eps (module doc);
    :func:`filtered_disk_profile` of the pill's radius rho and edge width delta."""
    return filtered_disk_profile(shape.pill_radius, shape.smoothing, width, step, kernel)


def filtered_disk_profile(
    radius: float, smoothing: float, width: float, step: float, kernel: str = "gaussian"
) -> np.ndarray:
    """g_eps(k step), k = 0, 1, ...: the profile 1/2 (1 + tanh((rho - |r|) / delta)) of a
    disk convolved with K_eps (module doc), the sum of the radial convolutions with the
    kernel's Gaussians. A pill's G and a disk plate's F (:mod:`pde_rotor.model.body_schemes`).

    The radial integral uses the trapezoidal rule with spacing h = min(delta, eps) / 64 up
    to rho + X_SATURATION delta, where g = 1/2 (1 + tanh((rho - s) / delta)) vanishes, with
    the Euler-Maclaurin end correction at s = 0: the integrand starts linearly, with
    slope g(0) exp(-d^2 / (2 eps^2)) / eps^2, which alone would cost O(h^2) = 2e-5.

    Args:
        radius: rho, the disk's radius.
        smoothing: delta, the width of its tanh edge.
        width: eps.
        step: spacing of the table in d.
        kernel: name in :data:`KERNELS`.

    Returns:
        The profile, ending where its magnitude falls below PILL_CUTOFF.
    """
    rho, delta = radius, smoothing
    parts = components(kernel, width)
    s_end = rho + X_SATURATION * delta
    ds = min(delta, width) / 64.0
    s = np.arange(0.0, s_end + ds, ds)
    g = 0.5 * (1.0 + np.tanh((rho - s) / delta))
    weights = np.full(s.size, ds)
    weights[0] = weights[-1] = 0.5 * ds
    d = np.arange(0.0, s_end + GAUSS_TRUNCATE * widest(kernel, width) + step, step)
    profile = np.zeros(d.size)
    for weight, w in parts:
        inv_var = 1.0 / (w * w)
        for lo in range(0, d.size, 256):
            dd = d[lo : lo + 256, None]
            radial = s * inv_var * np.exp(-0.5 * (dd - s) ** 2 * inv_var) * i0e(dd * s * inv_var)
            profile[lo : lo + 256] += weight * (radial @ (g * weights))
        profile += weight * ds * ds / 12.0 * g[0] * np.exp(-0.5 * d * d * inv_var) * inv_var
    keep = np.nonzero(np.abs(profile) > PILL_CUTOFF)[0]
    return np.ascontiguousarray(profile[: keep[-1] + 2])


Filter = tuple[str, float]
"""A prefilter: (kernel name in :data:`KERNELS`, width kappa in units of dx)."""


@lru_cache(maxsize=8)
def make_tables(
    shape: RotorShape, dx: float, refinement: int, plate: Filter, pill: Filter
) -> FilterTables:
    """The filter tables of one rotor shape on a grid of spacing dx (cached: the members
    of a sweep share them).

    Args:
        shape: the rotor.
        dx: grid spacing.
        refinement: plate table nodes per dx.
        plate: the prefilter of F (``numerics.plate_filter_kernel``, ``_width``).
        pill: the prefilter of G (``numerics.pill_filter_kernel``, ``_width``).
    """
    plate_kernel, plate_width = plate[0], plate[1] * dx
    pill_kernel, pill_width = pill[0], pill[1] * dx
    step = dx / refinement
    values, x0 = filtered_plate(shape, plate_width, step, plate_kernel)
    coef = spline_filter(values, order=3, mode="grid-constant")
    pill_step = dx / PROFILE_REFINEMENT
    edge_step = dx / EDGE_REFINEMENT
    edge, edge_u0 = filtered_edge_profile(shape, plate_width, edge_step, plate_kernel)
    reach = widest(plate_kernel, plate_width)
    end = corner_end(values, x0, step, (edge, edge_u0, edge_step), shape, CREASE_WIDTHS * reach)
    return FilterTables(
        plate_values=values,
        plate=np.ascontiguousarray(coef.reshape(-1)),
        plate_n=values.shape[0],
        plate_x0=x0,
        plate_step=step,
        pill=filtered_pill_profile(shape, pill_width, pill_step, pill_kernel),
        pill_step=pill_step,
        edge=edge,
        edge_u0=edge_u0,
        edge_step=edge_step,
        plate_reach=reach,
        corner_end=end,
    )


@lru_cache(maxsize=64)
def disk_profile(radius: float, smoothing: float, dx: float, filt: Filter) -> np.ndarray:
    """The filtered profile of a disk (:func:`filtered_disk_profile`) on a grid of
    spacing dx, tabulated with spacing dx / PROFILE_REFINEMENT as :func:`make_tables`
    tabulates a pill's (cached: the pills and disks of a run share them).

    Args:
        radius: rho.
        smoothing: delta.
        dx: grid spacing.
        filt: the prefilter (kernel name, width kappa in units of dx).
    """
    return filtered_disk_profile(radius, smoothing, filt[1] * dx, dx / PROFILE_REFINEMENT, filt[0])


@dataclass(frozen=True)
class StripTable:
    """The filtered F of a strip plate over one quadrant of its frame, as the kernels
    read it (:func:`strip_table`).

    Attributes:
        values: (m, n) F_eps at the nodes (k step, l step), k, l >= 0: x' along the
            strip's length, y' across it (for the numpy reference).
        coef: (m + 2) * (n + 2) cubic B-spline coefficients of F_eps on the nodes
            x0 + k step, x0 = -2 step, row-major (the mirror image of the quadrant's
            coefficients on the two nodes before the axes: F_eps is even in x' and y').
        rows: m + 2.
        columns: n + 2.
        x0: -2 step, the first node along both axes.
        step: table spacing.
    """

    values: np.ndarray
    coef: np.ndarray
    rows: int
    columns: int
    x0: float
    step: float


STRIP_PAD = 2
"""Nodes of a strip table before the axes x' = 0, y' = 0 (its cubic spline's taps reach
one: two keep a point on an axis, rounded down, inside)."""


@lru_cache(maxsize=16)
def strip_table(
    length: float, width: float, smoothing: float, dx: float, refinement: int, filt: Filter
) -> StripTable:
    """F_eps = F * K_eps of a strip plate (L x W, F = 1/2 [1 + tanh(-h / delta)], h =
    max(|x'| - L/2, |y'| - W/2)) over the quadrant x', y' >= 0 of its frame (cached:
    the members of a sweep and the equal strips of a run share it).

    A rectangle's two edges differ in length and a thin strip's corners see each other
    through the filter, so the whole quadrant is one 2-D table (spacing dx /
    `refinement`), which the kernels read at (|x'|, |y'|): F_eps has the rectangle's two
    mirror symmetries exactly. F is sampled on the quadrant's nodes out to X_SATURATION
    delta beyond the edges (where it is below 4.3e-18) and GAUSS_TRUNCATE widths of the
    filter more, filtered with :func:`scipy.ndimage.gaussian_filter` mirrored about the
    axes (mode ``mirror``: exact for the even F), and the filter's margin cut off. The
    spline coefficients are scipy's, mirrored too, so that they are those of the whole
    table.

    Args:
        length, width: L and W.
        smoothing: delta.
        dx: grid spacing.
        refinement: table nodes per dx (``numerics.table_refinement``).
        filt: the plate's prefilter (kernel name, width kappa in units of dx).
    """
    kernel, eps = filt[0], filt[1] * dx
    step = dx / refinement
    grow = X_SATURATION * smoothing + 4.0 * step
    rows = math.ceil((length / 2 + grow) / step) + 1
    columns = math.ceil((width / 2 + grow) / step) + 1
    pad = math.ceil(GAUSS_TRUNCATE * widest(kernel, eps) / step)
    x = step * np.arange(rows + pad)[:, None]
    y = step * np.arange(columns + pad)[None, :]
    sharp = 0.5 * (1.0 + np.tanh(-np.maximum(x - length / 2, y - width / 2) / smoothing))
    values = sum(
        weight * gaussian_filter(sharp, sigma=w / step, mode="mirror", truncate=GAUSS_TRUNCATE)
        for weight, w in components(kernel, eps)
    )
    values = np.ascontiguousarray(values[:rows, :columns])
    coef = np.pad(spline_filter(values, order=3, mode="mirror"), ((STRIP_PAD, 0),) * 2, "reflect")
    return StripTable(
        values=values,
        coef=np.ascontiguousarray(coef.reshape(-1)),
        rows=rows + STRIP_PAD,
        columns=columns + STRIP_PAD,
        x0=-STRIP_PAD * step,
        step=step,
    )


def filtered_strip(table: StripTable, x: np.ndarray, y: np.ndarray, phi: float) -> np.ndarray:
    """F_eps of a strip plate centred at the origin, its length along phi, at the points
    (x, y) (numpy reference): scipy's cubic spline of the quadrant's values (its own
    prefilter, mirrored about the axes) at (|x'|, |y'|), 0 where the kernels' taps would
    leave the table; independent of the kernels' code."""
    c, s = math.cos(phi), math.sin(phi)
    along = np.abs(c * x + s * y) / table.step
    across = np.abs(c * y - s * x) / table.step
    inside = (along < table.rows - 2 - STRIP_PAD) & (across < table.columns - 2 - STRIP_PAD)
    value = map_coordinates(table.values, np.stack([along, across]), order=3, mode="mirror")
    return np.where(inside, value, 0.0)


def filtered_polygon(
    tables: FilterTables, n_corners: int, apothem: float, x: np.ndarray, y: np.ndarray, phi: float
) -> np.ndarray:
    """F_eps of a regular N-gon plate centred at the origin, at angle phi, at the points
    (x, y) (numpy reference).

    numpy's linear interpolation of the edge profile away from the corner bisectors and
    scipy's cubic spline of the table values (its own prefilter), in the frame of the
    nearest edge, near them: independent of the kernels' code.
    """
    normals = edge_normal_angles(n_corners, phi)
    proj = np.stack([x * math.cos(a) + y * math.sin(a) for a in normals])
    nearest = normals[np.argmax(proj, axis=0)]
    h = np.max(proj, axis=0)
    q = y * np.cos(nearest) - x * np.sin(nearest)
    half = math.pi / n_corners
    crease_distance = (h * math.tan(half) - np.abs(q)) * math.cos(half)
    near_crease = (crease_distance <= CREASE_WIDTHS * tables.plate_reach) & (h < tables.corner_end)
    u = tables.edge_u0 + tables.edge_step * np.arange(tables.edge.size)
    F = np.interp(apothem - h, u, tables.edge, left=0.0, right=1.0)
    inv = 1.0 / tables.plate_step
    points = np.stack([(h - tables.plate_x0) * inv, (q - tables.plate_x0) * inv])
    table = map_coordinates(tables.plate_values, points, order=3, mode="grid-constant", cval=0.0)
    return np.where(near_crease, table, F)


def filtered_indicators(
    tables: FilterTables, shape: RotorShape, x: np.ndarray, y: np.ndarray, phi: float
) -> tuple[np.ndarray, np.ndarray]:
    """F_eps and G_eps at the points (x, y) for the plate at angle phi (numpy reference).

    F_eps from :func:`filtered_polygon`; G_eps by numpy's linear interpolation of the
    pill profile: independent of the kernels' code.
    """
    F = filtered_polygon(tables, shape.n_corners, shape.apothem, x, y, phi)
    d = np.arange(tables.pill.size) * tables.pill_step
    G = np.zeros(np.broadcast(x, y).shape)
    for px, py in pill_centres(shape, phi):
        G += np.interp(np.hypot(x - px, y - py), d, tables.pill, right=0.0)
    return F, G
