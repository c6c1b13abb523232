"""Compiled Euler step of the fields on cut cells: behind a no-flux dish wall
(``grid.wall: no_flux``) or in a vessel (``grid.vessel``).

:func:`euler_walled_fields` advances c on the cut cells of the circle (or vessel) and v
on the cells whose centre lies inside it, walking only the runs of wet cells of each
row (two across an annulus' hole), so that dry cells cost nothing, as
:func:`pde_rotor.kernels.body_fields.euler_body_fields` does with the absorbing wall: the
transport of c through the open part of each face (the physics' ``cut_cell_inflow``) and
its local terms (``local_rate``) by forward Euler, then the diffusion through the faces
of the stiff cut cells by backward Euler, by the sparse factors of the clusters' matrices
computed once per run (:mod:`pde_rotor.model.clusters`; :mod:`pde_rotor.model.wall`
takes the same step with numpy and computes the geometry these loops read). v and the
plate terms are the physics' ``plate_rates``.

The `wall` argument is :meth:`pde_rotor.model.wall.CutCells.arrays`: (volume, aperture_x,
aperture_y, explicit apertures along x and y, row_start, span_lo, span_hi, flowing,
the implicit clusters' index, levels and factor); :data:`NO_WALL` is the
same tuple, empty, for the absorbing dish wall.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ..physics.build import CPU, FASTMATH

_plate_rates = CPU.rates.plate_rates
_cut_cell_inflow = CPU.rates.cut_cell_inflow
_local_rate = CPU.rates.local_rate
_plate_velocity = CPU.rates.plate_velocity

_NONE = np.zeros(0)
_NO_INDEX = np.zeros(0, dtype=np.int64)
NO_WALL = (_NONE, _NONE, _NONE, _NONE, _NONE, _NO_INDEX, _NO_INDEX, _NO_INDEX,
           np.zeros(0, dtype=np.uint8), np.zeros((0, 2), dtype=np.int64), _NO_INDEX,
           np.zeros((0, 2)))  # fmt: skip
"""The `wall` of the absorbing wall: no cut cells (the compiled step takes the same types)."""


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH)
def run_strides(n):
    """(sx, sy, nn): the offsets of a cell's x and y neighbours and of the next field on
    the flat (3, n, n) state, unsigned (no test for a negative index at each load)."""
    sx = np.uint64(n)
    return sx, np.uint64(1), sx * sx


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH)
def cell_plate(maps, o, y, plate, motion):
    """(f, g, px, py) of the cell at offset `o`, centred at `y` along its row: with `plate`
    its owner's F, G (`maps` = (F, G)) and plate velocity U + omega z x (r - X) (the
    rates' ``plate_velocity``; `motion` = (U_x, U_y, omega, x - X_x of the row, X_y)),
    else none (0): the plate terms of a run of cells, one body's or none."""
    if not plate:
        return 0.0, 0.0, 0.0, 0.0
    u, v, omega, rx, y_k = motion
    px, py = _plate_velocity(u, v, omega, rx, y - y_k)
    return maps[0][o], maps[1][o], px, py


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH)
def _cut_cells(bufs, base, a, b, plate, motion, coef, dt, flow):
    """The explicit part of the step on the cells [a, b) of the row at offset `base`:
    c' on each (without flow also kappa c' in `rhs`), then, with `flow` (a literal), v_x
    and then v_y on those that flow, each in a pass of its own over the run (one loop over
    c and v held more array addresses than registers and reloaded 11 from the stack per
    iteration, the split passes 5 and 0). With `plate` the cells are one body's, its F, G
    and plate velocity (:func:`cell_plate`), else none.

    A run is short where a vessel's wall cuts the rows (median 13 cells across the
    narrow annulus of ``benchmarks/vessel_step.py``), so the entry of each vectorised
    loop counts: LLVM tests at run time that the ranges a loop stores miss those it
    reads (the fields at three rows, each aperture array), and runs below its threshold
    go scalar. With the flow, the c pass stores c' alone (:func:`cluster_rhs` writes
    kappa c' on the implicit clusters' cells, the only ones that read it): 14 overlap
    tests instead of 29, vectorised from 8 cells instead of 12; and one v pass storing
    both components made 23 tests and ran scalar below 24 cells, each component's pass
    makes 4 and vectorises from 8.
    `bufs` = (cur, nxt, F, G, coords, rhs, wall)."""
    cur, nxt, F, G, coords, rhs, wall = bufs
    volume, pass_x, pass_y, open_x, open_y, _, _, _, flowing = wall[:9]
    strides = run_strides(coords.size)
    nn = strides[2]
    for j in range(a, b):
        o = np.uint64(base + j)
        f, g, _, _ = cell_plate((F, G), o, coords[j], plate, motion)
        cc = cur[o]
        kappa = volume[o]
        q = _cut_cell_inflow(cur, o, strides, (open_x, open_y, pass_x, pass_y), coef, flow)
        r = kappa * cc + dt * (q + kappa * _local_rate(cc, f, g, coef, plate))
        if not flow:
            rhs[o] = r
        nxt[o] = r / kappa
    if flow:
        for j in range(a, b):
            o = np.uint64(base + j)
            if flowing[o]:
                f, g, px, py = cell_plate((F, G), o, coords[j], plate, motion)
                _, rate_x, _ = _plate_rates(cur, o, strides, f, g, (px, py), coef, flow, plate)
                nxt[o + nn] = cur[o + nn] + dt * rate_x
        for j in range(a, b):
            o = np.uint64(base + j)
            if flowing[o]:
                f, g, px, py = cell_plate((F, G), o, coords[j], plate, motion)
                _, _, rate_y = _plate_rates(cur, o, strides, f, g, (px, py), coef, flow, plate)
                nxt[o + nn + nn] = cur[o + nn + nn] + dt * rate_y


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def euler_walled_fields(states, maps, domain, wall, coef, dt, pose, flow, rhs):
    """One step of Eqs. (eqc), (eqv) on cut cells (compiled).

    Each run of wet cells of a row is walked as the bodies' runs cut it
    (:func:`pde_rotor.kernels.body_fields.body_segments`): a body's cells with its plate
    terms, the others without, as :func:`pde_rotor.kernels.body_fields.euler_body_fields`
    walks the rows of the absorbing wall.

    Args:
        states: (cur, nxt), the flat states (c, v_x, v_y) now and after the step.
        maps: (F, G, runs): flat indicators and the bodies' runs of each row (no runs:
            no bodies).
        domain: (coords, lo, hi) (only coords read).
        wall: the cut cells (:meth:`pde_rotor.model.wall.CutCells.arrays`).
        coef: the physics' ``rate_coefficients``.
        dt: time step.
        pose: (K, 13) the bodies' poses (plate velocity of each body's cells).
        flow: whether v evolves (else v = 0).
        rhs: scratch of n^2 values: kappa c' of the explicit part on the implicit
            clusters' cells (without flow on every wet cell; with it only there, by
            :func:`cluster_rhs`), changed by their forward substitution.
    """
    cur, nxt = states
    F, G, segments = maps
    index, _, factor = wall[9:]
    bufs = (cur, nxt, F, G, domain[0], rhs, wall)
    if flow:
        _walk_rows(bufs, segments, pose, coef, dt, True)
        cluster_rhs(nxt, rhs, wall[0], index)
    else:
        _walk_rows(bufs, segments, pose, coef, dt, False)
    implicit_clusters(nxt, rhs, index, factor)


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH)
def _walk_rows(bufs, segments, pose, coef, dt, flow):
    """The explicit part of :func:`euler_walled_fields` on every run of wet cells, each
    cut by the bodies' runs.

    `flow` is a literal, False or True (the caller compiles one copy of this walk for
    each), so that neither copy of the cell loop holds a branch on it: with a branch on a
    run-time `flow` numba cannot drop the reference counting of the arrays the rates'
    inflow binds (the state and the apertures, live across the branch's join), two
    atomic updates of each of three arrays at every cell: with the flow 40 to 52 ns a wet
    cell on the vessels of ``benchmarks/vessel_step.py`` instead of 4 to 14. The literal
    True also lets LLVM fuse other products into the flux sums than the run-time branch
    did: c differs from that step's at round-off (2e-16 relative after one step). The
    division by kappa > 0 (wet cells only) is IEEE's, without Python's zero test (the
    caller's ``error_model``), so that the loop has no branch left in it but the one on
    the flowing cells."""
    coords, wall = bufs[4], bufs[6]
    run_start, runs = segments
    row_start, span_lo, span_hi = wall[5], wall[6], wall[7]
    n = coords.size
    still = (0.0, 0.0, 0.0, 0.0, 0.0)
    for i in range(n):
        base = i * n
        for s in range(row_start[i], row_start[i + 1]):
            a, b = span_lo[s], span_hi[s]
            j = a
            for m in range(run_start[i], run_start[i + 1]):
                first, end, k = max(runs[0, m], a), min(runs[1, m], b), runs[2, m]
                if first >= end:
                    continue
                _cut_cells(bufs, base, j, first, False, still, coef, dt, flow)
                motion = (pose[k, 3], pose[k, 4], pose[k, 5], coords[i] - pose[k, 0], pose[k, 1])
                _cut_cells(bufs, base, first, end, True, motion, coef, dt, flow)
                j = end
            _cut_cells(bufs, base, j, b, False, still, coef, dt, flow)


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH)
def cluster_rhs(nxt, rhs, volume, index):
    """kappa c' of the explicit part in `rhs` on the implicit clusters' cells (each
    row's cell, ``index[:, 0]``), from their c' in `nxt`: the flow-on step's
    :func:`_cut_cells` stores c' alone. kappa (c' / kappa) is kappa c' to one rounding."""
    for g in range(index.shape[0]):
        o = np.uint64(index[g, 0])
        rhs[o] = volume[o] * nxt[o]


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def implicit_clusters(nxt, rhs, index, factor):
    """c' solving A c' = kappa c' of the explicit part (`rhs`) on each cluster of
    implicit faces, A = L D L^T by columns
    (:func:`pde_rotor.model.clusters.implicit_factors`).

    Forward substitution L y = rhs in place, each row's y, once its earlier rows have
    been taken off it, taken off its later rows; then back substitution L^T c' = D^-1 y
    from the last row up, each row's c' from its later rows' into `nxt`: one
    multiply-add a row and sweep for the row's parent in the elimination tree, one
    more for each other later row (a tree has none). Cell offsets unsigned, as in
    :func:`run_strides`."""
    rows, span = index.shape
    for g in range(rows):
        y = rhs[np.uint64(index[g, 0])]
        rhs[np.uint64(index[g, 1])] -= factor[g, 1] * y
        for e in range(2, span):
            rhs[np.uint64(index[g, e])] -= factor[g, e] * y
    for g in range(rows - 1, -1, -1):
        o = np.uint64(index[g, 0])
        x = rhs[o] * factor[g, 0]
        for e in range(span - 1, 1, -1):
            x -= factor[g, e] * nxt[np.uint64(index[g, e])]
        nxt[o] = x - factor[g, 1] * nxt[np.uint64(index[g, 1])]
