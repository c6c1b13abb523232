"""The CUDA kernel of K camphor bodies on one surface: E members in one launch, block m
advancing member m (the loop of :func:`pde_rotor.kernels.bodies.advance_bodies` on the
GPU, with Heun's method besides forward Euler).

The physics is the core's and the body core's (:mod:`pde_rotor.kernels.core`,
:mod:`pde_rotor.kernels.body_core`), compiled here as CUDA device functions; this module
only maps cells, bodies and sums to the threads of a block. Each evaluation of the
right-hand side (:func:`_stage`: once per Euler step, twice per Heun step):

1. every body whose pose changed since it was drawn is redrawn, one body after the
   other in their order (:func:`_draw`): its old footprint cleared, then, split among
   the threads, the footprint's cells checked (a cell outside the dish ends the run,
   as does a cell another body owns; the first such row decides, as on the CPU) and
   F_k, G_k and the owner written per cell (``body_plate_cell``, or for ``consistent``
   ``filtered_plate``, ``filtered_pill_term``, ``filtered_strip``; the pills' terms
   ``pill_term``, ``filtered_pill_term``, on the cells the CPU gives them);
2. the integrals of each moving body (:func:`_area_sums`: the cells of its box it owns,
   area form with central differences; for ``consistent`` the tension force and torque
   in contour form, :func:`_contour_sums`: the spline of c on the body's window, then its
   edges' or circles' nodes, ``edge_sums``, ``arc_node``), each a fixed-order tree
   reduction in shared memory, and its accelerations (``body_accelerations``);
3. one Euler step of Eqs. (eqc), (eqv) from one buffer into another
   (:func:`_euler_fields`: ``plate_rates`` with the owner's plate velocity,
   ``owner_plate``; behind a no-flux dish wall ``cut_cell_inflow`` and ``local_rate``
   on the cut cells, then the implicit clusters, :func:`_walled_fields`).

A step then moves the bodies that are not held (fixed, or in a stop of their own
schedule, ``stopped_at``): forward Euler (``euler_rotor``), or Heun: the predictor's
Euler step of fields and bodies, the right-hand side again at the predicted poses and
fields into a stage buffer, the fields' trapezoid (:func:`_average`) and the bodies'
(``heun_rotor``, the forces recorded those of the step's start), as the CPU rotor's
:func:`pde_rotor.kernels.cpu.advance`. The noise kick (``noise_kick``) follows, once
per step, for the bodies not held, from K standard normals per step drawn on the host.

A run that ends early (a body at the dish's edge or at another body, non-finite
accelerations) leaves the member at the start of that step and writes the step, the
reason (:data:`pde_rotor.kernels.bodies.STATUS_EDGE` ...) and the bodies to its status
row, as :func:`~pde_rotor.kernels.bodies.advance_bodies` returns them.

All arithmetic is fp64; sums are taken in a fixed order, so a result does not depend
on the launch (for a given number of threads per block). The kernel compiles on its
first launch (:func:`bodies_kernel`); with ``NUMBA_ENABLE_CUDASIM=1`` it runs in numba's
CUDA simulator on the CPU.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ..model.body_schemes import ARC_EDGES
from .bodies import STATUS_EDGE, STATUS_FINITE, STATUS_OVERLAP
from .body_core import (
    MOTION_FIXED,
    MOTION_FREE,
    PLATE_DISK,
    PLATE_NONE,
    PLATE_POLYGON,
    PLATE_STRIP,
    BodyCore,
    make_body_core,
)
from .cuda import GPU
from .cuda_target import cuda, device_function, float64, int64, kernel

GPU_BODIES: BodyCore = make_body_core(device_function, GPU)
"""The body core (:mod:`pde_rotor.kernels.body_core`) compiled as CUDA device functions."""

N_SUMS = 10
"""Integrals of a body per evaluation (those of :func:`pde_rotor.kernels.bodies.body_integrals`)."""

_plate_rates = GPU.plate_rates
_rate_coefficients = GPU.rate_coefficients
_cut_cell_inflow = GPU.cut_cell_inflow
_local_rate = GPU.local_rate
_stopped_at = GPU.stopped_at
_euler_rotor = GPU.euler_rotor
_heun_rotor = GPU.heun_rotor
_noise_kick = GPU.noise_kick
_pill_term = GPU.pill_term
_pill_reach = GPU.pill_reach
_filtered_pill_term = GPU.filtered_pill_term
_filtered_pill_reach = GPU.filtered_pill_reach
_filtered_plate = GPU.filtered_plate
_spline_line = GPU.spline_line
_owner_plate = GPU_BODIES.owner_plate
_body_plate_cell = GPU_BODIES.body_plate_cell
_filtered_strip = GPU_BODIES.filtered_strip
_body_accelerations = GPU_BODIES.body_accelerations
_edge_sums = GPU_BODIES.edge_sums
_arc_node = GPU_BODIES.arc_node


@device_function
def _reduce(red, count, tid, n_threads):
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
def _orient(m, k, bodies, scratch):
    """Body k's edge normals (a polygon's, Eq. (ejt0) turned by phi) or x axis (strip)
    into normals[m, k], its pills' lab-frame centres into centres[m] (one thread)."""
    body, pills, pose, _, _ = bodies
    normals, centres = scratch[0], scratch[1]
    b = body[m][k]
    phi = pose[m, k, 2]
    if b.plate == PLATE_POLYGON:
        for j in range(b.n_corners):
            angle = phi + 2.0 * math.pi * (j + 0.5) / b.n_corners
            normals[m, k, 0, j] = math.cos(angle)
            normals[m, k, 1, j] = math.sin(angle)
    else:
        normals[m, k, 0, 0] = math.cos(phi)
        normals[m, k, 1, 0] = math.sin(phi)
    for j in range(b.pill_start, b.pill_start + b.pill_count):
        angle = phi + pills[m, j, 5] + pills[m, j, 6]
        centres[m, 0, j] = pose[m, k, 0] + pills[m, j, 4] * math.cos(angle)
        centres[m, 1, j] = pose[m, k, 1] + pills[m, j, 4] * math.sin(angle)


