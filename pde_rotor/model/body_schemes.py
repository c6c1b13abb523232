"""The rotation-consistent scheme (``consistent``) for bodies: filtered F_k, G_k and the
contour form of each body's force and torque (numpy reference and the tables the kernels
read).

A stopped symmetric body on the ``paper`` scheme feels a spurious lattice force that
depends on where its centre sits within a cell (docs/bodies.md), as the rotor feels a
lattice torque (docs/model.md). The remedy is the rotor's (:mod:`pde_rotor.model.schemes`):

* **Prefilters.** F_k and G_k go through the isotropic prefilters of
  :mod:`pde_rotor.model.filtering` (``numerics.plate_filter_*`` for F, ``pill_filter_*``
  for G), so that the sampled indicators depend smoothly on the body's position and
  angle. A pill's G_eps and a disk plate's F_eps are radial profiles
  (:func:`~pde_rotor.model.filtering.disk_profile`); a body without a plate floats on its
  pills, and its F_eps is the sum of the pills' profiles filtered with the plate's
  kernel; a polygon plate's F_eps comes from the rotor's edge profile and corner table
  (:func:`~pde_rotor.model.filtering.make_tables`); a strip plate's from one table of the
  filtered rectangle over a quadrant of its frame, read at (|x'|, |y'|), so that it has
  the rectangle's two mirror symmetries exactly
  (:func:`~pde_rotor.model.filtering.strip_table`: its two edge lengths differ, and a thin
  strip's filtered corners overlap, so the polygon's nearest-edge frame does not serve).
* **Force and torque in contour form.** F = f(a - h(r)) with a gauge h whose level sets
  are the smoothed contour's parallels and |grad h| = 1: the distance |r - P| from a
  disk's centre P (a pill, or a disk plate about X), the polygon's max_j (r - X) . e_j,
  or the strip's max(|x'| - L/2, |y'| - W/2). Integrating by parts and by level sets
  (coarea formula),

      int F grad c dA = int w(h) oint_{h} c n ds dh,
      int F (r - X) x grad c dA = int w(h) oint_{h} c (r - X) x n ds dh,

  w = -dF/dh: the tension -k oint c n ds on every parallel of the contour, weighted
  across the smoothed edge, as the rotor's torque. c is its interpolating cubic spline.
  A polygon takes the rotor's rule: the model's F, w(h) dh = 1/2 sech^2(s) ds,
  s = (a - h) / delta, by the Gauss rule of ``numerics.band_nodes`` nodes
  (:func:`~pde_rotor.model.schemes.sech2_gauss`) and ``numerics.contour_nodes``
  Gauss-Legendre nodes along each edge. A strip takes the same rule on the four edges of
  the rectangle of half sides L/2 + h, W/2 + h (h = -delta s); h >= -min(L, W)/2
  everywhere, where the parallel shrinks to a segment whose two sides cancel, so the
  band nodes beyond have no parallel and are dropped. A circle takes the filtered F_eps
  that the field equations see, w = -f_eps' (:func:`ring_rule`: the midpoint rule, two
  radii per cell), and :data:`ARC_EDGES` times ``numerics.contour_nodes`` equally spaced angles
  (the trapezoidal rule, spectrally accurate for a periodic integrand). The sharp
  weight would put every node within a few delta of a pill's rim, where the source
  switches on and the spline of c errs by an amount that moves with the body's
  sub-cell position (a lattice force larger than the paper scheme's, docs/bodies.md);
  the smooth, wider weight of F_eps averages that error out. Every node moves and turns
  with the body. On a circle about its own centre (r - X) x n = 0: a disk plate feels
  no torque, a pill only through its lever P - X.

With one ``fixed_axis`` polygon body at the origin these are the rotor's F_eps, G_eps
and contour torque. :class:`BodyScheme` holds each body's tables and the quadrature
rules; :func:`filtered_body_fields` and :func:`contour_integrals` are the numpy
reference of :mod:`pde_rotor.kernels.bodies`, independent of its code (numpy's linear
interpolation of the profiles, scipy's spline of c over the whole grid).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import map_coordinates

from ..config import X_SATURATION, CamphorConfig, RotorConfig
from ..physics.spline import SPLINE_MARGIN
from .bodies import Body, BodyShape, Pose, pill_offsets
from .filtering import (
    PROFILE_REFINEMENT,
    Filter,
    FilterTables,
    StripTable,
    disk_profile,
    filtered_polygon,
    filtered_strip,
    make_tables,
    strip_table,
)
from .geometry import RotorShape, edge_normal_angles
from .schemes import sech2_gauss, surface_pressure

ARC_EDGES = 4
"""A circle carries as many equally spaced contour nodes as this many straight edges
(``numerics.contour_nodes`` each); a multiple of 4, so that the compiled kernels take the
nodes in orbits of four under the body frame's mirrors
(:func:`pde_rotor.kernels.body_arcs.circle_sums`)."""


@dataclass(frozen=True)
class BodyFilter:
    """The filtered indicators of one body (``consistent``).

    Attributes:
        pill_g: per pill, its G_eps profile g_eps(k step) (the pills' prefilter).
        pill_f: per pill, its F_eps profile (the plate's prefilter) where the body has
            no plate and floats on its pills; empty otherwise.
        disk: a disk plate's F_eps profile, or None.
        polygon: a polygon plate's filter tables (the rotor's), or None.
        strip: a strip plate's quadrant table, or None.
        rings: per circle of the contour (each pill of a body without a plate, or the
            disk plate), its radial rule (2, I): radii h_i and weights
            (:func:`ring_rule`).
    """

    pill_g: tuple[np.ndarray, ...]
    pill_f: tuple[np.ndarray, ...]
    disk: np.ndarray | None
    polygon: FilterTables | None
    strip: StripTable | None
    rings: tuple[np.ndarray, ...]


RING_NODES = 2
"""Radial nodes per cell of a circle's rule (:func:`ring_rule`)."""

RING_CUTOFF = 1e-12
"""A circle's rule ends where the weight falls below this part of its largest value."""


def ring_rule(profile: np.ndarray, step: float, dx: float, reach: float) -> np.ndarray:
    """The radial rule of a circle's contour form: int w(h) g(h) dh = sum_i W_i g(h_i).

    w = -f_eps', the radial derivative of a disk's filtered profile f_eps (spacing
    `step`, by central differences), the weight of its parallels h = |r - P| in
    int F_eps grad c dA = int w(h) oint_h c n ds dh. The midpoint rule with
    :data:`RING_NODES` nodes per cell, h_i = (i + 1/2) dx / RING_NODES, on the half cells
    out to where w falls below :data:`RING_CUTOFF` of its largest value, but none beyond
    the circle's `reach` (rho + w delta, w = ``numerics.footprint_widths``: beyond it
    F_eps is not drawn); W_i = w(h_i) dx / RING_NODES. At the default w = 20 the cutoff
    comes first on every shipped config (39 rings for a pill of radius 4 dx,
    delta = dx, against 48 half cells to its reach).

    Returns:
        (2, I): the radii h_i and the weights W_i.
    """
    d = np.arange(profile.size) * step
    weight = -np.gradient(profile, step)
    end = d[np.nonzero(np.abs(weight) > RING_CUTOFF * np.abs(weight).max())[0][-1]]
    spacing = dx / RING_NODES
    count = min(math.ceil(end / spacing), math.floor(reach / spacing))
    radii = spacing * (np.arange(count) + 0.5)
    return np.ascontiguousarray(np.stack([radii, np.interp(radii, d, weight) * spacing]))


def polygon_shape(shape: BodyShape) -> RotorShape:
    """The rotor shape of a polygon plate, for its filter tables (its pills play no part:
    the tables' pill profile is the first pill's or, without pills, a disk of radius R/2)."""
    n = shape.n_corners
    rho = float(shape.pills[0, 2]) if len(shape.pills) else shape.radius / 2
    return RotorShape(
        n_corners=n,
        radius=shape.radius,
        apothem=shape.apothem,
        pill_radius=rho,
        pill_distance=0.0,
        asymmetry=0.0,
        smoothing=shape.smoothing,
        support_radius=shape.radius + X_SATURATION * shape.smoothing / math.cos(math.pi / n),
    )


def make_body_filter(
    shape: BodyShape, dx: float, refinement: int, plate: Filter, pill: Filter
) -> BodyFilter:
    """The filtered indicators of one body on a grid of spacing dx.

    Args:
        shape: the body's shape.
        dx: grid spacing.
        refinement: nodes per dx of a polygon's corner table and a strip's table.
        plate: the prefilter of F (kernel, kappa).
        pill: the prefilter of G (kernel, kappa).
    """
    delta = shape.smoothing
    step = dx / PROFILE_REFINEMENT
    radii = [float(r) for r in shape.pills[:, 2]]
    pill_g = tuple(disk_profile(r, delta, dx, pill) for r in radii)
    pill_f = tuple(disk_profile(r, delta, dx, plate) for r in radii)
    disk = disk_profile(shape.radius, delta, dx, plate) if shape.plate == "disk" else None
    circles = pill_f if shape.plate == "none" else (disk,) if disk is not None else ()
    margin = shape.widths * delta
    ends = [r + margin for r in radii] if shape.plate == "none" else [shape.radius + margin]
    ends = ends[: len(circles)]
    return BodyFilter(
        pill_g=pill_g,
        pill_f=pill_f if shape.plate == "none" else (),
        disk=disk,
        polygon=(
            make_tables(polygon_shape(shape), dx, refinement, plate, pill)
            if shape.plate == "polygon"
            else None
        ),
        strip=(
            strip_table(shape.length, shape.width, delta, dx, refinement, plate)
            if shape.plate == "strip"
            else None
        ),
        rings=tuple(
            ring_rule(profile, step, dx, end) for profile, end in zip(circles, ends, strict=True)
        ),
    )


@dataclass(frozen=True)
class BodyScheme:
    """The numbers the bodies' kernels need for ``numerics.scheme`` (see the module).

    Attributes:
        name: ``paper`` or ``consistent``.
        filters: each body's filtered indicators (``consistent``; empty for ``paper``).
        quad_s: (2, M) nodes and weights across the edge (weight 1/2 sech^2).
        quad_t: (2, L) Gauss-Legendre nodes and weights on [-1, 1] along an edge.
        arc_nodes: equally spaced nodes around a circle.
        dx: the grid spacing.
    """

    name: str
    filters: tuple[BodyFilter, ...]
    quad_s: np.ndarray
    quad_t: np.ndarray
    arc_nodes: int
    dx: float

    @property
    def profile_step(self) -> float:
        """Spacing of the radial profiles (:func:`~pde_rotor.model.filtering.disk_profile`)."""
        return self.dx / PROFILE_REFINEMENT

    @property
    def consistent(self) -> bool:
        """Whether the scheme is ``consistent`` (filtered indicators, contour forms)."""
        return self.name == "consistent"

    @classmethod
    def from_config(cls, config: RotorConfig, bodies: tuple[Body, ...]) -> BodyScheme:
        """The scheme of a run's bodies (``numerics`` section)."""
        num = config.numerics
        dx = config.grid.dx
        if num.scheme != "consistent":
            return cls(num.scheme, (), np.zeros((2, 1)), np.zeros((2, 1)), 0, dx)
        plate = (num.plate_filter_kernel, num.plate_filter_width)
        pill = (num.pill_filter_kernel, num.pill_filter_width)
        filters = tuple(
            make_body_filter(b.shape, dx, num.table_refinement, plate, pill) for b in bodies
        )
        return cls(
            name=num.scheme,
            filters=filters,
            quad_s=np.ascontiguousarray(np.stack(sech2_gauss(num.band_nodes))),
            quad_t=np.ascontiguousarray(
                np.stack(np.polynomial.legendre.leggauss(num.contour_nodes))
            ),
            arc_nodes=ARC_EDGES * num.contour_nodes,
            dx=dx,
        )

    def contour_reach(self, shape: BodyShape, filt: BodyFilter) -> float:
        """The largest distance from X of a contour node of the body with the filtered
        indicators `filt` (the spline's taps lie within two cells more)."""
        if shape.plate == "polygon":
            band = shape.smoothing * float(np.abs(self.quad_s[0]).max())
            return (shape.apothem + band) / math.cos(math.pi / shape.n_corners)
        if shape.plate == "strip":
            band = shape.smoothing * float(np.abs(self.quad_s[0]).max())
            return math.hypot(shape.length / 2 + band, shape.width / 2 + band)
        if shape.plate == "disk":
            return float(filt.rings[0][0, -1])
        return max(
            math.hypot(x, y) + float(ring[0, -1])
            for (x, y), ring in zip(shape.pills[:, :2], filt.rings, strict=True)
        )

    def window_half(self, shape: BodyShape, filt: BodyFilter) -> int:
        """Half the side, in cells, of the square window about X whose c is turned into
        spline coefficients: the contour's taps plus
        :data:`~pde_rotor.physics.spline.SPLINE_MARGIN` cells (the rotor's window for a
        polygon at the origin)."""
        return math.ceil(self.contour_reach(shape, filt) / self.dx) + 2 + SPLINE_MARGIN


def _radial(profile: np.ndarray, step: float, distance: np.ndarray) -> np.ndarray:
    """A radial profile at `distance` by numpy's linear interpolation (0 beyond its end)."""
    d = np.arange(profile.size) * step
    return np.interp(distance, d, profile, right=0.0)


def filtered_body_fields(
    x: np.ndarray, y: np.ndarray, shape: BodyShape, pose: Pose, filt: BodyFilter, step: float
) -> tuple[np.ndarray, np.ndarray]:
    """F_eps and the source of Eq. (eqc) of one body at `pose`, at the points (x, y)
    (numpy reference, ``consistent``).

    Args:
        x, y: points on the surface.
        shape: the body's shape.
        pose: its pose.
        filt: its filtered indicators.
        step: spacing of the radial profiles.

    Returns:
        (F_eps, sum_j s_j / (pi rho_j^2) G_eps,j).
    """
    rx, ry = x - pose.x, y - pose.y
    F = np.zeros(np.broadcast(x, y).shape)
    source = np.zeros_like(F)
    offsets = pill_offsets(shape, pose.phi)
    for j, ((qx, qy), (_, _, rho, supply)) in enumerate(zip(offsets, shape.pills, strict=True)):
        dist = np.hypot(rx - qx, ry - qy)
        source += supply / (math.pi * rho**2) * _radial(filt.pill_g[j], step, dist)
        if shape.plate == "none":
            F += _radial(filt.pill_f[j], step, dist)
    if filt.disk is not None:
        F = _radial(filt.disk, step, np.hypot(rx, ry))
    if filt.polygon is not None:
        F = filtered_polygon(filt.polygon, shape.n_corners, shape.apothem, rx, ry, pose.phi)
    if filt.strip is not None:
        F = filtered_strip(filt.strip, rx, ry, pose.phi)
    return F, source


def _spline(c: np.ndarray, x0: float, y0: float, dx: float, x: np.ndarray, y: np.ndarray):
    """The interpolating cubic spline of c at (x, y) (scipy over the whole grid; c = 0
    beyond it, as on and outside the dish's circle)."""
    points = np.stack([(x - x0) / dx, (y - y0) / dx])
    return map_coordinates(c, points, order=3, mode="grid-constant", cval=0.0)


def _edges(
    c: np.ndarray, origin: tuple[float, float], dx: float, pose: Pose, normals: np.ndarray,
    distance: np.ndarray, half: np.ndarray, s_weights: np.ndarray, quad_t: np.ndarray,
    camphor: CamphorConfig | None,
) -> tuple[float, float, float]:  # fmt: skip
    """The straight edges of a contour form (see :func:`contour_integrals`): edge j's
    normal at the angle normals[j], its parallel of band node m at distance[j, m] from
    X, half[j, m] long each side of its foot; weight s_weights[m] across and the
    Gauss-Legendre rule `quad_t` along; c read through :func:`surface_pressure`.

    Returns:
        the force integrals (x, y) and the torque integral about X.
    """
    t_nodes, t_weights = quad_t
    t = half[:, :, None] * t_nodes[None, None, :]
    ex = np.cos(normals)[:, None, None]
    ey = np.sin(normals)[:, None, None]
    x = pose.x + distance[:, :, None] * ex - t * ey
    y = pose.y + distance[:, :, None] * ey + t * ex
    values = surface_pressure(_spline(c, *origin, dx, x, y), camphor)
    weights = (s_weights * half)[:, :, None] * t_weights[None, None, :] * values
    return np.sum(weights * ex), np.sum(weights * ey), -np.sum(weights * t)


def contour_integrals(
    c: np.ndarray, origin: tuple[float, float], dx: float, shape: BodyShape, pose: Pose,
    scheme: BodyScheme, index: int, camphor: CamphorConfig | None = None,
) -> np.ndarray:  # fmt: skip
    """int F grad P dA (x, y) and int F (r - X) x grad P dA of one body in contour form
    (numpy reference, ``consistent``; see the module docstring), P the surface pressure
    per slope of c (:func:`~pde_rotor.model.schemes.surface_pressure`; c for the linear
    law).

    Args:
        c: (n, n) concentration at the cell centres, axis 0 along x.
        origin: (x, y) of cell (0, 0)'s centre.
        dx: grid spacing.
        shape: the body's shape.
        pose: its pose.
        scheme: a consistent scheme (its quadrature rules).
        index: the body's index in the scheme (its circles' radial rules).
        camphor: the camphor section, its law of the surface tension (None: linear).

    Returns:
        (3,) the two force integrals and the torque integral (without s k).
    """
    s_nodes, s_weights = scheme.quad_s
    delta = shape.smoothing
    out = np.zeros(3)
    if shape.plate == "polygon":
        h = shape.apothem - delta * s_nodes
        normals = edge_normal_angles(shape.n_corners, pose.phi)
        distance = np.broadcast_to(h, (shape.n_corners, h.size))
        half = distance * math.tan(math.pi / shape.n_corners)
        quad_t = scheme.quad_t
        out[:] = _edges(c, origin, dx, pose, normals, distance, half, s_weights, quad_t, camphor)
        return out
    if shape.plate == "strip":
        h = -delta * s_nodes
        normals = pose.phi + 0.5 * math.pi * np.arange(4)
        sides = np.array([shape.length, shape.width] * 2)[:, None] / 2
        distance, half = sides + h, sides[[1, 0, 3, 2]] + h
        kept = s_weights * (h > -min(shape.length, shape.width) / 2)
        quad_t = scheme.quad_t
        out[:] = _edges(c, origin, dx, pose, normals, distance, half, kept, quad_t, camphor)
        return out
    n_arc = scheme.arc_nodes
    theta = pose.phi + 2.0 * math.pi * np.arange(n_arc) / n_arc
    ex, ey = np.cos(theta)[None, :], np.sin(theta)[None, :]
    if shape.plate == "disk":
        centres = [(0.0, 0.0)]
    else:
        centres = [(qx, qy) for qx, qy in pill_offsets(shape, pose.phi)]
    rings = scheme.filters[index].rings
    for (qx, qy), (radii, ring_weights) in zip(centres, rings, strict=True):
        h = radii[:, None]
        values = _spline(c, *origin, dx, pose.x + qx + h * ex, pose.y + qy + h * ey)
        values = surface_pressure(values, camphor)
        weights = (ring_weights[:, None] * h * (2.0 * math.pi / n_arc)) * values
        f_x, f_y = np.sum(weights * ex), np.sum(weights * ey)
        out += (f_x, f_y, qx * f_y - qy * f_x)
    return out
