"""The tension integral of Eqs. (torque) and (eq_motion), written once for every body.

The force and torque of the surface tension on a body about its position X,

    s k int F grad c dA,    s k int F (r - X) x grad c dA,

(s the sign of ``rotor.torque``, k the tension slope; the paper's rotor is the body at
X = 0), or, for the saturating law gamma(c) = gamma0 - k c / (1 + c / c_sat)
(``camphor.saturation``), the same with c replaced by the surface pressure per slope
Pi(c) / k = c / (1 + c / c_sat) (:func:`surface_pressure`, through which every
function below reads c), in two forms, each one function serving the rotor's loops and
the bodies':

* area form (scheme ``paper``): :func:`tension_integrand`, one cell's integrands with
  central differences, summed over the cells of the plate times dA;
* contour form (scheme ``consistent``, :mod:`pde_rotor.model.schemes` and
  :mod:`pde_rotor.model.body_schemes`): with the gauge h(r) the level sets of F are
  polygons (or circles), and

      int F grad c dA = int w(h) oint c n ds dh,
      int F (r - X) x grad c dA = int w(h) oint c (r - X) x n ds dh,

  w(h) = F'(s) / delta, s = (a - h) / delta; c from its cubic spline (:mod:`.spline`).
  A straight edge's node is :func:`edge_place` (where its taps lie and its weights) and
  :func:`edge_node` (its shares); :func:`edge_sums` adds an edge's nodes in order,
  :func:`polygon_band` gives the level of a polygon's band node and
  :func:`polygon_node` enumerates a polygon's nodes one by one (the GPU's threads). A
  circle's nodes come four at a time, mirror images of each other (:func:`arc_orbit`:
  :func:`orbit_points`, c at each from :func:`arc_value`, that is :func:`arc_place`
  and :func:`arc_read`, and :func:`orbit_share`).

A ``grid`` is the tuple (o0, n, x0, inv_dx): the offset of the first of the n x n
B-spline coefficients of c, their count along a side, the coordinate of cell 0's centre
and 1 / dx. An ``edge`` is (cx, cy, ex, ey, h, half): the centre X, the edge's normal e,
the level h and the half length of the edge, whose points are X + h e + t tau,
tau = e turned by +pi/2, |t| <= half. A circle's nodes are placed about the grid's middle,
the origin of the dish frame in which the kernels' coordinates and the poses are measured
(:mod:`pde_rotor.model.domain`), which both mirrors of the grid fix: its ``lattice`` is
(o0, n, inv_dx). Every function that reads c takes the run's
parameter record `p` (:data:`pde_rotor.kernels.records.PARAMS`, as
:mod:`pde_rotor.physics.rates` does) and reads the law's scalars from it, so that a new
scalar of the tension law is a field of the record read here, with no signature to change.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

from .spline import Spline


class Tension(NamedTuple):
    """The compiled tension functions for one target (see the module docstring)."""

    surface_pressure: Callable
    tension_integrand: Callable
    polygon_band: Callable
    edge_place: Callable
    edge_node: Callable
    edge_sums: Callable
    polygon_node: Callable
    arc_place: Callable
    arc_read: Callable
    arc_value: Callable
    orbit_points: Callable
    orbit_share: Callable
    arc_orbit: Callable


def make_tension(jit: Callable[[Callable], Callable], spline: Spline) -> Tension:
    """Compile the tension functions with `jit`.

    Args:
        jit: decorator turning a scalar Python function into a compiled one that other
            compiled functions of the same target can call (numba ``njit`` or
            ``cuda.jit(device=True)``, :func:`pde_rotor.physics.build.make_physics`).
        spline: the spline functions compiled with the same `jit`.

    Returns:
        The compiled functions.
    """
    spline_node = spline.spline_node
    mirror_node = spline.mirror_node
    bspline_weights = spline.bspline_weights
    spline_sum = spline.spline_sum

    @jit
    def surface_pressure(c, p):
        """Pi(c) / k = gamma0 - gamma(c) over k: c / (1 + c / c_sat), with 1 / c_sat the
        record `p`'s ``inv_saturation`` (0: the paper's linear law, Pi / k = c exactly;
        the test on the loop-invariant field leaves the linear law's loops without a
        division)."""
        inv_sat = p.inv_saturation
        if inv_sat == 0.0:
            return c
        return c / (1.0 + c * inv_sat)

    @jit
    def tension_integrand(buf, o, sx, sy, f, rx, ry, inv_2dx, p):
        """One cell's F grad P (x, y) and F (r - X) x grad P, P = Pi(c) / k
        (:func:`surface_pressure`; c itself for the linear law), central differences, no dA.

        (rx, ry) = r - X at the cell centre; `sx`, `sy` the offsets of the x and y
        neighbours (n and 1) of the caller's integer type. r x u = rx u_y - ry u_x.
        """
        east = surface_pressure(buf[o + sx], p)
        west = surface_pressure(buf[o - sx], p)
        north = surface_pressure(buf[o + sy], p)
        south = surface_pressure(buf[o - sy], p)
        dcdx = (east - west) * inv_2dx
        dcdy = (north - south) * inv_2dx
        return f * dcdx, f * dcdy, f * (rx * dcdy - ry * dcdx)

    @jit
    def polygon_band(apothem, delta, tan_half, quad_s, m):
        """(h, half) of band node m of a regular polygon's contour form: the level
        h = a - delta s_m of its gauge and the half length h tan(pi/N) of an edge there."""
        h = apothem - delta * quad_s[0, m]
        return h, h * tan_half

    @jit
    def edge_place(grid, edge, quad_s, quad_t, m, k_t):
        """Where node (m, k_t) of a straight edge takes the taps of the spline of c.

        Band node m of the weight 1/2 sech^2 (`quad_s` (2, M): nodes s_m and weights)
        and Gauss-Legendre node k_t along the edge (`quad_t` (2, L) on [-1, 1]), at
        t = half quad_t[0, k_t]; `grid` and `edge` as in the module docstring.

        Returns:
            (row, tx, ty, w, w_t): the offset of its first tap and the fractions along
            x and y (:func:`~pde_rotor.physics.spline` ``bspline_weights``,
            ``spline_sum``), the weight w of c in int F grad c dA (times e) and w_t in
            int F (r - X) x grad c dA, -w t.
        """
        o0, n, x0, inv_dx = grid
        cx, cy, ex, ey, h, half = edge
        t = half * quad_t[0, k_t]
        i, tx = spline_node(x0, inv_dx, cx + (h * ex - t * ey))
        k, ty = spline_node(x0, inv_dx, cy + (h * ey + t * ex))
        w = quad_s[1, m] * quad_t[1, k_t] * half
        return o0 + (i - 1) * n + k - 1, tx, ty, w, -quad_s[1, m] * quad_t[1, k_t] * half * t

    @jit
    def edge_node(coef, grid, edge, quad_s, quad_t, m, k_t, p):
        """Node (m, k_t) of a straight edge (:func:`edge_place`) with c from its spline,
        read through :func:`surface_pressure`.

        Returns:
            the node's shares of int F grad c dA (x, y), w c e, and of
            int F (r - X) x grad c dA, w_t c.
        """
        row, tx, ty, w, w_t = edge_place(grid, edge, quad_s, quad_t, m, k_t)
        n = grid[1]
        c = surface_pressure(
            spline_sum(coef, row, n, 1, bspline_weights(tx), bspline_weights(ty)), p
        )
        wc = w * c
        return wc * edge[2], wc * edge[3], w_t * c

    @jit
    def edge_sums(coef, grid, edge, quad_s, quad_t, m, p):
        """Band node m of a straight edge: the :func:`edge_node` shares of its
        Gauss-Legendre nodes along the edge, added in order. A polygon's edge
        (h, half) is :func:`polygon_band`'s, a strip's (L/2 or W/2 - delta s_m,
        W/2 or L/2 - delta s_m)."""
        pair_x = 0.0
        pair_y = 0.0
        pair_t = 0.0
        for k_t in range(quad_t.shape[1]):
            a, b, c = edge_node(coef, grid, edge, quad_s, quad_t, m, k_t, p)
            pair_x += a
            pair_y += b
            pair_t += c
        return pair_x, pair_y, pair_t

    @jit
    def polygon_node(coef, grid, tab, polygon, quad_s, quad_t, q, p):
        """Node q of the contour form of a regular polygon about the origin.

        `tab` (>= 2, N) holds the edge normals, `polygon` is (apothem, delta,
        tan(pi/N)); node q enumerates (edge j, band node m, edge node k_t) as
        q = (j M + m) L + k_t (:func:`edge_node` of that triple).

        Returns:
            the node's shares (x, y, torque), as :func:`edge_node`.
        """
        n_s = quad_s.shape[1]
        n_t = quad_t.shape[1]
        k_t = q % n_t
        m = (q // n_t) % n_s
        j = q // (n_t * n_s)
        apothem, delta, tan_half = polygon
        h, half = polygon_band(apothem, delta, tan_half, quad_s, m)
        edge = (0.0, 0.0, tab[0, j], tab[1, j], h, half)
        return edge_node(coef, grid, edge, quad_s, quad_t, m, k_t, p)

    @jit
    def arc_place(lattice, x, y):
        """Where the point (x, y) of the dish frame reads the spline of c: its taps those
        of :func:`~pde_rotor.physics.spline` ``mirror_node`` along both axes, so that
        its image under a mirror of the grid (x -> -x, y -> -y) reads the mirrored taps
        in the same order with the same fractions. `lattice` is (o0, n, inv_dx) (module
        docstring).

        Returns:
            (row, sx, sy, tx, ty): the first tap, the offsets of the next tap along x and
            y (+-n, +-1) and the fractions along x and y (:func:`arc_read`'s `place`).
        """
        o0, n, inv_dx = lattice
        i, step_i, tx = mirror_node(n, x * inv_dx)
        j, step_j, ty = mirror_node(n, y * inv_dx)
        return o0 + i * n + j, step_i * n, step_j, tx, ty

    @jit
    def arc_read(coef, place, p):
        """Pi(c) / k (:func:`surface_pressure`) from the 16 taps of the spline of c that
        :func:`arc_place` placed, `place` = (row, sx, sy, tx, ty)."""
        row, sx, sy, tx, ty = place
        value = spline_sum(coef, row, sx, sy, bspline_weights(tx), bspline_weights(ty))
        return surface_pressure(value, p)

    @jit
    def arc_value(coef, lattice, x, y, p):
        """Pi(c) / k at the point (x, y) of the dish frame from the spline of c
        (:func:`arc_place`, then :func:`arc_read`): at the point's images under the
        grid's mirrors the same arithmetic on mirrored coefficients, so that on
        coefficients symmetric under a mirror the values at a point and at its image
        agree bit for bit."""
        return arc_read(coef, arc_place(lattice, x, y), p)

    @jit
    def orbit_points(circle, ca, sa):
        """The four nodes of a circle's orbit (:func:`arc_orbit`) off the axes, 0 < a <
        pi/2: (x1, y1, .., x4, y4) at the angles a, pi - a, -a, pi + a of the body frame.

        Their offsets from P are sign flips of R(phi) (h ca, 0) and R(phi) (0, h sa), not
        cosines and sines of their own; the two products h ca and h sa, the only ones
        that round when phi = 0, are taken on their own (no fused multiply-add can take
        them into a sum at one node and not at its image).
        """
        cx, cy, h, cos_phi, sin_phi = circle
        along = h * ca
        across = h * sa
        ux, uy = cos_phi * along, sin_phi * along
        vx, vy = -sin_phi * across, cos_phi * across
        return (
            cx + (ux + vx), cy + (uy + vy), cx + (vx - ux), cy + (vy - uy),
            cx + (ux - vx), cy + (uy - vy), cx - (ux + vx), cy - (uy + vy),
        )  # fmt: skip

    @jit
    def orbit_share(ca, sa, values):
        """An orbit's share of int F grad c dA in the body frame, without the ring's
        weight, from Pi(c) / k at its four nodes (:func:`orbit_points`' order), the
        values at mirror images subtracted before anything else is added: ca ((c1 - c2)
        + (c3 - c4)) along the body's x axis, sa ((c1 - c3) + (c2 - c4)) along its y."""
        c1, c2, c3, c4 = values
        return ca * ((c1 - c2) + (c3 - c4)), sa * ((c1 - c3) + (c2 - c4))

    @jit
    def arc_orbit(coef, lattice, circle, ca, sa, p):
        """Four nodes of a circle of the contour form, the images of one another under
        the body frame's mirrors: the points P + h R(phi) (+-ca, +-sa) on the level set h
        of a disk's gauge |r - P|, P = (cx, cy) in the dish frame, R(phi) the body's
        turn; `circle` is (cx, cy, h, cos phi, sin phi), `lattice` as for
        :func:`arc_value`. (ca, sa) = (cos a, sin a), 0 < a < pi/2, gives the nodes at
        the angles a, pi - a, -a, pi + a of the body frame; (1, 0) the four on its axes,
        0, pi, pi/2, 3 pi/2.

        The nodes are :func:`orbit_points` (sign flips of two offsets, not cosines and
        sines of their own), c at each :func:`arc_value`, the share :func:`orbit_share`
        (the values at mirror images subtracted before anything else is added). So on a
        c symmetric under a mirror of the grid that is one of the body frame's (phi = 0,
        P on the mirror's axis) the images read the same coordinates, or opposite ones,
        each difference is 0 and so is the orbit's share across that axis, exactly.
        The CPU's :func:`pde_rotor.kernels.body_arcs.circle_sums` makes the same calls
        for a whole ring in two passes.

        Returns:
            the orbit's share of int F grad c dA in the body frame, without the ring's
            weight: sum c n, ca ((c1 - c2) + (c3 - c4)) along the body's x axis and
            sa ((c1 - c3) + (c2 - c4)) along its y axis (c1 .. c4 at a, pi - a, -a,
            pi + a); its torque about P is 0 ((r - P) x n = 0 on the circle).
        """
        cx, cy, h, cos_phi, sin_phi = circle
        if sa == 0.0:  # the axes: P +- R(phi) (h, 0) and P +- R(phi) (0, h)
            ux, uy = cos_phi * h, sin_phi * h
            east = arc_value(coef, lattice, cx + ux, cy + uy, p)
            west = arc_value(coef, lattice, cx - ux, cy - uy, p)
            north = arc_value(coef, lattice, cx - uy, cy + ux, p)
            south = arc_value(coef, lattice, cx + uy, cy - ux, p)
            return east - west, north - south
        x1, y1, x2, y2, x3, y3, x4, y4 = orbit_points(circle, ca, sa)
        c1 = arc_value(coef, lattice, x1, y1, p)
        c2 = arc_value(coef, lattice, x2, y2, p)
        c3 = arc_value(coef, lattice, x3, y3, p)
        c4 = arc_value(coef, lattice, x4, y4, p)
        return orbit_share(ca, sa, (c1, c2, c3, c4))

    return Tension(
        surface_pressure=surface_pressure,
        tension_integrand=tension_integrand,
        polygon_band=polygon_band,
        edge_place=edge_place,
        edge_node=edge_node,
        edge_sums=edge_sums,
        polygon_node=polygon_node,
        arc_place=arc_place,
        arc_read=arc_read,
        arc_value=arc_value,
        orbit_points=orbit_points,
        orbit_share=orbit_share,
        arc_orbit=arc_orbit,
    )
