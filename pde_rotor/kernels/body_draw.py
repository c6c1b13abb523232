"""Drawing a body on the grid: F_k, G_k and the owner map on the cells of its footprint.

:func:`draw_body` is step 2 of the bodies' loop (:func:`pde_rotor.kernels.bodies.advance_bodies`):
the plate's indicator F and the pills' source density G of one body at its pose, on the
chords of its footprint (the physics' ``footprint_chord``, which the field update of
:mod:`pde_rotor.kernels.body_fields` and the CUDA drawing read too), its cells marked as
its own in the owner map. The physics is :mod:`pde_rotor.physics`; this module only
walks the rows.
"""

from __future__ import annotations

import math

import numba as nb

from ..physics.build import CPU, FASTMATH
from ..physics.indicators import PLATE_DISK, PLATE_NONE, PLATE_POLYGON, PLATE_STRIP
from .indicators import CornerScratch, PolygonFilter, filtered_plate_row, plate_row

_body_plate_cell = CPU.indicators.body_plate_cell
_pill_term = CPU.indicators.pill_term
_pill_reach = CPU.indicators.pill_reach
_filtered_pill_term = CPU.indicators.filtered_pill_term
_filtered_pill_reach = CPU.indicators.filtered_pill_reach
_filtered_strip = CPU.indicators.filtered_strip
_footprint_chord = CPU.indicators.footprint_chord


STATUS_FINITE, STATUS_EDGE, STATUS_OVERLAP = 1, 2, 3
"""Why a run ended early (``status[0]``): non-finite state, a body at the dish's edge,
two bodies overlapping."""


@nb.njit(cache=True, nogil=True)
def _clear_body(F, G, owner, n, k, box):
    """Zero F and G on the cells body k owns in its last drawn box, and free them."""
    for i in range(box[k, 0], box[k, 1]):
        for j in range(box[k, 2], box[k, 3]):
            o = i * n + j
            if owner[o] == k:
                F[o] = 0.0
                G[o] = 0.0
                owner[o] = -1


@nb.njit(cache=True, nogil=True)
def orient(k, body, pills, pose, normals, centres):
    """Edge normals (polygon, lab frame, Eq. (ejt0) turned by phi) or the body's x axis
    (strip) into normals[:, :, k]; the pills' lab-frame centres into `centres`."""
    b = body[k]
    phi = pose[k, 2]
    if b.plate == PLATE_POLYGON:
        for j in range(b.n_corners):
            angle = phi + 2.0 * math.pi * (j + 0.5) / b.n_corners
            normals[0, j, k] = math.cos(angle)
            normals[1, j, k] = math.sin(angle)
    else:
        normals[0, 0, k] = math.cos(phi)
        normals[1, 0, k] = math.sin(phi)
    for j in range(b.pill_start, b.pill_start + b.pill_count):
        angle = phi + pills[j, 5] + pills[j, 6]
        centres[0, j] = pose[k, 0] + pills[j, 4] * math.cos(angle)
        centres[1, j] = pose[k, 1] + pills[j, 4] * math.sin(angle)


