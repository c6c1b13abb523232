"""A body's circles in the contour form of the tension on the CPU (compiled).

The ``consistent`` scheme's int F grad c dA over a disk plate or the pills of a body
(:mod:`pde_rotor.model.body_schemes`), read on the cubic spline of c that
:func:`pde_rotor.kernels.body_sums.body_contour` has filled: :func:`circle_sums`, the
circles' nodes four at a time, mirror images of each other in the body frame (the
tension's ``arc_orbit``), so that a circle on an axis of a mirror of the grid, on a c
symmetric under that mirror, feels no force across that axis, bit for bit.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ..model.body_schemes import ARC_EDGES
from ..physics.build import CPU, FASTMATH
from ..physics.indicators import PLATE_DISK

_arc_orbit = CPU.tension.arc_orbit


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def circle_sums(coef, lattice, k, bodies, p):
    """int F_k grad c dA (x, y) and int F_k (r - X_k) x grad c dA of body k's circles in
    contour form: a disk plate's about X_k, or each pill's about its centre P (its
    torque (P - X_k) x its force).

    Each ring h of a circle (its radial rule, the tables' ``rings``), the angles
    phi + 2 pi l / L, L = ``ARC_EDGES`` x ``contour_nodes``, as orbits of four
    (the tension's ``arc_orbit``, l = 0 .. L/4 - 1, cos and sin of 2 pi l / L taken once
    per call), the orbits' shares added in order, then the rings' times their weights
    (band weight times h times 2 pi / L) in the body frame, turned into the lab frame
    once per circle. `coef` holds the spline coefficients of c, `lattice` is
    (o0, n, 1 / dx) (the tension's module docstring), `bodies` as for
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
            o_x = 0.0
            o_y = 0.0
            for a_l in range(quarter):
                a, c = _arc_orbit(coef, lattice, circle, trig[0, a_l], trig[1, a_l], p)
                o_x += a
                o_y += c
            weight = rings[1, m] * h * step
            s_x += weight * o_x
            s_y += weight * o_y
        q_x = cos_phi * s_x - sin_phi * s_y
        q_y = sin_phi * s_x + cos_phi * s_y
        f_x += q_x
        f_y += q_y
        torque += (cx - x_k) * q_y - (cy - y_k) * q_x
    return f_x, f_y, torque
