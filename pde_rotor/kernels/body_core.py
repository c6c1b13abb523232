"""The physics of bodies, written once: indicators, plate velocity and motion of body k.

The model of Koyano et al. (Chaos 2020) generalised from one rotor to K bodies
(docs/bodies.md). Body k has a plate indicator F_k (a regular polygon, a disk, a strip,
or none: then its floating pills are the object), pills G_k (camphor sources), a
position X_k, an angle phi_k and a motion (``fixed``, ``fixed_axis``, ``free``). The
plate moves with the velocity field u_k(r) = U_k + omega_k z x (r - X_k), and

* Eq. (eqc) keeps its form with F = sum_k F_k and the source sum_k s_j/(pi rho_j^2)
  G_j over all pills (each pill its own supply);
* Eq. (eqv) is driven by eta sum_k F_k (u_k - v) (:func:`plate_velocity`);
* the force and torque on body k, Eqs. (torque) and (eq_motion) about X_k:

      f_k = s k int F_k grad c dA - mu_k int F_k (u_k - v) dA,
      T_k = s k int F_k (r - X_k) x grad c dA - mu_k int F_k (r - X_k) x (u_k - v) dA,

  with s = ``rotor.torque``'s sign (:data:`pde_rotor.model.pde.TORQUE_SIGN`), written
  with the body's integrals (area A, first moment M, polar moment J, and the flow's
  int F_k v and int F_k (r - X_k) x v) by :func:`body_accelerations`.

With one ``fixed_axis`` body at the origin these are the functions of
:mod:`pde_rotor.kernels.core` that the rotor's loops call: :func:`body_accelerations`
reduces to ``rotor_torques`` and ``angular_acceleration``, :func:`plate_velocity` to
omega (-y, x). The functions are built by :func:`make_body_core` for a compiler, as the
core's are, and call the core's primitives (``logistic``, ``pill_term``, ``projection``).

The loops that call them are :mod:`pde_rotor.kernels.bodies` (CPU).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

from .core import CPU, Core, _cpu_jit

PLATE_NONE, PLATE_POLYGON, PLATE_DISK, PLATE_STRIP = 0, 1, 2, 3
"""Plate shapes in the body record (:mod:`pde_rotor.kernels.records`, ``BODY``)."""

MOTION_FIXED, MOTION_FIXED_AXIS, MOTION_FREE = 0, 1, 2
"""Motions in the body record."""


class BodyCore(NamedTuple):
    """The compiled body functions for one target (see the module docstring)."""

    plate_velocity: Callable
    owner_plate: Callable
    strip_gauge: Callable
    filtered_strip: Callable
    polygon_gauge: Callable
    body_plate_cell: Callable
    body_accelerations: Callable
    edge_node: Callable
    edge_sums: Callable
    arc_node: Callable


def make_body_core(jit: Callable[[Callable], Callable], core: Core) -> BodyCore:
    """Compile the body functions with `jit` on top of the physics core `core`.

    Args:
        jit: as for :func:`pde_rotor.kernels.core.make_core`.
        core: the core compiled with the same `jit`.

    Returns:
        The compiled functions.
    """
    logistic = core.logistic
    interpolate = core.interpolate
    pill_term = core.pill_term
    projection = core.projection
    gauge_step = core.gauge_step
    tangential = core.tangential
    spline_node = core.spline_node
    corner_sum = core.corner_sum

    @jit
    def plate_velocity(u, v, omega, rx, ry):
        """u_k at r = X_k + (rx, ry): U_k + omega_k z x (r - X_k) = (u - omega ry, v + omega rx)."""
        return u - omega * ry, v + omega * rx

    @jit
    def owner_plate(F, G, owner, pose, o, x, y):
        """F, G and the plate velocity u_k of the owner k of the cell at offset `o`,
        centred at (x, y) in the dish frame: the plate terms of Eqs. (eqc), (eqv) with K
        bodies, (f, g, px, py); a cell without an owner has no plate velocity."""
        k = owner[o]
        if k < 0:
            return F[o], G[o], 0.0, 0.0
        px, py = plate_velocity(pose[k, 3], pose[k, 4], pose[k, 5], x - pose[k, 0], y - pose[k, 1])
        return F[o], G[o], px, py

    @jit
    def polygon_gauge(rx, ry, normals, n_corners):
        """h = max_j (r - X) . e_j over the edge normals `normals` (2, >= N), lab frame."""
        h = projection(rx, ry, normals[0, 0], normals[1, 0])
        for j in range(1, n_corners):
            h = gauge_step(h, rx, ry, normals[0, j], normals[1, j])
        return h

    @jit
    def strip_gauge(rx, ry, ex, ey, half_length, half_width):
        """max(|r . e| - L/2, |r . tau| - W/2): a rectangle's gauge, e the body's x axis.

        Its level set 0 is the strip's outline and it grows by the distance from the
        nearer edge, like the polygon's max over edges h - R cos(pi/N).
        """
        along = abs(projection(rx, ry, ex, ey)) - half_length
        across = abs(ey * rx - ex * ry) - half_width
        return along if along > across else across

    @jit
    def filtered_strip(rx, ry, ex, ey, plate, rows, columns, t_x0, t_inv):
        """F_eps of a strip plate at r = X + (rx, ry) (``consistent``,
        :func:`pde_rotor.model.filtering.strip_table`), e = (ex, ey) its x axis: the cubic
        spline of the quadrant table `plate` (rows x columns coefficients on the nodes
        t_x0 + k / t_inv, x' along the rows) at (|x'|, |y'|), so that F_eps has the
        rectangle's two mirror symmetries exactly; 0 where the taps leave the table
        (beyond, F_eps is below 1e-17). t_x0 < 0: the taps of a point on an axis lie in
        the table's mirrored nodes."""
        along = abs(projection(rx, ry, ex, ey))
        across = abs(tangential(rx, ry, ex, ey))
        fx = (along - t_x0) * t_inv
        fy = (across - t_x0) * t_inv
        if not (fx < rows - 2.0 and fy < columns - 2.0):
            return 0.0
        i, tx = spline_node(t_x0, t_inv, along)
        j, ty = spline_node(t_x0, t_inv, across)
        return corner_sum(plate, (i - 1) * columns + j - 1, columns, 1, tx, ty)

    @jit
    def body_plate_cell(rx, ry, plate, normals, n_corners, size_a, size_b, inv_delta):
        """F_k at r = X_k + (rx, ry) for the plate kind `plate` (``paper`` scheme point value).

        polygon: 1/2 [1 + tanh((a - h) / delta)], h the polygon gauge, a = `size_a` the
        apothem; disk: the same with h = |r - X| and a the radius; strip:
        1/2 [1 + tanh(-h / delta)], h the strip gauge with `size_a`, `size_b` the half
        length and half width. A body without a plate has the pills' own indicator for F
        (the sum of ``pill_term`` over them, :mod:`pde_rotor.kernels.bodies`).
        """
        if plate == PLATE_POLYGON:
            return logistic((size_a - polygon_gauge(rx, ry, normals, n_corners)) * inv_delta)
        if plate == PLATE_DISK:
            return pill_term(rx, ry, size_a, inv_delta)
        if plate == PLATE_STRIP:
            h = strip_gauge(rx, ry, normals[0, 0], normals[1, 0], size_a, size_b)
            return logistic(-h * inv_delta)
        return 0.0

    @jit
    def body_accelerations(integrals, u, v, omega, sign_k, mu, mass, inertia):
        """Force, torque and accelerations of a body from its integrals (see the module).

        Args:
            integrals: (8,) int F grad c (x, y), int F (r - X) x grad c, int F, int F (r - X)
                (x, y), int F |r - X|^2, int F (r - X) x v, over the body's plate (times
                dA), then int F v (x, y) in [8], [9] (length 10).
            u, v, omega: the body's velocity U and angular velocity.
            sign_k: s k, the sign of ``rotor.torque`` times the tension slope.
            mu: the body's friction coefficient.
            mass, inertia: m and I (mass unused for a body that does not translate).

        Returns:
            (f_x, f_y, T, friction f_x, friction f_y, friction torque, dU/dt, dV/dt,
            domega/dt): tension force and torque, friction force and torque, and the
            accelerations (f + friction) / m, (T + friction torque) / I.
        """
        grad_x, grad_y, cross_grad = integrals[0], integrals[1], integrals[2]
        area, m_x, m_y, polar, cross_v = (
            integrals[3],
            integrals[4],
            integrals[5],
            integrals[6],
            integrals[7],
        )
        flow_x, flow_y = integrals[8], integrals[9]
        torque = sign_k * cross_grad
        friction = -mu * (polar * omega - cross_v + (m_x * v - m_y * u))
        force_x = sign_k * grad_x
        force_y = sign_k * grad_y
        drag_x = -mu * (area * u - omega * m_y - flow_x)
        drag_y = -mu * (area * v + omega * m_x - flow_y)
        inv_m = 1.0 / mass
        return (
            force_x,
            force_y,
            torque,
            drag_x,
            drag_y,
            friction,
            (force_x + drag_x) * inv_m,
            (force_y + drag_y) * inv_m,
            (friction + torque) * (1.0 / inertia),
        )

    @jit
    def edge_node(coef, n, x0, inv_dx, cx, cy, ex, ey, h, half, quad_s, quad_t, m, k_t):
        """Node (m, k_t) of a straight edge of the contour form (``consistent``).

        The edge of the level set h of a polygon's gauge about (cx, cy): normal
        e = (ex, ey), the points (cx, cy) + h e + t tau, tau = e turned by +pi/2,
        t = half quad_t[0, k_t]; band node m of the weight 1/2 sech^2 (`quad_s`) and
        Gauss-Legendre node k_t along the edge (`quad_t`). c from its cubic spline
        (``interpolate`` of the B-spline coefficients `coef`, n x n, x0 and 1/dx).

        Returns:
            the node's shares of int F grad c dA (x, y), w c e, and of
            int F (r - X) x grad c dA, -w t c (the rotor's ``contour_point``), with
            w = quad_s[1, m] quad_t[1, k_t] half.
        """
        t = half * quad_t[0, k_t]
        c = interpolate(coef, 0, n, x0, inv_dx, cx + (h * ex - t * ey), cy + (h * ey + t * ex))
        w = quad_s[1, m] * quad_t[1, k_t] * half * c
        return w * ex, w * ey, -quad_s[1, m] * quad_t[1, k_t] * half * t * c

    @jit
    def edge_sums(coef, n, x0, inv_dx, cx, cy, ex, ey, h, half, quad_s, quad_t, m):
        """Band node m of a straight edge of the contour form (``consistent``): the
        :func:`edge_node` shares of its Gauss-Legendre nodes along the edge, added in
        order (the rotor's contour torque). A polygon's edge (h, half) = (a - delta s_m,
        h tan(pi/N)), a strip's (L/2 or W/2 - delta s_m, W/2 or L/2 - delta s_m)."""
        pair_x = 0.0
        pair_y = 0.0
        pair_t = 0.0
        for k_t in range(quad_t.shape[1]):
            a, c, e = edge_node(
                coef, n, x0, inv_dx, cx, cy, ex, ey, h, half, quad_s, quad_t, m, k_t
            )
            pair_x += a
            pair_y += c
            pair_t += e
        return pair_x, pair_y, pair_t

    @jit
    def arc_node(coef, n, x0, inv_dx, cx, cy, h, ca, sa, weight):
        """A node of a circle of the contour form (``consistent``): the point
        (cx, cy) + h (ca, sa) on the level set h of a disk's gauge |r - P|, P = (cx, cy),
        with the quadrature weight `weight` (band weight times h times the angle step).

        Returns:
            the node's share of int F grad c dA (x, y), weight c (ca, sa); its torque
            about P is 0 ((r - P) x n = 0 on the circle).
        """
        c = interpolate(coef, 0, n, x0, inv_dx, cx + h * ca, cy + h * sa)
        w = weight * c
        return w * ca, w * sa

    return BodyCore(
        plate_velocity=plate_velocity,
        owner_plate=owner_plate,
        strip_gauge=strip_gauge,
        filtered_strip=filtered_strip,
        polygon_gauge=polygon_gauge,
        body_plate_cell=body_plate_cell,
        body_accelerations=body_accelerations,
        edge_node=edge_node,
        edge_sums=edge_sums,
        arc_node=arc_node,
    )


CPU_BODIES: BodyCore = make_body_core(_cpu_jit, CPU)
"""The body functions compiled for the CPU."""