SCRATCH_ROWS = 5
"""Rows of the float scratch (SCRATCH_ROWS, n) of :func:`draw_body`."""


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def draw_body(F, G, owner, domain, k, bodies, p, work, moved):
    """Draw body k at its pose: F_k, G_k and owner k on the cells of its footprint.

    The footprint is the disk of radius ``body[k].reach`` about X_k, beyond which F_k and
    G_k are 0 to within 4.3e-18 (:data:`pde_rotor.config.X_SATURATION`). Row by row, on
    the row's chord of the footprint: the owner and the plate's F, the loop over the
    edges outside the loop over the cells (the rotor's row functions
    :func:`~pde_rotor.kernels.indicators.plate_row` and, for the ``consistent`` scheme,
    ``filtered_plate_row``, in the body's frame; a disk's or strip's ``body_plate_cell``,
    a disk's filtered profile ``filtered_pill_term``, a strip's quadrant table
    ``filtered_strip``), then each pill's term on the
    cells of its own bounding square (a pill's term is below 4.3e-18 beyond
    rho + X_SATURATION delta; a filtered term is 0 beyond its profile, so only the
    square's chord of that disk), in the pills' order, as the rotor's ``pill_row`` sums
    them; the terms of a body without a plate are its F too. G holds the pills' source
    densities relative to the record's ``source`` (1 for the paper's pills, so that G is
    the paper's indicator sum). `tables` as for
    :func:`~pde_rotor.kernels.bodies.advance_bodies` (read where the
    record `p`'s ``filtered`` is set); `bodies` is the bundle of
    :func:`pde_rotor.kernels.bodies.advance_bodies`; `work` is (scratch
    (:data:`SCRATCH_ROWS`, n), taps (n, unsigned)). The cells of the last drawn
    footprint are cleared first where X_k `moved` since (else the new footprint is the
    same cells, all redrawn).

    Returns:
        0, or ``STATUS_EDGE`` (a footprint cell outside the dish), or ``-1 - j`` when
        the footprint meets body j's (the first such cell in row-major order decides).
    """
    coords, lo, hi, _, _ = domain
    body, pills, pose, _, box, normals, centres, tables = bodies
    scratch, taps = work
    _, _, profiles, pill_tab, corner, edges, _, _, _ = tables
    n = coords.size
    if moved:
        _clear_body(F, G, owner, n, k, box)
    orient(k, body, pills, pose, normals, centres)
    b = body[k]
    filtered = p.filtered
    inv_delta = 1.0 / p.smoothing
    inv_step = p.profile_inv_step
    x_k, y_k, reach = pose[k, 0], pose[k, 1], b.reach
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    i0 = max(0, math.ceil((x_k - reach - x0) * inv_dx))
    i1 = min(n, math.floor((x_k + reach - x0) * inv_dx) + 1)
    j0 = max(0, math.ceil((y_k - reach - x0) * inv_dx))
    j1 = min(n, math.floor((y_k + reach - x0) * inv_dx) + 1)
    box[k, 0], box[k, 1], box[k, 2], box[k, 3] = i0, i1, j0, j1
    tab = normals[:, :, k]
    no_plate = b.plate == PLATE_NONE
    disk = profiles[b.f_start : b.f_start + b.f_count]
    plate = corner[b.table_start : b.table_start + b.table_n * b.table_m]
    edge = edges[b.edge_start : b.edge_start + b.edge_count]
    for i in range(i0, i1):
        x = coords[i]
        rx = x - x_k
        ja, jb = _footprint_chord(coords, j0, j1, rx, y_k, reach)
        if ja >= jb:
            continue
        if ja < lo[i]:
            return STATUS_EDGE
        base = i * n
        row_o = owner[base + ja : base + max(ja, min(jb, hi[i]))]
        other = False
        for j in range(row_o.size):  # branch-free, several cells at a time
            other |= (row_o[j] >= 0) & (row_o[j] != k)
        if other:
            for j in range(row_o.size):
                if row_o[j] >= 0 and row_o[j] != k:
                    return -1 - row_o[j]
        if jb > hi[i]:
            return STATUS_EDGE
        row_o = owner[base + ja : base + jb]
        row_f = F[base + ja : base + jb]
        row_g = G[base + ja : base + jb]
        row_x = coords[ja:jb]
        row_y = scratch[0, ja:jb]
        for j in range(row_y.size):
            row_o[j] = k
            row_g[j] = 0.0
            row_y[j] = row_x[j] - y_k
        if filtered and b.plate == PLATE_POLYGON:
            polygon = PolygonFilter(
                b.n_corners, b.size_a, b.tan_half, b.crease, b.corner_end, edge, b.edge_u0,
                p.edge_inv_step, plate, b.table_n, b.table_x0, p.table_inv_step,
            )  # fmt: skip
            rows = CornerScratch(
                scratch[1, ja:jb], scratch[2, ja:jb], scratch[3, ja:jb], scratch[4, ja:jb],
                taps[ja:jb],
            )  # fmt: skip
            filtered_plate_row(row_f, rx, row_y, tab, polygon, rows)
        elif filtered and b.plate == PLATE_DISK:
            for j in range(row_y.size):
                row_f[j] = _filtered_pill_term(rx, row_y[j], disk, inv_step)
        elif filtered and b.plate == PLATE_STRIP:
            ex, ey = tab[0, 0], tab[1, 0]
            for j in range(row_y.size):
                row_f[j] = _filtered_strip(
                    rx, row_y[j], ex, ey, plate, b.table_n, b.table_m, b.table_x0,
                    p.table_inv_step,
                )  # fmt: skip
        elif filtered or no_plate:
            for j in range(row_y.size):
                row_f[j] = 0.0
        elif b.plate == PLATE_POLYGON:
            plate_row(row_f, rx, row_y, tab, b.n_corners, b.size_a, inv_delta, scratch[1, ja:jb])
        else:
            for j in range(row_y.size):
                row_f[j] = _body_plate_cell(
                    rx, row_y[j], b.plate, tab, b.n_corners, b.size_a, b.size_b, inv_delta
                )
        for m in range(b.pill_start, b.pill_start + b.pill_count):
            px, py, rho, weight = centres[0, m], centres[1, m], pills[m, 2], pills[m, 3]
            g_prof = profiles[pill_tab[m, 0] : pill_tab[m, 0] + pill_tab[m, 1]]
            f_prof = profiles[pill_tab[m, 2] : pill_tab[m, 2] + pill_tab[m, 3]]
            if filtered:
                pill_reach = _filtered_pill_reach(g_prof, inv_step)
                if no_plate:
                    pill_reach = max(pill_reach, _filtered_pill_reach(f_prof, inv_step))
            else:
                pill_reach = _pill_reach(rho, inv_delta)
            if math.ceil((px - pill_reach - x0) * inv_dx) > i:
                continue
            if math.floor((px + pill_reach - x0) * inv_dx) < i:
                continue
            dx_p = x - px
            half = pill_reach
            if filtered:  # the terms are 0 off the disk: its chord, a cell more each side
                if abs(dx_p) >= pill_reach:
                    continue
                half = math.sqrt(pill_reach * pill_reach - dx_p * dx_p) + 1.0 / inv_dx
            ca = max(ja, math.ceil((py - half - x0) * inv_dx))
            cb = max(ca, min(jb, math.floor((py + half - x0) * inv_dx) + 1))
            cell_y = coords[ca:cb]
            cell_g = G[base + ca : base + cb]
            cell_f = F[base + ca : base + cb]
            if filtered:
                for j in range(cell_y.size):
                    cell_g[j] += weight * _filtered_pill_term(
                        dx_p, cell_y[j] - py, g_prof, inv_step
                    )
                if no_plate:
                    for j in range(cell_y.size):
                        cell_f[j] += _filtered_pill_term(dx_p, cell_y[j] - py, f_prof, inv_step)
            elif no_plate:
                for j in range(cell_y.size):
                    term = _pill_term(dx_p, cell_y[j] - py, rho, inv_delta)
                    cell_g[j] += weight * term
                    cell_f[j] += term
            else:
                for j in range(cell_y.size):
                    cell_g[j] += weight * _pill_term(dx_p, cell_y[j] - py, rho, inv_delta)
    return 0
