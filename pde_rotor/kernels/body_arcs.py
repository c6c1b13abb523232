"""A body's circles in the contour form of the tension on the CPU (compiled).

The ``consistent`` scheme's int F grad c dA over a disk plate or the pills of a body
(:mod:`pde_rotor.model.body_schemes`), read on the cubic spline of c that
:func:`pde_rotor.kernels.body_sums.body_contour` has filled: :func:`circle_sums`, the
circles' nodes four at a time, mirror images of each other in the body frame (the
tension's ``arc_orbit``), so that a circle on an axis of a mirror of the grid, on a c
symmetric under that mirror, feels no force across that axis, bit for bit. A ring's
orbits off the axes are taken in two passes (:func:`place_ring`, :func:`ring_sum`), as a
straight edge's nodes are (:func:`pde_rotor.kernels.spline.place_nodes`): first where
every node reads the spline, several nodes at a time (SIMD), then the taps node by node.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ..model.body_schemes import ARC_EDGES
from ..physics.build import CPU, FASTMATH
from ..physics.indicators import PLATE_DISK

_arc_orbit = CPU.tension.arc_orbit
_orbit_points = CPU.tension.orbit_points
_arc_place = CPU.tension.arc_place
_arc_read = CPU.tension.arc_read
_orbit_share = CPU.tension.orbit_share


@nb.njit(inline="always", cache=True, nogil=True)
def ring_scratch(quarter):
    """The scratch of :func:`place_ring` for rings of 4 `quarter` nodes: (points (8, Q),
    taps (3, 4, Q) ints, fractions (2, 4, Q))."""
    return (
        np.empty((8, quarter)),
        np.empty((3, 4, quarter), np.int64),
        np.empty((2, 4, quarter)),
    )


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def place_ring(lattice, circle, trig, scratch):
    """Where the nodes of a ring's orbits l = 1 .. Q - 1 read the spline of c (the first
    pass of :func:`circle_sums`): the tension's ``orbit_points`` of each orbit, then, one
    of the orbit's four nodes at a time, ``arc_place`` of each; no loop loads back a
    place it wrote, so that LLVM computes several orbits at a time.

    Args:
        lattice: (o0, n, 1 / dx) (the tension's module docstring).
        circle: (cx, cy, h, cos phi, sin phi), as ``arc_orbit``'s.
        trig: (2, Q) the cos and sin of the orbits' angles 2 pi l / (4 Q).
        scratch: :func:`ring_scratch`'s (points, taps, fractions); taps[:, s, l] and
            fractions[:, s, l] are written: node s of orbit l's first tap and offsets
            (row, sx, sy) and its fractions (tx, ty).
    """
    points, taps, fractions = scratch
    for a_l in range(1, trig.shape[1]):
        u = np.uint64(a_l)
        x1, y1, x2, y2, x3, y3, x4, y4 = _orbit_points(circle, trig[0, u], trig[1, u])
        points[0, u], points[1, u], points[2, u], points[3, u] = x1, y1, x2, y2
        points[4, u], points[5, u], points[6, u], points[7, u] = x3, y3, x4, y4
    for s in range(4):
        xs, ys = points[2 * s], points[2 * s + 1]
        rows, steps_x, steps_y = taps[0, s], taps[1, s], taps[2, s]
        fx, fy = fractions[0, s], fractions[1, s]
        for a_l in range(1, trig.shape[1]):
            u = np.uint64(a_l)
            rows[u], steps_x[u], steps_y[u], fx[u], fy[u] = _arc_place(lattice, xs[u], ys[u])


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def _node(coef, taps, fractions, s, a_l, p):
    """Pi(c) / k at node s of orbit l (``arc_read`` of :func:`place_ring`'s place)."""
    row, sx, sy = taps[0, s, a_l], taps[1, s, a_l], taps[2, s, a_l]
    return _arc_read(coef, (row, sx, sy, fractions[0, s, a_l], fractions[1, s, a_l]), p)


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def ring_sum(coef, trig, scratch, share, p):
    """A ring's orbits l = 1 .. Q - 1 read on the places :func:`place_ring` wrote (the
    second pass of :func:`circle_sums`): each orbit's ``orbit_share`` into the scratch's
    points (rows 0 and 1), then added in order to `share`, the axes' orbit l = 0. Added
    in a loop of their own, no share's product is fused into the sum (as none is where
    ``arc_orbit`` returns it from one of its two branches): the sums have the bits of
    ``arc_orbit``'s, orbit by orbit.

    Returns:
        the ring's sum (x, y) in the body frame, without the ring's weight.
    """
    points, taps, fractions = scratch
    for a_l in range(1, trig.shape[1]):
        values = (
            _node(coef, taps, fractions, 0, a_l, p), _node(coef, taps, fractions, 1, a_l, p),
            _node(coef, taps, fractions, 2, a_l, p), _node(coef, taps, fractions, 3, a_l, p),
        )  # fmt: skip
        points[0, a_l], points[1, a_l] = _orbit_share(trig[0, a_l], trig[1, a_l], values)
    o_x, o_y = share
    for a_l in range(1, trig.shape[1]):
        o_x += points[0, a_l]
        o_y += points[1, a_l]
    return o_x, o_y


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def circle_sums(coef, lattice, k, bodies, p):
    """int F_k grad c dA (x, y) and int F_k (r - X_k) x grad c dA of body k's circles in
    contour form: a disk plate's about X_k, or each pill's about its centre P (its
    torque (P - X_k) x its force).

    Each ring h of a circle (its radial rule, the tables' ``rings``), the angles
    phi + 2 pi l / L, L = ``ARC_EDGES`` x ``contour_nodes``, as orbits of four
    (l = 0 .. L/4 - 1, cos and sin of 2 pi l / L taken once per call: the axes' orbit
    l = 0 the tension's ``arc_orbit``, the others its pieces in two passes,
    :func:`place_ring` and :func:`ring_sum`), the orbits' shares added in order, then the
    rings' times their weights (band weight times h times 2 pi / L) in the body frame,
    turned into the lab frame once per circle. `coef` holds the spline coefficients of
    c, `lattice` is (o0, n, 1 / dx) (the tension's module docstring), `bodies` as for
    :func:`pde_rotor.kernels.bodies.advance_bodies` (the pills' centres oriented at the
    pose).

    Returns:
        (f_x, f_y, torque).
    """
    body, _, pose, _, _, _, centres, tables = bodies
    quad_t, pill_tab, rings = tables[1], tables[3], tables[6]
    b = body[k]
    x_k, y_k, phi = pose[k, 0], pose[k, 1], pose[k, 2]
    quarter = ARC_EDGES * quad_t.shape[1] // 4  # ARC_EDGES is 4: orbits of four
    step = 0.5 * math.pi / quarter
    cos_phi, sin_phi = math.cos(phi), math.sin(phi)
    trig = np.empty((2, quarter))  # the orbits' directions, shared by every ring
    scratch = ring_scratch(quarter)
    for a_l in range(quarter):
        trig[0, a_l] = math.cos(step * a_l)
        trig[1, a_l] = math.sin(step * a_l)
    first, last = b.pill_start, b.pill_start + b.pill_count
    if b.plate == PLATE_DISK:
        first, last = 0, 1
    f_x = 0.0
    f_y = 0.0
    torque = 0.0
    for q in range(first, last):
        cx, cy, r0, r1 = x_k, y_k, b.ring_start, b.ring_start + b.ring_count
        if b.plate != PLATE_DISK:
            cx, cy = centres[0, q], centres[1, q]
            r0, r1 = pill_tab[q, 4], pill_tab[q, 4] + pill_tab[q, 5]
        s_x = 0.0  # the circle's force in the body frame
        s_y = 0.0
        for m in range(r0, r1):
            h = rings[0, m]
            circle = (cx, cy, h, cos_phi, sin_phi)
            place_ring(lattice, circle, trig, scratch)
            axes = _arc_orbit(coef, lattice, circle, trig[0, 0], trig[1, 0], p)
            o_x, o_y = ring_sum(coef, trig, scratch, axes, p)
            weight = rings[1, m] * h * step
            s_x += weight * o_x
            s_y += weight * o_y
        q_x = cos_phi * s_x - sin_phi * s_y
        q_y = sin_phi * s_x + cos_phi * s_y
        f_x += q_x
        f_y += q_y
        torque += (cx - x_k) * q_y - (cy - y_k) * q_x
    return f_x, f_y, torque