@device_function
def _plate_value(rx, ry, b, tab, tables, p):
    """F_k of the body record `b` at r = X_k + (rx, ry) without its pills: the point value
    (``paper``) or the filtered plate (``consistent``); 0 for a body without a plate."""
    _, _, profiles, _, corner, edges, _ = tables
    if not p.filtered:
        return _body_plate_cell(
            rx, ry, b.plate, tab, b.n_corners, b.size_a, b.size_b, 1.0 / p.smoothing
        )
    if b.plate == PLATE_POLYGON:
        return _filtered_plate(
            rx,
            ry,
            tab,
            b.n_corners,
            b.size_a,
            b.tan_half,
            b.crease,
            b.corner_end,
            edges[b.edge_start : b.edge_start + b.edge_count],
            b.edge_u0,
            p.edge_inv_step,
            corner[b.table_start : b.table_start + b.table_n * b.table_m],
            b.table_n,
            b.table_x0,
            p.table_inv_step,
        )
    if b.plate == PLATE_DISK:
        return _filtered_pill_term(
            rx, ry, profiles[b.f_start : b.f_start + b.f_count], p.profile_inv_step
        )
    if b.plate == PLATE_STRIP:
        return _filtered_strip(
            rx,
            ry,
            tab[0, 0],
            tab[1, 0],
            corner[b.table_start : b.table_start + b.table_n * b.table_m],
            b.table_n,
            b.table_m,
            b.table_x0,
            p.table_inv_step,
        )
    return 0.0


@device_function
def _pill_values(i, j, m, b, pills, centres, tables, p, coords):
    """The pills' terms of body record `b` at the cell (i, j): (their F,
    for a body without a plate, and G), added in the pills' order on the cells the CPU's
    drawing gives them (:func:`pde_rotor.kernels.bodies.draw_body`)."""
    _, _, profiles, pill_tab, _, _, _ = tables
    x, y = coords[i], coords[j]
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    no_plate = b.plate == PLATE_NONE
    inv_delta = 1.0 / p.smoothing
    inv_step = p.profile_inv_step
    f = 0.0
    g = 0.0
    for q in range(b.pill_start, b.pill_start + b.pill_count):
        px, py, rho, weight = centres[m, 0, q], centres[m, 1, q], pills[m, q, 2], pills[m, q, 3]
        g_prof = profiles[pill_tab[q, 0] : pill_tab[q, 0] + pill_tab[q, 1]]
        f_prof = profiles[pill_tab[q, 2] : pill_tab[q, 2] + pill_tab[q, 3]]
        if p.filtered:
            reach = _filtered_pill_reach(g_prof, inv_step)
            if no_plate:
                reach = max(reach, _filtered_pill_reach(f_prof, inv_step))
        else:
            reach = _pill_reach(rho, inv_delta)
        if math.ceil((px - reach - x0) * inv_dx) > i or math.floor((px + reach - x0) * inv_dx) < i:
            continue
        dx_p = x - px
        half = reach
        if p.filtered:
            if abs(dx_p) >= reach:
                continue
            half = math.sqrt(reach * reach - dx_p * dx_p) + 1.0 / inv_dx
        if math.ceil((py - half - x0) * inv_dx) > j or math.floor((py + half - x0) * inv_dx) < j:
            continue
        if p.filtered:
            g += weight * _filtered_pill_term(dx_p, y - py, g_prof, inv_step)
            if no_plate:
                f += _filtered_pill_term(dx_p, y - py, f_prof, inv_step)
        else:
            term = _pill_term(dx_p, y - py, rho, inv_delta)
            g += weight * term
            if no_plate:
                f += term
    return f, g


