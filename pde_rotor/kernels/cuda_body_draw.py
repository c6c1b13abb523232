"""Drawing a body on the GPU: F_k, G_k and its owner on its footprint's cells (the
CPU's :func:`pde_rotor.kernels.body_draw.draw_body`, split among a block's threads), for the
kernel of :mod:`pde_rotor.kernels.cuda_bodies`.

The footprint's rows are checked first (a cell outside the dish, a cell another body
owns: the first such row decides, found by a min tree over the threads), then each cell
takes the plate's value (``body_plate_cell``, or for ``consistent`` ``filtered_plate``,
``filtered_pill_term``, ``filtered_strip``) and the pills' terms (``pill_term``,
``filtered_pill_term``) on the cells the CPU gives them. The physics is
:mod:`pde_rotor.physics.indicators`, compiled as CUDA device functions
(:data:`pde_rotor.kernels.cuda.GPU`).
"""

from __future__ import annotations

import math

from ..physics.indicators import (
    PLATE_DISK,
    PLATE_NONE,
    PLATE_POLYGON,
    PLATE_STRIP,
    PolygonFilter,
)
from .body_draw import STATUS_EDGE
from .cuda import GPU
from .cuda_target import cuda, device_function

_pill_term = GPU.indicators.pill_term
_pill_reach = GPU.indicators.pill_reach
_footprint_chord = GPU.indicators.footprint_chord
_filtered_pill_term = GPU.indicators.filtered_pill_term
_filtered_pill_reach = GPU.indicators.filtered_pill_reach
_filtered_plate = GPU.indicators.filtered_plate
_body_plate_cell = GPU.indicators.body_plate_cell
_filtered_strip = GPU.indicators.filtered_strip


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
        polygon = PolygonFilter(
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
        return _filtered_plate(rx, ry, tab, polygon)
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
    drawing gives them (:func:`pde_rotor.kernels.body_draw.draw_body`)."""
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
def _row_code(i, k, m, state, surface, bodies):
    """0 if body k may own the cells of its footprint's chord on row i, else why not, as
    the CPU's drawing says it: ``STATUS_EDGE`` (a cell outside the dish), or ``-1 - j``
    (the first cell owned by body j); a body that spans its channel may own cells beyond
    the vessel's walls, anywhere inside the grid's outermost ring of cells."""
    owner = state[3]
    coords, interior = surface
    body, _, pose, _, box = bodies
    n = coords.size
    x_k, y_k = pose[m, k, 0], pose[m, k, 1]
    ja, jb = _footprint_chord(
        coords, box[m, k, 2], box[m, k, 3], coords[i] - x_k, y_k, body[m][k].reach
    )
    if ja >= jb:
        return 0
    spans = body[m][k].spans != 0
    first, last = (1, n - 1) if spans else (interior[0, i], interior[1, i])
    if ja < first or (spans and (i == 0 or i == n - 1)):
        return STATUS_EDGE
    for j in range(ja, max(ja, min(jb, last))):
        who = owner[m, i * n + j]
        if who >= 0 and who != k:
            return -1 - who
    if jb > last:
        return STATUS_EDGE
    return 0


@device_function
def box_size(box, m, k):
    """The number of cells of body k's box (member m; rows box[0]:box[1], columns
    box[2]:box[3]), which the threads of a block share as q = tid, tid + n_threads, ..."""
    return (box[m, k, 1] - box[m, k, 0]) * (box[m, k, 3] - box[m, k, 2])


@device_function
def box_cell(box, m, k, q, n):
    """(i, j, i n + j): cell q of body k's box in row-major order (q < :func:`box_size`)."""
    j0 = box[m, k, 2]
    width = box[m, k, 3] - j0
    i = box[m, k, 0] + q // width
    j = j0 + q % width
    return i, j, i * n + j


@device_function
def draw_body(k, m, moved, state, surface, bodies, scratch, tables, p, red):
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
        for q in range(tid, box_size(box, m, k), n_threads):
            _, _, o = box_cell(box, m, k, q, n)
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
