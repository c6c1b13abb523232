"""The cubic spline of c for the contour torque on the CPU: many lines filtered at once.

The contour form of the torque (scheme ``consistent``, :mod:`pde_rotor.model.schemes`)
interpolates c with its cubic spline, whose B-spline coefficients come from Unser's
recursive prefilter, written as two recursions from the line's two ends so that it
commutes with mirroring bit for bit, along both axes of a square window of cells around
the plate (:class:`~pde_rotor.model.schemes.Scheme`, ``window``): first along y (the
rows), then along x (the columns). Each line is a recursion, one sample after the other;
filtered one line at a time, a line waits on the latency of each step. Here the steps of
the physics core (:mod:`pde_rotor.physics`: ``spline_reach`` and ``spline_coefficient``,
the steps of ``spline_line``) advance several lines side by side (:func:`spline_lines`):
a group of rows together, and the columns together, where the lines lie next to each
other in memory and LLVM computes them four or eight at a time (SIMD). Each line's
arithmetic is that of ``spline_line``, so the coefficients do not depend on how lines
are grouped (or shared among threads).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ..physics.build import CPU, FASTMATH

_spline_reach = CPU.spline.spline_reach
_spline_coefficient = CPU.spline.spline_coefficient
_edge_place = CPU.tension.edge_place
_bspline_weights = CPU.spline.bspline_weights
_spline_sum = CPU.spline.spline_sum
_surface_pressure = CPU.tension.surface_pressure

_LINES = {"cache": True, "nogil": True, "error_model": "numpy"}
"""numba options of the loops below (inlined into the time step that calls them): no
fastmath, so that no multiply-add is fused and each coefficient has the bits of
``spline_line`` (scalar, as the GPU's) exactly."""


@nb.njit(inline="always", **_LINES)
def spline_lines(src, buf, o, stride, count, lane_stride, lanes, wanted, carry):
    """The physics' ``spline_line`` on `lanes` lines at once, from `src` into `buf`.

    Line r holds the `count` samples src[o + r lane_stride + k stride], its coefficients
    go to the same places of `buf` (another array than `src`); step k of every line is
    taken before step k + 1 of any, so the recursions run side by side. Only the
    coefficients keep <= k < end are wanted, `wanted` = (keep, end): the backward
    recursion stores from end - 1 down to keep, the forward one runs to end and stores
    from keep on (the other places of `buf` keep what they held; a wanted coefficient
    has the bits of the whole line's). `carry` (>= lanes) holds each line's reach
    (``spline_reach``). Indexed with unsigned offsets (no slices, which would count
    references on each step, and no negative-wraparound checks).
    """
    keep, end = wanted
    o = np.uint64(o)
    stride = np.uint64(stride)
    lane_stride = np.uint64(lane_stride)
    for r in range(lanes):
        carry[r] = 0.0
    at = o + np.uint64(count) * stride
    for _ in range(count - 1, end - 1, -1):
        at -= stride
        for r in range(lanes):
            carry[r] = _spline_reach(src[at + np.uint64(r) * lane_stride] + carry[r])
    for _ in range(end - 1, keep - 1, -1):
        at -= stride
        for r in range(lanes):
            place = at + np.uint64(r) * lane_stride
            buf[place] = carry[r]
            carry[r] = _spline_reach(src[place] + carry[r])
    for r in range(lanes):
        carry[r] = 0.0
    at = o
    for _ in range(keep):
        for r in range(lanes):
            carry[r] = _spline_reach(src[at + np.uint64(r) * lane_stride] + carry[r])
        at += stride
    for _ in range(keep, end):
        for r in range(lanes):
            place = at + np.uint64(r) * lane_stride
            sample = src[place]
            buf[place] = _spline_coefficient(carry[r], buf[place], sample)
            carry[r] = _spline_reach(sample + carry[r])
        at += stride


@nb.njit(inline="always", **_LINES)
def adjacent_lines(buf, o, stride, count, lanes, wanted, carry):
    """:func:`spline_lines` in place for lines next to each other (lane_stride 1): the
    same steps over contiguous slices, which LLVM computes several lanes at a time (SIMD);
    the coefficients keep <= k < end are wanted, `wanted` = (keep, end) (elsewhere the
    samples are left). The backward reaches wait in an array of their own until the
    forward pass needs them with the samples they would have replaced."""
    keep, end = wanted
    back = np.empty((end - keep) * lanes)
    for r in range(lanes):
        carry[r] = 0.0
    for k in range(count - 1, end - 1, -1):
        line = buf[o + k * stride : o + k * stride + lanes]
        for r in range(lanes):
            carry[r] = _spline_reach(line[r] + carry[r])
    for k in range(end - 1, keep - 1, -1):
        line = buf[o + k * stride : o + k * stride + lanes]
        reach = back[(k - keep) * lanes : (k - keep + 1) * lanes]
        for r in range(lanes):
            reach[r] = carry[r]
            carry[r] = _spline_reach(line[r] + carry[r])
    for r in range(lanes):
        carry[r] = 0.0
    for k in range(keep):
        line = buf[o + k * stride : o + k * stride + lanes]
        for r in range(lanes):
            carry[r] = _spline_reach(line[r] + carry[r])
    for k in range(keep, end):
        line = buf[o + k * stride : o + k * stride + lanes]
        reach = back[(k - keep) * lanes : (k - keep + 1) * lanes]
        for r in range(lanes):
            sample = line[r]
            line[r] = _spline_coefficient(carry[r], reach[r], sample)
            carry[r] = _spline_reach(sample + carry[r])


@nb.njit(inline="always", **_LINES)
def spline_rows(cur, coef, n, i0, i1, lo, hi, wanted, carry):
    """coef = c (cur[:n^2]) on rows [i0, i1), columns [lo, hi), prefiltered along the rows
    (y), the rows side by side (`carry` >= i1 - i0); wanted on the columns [keep, end),
    `wanted` = (keep, end) (the other columns keep what they held)."""
    keep, end = wanted
    spline_lines(cur, coef, i0 * n + lo, 1, hi - lo, n, i1 - i0, (keep - lo, end - lo), carry)


@nb.njit(inline="always", **_LINES)
def spline_columns(coef, n, lo, hi, j0, j1, wanted, carry):
    """Prefilter coef along the columns (x) [j0, j1) over the rows [lo, hi), the columns
    side by side (contiguous: SIMD; `carry` >= j1 - j0), wanted on the rows [keep, end),
    `wanted` = (keep, end)."""
    keep, end = wanted
    adjacent_lines(coef, lo * n + j0, n, hi - lo, j1 - j0, (keep - lo, end - lo), carry)


ROW_GROUP = 16
"""Rows prefiltered side by side: enough to hide the latency of a step of the recursion
(the window's rows cost 0.0105 ms with 16, 0.0126 with 8, 0.0197 with 4; thread CPU
time, one thread, paper grid)."""


@nb.njit(**_LINES)
def spline_window(cur, coef, n, lo, hi, taps_lo, taps_hi):
    """coef = cubic B-spline coefficients of c (cur[:n^2]) on rows, columns [lo, hi),
    wanted on the rows and columns [taps_lo, taps_hi) (compiled): :func:`spline_rows` in
    groups of :data:`ROW_GROUP` rows, then :func:`spline_columns` of the wanted columns;
    the time step does the same, shared among threads."""
    carry = np.empty(max(ROW_GROUP, hi - lo))
    for i0 in range(lo, hi, ROW_GROUP):
        spline_rows(cur, coef, n, i0, min(hi, i0 + ROW_GROUP), lo, hi, (taps_lo, hi), carry)
    spline_columns(coef, n, lo, hi, taps_lo, taps_hi, (taps_lo, hi), carry)


@nb.njit(inline="always", cache=True, nogil=True)
def node_scratch(nodes):
    """The scratch of :func:`place_nodes` for `nodes` nodes along an edge: (taps (L,)
    unsigned, weights (10, L))."""
    return np.empty(nodes, np.uint64), np.empty((10, nodes))


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def place_nodes(grid, edge, quad_s, quad_t, m, taps, weights):
    """Where the nodes of band node m along a straight edge read the spline of c: the
    first of the contour form's two passes over an edge's nodes (the rotor's
    :func:`pde_rotor.kernels.cpu.contour_torque`, the bodies'
    :func:`pde_rotor.kernels.body_sums.body_contour`).

    Node k takes its taps' first cell and its weights from the physics' ``edge_place``
    and ``bspline_weights`` (the tension's nodes of Eq. (eq_motion) in contour form);
    no node's place is loaded back, so that LLVM computes several nodes at a time. The
    second pass sums the 16 taps node by node in order (``spline_sum``).

    Args:
        grid, edge, quad_s, quad_t, m: as ``edge_place``.
        taps: (L,) unsigned, each node's first tap (flat cell index), written.
        weights: (10, L) (:func:`node_scratch`), written: rows 0-3 the x weights, 4-7
            the y weights, 8 the node's force weight w, 9 its torque weight w_t.
    """
    for k_t in range(quad_t.shape[1]):
        row, tx, ty, w, w_t = _edge_place(grid, edge, quad_s, quad_t, m, k_t)
        wx0, wx1, wx2, wx3 = _bspline_weights(tx)
        wy0, wy1, wy2, wy3 = _bspline_weights(ty)
        taps[k_t] = np.uint64(row)
        weights[0, k_t], weights[1, k_t], weights[2, k_t], weights[3, k_t] = wx0, wx1, wx2, wx3
        weights[4, k_t], weights[5, k_t], weights[6, k_t], weights[7, k_t] = wy0, wy1, wy2, wy3
        weights[8, k_t], weights[9, k_t] = w, w_t


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def node_pressure(coef, taps, weights, k_t, sx, sy, p):
    """Node k_t's Pi(c) / k (the tension's ``surface_pressure``) from the 16 taps that
    :func:`place_nodes` placed: the second pass of the contour form of Eq. (eq_motion),
    node by node (``spline_sum``, unsigned offsets `sx`, `sy`), shared by the rotor's
    :func:`pde_rotor.kernels.cpu.contour_torque` and the bodies'
    :func:`pde_rotor.kernels.body_sums.body_contour`.

    Returns:
        Pi(c) / k at the node, to be weighted by the node's w (row 8) or w_t (row 9).
    """
    wx = (weights[0, k_t], weights[1, k_t], weights[2, k_t], weights[3, k_t])
    wy = (weights[4, k_t], weights[5, k_t], weights[6, k_t], weights[7, k_t])
    return _surface_pressure(_spline_sum(coef, taps[k_t], sx, sy, wx, wy), p)
