"""F and G on the CPU: the smoothed plate and pill indicators on the support cells.

Every step the plate turns, F and G (the equations after Eq. (rj) of Koyano et al.,
Chaos 2020; filtered for the scheme ``consistent``, :mod:`pde_rotor.model.filtering`) are
recomputed on the cells within reach of the plate. The terms are the physics core's
(:mod:`pde_rotor.kernels.core`: ``plate_profile``, ``pill_term``, ``filtered_edge``,
``filtered_corner``, ``filtered_pill_term``), the same the GPU sums once per cell in
``plate_cell``, ``pill_cell``, ``filtered_plate`` and ``filtered_pills``. Here the loops
over edges and pills stand outside the loops over a row's cells, so that LLVM computes
a row four cells at a time (SIMD): the loops run over slices, whose indices numba knows
to be non-negative, the terms are branch-free, and ``error_model="numpy"`` drops the
division-by-zero branch. tests/test_indicators.py checks the rows against the cell
functions.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from .core import (
    CPU,
    FASTMATH,
    M_CREASE,
    M_EDGE_INV_STEP,
    M_EDGE_U0,
    M_FILTERED,
    M_PROFILE_INV_STEP,
    M_TABLE_INV_STEP,
    M_TABLE_N,
    M_TABLE_X0,
    M_TAN_HALF,
    S_APOTHEM,
    S_ASYM,
    S_DELTA,
    S_N,
    S_RC,
    S_RHO,
    X_SATURATION,
)

_rotor_table = CPU.rotor_table
_plate_profile = CPU.plate_profile
_pill_term = CPU.pill_term
_filtered_edge = CPU.filtered_edge
_filtered_corner = CPU.filtered_corner
_filtered_pill_term = CPU.filtered_pill_term


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def plate_rows(F, coords, slo, shi, tab, n_corners, apothem, inv_delta):
    """F of the scheme ``paper`` on the support cells (compiled).

    The gauge and profile of :func:`~pde_rotor.kernels.core.make_core`'s ``plate_cell``, with
    the loop over the edges outside the loop over a row's cells, so that a row is
    computed four cells at a time (SIMD; the loops run over slices, whose indices numba
    knows to be non-negative).
    """
    n = coords.size
    h = np.empty(n)
    for i in range(n):
        x = coords[i]
        j0, j1 = slo[i], shi[i]
        row_y = coords[j0:j1]
        row_h = h[j0:j1]
        ex, ey = tab[0, 0], tab[1, 0]
        for j in range(row_y.size):
            row_h[j] = x * ex + row_y[j] * ey
        for k in range(1, n_corners):
            ex, ey = tab[0, k], tab[1, k]
            for j in range(row_y.size):
                p = x * ex + row_y[j] * ey
                row_h[j] = p if p > row_h[j] else row_h[j]
        row_f = F[i * n + j0 : i * n + j1]
        for j in range(row_y.size):
            row_f[j] = _plate_profile(row_h[j], apothem, inv_delta)


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def filtered_plate_rows(F, coords, slo, shi, tab, n_corners, apothem, num, edge, plate):
    """F_eps of the scheme ``consistent`` on the support cells (compiled).

    ``filtered_plate`` of :func:`~pde_rotor.kernels.core.make_core` in two passes over a row:
    the nearest edge (h, q) and the edge profile for every cell four at a time (SIMD,
    as :func:`plate_rows`), then the 2-D corner table for the cells within the crease
    width of a corner bisector, one at a time.
    """
    tan_half, crease = num[M_TAN_HALF], num[M_CREASE]
    e_u0, e_inv = num[M_EDGE_U0], num[M_EDGE_INV_STEP]
    t_n, t_x0, t_inv = int(num[M_TABLE_N]), num[M_TABLE_X0], num[M_TABLE_INV_STEP]
    n = coords.size
    h = np.empty(n)
    q = np.empty(n)
    for i in range(n):
        x = coords[i]
        j0, j1 = slo[i], shi[i]
        row_y = coords[j0:j1]
        row_h = h[j0:j1]
        row_q = q[j0:j1]
        ex, ey = tab[0, 0], tab[1, 0]
        for j in range(row_y.size):
            row_h[j] = x * ex + row_y[j] * ey
            row_q[j] = row_y[j] * ex - x * ey
        for k in range(1, n_corners):
            ex, ey = tab[0, k], tab[1, k]
            for j in range(row_y.size):
                p = x * ex + row_y[j] * ey
                nearer = p > row_h[j]
                row_q[j] = row_y[j] * ex - x * ey if nearer else row_q[j]
                row_h[j] = p if nearer else row_h[j]
        row_f = F[i * n + j0 : i * n + j1]
        for j in range(row_y.size):
            row_f[j] = _filtered_edge(row_h[j], apothem, edge, e_u0, e_inv)
        for j in range(row_y.size):
            if row_h[j] * tan_half - abs(row_q[j]) <= crease:
                row_f[j] = _filtered_corner(row_h[j], row_q[j], plate, t_n, t_x0, t_inv)


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def pill_rows(G, coords, slo, shi, tab, n_corners, reach, rho, inv_delta, profile, inv_step):
    """G on the support cells (compiled): the pill terms of the scheme ``paper``, or of
    ``consistent`` where `profile` is not empty (its filtered radial profile).

    The terms of ``pill_cell`` / ``filtered_pills`` summed in the same order, the loop
    over the pills outside the loop over a row's cells (SIMD, as :func:`plate_rows`). A
    pill adds to the cells of its bounding square of half-width `reach` only: beyond,
    its term is 0 (``consistent``) or below 4.3e-18 (``paper``).
    """
    n = coords.size
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    filtered = profile.size > 0
    g = np.empty(n)
    for i in range(n):
        x = coords[i]
        j0, j1 = slo[i], shi[i]
        row_g = g[j0:j1]
        for j in range(row_g.size):
            row_g[j] = 0.0
        for k in range(n_corners):
            px, py = x - tab[2, k], tab[3, k]
            if abs(px) >= reach:
                continue
            ja = max(j0, math.ceil((py - reach - x0) * inv_dx))
            jb = max(ja, min(j1, math.floor((py + reach - x0) * inv_dx) + 1))
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


@nb.njit(cache=True, nogil=True)
def update_indicators(F, G, coords, slo, shi, shape, tab, num, plate_tab, edge_tab, pill_tab, phi):
    """Recompute F and G (flat n*n arrays) on the support cells for angle phi (compiled).

    Cells outside the support keep F = G = 0. `tab` (4, >= N) receives the edge normals
    and pill centres; `num` is :meth:`~pde_rotor.model.schemes.Scheme.as_array`: point values
    (:func:`plate_rows`, :func:`pill_rows`), or (``consistent``) the filtered fields
    from `plate_tab`, `edge_tab` and `pill_tab`
    (:meth:`~pde_rotor.model.schemes.Scheme.table_arrays`).
    """
    n_corners = int(shape[S_N])
    apothem, rho, inv_delta = shape[S_APOTHEM], shape[S_RHO], 1.0 / shape[S_DELTA]
    _rotor_table(phi, n_corners, shape[S_RC], shape[S_ASYM], tab)
    if num[M_FILTERED] == 0.0:
        plate_rows(F, coords, slo, shi, tab, n_corners, apothem, inv_delta)
        reach = rho + X_SATURATION / inv_delta
        pill_rows(G, coords, slo, shi, tab, n_corners, reach, rho, inv_delta, pill_tab[:0], 1.0)
        return
    p_inv = num[M_PROFILE_INV_STEP]
    pill_rows(
        G, coords, slo, shi, tab, n_corners, (pill_tab.size - 1) / p_inv, rho, inv_delta,
        pill_tab, p_inv,
    )  # fmt: skip
    filtered_plate_rows(F, coords, slo, shi, tab, n_corners, apothem, num, edge_tab, plate_tab)
