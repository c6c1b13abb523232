"""A body's integrals on the GPU, for the kernel of :mod:`pde_rotor.kernels.cuda_bodies`:
the area form over the cells of its box it owns (central differences, :func:`owned_sums`;
the CPU's :func:`pde_rotor.kernels.body_sums.body_integrals`) and, for ``consistent``, the tension
force and torque in contour form (the spline of c on the body's window, then its edges'
or circles' nodes, ``edge_sums``, ``arc_orbit``; the CPU's
:func:`pde_rotor.kernels.body_sums.body_contour`), each split among a block's threads and
summed by a fixed-order tree in shared memory (:func:`reduce_sums`); for a body that
spans its channel, the same integrals over the wet cells it owns (also
:func:`owned_sums`; the CPU's :func:`pde_rotor.kernels.body_sums.spanning_integrals`).
"""

from __future__ import annotations

import math

from ..model.body_schemes import ARC_EDGES
from ..physics.indicators import PLATE_DISK, PLATE_POLYGON, PLATE_STRIP
from ..physics.motion import N_INTEGRALS
from .cuda import GPU
from .cuda_body_draw import box_cell, box_size
from .cuda_target import cuda, device_function

N_SUMS = N_INTEGRALS
"""Integrals of a body per evaluation (those of
:func:`pde_rotor.kernels.body_sums.body_integrals`)."""

_spline_line = GPU.spline.spline_line
_cell_integrals = GPU.motion.cell_integrals
_wet_cell_integrals = GPU.motion.wet_cell_integrals
_polygon_band = GPU.tension.polygon_band
_edge_sums = GPU.tension.edge_sums
_arc_orbit = GPU.tension.arc_orbit


@device_function
def reduce_sums(red, count, tid, n_threads):
    """Sum `count` rows of `n_threads` partial sums in shared memory into their first
    entries, a tree in a fixed order (every thread of the block calls it)."""
    cuda.syncthreads()
    half = n_threads // 2
    while half > 0:
        if tid < half:
            for q in range(count):
                red[q * n_threads + tid] += red[q * n_threads + tid + half]
        cuda.syncthreads()
        half //= 2


@device_function
def store_sums(red, s, tid, n_threads):
    """Thread tid's partial integrals `s` (:data:`N_SUMS`) into red[q n_threads + tid],
    then their sums over the block into red[q n_threads] (:func:`reduce_sums`)."""
    for q in range(N_SUMS):
        red[q * n_threads + tid] = s[q]
    reduce_sums(red, N_SUMS, tid, n_threads)


@device_function
def owned_sums(src, k, m, state, surface, bodies, volume, p, red):
    """Body k's integrals over the cells of its box it owns, into red[q n_threads]
    (q < :data:`N_SUMS`, not yet times dA; all threads): the area form with central
    differences (the motion's ``cell_integrals``; the tension's terms 0 for the contour
    form, which replaces them; the sums of
    :func:`pde_rotor.kernels.body_sums.body_integrals`), or for a body that spans its
    channel each wet cell's share weighted by its volume fraction kappa (the motion's
    ``wet_cell_integrals``, `volume` flat, dry cells skipped; the sums of
    :func:`pde_rotor.kernels.body_sums.spanning_integrals`)."""
    buf, F, _, owner = state
    coords, _ = surface
    body, _, pose, _, box = bodies
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    inv_2dx = 0.5 / (coords[1] - coords[0])
    terms = (not p.contour, p.flow)
    spans = body[m][k].spans != 0
    fm = F[m]
    x_k, y_k = pose[m, k, 0], pose[m, k, 1]
    s = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    for q in range(tid, box_size(box, m, k), n_threads):
        i, j, o = box_cell(box, m, k, q, n)
        if owner[m, o] != k:
            continue
        r = (coords[i] - x_k, coords[j] - y_k)
        if spans:
            kappa = volume[o]
            if kappa == 0.0:
                continue
            cell = (src + o, o)
            s = _wet_cell_integrals(s, buf, cell, fm, (n, n * n), kappa, r, inv_2dx, p, p.flow)
        else:
            f = fm[o]
            if f == 0.0:
                continue
            s = _cell_integrals(s, buf, src + o, (n, 1, n * n), f, r, inv_2dx, p, terms)
    store_sums(red, s, tid, n_threads)


