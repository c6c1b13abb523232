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
  circle's node is :func:`arc_node`.

A ``grid`` is the tuple (o0, n, x0, inv_dx): the offset of the first of the n x n
B-spline coefficients of c, their count along a side, the coordinate of cell 0's centre
and 1 / dx. An ``edge`` is (cx, cy, ex, ey, h, half): the centre X, the edge's normal e,
the level h and the half length of the edge, whose points are X + h e + t tau,
tau = e turned by +pi/2, |t| <= half. Every function that reads c takes the run's
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
    arc_node: Callable


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
    def arc_node(coef, grid, cx, cy, h, ca, sa, weight, p):
        """A node of a circle of the contour form: the point (cx, cy) + h (ca, sa) on the
        level set h of a disk's gauge |r - P|, P = (cx, cy), with the quadrature weight
        `weight` (band weight times h times the angle step).

        Returns:
            the node's share of int F grad c dA (x, y), weight c (ca, sa); its torque
            about P is 0 ((r - P) x n = 0 on the circle).
        """
        o0, n, x0, inv_dx = grid
        i, tx = spline_node(x0, inv_dx, cx + h * ca)
        j, ty = spline_node(x0, inv_dx, cy + h * sa)
        row = o0 + (i - 1) * n + j - 1
        c = surface_pressure(
            spline_sum(coef, row, n, 1, bspline_weights(tx), bspline_weights(ty)), p
        )
        w = weight * c
        return w * ca, w * sa

    return Tension(
        surface_pressure=surface_pressure,
        tension_integrand=tension_integrand,
        polygon_band=polygon_band,
        edge_place=edge_place,
        edge_node=edge_node,
        edge_sums=edge_sums,
        polygon_node=polygon_node,
        arc_node=arc_node,
    )