@device_function
def _chord(coords, j0, j1, rx, y_k, reach):
    """[ja, jb): the columns of [j0, j1) within the footprint |r - X_k| < reach on a row
    rx from X_k (scanned in from both ends, as the CPU's drawing)."""
    limit = reach * reach
    ja = j0
    while ja < j1:
        ry = coords[ja] - y_k
        if rx * rx + ry * ry < limit:
            break
        ja += 1
    jb = j1
    while jb > ja:
        ry = coords[jb - 1] - y_k
        if rx * rx + ry * ry < limit:
            break
        jb -= 1
    return ja, jb


@device_function
def _row_code(i, k, m, state, surface, bodies):
    """0 if body k may own the cells of its footprint's chord on row i, else why not, as
    the CPU's drawing says it: ``STATUS_EDGE`` (a cell outside the dish), or ``-1 - j``
    (the first cell owned by body j)."""
    owner = state[3]
    coords, interior = surface
    body, _, pose, _, box = bodies
    n = coords.size
    x_k, y_k = pose[m, k, 0], pose[m, k, 1]
    ja, jb = _chord(coords, box[m, k, 2], box[m, k, 3], coords[i] - x_k, y_k, body[m][k].reach)
    if ja >= jb:
        return 0
    if ja < interior[0, i]:
        return STATUS_EDGE
    for j in range(ja, max(ja, min(jb, interior[1, i]))):
        who = owner[m, i * n + j]
        if who >= 0 and who != k:
            return -1 - who
    if jb > interior[1, i]:
        return STATUS_EDGE
    return 0