@device_function
def contour_sums(src, k, m, state, surface, bodies, scratch, tables, p, red):
    """Body k's int F_k grad c dA (x, y) and int F_k (r - X_k) x grad c dA in contour form
    (``consistent``) into red[0], red[n_threads], red[2 n_threads] (all threads; the
    sums of :func:`pde_rotor.kernels.body_sums.body_contour`: a thread takes a polygon's
    or strip's (edge, band node), or a circle's orbit of four mirror-image nodes on one
    ring, ``arc_orbit``, turned into the lab frame on its own)."""
    buf = state[0]
    coords, _ = surface
    body, _, pose, _, _ = bodies
    normals, centres, coef = scratch[0], scratch[1], scratch[4]
    quad_s, quad_t, _, pill_tab, _, _, rings = tables
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    b = body[m][k]
    x_k, y_k, phi = pose[m, k, 0], pose[m, k, 1], pose[m, k, 2]
    half = b.window_half
    ic = int(math.floor((x_k - x0) * inv_dx)) + 1  # noqa: RUF046
    jc = int(math.floor((y_k - x0) * inv_dx)) + 1  # noqa: RUF046
    i0, i1 = max(1, ic - half), min(n - 1, ic + half)
    j0, j1 = max(1, jc - half), min(n - 1, jc + half)
    rows, cols = i1 - i0, j1 - j0
    cm = coef[m]
    nn = n * n  # the rows' prefiltered c after the coefficients, which the columns filter
    for q in range(tid, rows, n_threads):
        o = (i0 + q) * n + j0
        _spline_line(buf, src + o, cm, nn + o, 1, cols)
    cuda.syncthreads()
    for q in range(tid, cols, n_threads):
        o = i0 * n + j0 + q
        _spline_line(cm, nn + o, cm, o, n, rows)
    cuda.syncthreads()
    n_s, n_t = quad_s.shape[1], quad_t.shape[1]
    delta = p.smoothing
    grid = (0, n, x0, inv_dx)
    lattice = (0, n, inv_dx)
    f_x = 0.0
    f_y = 0.0
    torque = 0.0
    if b.plate == PLATE_POLYGON:
        for q in range(tid, b.n_corners * n_s, n_threads):
            j = q // n_s
            ms = q % n_s
            ex, ey = normals[m, k, 0, j], normals[m, k, 1, j]
            h, half = _polygon_band(b.size_a, delta, b.tan_half, quad_s, ms)
            edge = (x_k, y_k, ex, ey, h, half)
            a, c, e = _edge_sums(cm, grid, edge, quad_s, quad_t, ms, p)
            f_x += a
            f_y += c
            torque += e
    elif b.plate == PLATE_STRIP:
        thinner = min(b.size_a, b.size_b)
        for q in range(tid, 4 * n_s, n_threads):
            j = q // n_s
            ms = q % n_s
            h = -delta * quad_s[0, ms]
            if h <= -thinner:
                continue
            ex, ey = normals[m, k, 0, 0], normals[m, k, 1, 0]
            for _ in range(j):  # the edges' normals e, z x e, -e, -z x e
                ex, ey = -ey, ex
            side, along = (b.size_a, b.size_b) if j % 2 == 0 else (b.size_b, b.size_a)
            edge = (x_k, y_k, ex, ey, side + h, along + h)
            a, c, e = _edge_sums(cm, grid, edge, quad_s, quad_t, ms, p)
            f_x += a
            f_y += c
            torque += e
    else:  # a disk plate's circles about X_k, or each pill's about its centre
        quarter = ARC_EDGES * n_t // 4  # the nodes in orbits of four mirror images
        step = 0.5 * math.pi / quarter
        cos_phi, sin_phi = math.cos(phi), math.sin(phi)
        first, last = b.pill_start, b.pill_start + b.pill_count
        if b.plate == PLATE_DISK:
            first, last = 0, 1
        total = 0
        for q in range(first, last):
            total += (b.ring_count if b.plate == PLATE_DISK else pill_tab[q, 5]) * quarter
        for orbit in range(tid, total, n_threads):  # (circle, ring node, orbit) in order
            rest = orbit
            q = first
            r0, r_count = b.ring_start, b.ring_count
            for each in range(first, last):
                q = each
                if b.plate != PLATE_DISK:
                    r0, r_count = pill_tab[each, 4], pill_tab[each, 5]
                if rest < r_count * quarter:
                    break
                rest -= r_count * quarter
            cx, cy = x_k, y_k
            if b.plate != PLATE_DISK:
                cx, cy = centres[m, 0, q], centres[m, 1, q]
            ring = r0 + rest // quarter
            h = rings[0, ring]
            weight = rings[1, ring] * h * step
            angle = step * (rest % quarter)
            circle = (cx, cy, h, cos_phi, sin_phi)
            s_x, s_y = _arc_orbit(cm, lattice, circle, math.cos(angle), math.sin(angle), p)
            s_x *= weight
            s_y *= weight
            a = cos_phi * s_x - sin_phi * s_y
            c = sin_phi * s_x + cos_phi * s_y
            f_x += a
            f_y += c
            torque += (cx - x_k) * c - (cy - y_k) * a
    cuda.syncthreads()
    red[tid] = f_x
    red[n_threads + tid] = f_y
    red[2 * n_threads + tid] = torque
    reduce_sums(red, 3, tid, n_threads)
