"""The bodies' field update: one Euler step of Eqs. (eqc), (eqv) with K bodies (compiled, CPU).

A cell's plate terms (its owner's F, G and plate velocity) cost only where a body owns
it. :func:`body_segments` lists, row by row, the chord of each body's footprint (the
physics' ``footprint_chord``, the cells :func:`pde_rotor.kernels.body_draw.draw_body`
gives the body), sorted along the row; :func:`euler_body_fields` walks each row as runs
of bare cells (no plate: the surface's own update, the rates' ``plate_rates`` without
plate terms) and runs of one body's cells (its plate terms, the velocity of its plate
from the row's constants), so that a crowd of small bodies costs by their footprints,
not by the rows' extent between them. Behind a no-flux wall (or in a vessel) the update
is :func:`pde_rotor.kernels.wall.euler_walled_fields`, which cuts each row's runs of wet
cells by the same bodies' runs. :func:`fields` picks one; :func:`average_fields` is
Heun's average.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ..physics.build import CPU, FASTMATH
from .wall import cell_plate, euler_walled_fields, run_strides

_plate_rates = CPU.rates.plate_rates
_rate_coefficients = CPU.rates.rate_coefficients


@nb.njit(cache=True, nogil=True)
def body_segments(bodies, chords, segments):
    """The chords of the bodies' drawn footprints, row by row (compiled).

    segments = (row_start (n + 1), runs (3, K n)): the runs of row i are
    runs[:, row_start[i]:row_start[i + 1]], each (first column, end column, body),
    sorted by their first column (footprints do not overlap, so neither do the runs).
    A body's runs are its non-empty `chords` (2, K, n) on the rows of its drawn box, the
    cells :func:`~pde_rotor.kernels.body_draw.draw_body` made its own; `bodies` as for
    :func:`pde_rotor.kernels.bodies.advance_bodies`.
    """
    body, _, _, _, box, _, _, _ = bodies
    row_start, runs = segments
    n = row_start.size - 1
    for i in range(n + 1):
        row_start[i] = 0
    for k in range(body.shape[0]):
        for i in range(box[k, 0], box[k, 1]):
            if chords[0, k, i] < chords[1, k, i]:
                row_start[i + 1] += 1
    for i in range(n):
        row_start[i + 1] += row_start[i]
    fill = row_start[:n].copy()
    for k in range(body.shape[0]):
        for i in range(box[k, 0], box[k, 1]):
            ja, jb = chords[0, k, i], chords[1, k, i]
            if ja < jb:
                s = fill[i]
                runs[0, s], runs[1, s], runs[2, s] = ja, jb, k
                fill[i] = s + 1
    for i in range(n):  # insertion sort of each row's few runs by their first column
        for s in range(row_start[i] + 1, row_start[i + 1]):
            a, b, k = runs[0, s], runs[1, s], runs[2, s]
            t = s
            while t > row_start[i] and runs[0, t - 1] > a:
                runs[0, t], runs[1, t], runs[2, t] = runs[0, t - 1], runs[1, t - 1], runs[2, t - 1]
                t -= 1
            runs[0, t], runs[1, t], runs[2, t] = a, b, k


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH)
def _run_cells(bufs, base, a, b, plate, motion, coef, dt, flow):
    """The Euler step on the cells [a, b) of the row at offset `base`: with `plate` all
    owned by one body, its F, G and plate velocity (:func:`~pde_rotor.kernels.wall.cell_plate`,
    `motion` = (U_x, U_y, omega, x - X_x of the row, X_y)), else none owned (F = G = 0: no
    plate terms); `bufs` = (cur, nxt, F, G, coords)."""
    cur, nxt, F, G, coords = bufs
    strides = run_strides(coords.size)
    nn = strides[2]
    for j in range(a, b):
        o = np.uint64(base + j)
        f, g, px, py = cell_plate((F, G), o, coords[j], plate, motion)
        cc = cur[o]
        ux = cur[o + nn] if flow else 0.0
        uy = cur[o + nn + nn] if flow else 0.0
        rate_c, rate_x, rate_y = _plate_rates(cur, o, strides, f, g, (px, py), coef, flow, plate)
        nxt[o] = cc + dt * rate_c
        if flow:
            nxt[o + nn] = ux + dt * rate_x
            nxt[o + nn + nn] = uy + dt * rate_y


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def euler_body_fields(cur, nxt, F, G, pose, domain, segments, coef, dt, flow):
    """One Euler step of Eqs. (eqc), (eqv) on the interior cells (compiled): each row's
    runs of bare cells without plate terms, each body's run (:func:`body_segments`) with
    its plate terms, the plate velocity its own (the rates' ``plate_velocity``).

    Args:
        cur, nxt: flat states (c, v_x, v_y) now and after the step.
        F, G: flat indicators.
        pose: (K, 13) the bodies' poses.
        domain: (coords, lo, hi).
        segments: the runs of :func:`body_segments` (no runs: the bare surface).
        coef: the physics' ``rate_coefficients``.
        dt: time step.
        flow: whether v evolves (else only c is written).
    """
    coords, lo, hi = domain[0], domain[1], domain[2]
    row_start, runs = segments
    n = coords.size
    bufs = (cur, nxt, F, G, coords)
    still = (0.0, 0.0, 0.0, 0.0, 0.0)
    for i in range(n):
        base = i * n
        j = lo[i]
        for s in range(row_start[i], row_start[i + 1]):
            a, b, k = runs[0, s], runs[1, s], runs[2, s]
            _run_cells(bufs, base, j, a, False, still, coef, dt, flow)
            motion = (pose[k, 3], pose[k, 4], pose[k, 5], coords[i] - pose[k, 0], pose[k, 1])
            _run_cells(bufs, base, a, b, True, motion, coef, dt, flow)
            j = b
        _run_cells(bufs, base, j, hi[i], False, still, coef, dt, flow)


@nb.njit(cache=True, nogil=True)
def fields(cur, nxt, maps, domain, surface, p, pose, rhs):
    """One Euler step of the fields from `cur` into `nxt` with the bodies at `pose`
    (compiled): behind the no-flux wall :func:`~pde_rotor.kernels.wall.euler_walled_fields`,
    else :func:`euler_body_fields`, both over the bodies' runs; `maps` = (F, G, owner),
    `surface` = (wall, segments), `rhs` the wall's scratch."""
    F, G, _ = maps
    wall, segments = surface
    coef = _rate_coefficients(p)
    if wall[0].size > 0:
        euler_walled_fields(
            (cur, nxt), (F, G, segments), domain, wall, coef, p.dt, pose, p.flow, rhs
        )
    else:
        euler_body_fields(cur, nxt, F, G, pose, domain, segments, coef, p.dt, p.flow)


@nb.njit(cache=True, nogil=True)
def average_fields(cur, stage, nxt, domain, wall, flow):
    """nxt = (cur + stage) / 2 where a step writes (compiled): c on the interior cells (on
    the runs of cut cells of each row behind a no-flux wall or in a vessel), v on the
    interior cells with `flow`."""
    coords, lo, hi = domain[0], domain[1], domain[2]
    n = coords.size
    nn = n * n
    if wall[0].size > 0:
        row_start, span_lo, span_hi = wall[5], wall[6], wall[7]
        for i in range(n):
            for s in range(row_start[i], row_start[i + 1]):
                for j in range(span_lo[s], span_hi[s]):
                    o = i * n + j
                    nxt[o] = 0.5 * (cur[o] + stage[o])
    else:
        for i in range(n):
            for j in range(lo[i], hi[i]):
                o = i * n + j
                nxt[o] = 0.5 * (cur[o] + stage[o])
    if flow:
        for ch in range(1, 3):
            for i in range(n):
                for j in range(lo[i], hi[i]):
                    o = ch * nn + i * n + j
                    nxt[o] = 0.5 * (cur[o] + stage[o])
