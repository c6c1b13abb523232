"""A body's integrals over its plate: area form and contour form (compiled, CPU).

* :func:`body_integrals`: the tension's and the friction's integrals over the cells a
  body owns, area form with central differences (the ``paper`` scheme);
* :func:`body_contour`: for ``consistent``, the tension's force and torque in contour
  form, on the cubic spline of c over a window about the body (:func:`spline_box`);
* :func:`spanning_integrals`: the same integrals of a body that spans its channel (a
  ``track`` body with ``spans``), over the wet part of its plate only.

Step 3 of the bodies' loop (:func:`pde_rotor.kernels.bodies.advance_bodies`); the
integrands are those of :mod:`pde_rotor.physics.tension` and
:mod:`pde_rotor.physics.motion`.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ..physics.build import CPU, FASTMATH
from ..physics.indicators import PLATE_POLYGON, PLATE_STRIP
from ..physics.spline import SPLINE_MARGIN
from .body_arcs import circle_sums
from .body_draw import orient
from .spline import (
    ROW_GROUP,
    node_pressure,
    node_scratch,
    place_nodes,
    spline_columns,
    spline_rows,
)

_cell_integrals = CPU.motion.cell_integrals
_wet_cell_integrals = CPU.motion.wet_cell_integrals
_polygon_band = CPU.tension.polygon_band


SUM_FASTMATH = FASTMATH | {"reassoc"}
"""fastmath of the area sums: :data:`~pde_rotor.physics.build.FASTMATH` and reassociation,
so that LLVM vectorises the sums along a chord (their order, and so their rounding, is
LLVM's: the sums agree with row-major order to rounding)."""


def make_chord_sums(flow: bool, tension: bool):
    """The sums of :func:`body_integrals` over a chord, compiled for `flow` (v read, or 0)
    and `tension` (the tension's terms taken, or 0 where the contour form replaces them),
    constants of the loop, so that LLVM vectorises it.

    Returns:
        ``sums(cur, F, base, ja, jb, frame, consts)``: the ten sums over the cells
        [ja, jb) of the row at offset `base` (the motion's ``cell_integrals``); `frame` =
        (coords, rx, y_k) (rx = x - X_x of the row), `consts` = (n, 1 / (2 dx), the
        parameter record).
    """
    terms = (tension, flow)

    @nb.njit(cache=True, nogil=True, fastmath=SUM_FASTMATH)
    def sums(cur, F, base, ja, jb, frame, consts):
        coords, rx, y_k = frame
        n, inv_2dx, p = consts
        sx = np.uint64(n)  # unsigned offsets: no test for negative indices at each load
        strides = (sx, np.uint64(1), sx * sx)
        total = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        for j in range(ja, jb):
            o = np.uint64(base + j)
            r = (rx, coords[j] - y_k)
            total = _cell_integrals(total, cur, o, strides, F[o], r, inv_2dx, p, terms)
        return total

    return sums


_CHORD_SUMS = tuple(
    make_chord_sums(flow, tension) for flow in (False, True) for tension in (False, True)
)
"""The chord sums without and with flow, each without and with the tension's terms."""
_still_contour, _still_sums, _flow_contour, _flow_sums = _CHORD_SUMS


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def body_integrals(cur, F, coords, k, bodies, p, out):
    """The integrals of body k over its plate, area form (central differences) (compiled).

    out[:] = (int F grad c (x, y), int F (r - X) x grad c, int F, int F (r - X) (x, y),
    int F |r - X|^2, int F (r - X) x v, int F v (x, y)), each times dA (the motion's
    ``cell_integrals``), summed over the cells body k owns: row by row, the chord of its
    footprint its drawing made its own (`bodies` = (the bundle of
    :func:`pde_rotor.kernels.bodies.advance_bodies`, chords (2, K, n) of
    :func:`~pde_rotor.kernels.body_draw.draw_body`); the body must be drawn at its
    pose), each chord's sums vectorised (:func:`make_chord_sums`). For the contour form
    (the record's ``contour``) the first three are 0: :func:`body_contour` gives them.
    With X = 0 the torque's integrals are those of
    :func:`pde_rotor.kernels.cpu.rotor_integrals` to rounding.
    """
    (_, _, pose, _, box, _, _, _), chords = bodies
    n = coords.size
    dx = coords[1] - coords[0]
    consts = (n, 0.5 / dx, p)
    x_k, y_k = pose[k, 0], pose[k, 1]
    # the sums in locals, which stay in registers (out might alias cur or F)
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = s8 = s9 = 0.0
    for i in range(box[k, 0], box[k, 1]):
        ja, jb = chords[0, k, i], chords[1, k, i]
        frame = (coords, coords[i] - x_k, y_k)
        if p.flow and p.contour:
            t = _flow_contour(cur, F, i * n, ja, jb, frame, consts)
        elif p.flow:
            t = _flow_sums(cur, F, i * n, ja, jb, frame, consts)
        elif p.contour:
            t = _still_contour(cur, F, i * n, ja, jb, frame, consts)
        else:
            t = _still_sums(cur, F, i * n, ja, jb, frame, consts)
        s0 += t[0]
        s1 += t[1]
        s2 += t[2]
        s3 += t[3]
        s4 += t[4]
        s5 += t[5]
        s6 += t[6]
        s7 += t[7]
        s8 += t[8]
        s9 += t[9]
    area = dx * dx
    out[0], out[1], out[2], out[3], out[4] = s0 * area, s1 * area, s2 * area, s3 * area, s4 * area
    out[5], out[6], out[7], out[8], out[9] = s5 * area, s6 * area, s7 * area, s8 * area, s9 * area


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def spanning_integrals(cur, F, volume, coords, k, bodies, p, out):
    """The integrals of :func:`body_integrals` for body k that spans its channel, over
    the wet part of its plate (compiled).

    Its plate crosses the vessel's no-flux walls, where c stops: the water pulls only the
    part of the plate's edge that it wets, so the tension's force and torque are taken in
    the form that reads c on wet cells only,

        int F grad c dA = -int c grad F dA,
        int F (r - X) x grad c dA = -int c (r - X) x grad F dA

    (Pi(c) / k for c with the saturating law; the two forms agree away from walls, the
    area form's central differences of c moved onto F by summation by parts), and every
    cell's share, the friction's moments too, is weighted by its volume fraction kappa
    (0 on dry cells): sum_P kappa_P [-Pi(c_P) (D F)_P, ...] dA, D the central difference
    (the motion's ``wet_cell_integrals``, which the GPU's sums share).
    The chords and `bodies` are those of :func:`body_integrals`; `volume` is the cut
    cells' kappa, flat (:meth:`pde_rotor.model.wall.CutCells.arrays`).
    """
    (_, _, pose, _, box, _, _, _), chords = bodies
    n = coords.size
    dx = coords[1] - coords[0]
    inv_2dx = 0.5 / dx
    nn = n * n
    x_k, y_k = pose[k, 0], pose[k, 1]
    strides = (n, nn)
    total = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    for i in range(box[k, 0], box[k, 1]):
        rx = coords[i] - x_k
        for j in range(chords[0, k, i], chords[1, k, i]):
            o = i * n + j
            kappa = volume[o]
            if kappa == 0.0:
                continue
            r = (rx, coords[j] - y_k)
            total = _wet_cell_integrals(
                total, cur, (o, o), F, strides, kappa, r, inv_2dx, p, p.flow
            )
    area = dx * dx
    for q in range(10):
        out[q] = total[q] * area


@nb.njit(cache=True, nogil=True, error_model="numpy")
def spline_box(cur, coef, n, window, taps, carry):
    """coef = cubic B-spline coefficients of c (cur[:n^2]) of the window of rows
    [i0, i1) and columns [j0, j1), `window` = (i0, i1, j0, j1), wanted on the rows and
    columns of `taps` = (ti0, ti1, tj0, tj1) inside it (compiled): every row of the
    window prefiltered in groups of ``ROW_GROUP``, its coefficients kept on the columns
    [tj0, tj1), then only those columns, kept on the rows [ti0, ti1), as the rotor's
    window (:func:`pde_rotor.kernels.spline.spline_window`, which keeps them to the
    window's end). A wanted coefficient has the same bits as with the whole window
    wanted (each line's backward recursion runs from the window's end, its forward one
    from its start to the last wanted coefficient; only what is stored changes); the
    others are left as they were. `carry` >= n."""
    i0, i1, j0, j1 = window
    ti0, ti1, tj0, tj1 = taps
    for r0 in range(i0, i1, ROW_GROUP):
        spline_rows(cur, coef, n, r0, min(i1, r0 + ROW_GROUP), j0, j1, (tj0, tj1), carry)
    spline_columns(coef, n, i0, i1, tj0, tj1, (ti0, ti1), carry)


@nb.njit(cache=True, nogil=True)
def spline_bounds(x_k, y_k, half, coords):
    """The spline window of a body at (`x_k`, `y_k`) whose window reaches `half` cells from
    its centre's cell, ``(i0, i1, j0, j1)`` clipped to the interior, and the part of it
    that the contour's taps read (:func:`spline_box`'s `taps`: the window less its
    margin)."""
    n = coords.size
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    ic = math.floor((x_k - x0) * inv_dx) + 1
    jc = math.floor((y_k - x0) * inv_dx) + 1
    i0, i1 = max(1, ic - half), min(n - 1, ic + half)
    j0, j1 = max(1, jc - half), min(n - 1, jc + half)
    inner = half - SPLINE_MARGIN + 1
    taps = (max(i0, ic - inner), min(i1, ic + inner), max(j0, jc - inner), min(j1, jc + inner))
    return (i0, i1, j0, j1), taps


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def _edge_pair(coef, grid, edge, quad, m, p, scratch):
    """Band node m of a straight edge, the tension's ``edge_sums`` in two passes over
    its nodes along the edge (as the rotor's contour nodes,
    :func:`pde_rotor.kernels.cpu.contour_torque`): where each node takes its taps and
    its weights (:func:`~pde_rotor.kernels.spline.place_nodes`), then the 16-tap sums
    (``spline_sum``, unsigned offsets) through ``surface_pressure``, the shares of
    ``edge_node`` added in order: the same sums, bit for bit. `quad` = (quad_s, quad_t); `scratch` =
    (taps (L,) unsigned, weights (10, L)).

    Returns:
        The pair's (x, y, torque) shares, as ``edge_sums``.
    """
    quad_s, quad_t = quad
    taps, weights = scratch
    n_t = quad_t.shape[1]
    place_nodes(grid, edge, quad_s, quad_t, m, taps, weights)
    sx, sy = np.uint64(grid[1]), np.uint64(1)
    ex, ey = edge[2], edge[3]
    pair_x = 0.0
    pair_y = 0.0
    pair_t = 0.0
    for k_t in range(n_t):
        c = node_pressure(coef, taps, weights, k_t, sx, sy, p)
        wc = weights[8, k_t] * c
        pair_x += wc * ex
        pair_y += wc * ey
        pair_t += weights[9, k_t] * c
    return pair_x, pair_y, pair_t


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def body_contour(cur, coords, k, bodies, p, out):
    """int F_k grad c dA (x, y) and int F_k (r - X_k) x grad c dA in contour form
    (``consistent``; :mod:`pde_rotor.model.body_schemes`) into out[0:3] (compiled).

    The spline of c on the square window of half side ``window_half`` cells about the
    cell of X_k (:func:`spline_box`), its coefficients wanted only where the contour's
    taps lie (the window less ``SPLINE_MARGIN`` - 1 cells each side; the taps lie within
    ``window_half`` - ``SPLINE_MARGIN`` cells of that cell), then the contour nodes of
    the tension: a
    polygon's or a strip's edges (the tension's ``edge_sums`` in two passes,
    :func:`_edge_pair`; per (edge, band node) the sum along
    the edge, the pairs added in order, as the rotor's contour torque; a strip's four
    edges of two lengths, its band nodes without a parallel skipped), or a disk plate's
    circle about X_k or each pill's about its centre, its torque (P - X) x its force
    (:func:`~pde_rotor.kernels.body_arcs.circle_sums`, the nodes in orbits of four
    mirror images). `delta` is the edge width; `bodies` as for
    :func:`pde_rotor.kernels.bodies.advance_bodies`.
    """
    body, pills, pose, _, _, normals, centres, tables = bodies
    quad_s, quad_t, _, _, _, _, _, coef, carry = tables
    delta = p.smoothing
    orient(k, body, pills, pose, normals, centres)  # scratch: a new stepper starts with 0
    b = body[k]
    n = coords.size
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    x_k, y_k = pose[k, 0], pose[k, 1]
    window, taps = spline_bounds(x_k, y_k, b.window_half, coords)
    spline_box(cur, coef, n, window, taps, carry)
    n_s = quad_s.shape[1]
    grid = (0, n, x0, inv_dx)
    quad = (quad_s, quad_t)
    scratch = node_scratch(quad_t.shape[1])
    f_x = 0.0
    f_y = 0.0
    torque = 0.0
    if b.plate == PLATE_POLYGON:
        for j in range(b.n_corners):
            ex, ey = normals[0, j, k], normals[1, j, k]
            for m in range(n_s):
                h, half = _polygon_band(b.size_a, delta, b.tan_half, quad_s, m)
                edge = (x_k, y_k, ex, ey, h, half)
                pair_x, pair_y, pair_t = _edge_pair(coef, grid, edge, quad, m, p, scratch)
                f_x += pair_x
                f_y += pair_y
                torque += pair_t
    elif b.plate == PLATE_STRIP:
        ex, ey = normals[0, 0, k], normals[1, 0, k]
        thinner = min(b.size_a, b.size_b)
        for j in range(4):  # the edges' normals e, z x e, -e, -z x e; sides L/2, W/2
            side, along = (b.size_a, b.size_b) if j % 2 == 0 else (b.size_b, b.size_a)
            for m in range(n_s):
                h = -delta * quad_s[0, m]
                if h <= -thinner:  # no parallel: the gauge is >= -W/2 (L/2) everywhere
                    continue
                edge = (x_k, y_k, ex, ey, side + h, along + h)
                pair_x, pair_y, pair_t = _edge_pair(coef, grid, edge, quad, m, p, scratch)
                f_x += pair_x
                f_y += pair_y
                torque += pair_t
            ex, ey = -ey, ex
    else:
        f_x, f_y, torque = circle_sums(coef, (0, n, inv_dx), k, bodies, p)
    out[0], out[1], out[2] = f_x, f_y, torque