@device_function
def _draw(k, m, moved, state, surface, bodies, scratch, tables, p, red):
    """Draw body k of member m at its pose (all threads): F_k, G_k and owner k on the
    cells of its footprint, the old footprint cleared first where X_k `moved`.

    Returns:
        0, or the code of :func:`_row_code` for the first footprint row that fails.
    """
    _, F, G, owner = state
    coords, _ = surface
    body, pills, pose, _, box = bodies
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    if moved:
        i0, j0 = box[m, k, 0], box[m, k, 2]
        width = box[m, k, 3] - j0
        for q in range(tid, (box[m, k, 1] - i0) * width, n_threads):
            o = (i0 + q // width) * n + j0 + q % width
            if owner[m, o] == k:
                F[m, o] = 0.0
                G[m, o] = 0.0
                owner[m, o] = -1
    cuda.syncthreads()
    b = body[m][k]
    x_k, y_k, reach = pose[m, k, 0], pose[m, k, 1], b.reach
    if tid == 0:
        _orient(m, k, bodies, scratch)
        x0 = coords[0]
        inv_dx = 1.0 / (coords[1] - x0)
        # int(): numba-cuda types math.floor and math.ceil as float64
        box[m, k, 0] = max(0, int(math.ceil((x_k - reach - x0) * inv_dx)))  # noqa: RUF046
        box[m, k, 1] = min(n, int(math.floor((x_k + reach - x0) * inv_dx)) + 1)  # noqa: RUF046
        box[m, k, 2] = max(0, int(math.ceil((y_k - reach - x0) * inv_dx)))  # noqa: RUF046
        box[m, k, 3] = min(n, int(math.floor((y_k + reach - x0) * inv_dx)) + 1)  # noqa: RUF046
    cuda.syncthreads()
    i0, i1, j0, j1 = box[m, k, 0], box[m, k, 1], box[m, k, 2], box[m, k, 3]
    mine = n  # the first failing row of this thread's rows, then of all (a min tree)
    for i in range(i0 + tid, i1, n_threads):
        if _row_code(i, k, m, state, surface, bodies) != 0:
            mine = i
            break
    red[tid] = mine
    cuda.syncthreads()
    half = n_threads // 2
    while half > 0:
        if tid < half:
            red[tid] = min(red[tid], red[tid + half])
        cuda.syncthreads()
        half //= 2
    first = int(red[0])
    cuda.syncthreads()
    if first < n:
        return _row_code(first, k, m, state, surface, bodies)
    tab = scratch[0][m, k]
    centres = scratch[1]
    width = j1 - j0
    limit = reach * reach
    for q in range(tid, (i1 - i0) * width, n_threads):
        i = i0 + q // width
        j = j0 + q % width
        rx = coords[i] - x_k
        ry = coords[j] - y_k
        if rx * rx + ry * ry >= limit:
            continue
        o = i * n + j
        f_pills, g = _pill_values(i, j, m, b, pills, centres, tables, p, coords)
        owner[m, o] = k
        F[m, o] = _plate_value(rx, ry, b, tab, tables, p) + f_pills
        G[m, o] = g
    cuda.syncthreads()
    return 0


@device_function
def _area_sums(src, k, m, state, surface, bodies, red):
    """Body k's integrals over the cells of its box it owns, area form with central
    differences, into red[q n_threads] (q < :data:`N_SUMS`, not yet times dA; all
    threads; the sums of :func:`pde_rotor.kernels.bodies.body_integrals`)."""
    buf, F, _, owner = state
    coords, _ = surface
    _, _, pose, _, box = bodies
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    nn = n * n
    inv_2dx = 0.5 / (coords[1] - coords[0])
    x_k, y_k = pose[m, k, 0], pose[m, k, 1]
    i0, j0 = box[m, k, 0], box[m, k, 2]
    width = box[m, k, 3] - j0
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = s8 = s9 = 0.0
    for q in range(tid, (box[m, k, 1] - i0) * width, n_threads):
        i = i0 + q // width
        j = j0 + q % width
        o = i * n + j
        if owner[m, o] != k:
            continue
        f = F[m, o]
        if f == 0.0:
            continue
        rx = coords[i] - x_k
        ry = coords[j] - y_k
        c = src + o
        dcdx = (buf[c + n] - buf[c - n]) * inv_2dx
        dcdy = (buf[c + 1] - buf[c - 1]) * inv_2dx
        s0 += f * dcdx
        s1 += f * dcdy
        s2 += f * (rx * dcdy - ry * dcdx)
        s3 += f
        s4 += f * rx
        s5 += f * ry
        s6 += f * (rx * rx + ry * ry)
        vx = buf[c + nn]
        vy = buf[c + 2 * nn]
        s7 += f * (rx * vy - ry * vx)
        s8 += f * vx
        s9 += f * vy
    red[tid] = s0
    red[n_threads + tid] = s1
    red[2 * n_threads + tid] = s2
    red[3 * n_threads + tid] = s3
    red[4 * n_threads + tid] = s4
    red[5 * n_threads + tid] = s5
    red[6 * n_threads + tid] = s6
    red[7 * n_threads + tid] = s7
    red[8 * n_threads + tid] = s8
    red[9 * n_threads + tid] = s9
    _reduce(red, N_SUMS, tid, n_threads)


@device_function
def _contour_sums(src, k, m, state, surface, bodies, scratch, tables, p, red):
    """Body k's int F_k grad c dA (x, y) and int F_k (r - X_k) x grad c dA in contour form
    (``consistent``) into red[0], red[n_threads], red[2 n_threads] (all threads; the
    sums of :func:`pde_rotor.kernels.bodies.body_contour`)."""
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
    for q in range(tid, rows * cols, n_threads):
        o = (i0 + q // cols) * n + j0 + q % cols
        cm[o] = buf[src + o]
    cuda.syncthreads()
    for q in range(tid, rows, n_threads):
        _spline_line(cm, (i0 + q) * n + j0, 1, cols)
    cuda.syncthreads()
    for q in range(tid, cols, n_threads):
        _spline_line(cm, i0 * n + j0 + q, n, rows)
    cuda.syncthreads()
    n_s, n_t = quad_s.shape[1], quad_t.shape[1]
    delta = p.smoothing
    f_x = 0.0
    f_y = 0.0
    torque = 0.0
    if b.plate == PLATE_POLYGON:
        for q in range(tid, b.n_corners * n_s, n_threads):
            j = q // n_s
            ms = q % n_s
            ex, ey = normals[m, k, 0, j], normals[m, k, 1, j]
            h = b.size_a - delta * quad_s[0, ms]
            a, c, e = _edge_sums(
                cm, n, x0, inv_dx, x_k, y_k, ex, ey, h, h * b.tan_half, quad_s, quad_t, ms
            )
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
            a, c, e = _edge_sums(
                cm, n, x0, inv_dx, x_k, y_k, ex, ey, side + h, along + h, quad_s, quad_t, ms
            )
            f_x += a
            f_y += c
            torque += e
    else:  # a disk plate's circles about X_k, or each pill's about its centre
        n_arc = ARC_EDGES * n_t
        step = 2.0 * math.pi / n_arc
        first, last = b.pill_start, b.pill_start + b.pill_count
        if b.plate == PLATE_DISK:
            first, last = 0, 1
        total = 0
        for q in range(first, last):
            total += (b.ring_count if b.plate == PLATE_DISK else pill_tab[q, 5]) * n_arc
        for node in range(tid, total, n_threads):  # (circle, ring node, angle) in order
            rest = node
            q = first
            r0, r_count = b.ring_start, b.ring_count
            for each in range(first, last):
                q = each
                if b.plate != PLATE_DISK:
                    r0, r_count = pill_tab[each, 4], pill_tab[each, 5]
                if rest < r_count * n_arc:
                    break
                rest -= r_count * n_arc
            cx, cy = x_k, y_k
            if b.plate != PLATE_DISK:
                cx, cy = centres[m, 0, q], centres[m, 1, q]
            ring = r0 + rest // n_arc
            h = rings[0, ring]
            weight = rings[1, ring] * h * step
            angle = phi + step * (rest % n_arc)
            a, c = _arc_node(cm, n, x0, inv_dx, cx, cy, h, math.cos(angle), math.sin(angle), weight)
            f_x += a
            f_y += c
            torque += (cx - x_k) * c - (cy - y_k) * a
    cuda.syncthreads()
    red[tid] = f_x
    red[n_threads + tid] = f_y
    red[2 * n_threads + tid] = torque
    _reduce(red, 3, tid, n_threads)


@device_function
def _euler_fields(src, dst, m, state, surface, bodies, p):
    """One Euler step of Eqs. (eqc), (eqv) on the interior cells from buf[src:] into
    buf[dst:], the plate terms those of each cell's owner (all threads)."""
    buf, F, G, owner = state
    coords, interior = surface
    pose = bodies[2]
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    nn = n * n
    coef = _rate_coefficients(p)
    dt = p.dt
    flow = p.flow
    lanes = min(n_threads, 32)
    for i in range(tid // lanes, n, n_threads // lanes):
        x = coords[i]
        for j in range(interior[0, i] + tid % lanes, interior[1, i], lanes):
            o = i * n + j
            plate = owner[m, o] >= 0
            f, g, px, py = 0.0, 0.0, 0.0, 0.0
            if plate:
                f, g, px, py = _owner_plate(F[m], G[m], owner[m], pose[m], o, x, coords[j])
            rate_c, rate_x, rate_y = _plate_rates(
                buf, src + o, n, 1, nn, f, g, px, py, coef, flow, plate
            )
            buf[dst + o] = buf[src + o] + dt * rate_c
            if flow:
                buf[dst + o + nn] = buf[src + o + nn] + dt * rate_x
                buf[dst + o + 2 * nn] = buf[src + o + 2 * nn] + dt * rate_y
    cuda.syncthreads()


@device_function
def _walled_fields(src, dst, m, state, surface, bodies, wall, rhs, p):
    """One step of Eqs. (eqc), (eqv) behind the no-flux dish wall (all threads): the
    explicit part on the cut cells (``cut_cell_inflow``, ``local_rate``), v on the
    interior cells, then c' = inverse (kappa c') on each cluster of implicit faces
    (:func:`pde_rotor.kernels.wall.euler_walled_fields`)."""
    buf, F, G, owner = state
    coords, interior = surface
    pose = bodies[2]
    volume, pass_x, pass_y, open_x, open_y, wlo, whi, members, offsets, blocks, starts = wall
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    nn = n * n
    coef = _rate_coefficients(p)
    dt = p.dt
    flow = p.flow
    lanes = min(n_threads, 32)
    rm = rhs[m]
    for i in range(tid // lanes, n, n_threads // lanes):
        x = coords[i]
        for j in range(wlo[i] + tid % lanes, whi[i], lanes):
            o = i * n + j
            plate = owner[m, o] >= 0
            f, g, px, py = 0.0, 0.0, 0.0, 0.0
            if plate:
                f, g, px, py = _owner_plate(F[m], G[m], owner[m], pose[m], o, x, coords[j])
            cc = buf[src + o]
            kappa = volume[o]
            q = _cut_cell_inflow(buf[src:], o, n, 1, nn, open_x, open_y, pass_x, pass_y, coef, flow)
            r = kappa * cc + dt * (q + kappa * _local_rate(cc, f, g, coef, plate))
            rm[o] = r
            buf[dst + o] = r / kappa
            if flow and interior[0, i] <= j and j < interior[1, i]:
                _, rate_x, rate_y = _plate_rates(
                    buf, src + o, n, 1, nn, f, g, px, py, coef, flow, plate
                )
                buf[dst + o + nn] = buf[src + o + nn] + dt * rate_x
                buf[dst + o + 2 * nn] = buf[src + o + 2 * nn] + dt * rate_y
    cuda.syncthreads()
    for c in range(tid, offsets.size - 1, n_threads):
        first = offsets[c]
        size = offsets[c + 1] - first
        block = starts[c]
        for u in range(size):
            total = 0.0
            row = block + u * size
            for w in range(size):
                total += blocks[row + w] * rm[members[first + w]]
            buf[dst + members[first + u]] = total
    cuda.syncthreads()


@device_function
def _average(cur, stage, dst, buf, surface, wall, p):
    """buf[dst:] = (buf[cur:] + buf[stage:]) / 2 on the cells the step writes (Heun's
    trapezoid, :func:`pde_rotor.kernels.cpu.heun_average`; all threads)."""
    coords, interior = surface
    wlo, whi = wall[5], wall[6]
    walled = wlo.size > 0
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    nn = n * n
    for i in range(tid, n, n_threads):
        lo_c = wlo[i] if walled else interior[0, i]
        hi_c = whi[i] if walled else interior[1, i]
        for j in range(lo_c, hi_c):
            o = i * n + j
            buf[dst + o] = 0.5 * (buf[cur + o] + buf[stage + o])
        if p.flow:
            for j in range(interior[0, i], interior[1, i]):
                for ch in range(1, 3):
                    o = ch * nn + i * n + j
                    buf[dst + o] = 0.5 * (buf[cur + o] + buf[stage + o])
    cuda.syncthreads()


@device_function
def _stage(where, state, surface, bodies, scratch, tables, walls, p, shared):
    """One evaluation of the right-hand side of member m at the bodies' poses and the
    fields in buf[src:], `where` = (src, dst, stage, m) (all threads): the bodies
    redrawn, the integrals and accelerations of the moving ones into accel[m, k, stage]
    (at `stage` 0 their forces also into the pose's columns 6..11), and the fields'
    Euler step into buf[dst:].

    Returns:
        0, or the reason the run ends (``STATUS_*``), the bodies in flags[2], flags[3].
    """
    body, _, pose, drawn, _ = bodies
    accel = scratch[2]
    wall, rhs = walls
    red, flags, ints = shared
    src, dst, stage, m = where
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n_bodies = body.shape[1]
    for k in range(n_bodies):
        cuda.syncthreads()
        moved = pose[m, k, 0] != drawn[m, k, 0] or pose[m, k, 1] != drawn[m, k, 1]
        if moved or pose[m, k, 2] != drawn[m, k, 2]:
            code = _draw(k, m, moved, state, surface, bodies, scratch, tables, p, red)
            if code != 0:
                if tid == 0:
                    flags[2] = k
                    flags[3] = -1 - code if code < 0 else -1
                cuda.syncthreads()
                return STATUS_EDGE if code > 0 else STATUS_OVERLAP
            if tid == 0:
                drawn[m, k, 0], drawn[m, k, 1], drawn[m, k, 2] = (
                    pose[m, k, 0],
                    pose[m, k, 1],
                    pose[m, k, 2],
                )
    cuda.syncthreads()
    coords = surface[0]
    dx = coords[1] - coords[0]
    area = dx * dx
    sign_k = p.torque_sign * p.tension_slope
    for k in range(n_bodies):
        b = body[m][k]
        if b.motion == MOTION_FIXED:
            continue
        _area_sums(src, k, m, state, surface, bodies, red)
        if tid == 0:
            for q in range(N_SUMS):
                ints[q] = red[q * n_threads] * area
        cuda.syncthreads()
        if p.contour:
            _contour_sums(src, k, m, state, surface, bodies, scratch, tables, p, red)
            if tid == 0:
                ints[0] = red[0]
                ints[1] = red[n_threads]
                ints[2] = red[2 * n_threads]
        cuda.syncthreads()
        if tid == 0:
            out = _body_accelerations(
                ints, pose[m, k, 3], pose[m, k, 4], pose[m, k, 5], sign_k, b.friction, b.mass,
                b.inertia,
            )  # fmt: skip
            if stage == 0:
                pose[m, k, 6], pose[m, k, 7], pose[m, k, 8] = out[0], out[1], out[2]
                pose[m, k, 9], pose[m, k, 10], pose[m, k, 11] = out[3], out[4], out[5]
            accel[m, k, stage, 0], accel[m, k, stage, 1] = out[6], out[7]
            accel[m, k, stage, 2] = out[8]
            if not (math.isfinite(out[6]) and math.isfinite(out[7]) and math.isfinite(out[8])):
                flags[1] = STATUS_FINITE
                flags[2] = k
                flags[3] = -1
        cuda.syncthreads()
        if flags[1] != 0:
            return STATUS_FINITE
    if wall[0].size > 0:
        _walled_fields(src, dst, m, state, surface, bodies, wall, rhs, p)
    else:
        _euler_fields(src, dst, m, state, surface, bodies, p)
    return 0


@device_function
def _hold(step, m, bodies, scratch):
    """Which bodies are held this step (fixed, or in a stop of their own schedule): the
    pose's column 12, their velocities 0; each body's pose and velocities at the step's
    start into start[m] (one thread)."""
    body, _, pose, _, _ = bodies
    start = scratch[3]
    for k in range(body.shape[1]):
        b = body[m][k]
        held = b.motion == MOTION_FIXED or _stopped_at(
            step, b.n_ini, b.n_stop, b.n_period, b.cycles
        )
        pose[m, k, 12] = 1.0 if held else 0.0
        if held:
            pose[m, k, 3] = 0.0
            pose[m, k, 4] = 0.0
            pose[m, k, 5] = 0.0
        for q in range(6):
            start[m, k, q] = pose[m, k, q]


@device_function
def _move(m, phase, bodies, scratch, dt):
    """Move the bodies that are not held (one thread): `phase` 0, forward Euler from the
    start with the start's accelerations (Euler's step and Heun's predictor); 1, Heun's
    corrector from the start with the start's and the predicted rates (the predicted
    velocities in the pose, the accelerations at the predicted point in accel[m, k, 1])."""
    body, _, pose, _, _ = bodies
    accel, start = scratch[2], scratch[3]
    for k in range(body.shape[1]):
        if pose[m, k, 12] != 0.0:
            continue
        free = body[m][k].motion == MOTION_FREE
        for axis in range(3):  # x with u, y with v, phi with omega
            if axis < 2 and not free:
                continue
            x, u, a = start[m, k, axis], start[m, k, 3 + axis], accel[m, k, 0, axis]
            if phase == 0:
                x, u = _euler_rotor(x, u, a, dt)
            else:
                x, u = _heun_rotor(x, u, a, pose[m, k, 3 + axis], accel[m, k, 1, axis], dt)
            pose[m, k, axis] = x
            pose[m, k, 3 + axis] = u


def _advance_bodies(state, surface, body, arrays, scratch, tables, walls, params, run, steps):
    """Advance every member by `n_steps` steps, Euler or Heun; block m advances member m.

    Args:
        state: (buf, F, G, owner): buf three state buffers (3, E, 3, n, n) of
            (c, v_x, v_y), flattened (two alternate, the third is Heun's stage), buffer
            `parity0` holding the state at step0, the result in buffer
            (parity0 + n_steps) % 2; F, G (E, n^2) and owner (E, n^2) the indicators
            and owner map (-1: none), kept between launches.
        surface: (coords, interior): (n,) cell centres of the dish frame and (2, n) the
            columns [lo, hi) of the interior cells per row.
        body: (E, K) the bodies' records (``BODY``; an argument of its own, so that numba's
            CUDA simulator reads its fields by name).
        arrays: (pills (E, P, 7), pose (E, K, 13) updated, drawn (E, K, 3) and box
            (E, K, 4) of the last drawing, kept between launches), as for
            :func:`pde_rotor.kernels.bodies.advance_bodies`.
        scratch: (normals (E, K, 2, C), centres (E, 2, P), accel (E, K, 2, 3), start
            (E, K, 6), spline coefficients (E, n^2)).
        tables: the bodies' scheme tables (quad_s, quad_t, profiles, pill table, corner
            tables, edge profiles, rings; :func:`pde_rotor.kernels.records.make_body_tables`),
            shared by the members.
        walls: (wall, rhs): the cut cells of a no-flux wall
            (:meth:`pde_rotor.model.wall.CutCells.arrays`, empty for the absorbing wall),
            shared, and (E, n^2) scratch.
        params: (E,) parameter records (:func:`pde_rotor.kernels.records.make_record`).
        run: (xi, status): xi (E, n_steps K) standard normals, K per step (read where a
            body's kick != 0); status (E, 4) the step at which a member's run ended (-1:
            none), the reason (``STATUS_*``), the body and the other body (-1: none).
        steps: (step0, n_steps, parity0, heun): the first step's global index, the
            number of steps, the buffer holding the state at step0, 1 for Heun's method.
    """
    m = cuda.blockIdx.x
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    xi, status = run
    if status[m, 0] >= 0:
        return
    red = cuda.shared.array(0, float64)  # N_SUMS * n_threads partial sums
    flags = cuda.shared.array(4, int64)
    ints = cuda.shared.array(N_SUMS, float64)
    shared = (red, flags, ints)
    step0, n_steps, parity0, heun = steps
    p = params[m]
    buf = state[0]
    pose = arrays[1]
    bodies = (body, arrays[0], pose, arrays[2], arrays[3])
    n_bodies = body.shape[1]
    n_members = body.shape[0]
    n = surface[0].size
    nn = n * n
    size = 3 * nn
    if tid == 0:
        flags[1] = 0
    if not p.flow:  # v = 0 and stays 0
        for slot in range(3):
            base = (slot * n_members + m) * size
            for q in range(nn + tid, size, n_threads):
                buf[base + q] = 0.0
    cuda.syncthreads()
    for s in range(n_steps):
        step = step0 + s
        parity = (parity0 + s) % 2
        cur = (parity * n_members + m) * size
        nxt = ((1 - parity) * n_members + m) * size
        stg = (2 * n_members + m) * size
        if tid == 0:
            _hold(step, m, bodies, scratch)
        cuda.syncthreads()
        code = _stage((cur, nxt, 0, m), state, surface, bodies, scratch, tables, walls, p, shared)
        if code == 0 and heun:
            if tid == 0:
                _move(m, 0, bodies, scratch, p.dt)
            cuda.syncthreads()
            code = _stage(
                (nxt, stg, 1, m), state, surface, bodies, scratch, tables, walls, p, shared
            )
            if code == 0:
                _average(cur, stg, nxt, buf, surface, walls[0], p)
        if code != 0:  # the member ends: left at the start of this step
            if tid == 0:
                status[m, 0], status[m, 1] = step, code
                status[m, 2], status[m, 3] = flags[2], flags[3]
                for k in range(n_bodies):
                    for q in range(6):
                        pose[m, k, q] = scratch[3][m, k, q]
            for q in range(tid, size, n_threads):
                buf[nxt + q] = buf[cur + q]
            cuda.syncthreads()
            return
        if tid == 0:
            _move(m, 1 if heun else 0, bodies, scratch, p.dt)
            for k in range(n_bodies):
                b = body[m][k]
                if pose[m, k, 12] == 0.0 and b.kick != 0.0:
                    pose[m, k, 5] = _noise_kick(pose[m, k, 5], xi[m, s * n_bodies + k], b)
        cuda.syncthreads()


_KERNELS: dict[int, Callable] = {}


def bodies_kernel(threads_per_block: int) -> Callable:
    """The bodies' kernel for a block size (compiled on its first launch); launch it with
    E blocks and ``N_SUMS * threads_per_block * 8`` bytes of dynamic shared memory."""
    if threads_per_block not in _KERNELS:
        _KERNELS[threads_per_block] = kernel(_advance_bodies, (threads_per_block,))
    return _KERNELS[threads_per_block]
