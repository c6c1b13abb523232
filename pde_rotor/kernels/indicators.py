"""F and G on the CPU: the smoothed plate and pill indicators on the support cells.

Every step the plate turns, F and G (the equations after Eq. (rj) of Koyano et al.,
Chaos 2020; filtered for the scheme ``consistent``, :mod:`pde_rotor.model.filtering`) are
recomputed on the cells within reach of the plate. The terms are the physics'
(:mod:`pde_rotor.physics`: the gauge and nearest-edge frame ``projection``,
``farther``, ``gauge_step``, ``tangential``, ``near_corner``, the pills' reach ``pill_reach``,
``filtered_pill_reach``, and ``plate_profile``, ``pill_term``, ``filtered_edge``,
``corner_taps``, ``corner_sum``, ``filtered_pill_term``), the same the GPU sums once per cell in
``plate_cell``, ``pill_cell``, ``filtered_plate`` and ``filtered_pills``. Here the loops
over edges and pills stand outside the loops over a row's cells, so that LLVM computes
a row four cells at a time (SIMD): the loops run over slices, whose indices numba knows
to be non-negative, the terms are branch-free, and ``error_model="numpy"`` drops the
division-by-zero branch. A body's strip plate has its own row
(:func:`filtered_strip_row`, the physics' ``filtered_strip``): the places and weights of
its table's taps first, several cells at a time, then the loads, which LLVM does not
vectorise. tests/kernels/test_indicators.py checks the rows against the cell functions.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba as nb
import numpy as np

from ..physics.build import CPU, FASTMATH
from ..physics.indicators import PolygonFilter

_rotor_table = CPU.indicators.rotor_table
_projection = CPU.indicators.projection
_gauge_step = CPU.indicators.gauge_step
_farther = CPU.indicators.farther
_tangential = CPU.indicators.tangential
_near_corner = CPU.indicators.near_corner
_pill_reach = CPU.indicators.pill_reach
_filtered_pill_reach = CPU.indicators.filtered_pill_reach
_plate_profile = CPU.indicators.plate_profile
_pill_term = CPU.indicators.pill_term
_filtered_edge = CPU.indicators.filtered_edge
_corner_taps = CPU.indicators.corner_taps
_corner_sum = CPU.indicators.corner_sum
_filtered_pill_term = CPU.indicators.filtered_pill_term
_spline_node = CPU.spline.spline_node
_bspline_weights = CPU.spline.bspline_weights
_spline_sum = CPU.spline.spline_sum


_ROW = {"cache": True, "nogil": True, "fastmath": FASTMATH, "error_model": "numpy"}
"""numba options of the row functions: inlined into the loops over rows that call them."""


class CornerScratch(NamedTuple):
    """The scratch rows of :func:`filtered_plate_row`, each as long as the row and each
    a 1-D array of its own (as a slice of a 2-D slice its stride would be unknown, and
    LLVM would not vectorise the loops): the edge frame (h, q), the corner table's
    fractions (tx, ty) and its first taps (unsigned)."""

    h: np.ndarray
    q: np.ndarray
    tx: np.ndarray
    ty: np.ndarray
    taps: np.ndarray


@nb.njit(inline="always", **_ROW)
def plate_row(row_f, x, row_y, tab, n_corners, apothem, inv_delta, row_h):
    """F of the scheme ``paper`` on a row of cells (compiled): row_f[j] at the point
    (x, row_y[j]) of the plate's frame (its centre at the origin, the edge normals `tab`
    (2, >= N) in the lab's axes).

    The gauge (``projection``, ``gauge_step``) and profile of the physics'
    ``plate_cell``, with the loop over the edges outside the loop over the row's cells,
    so that the row is computed four cells at a time (SIMD; the loops run over slices,
    whose indices numba knows to be non-negative). `row_h` (as long) is scratch. The
    rotor's rows and the bodies' (:mod:`pde_rotor.kernels.bodies`) call it.
    """
    ex, ey = tab[0, 0], tab[1, 0]
    for j in range(row_y.size):
        row_h[j] = _projection(x, row_y[j], ex, ey)
    for k in range(1, n_corners):
        ex, ey = tab[0, k], tab[1, k]
        for j in range(row_y.size):
            row_h[j] = _gauge_step(row_h[j], x, row_y[j], ex, ey)
    for j in range(row_y.size):
        row_f[j] = _plate_profile(row_h[j], apothem, inv_delta)


@nb.njit(inline="always", **_ROW)
def filtered_plate_row(row_f, x, row_y, tab, polygon, rows):
    """F_eps of the scheme ``consistent`` on a row of cells (compiled): row_f[j] at the
    point (x, row_y[j]) of the plate's frame, as for :func:`plate_row`.

    The physics' ``filtered_plate`` of the plate `polygon`
    (:class:`~pde_rotor.physics.indicators.PolygonFilter`) in passes over the row, all but
    the last four cells at a time (SIMD, as :func:`plate_row`): the frame of the nearest
    edge (h, q) (``nearer_edge`` from ``projection``, ``farther`` and ``tangential``); the
    edge profile (``filtered_edge``); where the 2-D corner table's taps lie
    (``corner_taps``), kept for the cells within the crease width of a corner bisector and
    short of the table's end (``near_corner``); last, one cell at a time, the table's spline
    on those cells (``corner_sum``: 16 loads from computed places, which LLVM does not
    vectorise). Split so, the corner cells cost 10 % less than with the table looked up
    whole (``filtered_corner``) in the loop over the cells. `rows` (:class:`CornerScratch`)
    is scratch.
    """
    n_corners, apothem, tan_half, crease, corner_end, edge = polygon[0:6]
    e_u0, e_inv, plate, t_n, t_x0, t_inv = polygon[6:12]
    row_h, row_q, row_tx, row_ty, row_taps = rows
    ex, ey = tab[0, 0], tab[1, 0]
    for j in range(row_y.size):
        row_h[j] = _projection(x, row_y[j], ex, ey)
        row_q[j] = _tangential(x, row_y[j], ex, ey)
    for k in range(1, n_corners):
        ex, ey = tab[0, k], tab[1, k]
        for j in range(row_y.size):
            # the physics' nearer_edge, spelt out: LLVM vectorises this loop only so
            proj = _projection(x, row_y[j], ex, ey)
            nearer = _farther(proj, row_h[j])
            row_q[j] = _tangential(x, row_y[j], ex, ey) if nearer else row_q[j]
            row_h[j] = proj if nearer else row_h[j]
    for j in range(row_y.size):
        row_f[j] = _filtered_edge(row_h[j], apothem, edge, e_u0, e_inv)
    skip = np.uint64(-1)
    for j in range(row_y.size):
        near = _near_corner(row_h[j], row_q[j], tan_half, crease, corner_end)
        inside, first, row_tx[j], row_ty[j] = _corner_taps(row_h[j], row_q[j], t_n, t_x0, t_inv)
        take = near & inside
        value = row_f[j]  # loaded whatever take is, so that the loop stays branch-free
        row_f[j] = value if take == near else 0.0  # near, but the taps leave the table
        row_taps[j] = np.uint64(first) if take else skip
    sx, sy = np.uint64(t_n), np.uint64(1)
    for j in range(row_y.size):
        if row_taps[j] != skip:
            row_f[j] = _corner_sum(plate, row_taps[j], sx, sy, row_tx[j], row_ty[j])


class StripRows(NamedTuple):
    """The scratch of :func:`filtered_strip_row`: the B-spline weights of each cell of
    the row, `weights` (8, >= the row) along x' (the first four) and y', and the first of
    its taps (unsigned), `taps` (>= the row)."""

    weights: np.ndarray
    taps: np.ndarray


@nb.njit(inline="always", **_ROW)
def filtered_strip_row(row_f, x, row_y, axis, strip, rows):
    """F_eps of a strip plate (scheme ``consistent``) on a row of cells (compiled):
    row_f[j] at the point (x, row_y[j]) of the body's frame (its centre at the origin,
    its x axis `axis` = (ex, ey) in the lab's axes), the physics' ``filtered_strip``
    cell by cell, bit for bit.

    `strip` is (plate, rows, columns, t_x0, t_inv), the quadrant table and its size,
    first abscissa and inverse step. Two passes over the row: first where the taps of
    each cell lie and their weights (|x'|, |y'|, whether the taps stay in the table,
    ``spline_node`` and ``bspline_weights`` along both, unsigned offsets), several cells
    at a time (SIMD: no branch, no load from a computed place); then, one cell at a
    time, the table's 16 taps (``spline_sum``) on the cells whose taps lie in the table,
    0 on the others. `rows` (:class:`StripRows`) is scratch.
    """
    ex, ey = axis
    plate, t_rows, t_cols, t_x0, t_inv = strip
    weights, row_taps = rows
    skip = np.uint64(-1)
    for j in range(row_y.size):
        along = abs(_projection(x, row_y[j], ex, ey))
        across = abs(_tangential(x, row_y[j], ex, ey))
        fx = (along - t_x0) * t_inv
        fy = (across - t_x0) * t_inv
        inside = (fx < t_rows - 2.0) & (fy < t_cols - 2.0)
        i, tx = _spline_node(t_x0, t_inv, along)
        k, ty = _spline_node(t_x0, t_inv, across)
        weights[0, j], weights[1, j], weights[2, j], weights[3, j] = _bspline_weights(tx)
        weights[4, j], weights[5, j], weights[6, j], weights[7, j] = _bspline_weights(ty)
        row_taps[j] = np.uint64((i - 1) * t_cols + k - 1) if inside else skip
    sx, sy = np.uint64(t_cols), np.uint64(1)
    for j in range(row_y.size):
        first = row_taps[j]
        if first == skip:
            row_f[j] = 0.0
        else:
            wx = (weights[0, j], weights[1, j], weights[2, j], weights[3, j])
            wy = (weights[4, j], weights[5, j], weights[6, j], weights[7, j])
            row_f[j] = _spline_sum(plate, first, sx, sy, wx, wy)


@nb.njit(inline="always", **_ROW)
def pill_row(G, i, coords, j0, j1, tab, pills, g):
    """G on the support cells [j0, j1) of row i (compiled): the pill terms of the scheme
    ``paper``, or of ``consistent`` where `profile` is not empty (its filtered radial
    profile); `pills` is (n_corners, reach, rho, inv_delta, profile, inv_step). `g`
    (>= n) is scratch.

    The terms of ``pill_cell`` / ``filtered_pills`` summed in the same order, the loop
    over the pills outside the loop over the row's cells (SIMD, as :func:`plate_row`). A
    pill adds to the cells of its bounding square of half-width `reach` only: beyond,
    its term is below 4.3e-18 (``paper``); for ``consistent``, whose terms are 0 from
    `reach` on, to the cells of the row's chord of the disk of radius `reach` (and one
    cell more each side, against rounding): a fifth fewer terms, the same sums.
    """
    n_corners, reach, rho, inv_delta, profile, inv_step = pills
    n = coords.size
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    filtered = profile.size > 0
    x = coords[i]
    row_g = g[j0:j1]
    for j in range(row_g.size):
        row_g[j] = 0.0
    for k in range(n_corners):
        px, py = x - tab[2, k], tab[3, k]
        if abs(px) >= reach:
            continue
        half = math.sqrt(reach * reach - px * px) + 1.0 / inv_dx if filtered else reach
        ja = max(j0, math.ceil((py - half - x0) * inv_dx))
        jb = max(ja, min(j1, math.floor((py + half - x0) * inv_dx) + 1))
        box_y = coords[ja:jb]
        box_g = g[ja:jb]
        if filtered:
            for j in range(box_y.size):
                box_g[j] += _filtered_pill_term(px, box_y[j] - py, profile, inv_step)
        else:
            for j in range(box_y.size):
                box_g[j] += _pill_term(px, box_y[j] - py, rho, inv_delta)
    row_out = G[i * n + j0 : i * n + j1]
    for j in range(row_g.size):
        row_out[j] = row_g[j]


SCRATCH_ROWS = 5
"""Rows of the float scratch (SCRATCH_ROWS, n) of :func:`indicator_row`."""


@nb.njit(inline="always", **_ROW)
def indicator_row(F, G, i, coords, j0, j1, p, tab, tables, work):
    """F and G on the support cells [j0, j1) of row i at the angle of the rotor table
    `tab` (compiled): point values (:func:`plate_row`, :func:`pill_row`), or
    (``consistent``) the filtered fields from the filter tables. `p` is the parameter
    record, `tables` the scheme's (quad_s, quad_t, plate, edge, pill), `work` the
    scratch (scratch (:data:`SCRATCH_ROWS`, n), taps (n, unsigned))."""
    scratch, taps = work
    _, _, plate_tab, edge_tab, pill_tab = tables
    n_corners, rho, inv_delta = p.n_corners, p.pill_radius, 1.0 / p.smoothing
    n = coords.size
    x = coords[i]
    row_y = coords[j0:j1]
    row_f = F[i * n + j0 : i * n + j1]
    if not p.filtered:
        plate_row(row_f, x, row_y, tab, n_corners, p.apothem, inv_delta, scratch[0, j0:j1])
        reach = _pill_reach(rho, inv_delta)
        pills = (n_corners, reach, rho, inv_delta, pill_tab[:0], 1.0)
        pill_row(G, i, coords, j0, j1, tab, pills, scratch[4])
        return
    p_inv = p.profile_inv_step
    reach = _filtered_pill_reach(pill_tab, p_inv)
    pills = (n_corners, reach, rho, inv_delta, pill_tab, p_inv)
    pill_row(G, i, coords, j0, j1, tab, pills, scratch[4])
    polygon = PolygonFilter(
        n_corners, p.apothem, p.tan_half, p.crease, p.corner_end, edge_tab, p.edge_u0,
        p.edge_inv_step, plate_tab, p.table_n, p.table_x0, p.table_inv_step,
    )  # fmt: skip
    rows = CornerScratch(
        scratch[0, j0:j1], scratch[1, j0:j1], scratch[2, j0:j1], scratch[3, j0:j1], taps[j0:j1]
    )
    filtered_plate_row(row_f, x, row_y, tab, polygon, rows)


@nb.njit(**_ROW)
def update_indicators(F, G, domain, params, tab, tables, phi):
    """Recompute F and G (flat n*n arrays) on the support cells for angle phi (compiled).

    Cells outside the support keep F = G = 0. `domain` is (coords, lo, hi, slo, shi) of
    :func:`pde_rotor.kernels.cpu.advance`, `params` the (1,) parameter record array
    (:mod:`pde_rotor.kernels.records`), `tables` the scheme's (quad_s, quad_t, plate,
    edge, pill). `tab` (4, >= N) receives the edge normals and pill centres. Row by row
    (:func:`indicator_row`), as the time step does.
    """
    p = params[0]
    coords, _, _, slo, shi = domain
    _rotor_table(phi, p.n_corners, p.pill_distance, p.asymmetry, tab)
    scratch = np.empty((SCRATCH_ROWS, coords.size))
    taps = np.empty(coords.size, np.uint64)
    for i in range(coords.size):
        if shi[i] > slo[i]:
            indicator_row(F, G, i, coords, slo[i], shi[i], p, tab, tables, (scratch, taps))
