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
import numpy as np

from ..physics.build import CPU, FASTMATH
from ..physics.indicators import PLATE_DISK, PLATE_NONE, PLATE_POLYGON, PLATE_STRIP
from .indicators import (
    CornerScratch,
    PolygonFilter,
    StripRows,
    filtered_plate_row,
    filtered_strip_row,
    plate_row,
)

_body_plate_cell = CPU.indicators.body_plate_cell
_pill_term = CPU.indicators.pill_term
_pill_reach = CPU.indicators.pill_reach
_filtered_pill_term = CPU.indicators.filtered_pill_term
_profile_place = CPU.indicators.profile_place
_profile_value = CPU.indicators.profile_value
_filtered_pill_reach = CPU.indicators.filtered_pill_reach
_footprint_chord = CPU.indicators.footprint_chord


STATUS_FINITE, STATUS_EDGE, STATUS_OVERLAP = 1, 2, 3
"""Why a run ended early (``status[0]``): non-finite state, a body at the dish's edge,
two bodies overlapping."""


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


SCRATCH_ROWS = 9
"""Rows of the float scratch (SCRATCH_ROWS, n) of :func:`draw_body`."""


@nb.njit(cache=True, nogil=True)
def footprint_rows(coords, k, bodies, chords):
    """chords[:, k, i] = [ja, jb), the chord of body k's footprint on each row i of its
    last drawn box, at the pose it was drawn at (the physics' ``footprint_chord``): the
    cells its drawing owns (compiled). `bodies` as for
    :func:`pde_rotor.kernels.bodies.advance_bodies`; a body never drawn has no rows."""
    body, _, _, drawn, box, _, _, _ = bodies
    x_k, y_k, reach = drawn[k, 0], drawn[k, 1], body[k].reach
    for i in range(box[k, 0], box[k, 1]):
        ja, jb = _footprint_chord(coords, box[k, 2], box[k, 3], coords[i] - x_k, y_k, reach)
        chords[0, k, i], chords[1, k, i] = ja, jb


@nb.njit(cache=True, nogil=True)
def _claim(owner, domain, k, new_box, frame, fresh):
    """The chords of body k's footprint on the rows of `new_box` into `fresh` (2, n),
    and whether it may own them: 0, ``STATUS_EDGE`` (a cell outside the dish), or
    ``-1 - j`` (the first cell, in row-major order, that body j owns); `frame` is
    (X_x, X_y, reach, spans): a body that spans its channel may own cells beyond the
    vessel's walls, anywhere inside the grid's outermost ring of cells. Nothing is
    written but `fresh`."""
    coords, lo, hi = domain[0], domain[1], domain[2]
    i0, i1, j0, j1 = new_box
    x_k, y_k, reach, spans = frame
    n = coords.size
    for i in range(i0, i1):
        ja, jb = _footprint_chord(coords, j0, j1, coords[i] - x_k, y_k, reach)
        fresh[0, i], fresh[1, i] = ja, jb
        if ja >= jb:
            continue
        first, last = (1, n - 1) if spans else (lo[i], hi[i])
        if ja < first or (spans and (i == 0 or i == n - 1)):
            return STATUS_EDGE
        end = max(ja, min(jb, last))
        other = False
        for j in range(ja, end):  # branch-free, several cells at a time
            who = owner[np.uint64(i * n + j)]
            other |= (who >= 0) & (who != k)
        if other:
            for j in range(ja, end):
                who = owner[np.uint64(i * n + j)]
                if who >= 0 and who != k:
                    return -1 - who
        if jb > last:
            return STATUS_EDGE
    return 0


@nb.njit(cache=True, nogil=True)
def _release(F, G, owner, n, k, old, new):
    """Free the cells of body k's last drawn footprint that its new one leaves: F = G = 0
    and owner -1 on each old chord's cells outside the new chord of its row; `old` and
    `new` are (box (4,), chords (2, n)) of the two drawings (a row outside a box has no
    chord)."""
    old_box, old_rows = old
    new_box, new_rows = new
    for i in range(old_box[0], old_box[1]):
        oa, ob = old_rows[0, i], old_rows[1, i]
        na, nb_ = ob, ob  # the new chord, clipped to the old (empty: the whole old chord)
        if new_box[0] <= i < new_box[1] and new_rows[0, i] < new_rows[1, i]:
            na, nb_ = max(oa, min(ob, new_rows[0, i])), max(oa, min(ob, new_rows[1, i]))
        for a, b in ((oa, na), (nb_, ob)):
            for j in range(a, b):
                o = np.uint64(i * n + j)
                if owner[o] == k:
                    F[o] = 0.0
                    G[o] = 0.0
                    owner[o] = -1


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def _pill_cells(grid, i, row, pill, reach):
    """[ca, cb): the cells of row i's chord that a pill's term covers (ca = cb: none):
    those of its bounding square, rho + X_SATURATION delta about its centre (scheme
    ``paper``, beyond which its term is below 4.3e-18), or of the chord of its filtered
    profile's disk, a cell more each side (``consistent``: the terms are 0 off the
    disk). `grid` = (coords, x0, 1 / dx), `row` = (offset, ja, jb, k), `pill` = (its
    centre x, y, rho, weight), `reach` = (its reach, whether filtered)."""
    _, x0, inv_dx = grid
    _, ja, jb, _ = row
    px, py = pill[0], pill[1]
    pill_reach, filtered = reach
    if math.ceil((px - pill_reach - x0) * inv_dx) > i:
        return jb, jb
    if math.floor((px + pill_reach - x0) * inv_dx) < i:
        return jb, jb
    dx_p = grid[0][i] - px
    half = pill_reach
    if filtered:
        if abs(dx_p) >= pill_reach:
            return jb, jb
        half = math.sqrt(pill_reach * pill_reach - dx_p * dx_p) + 1.0 / inv_dx
    ca = max(ja, math.ceil((py - half - x0) * inv_dx))
    return ca, max(ca, min(jb, math.floor((py + half - x0) * inv_dx) + 1))


@nb.njit(inline="always", cache=True, nogil=True)
def _unowned(maps, base, a, b, k):
    """Owner k and F = G = 0 on the cells [a, b) of the row at offset `base`; `maps` =
    (F, G, owner). Unsigned offsets into the whole arrays, not slices: numba knows
    them non-negative (LLVM vectorises) and counts no references per row."""
    F, G, owner = maps
    for j in range(a, b):
        o = np.uint64(base + j)
        owner[o] = k
        F[o] = 0.0
        G[o] = 0.0


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def _lone_pill_row(maps, row, pill, coords, inv_delta):
    """Row of a body without a plate and with one pill (scheme ``paper``): on the
    chord's cells the owner k, and on its pill's cells the pill's term (``pill_term``)
    in F and its weighted term in G, 0 on the others, each cell written once: what the
    general row writes (F and G zeroed, then the pill's terms added: 0 + t = t).

    Args:
        maps: (F, G, owner).
        row: (offset of the row, ja, ca, cb, jb, k): the chord [ja, jb) and the pill's
            cells [ca, cb) in it (ja <= ca <= cb, or ca >= jb: none), the body k.
        pill: (dx from the pill's centre, its y, rho, weight).
        coords: the cells' centres.
        inv_delta: 1 / delta.
    """
    F, G, owner = maps
    base, ja, ca, cb, jb, k = row
    dx_p, py, rho, weight = pill
    za = min(ca, jb)
    zb = max(za, cb)
    _unowned(maps, base, ja, za, k)
    for j in range(za, zb):
        o = np.uint64(base + j)
        term = _pill_term(dx_p, coords[np.uint64(j)] - py, rho, inv_delta)
        owner[o] = k
        G[o] = weight * term
        F[o] = term
    _unowned(maps, base, zb, jb, k)


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def _lone_filtered_row(maps, row, pill, coords, inv_step):
    """:func:`_lone_pill_row` of the scheme ``consistent``: the pill's filtered terms
    (``filtered_pill_term``) of its G profile, weighted, in G and of its F profile in F;
    `pill` = (dx from the pill's centre, its y, weight, G profile, F profile)."""
    F, G, owner = maps
    base, ja, ca, cb, jb, k = row
    dx_p, py, weight, g_prof, f_prof = pill
    za = min(ca, jb)
    zb = max(za, cb)
    _unowned(maps, base, ja, za, k)
    for j in range(za, zb):
        o = np.uint64(base + j)
        dy = coords[np.uint64(j)] - py
        owner[o] = k
        G[o] = weight * _filtered_pill_term(dx_p, dy, g_prof, inv_step)
        F[o] = _filtered_pill_term(dx_p, dy, f_prof, inv_step)
    _unowned(maps, base, zb, jb, k)


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def _filtered_pill_cells(cell_g, pill, cell_y, profile, inv_step, rest):
    """cell_g[j] += weight g_eps(|(dx, cell_y[j] - py)|), a pill's weighted filtered terms
    on a row's cells (``filtered_pill_term`` cell by cell, bit for bit), in two passes:
    where each cell reads the radial `profile` (``profile_place``: the distance's root,
    several cells at a time, SIMD), then, one cell at a time, the two nodes it reads
    (``profile_value``). `pill` = (dx from the pill's centre, its y, weight); `rest` =
    (fractions, nodes (unsigned)) is scratch, as long as the row."""
    dx_p, py, weight = pill
    frac, nodes = rest
    last = profile.size - 1
    skip = np.uint64(-1)
    for j in range(cell_y.size):
        node, frac[j], inside = _profile_place(dx_p, cell_y[j] - py, last, inv_step)
        nodes[j] = np.uint64(node) if inside else skip
    for j in range(cell_y.size):
        inside = nodes[j] != skip
        node = np.int64(nodes[j]) if inside else 0
        cell_g[j] += weight * _profile_value(profile, node, frac[j], inside)


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def draw_body(F, G, owner, domain, k, bodies, p, work, moved):
    """Draw body k at its pose: F_k, G_k and owner k on the cells of its footprint.

    The footprint is the disk of radius ``body[k].reach`` about X_k: plate and pills grown
    by w delta, w = ``numerics.footprint_widths`` (default
    :data:`pde_rotor.config.X_SATURATION`, where F_k and G_k are 0 to within 4.3e-18;
    beyond a cut one every dropped term is below e^(-2 w)). First its chord
    on each row (the physics' ``footprint_chord``) and whether the body may own it
    (:func:`_claim`: inside the dish, no other body's cell; nothing is written
    otherwise); then, where X_k `moved`, the cells of the last drawn footprint that the
    new one leaves are freed (:func:`_release`; else the new footprint is the same
    cells, all redrawn); then row by row, on the row's chord: the owner and the plate's
    F, the loop over the edges outside the loop over the cells (the rotor's row
    functions :func:`~pde_rotor.kernels.indicators.plate_row` and, for the
    ``consistent`` scheme, ``filtered_plate_row``, in the body's frame; a disk's or
    strip's ``body_plate_cell``, a disk's filtered profile ``filtered_pill_term``, a
    strip's quadrant table in two passes,
    :func:`~pde_rotor.kernels.indicators.filtered_strip_row`), then each pill's term
    on the cells of
    its own bounding square (a pill's term is below 4.3e-18 beyond rho + X_SATURATION
    delta; a filtered term is 0 beyond its profile, so only the square's chord of that
    disk; a plate's pills' filtered G in two passes, :func:`_filtered_pill_cells`), in
    the pills' order, as the rotor's ``pill_row`` sums them; the terms of a
    body without a plate are its F too (one pill alone: one pass,
    :func:`_lone_pill_row`, :func:`_lone_filtered_row`). G holds the pills' source
    densities relative to the record's ``source`` (1 for the paper's pills, so that G
    is the paper's indicator sum). `bodies` is the bundle of
    :func:`pde_rotor.kernels.bodies.advance_bodies` (its `tables` read where the record
    `p`'s ``filtered`` is set); `domain` is (coords, lo, hi); `work` is (scratch
    (:data:`SCRATCH_ROWS`, n), taps (n, unsigned), chords (2, K, n), fresh (2, n)
    ints): the chords of every body's last drawing (:func:`footprint_rows`), updated,
    and scratch.

    Returns:
        0, or ``STATUS_EDGE`` (a footprint cell outside the dish), or ``-1 - j`` when
        the footprint meets body j's (the first such cell in row-major order decides).
    """
    coords = domain[0]
    body, pills, pose, _, box, normals, centres, tables = bodies
    scratch, taps, chords, fresh = work
    _, _, profiles, pill_tab, corner, edges, _, _, _ = tables
    n = coords.size
    b = body[k]
    x_k, y_k, reach = pose[k, 0], pose[k, 1], b.reach
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    i0 = max(0, math.ceil((x_k - reach - x0) * inv_dx))
    i1 = min(n, math.floor((x_k + reach - x0) * inv_dx) + 1)
    j0 = max(0, math.ceil((y_k - reach - x0) * inv_dx))
    j1 = min(n, math.floor((y_k + reach - x0) * inv_dx) + 1)
    code = _claim(owner, domain, k, (i0, i1, j0, j1), (x_k, y_k, reach, b.spans != 0), fresh)
    if code != 0:
        return code
    if moved:
        old = (box[k], chords[:, k])
        _release(F, G, owner, n, k, old, ((i0, i1, j0, j1), fresh))
    box[k, 0], box[k, 1], box[k, 2], box[k, 3] = i0, i1, j0, j1
    for i in range(i0, i1):
        chords[0, k, i], chords[1, k, i] = fresh[0, i], fresh[1, i]
    orient(k, body, pills, pose, normals, centres)
    filtered = p.filtered
    inv_delta = 1.0 / p.smoothing
    inv_step = p.profile_inv_step
    tab = normals[:, :, k]
    no_plate = b.plate == PLATE_NONE
    lone = no_plate and b.pill_count == 1
    disk = profiles[b.f_start : b.f_start + b.f_count]
    plate = corner[b.table_start : b.table_start + b.table_n * b.table_m]
    edge = edges[b.edge_start : b.edge_start + b.edge_count]
    grid = (coords, x0, inv_dx)
    maps = (F, G, owner)
    # a lone pill's constants, once per drawing (an array made in the rows' loop costs
    # a reference count each time)
    lone_pill, lone_reach, g_lone, f_lone = (0.0, 0.0, 0.0, 0.0), 0.0, profiles[:0], profiles[:0]
    if lone:
        m = b.pill_start
        lone_pill = (centres[0, m], centres[1, m], pills[m, 2], pills[m, 3])
        g_lone = profiles[pill_tab[m, 0] : pill_tab[m, 0] + pill_tab[m, 1]]
        f_lone = profiles[pill_tab[m, 2] : pill_tab[m, 2] + pill_tab[m, 3]]
        lone_reach = _pill_reach(lone_pill[2], inv_delta)
        if filtered:
            lone_reach = max(
                _filtered_pill_reach(g_lone, inv_step), _filtered_pill_reach(f_lone, inv_step)
            )
    rest = (scratch[1], taps)  # the pills' scratch: the plate's rows are done with it
    for i in range(i0, i1):
        ja, jb = fresh[0, i], fresh[1, i]
        if ja >= jb:
            continue
        x = coords[i]
        base = i * n
        row = (base, ja, jb, k)
        if lone:  # one pass writes the whole row
            ca, cb = _pill_cells(grid, i, row, lone_pill, (lone_reach, filtered))
            dx_p = x - lone_pill[0]
            if filtered:
                pill_f = (dx_p, lone_pill[1], lone_pill[3], g_lone, f_lone)
                _lone_filtered_row(maps, (base, ja, ca, cb, jb, k), pill_f, coords, inv_step)
            else:
                pill_p = (dx_p, lone_pill[1], lone_pill[2], lone_pill[3])
                _lone_pill_row(maps, (base, ja, ca, cb, jb, k), pill_p, coords, inv_delta)
            continue
        rx = x - x_k
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
            strip = (plate, b.table_n, b.table_m, b.table_x0, p.table_inv_step)
            cells = StripRows(scratch[1:], taps[ja:jb])
            filtered_strip_row(row_f, rx, row_y, (tab[0, 0], tab[1, 0]), strip, cells)
        elif filtered or no_plate:
            for j in range(row_y.size):
                row_f[j] = 0.0
        elif b.plate == PLATE_POLYGON:
            plate_row(row_f, rx, row_y, tab, b.n_corners, b.size_a, inv_delta, scratch[1, ja:jb])
        elif b.plate == PLATE_STRIP:  # the kind a constant of each loop: SIMD
            for j in range(row_y.size):
                row_f[j] = _body_plate_cell(
                    rx, row_y[j], PLATE_STRIP, tab, b.n_corners, b.size_a, b.size_b, inv_delta
                )
        else:
            for j in range(row_y.size):
                row_f[j] = _body_plate_cell(
                    rx, row_y[j], PLATE_DISK, tab, b.n_corners, b.size_a, b.size_b, inv_delta
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
            ca, cb = _pill_cells(grid, i, row, (px, py, rho, weight), (pill_reach, filtered))
            dx_p = x - px
            cell_y = coords[ca:cb]
            cell_g = G[base + ca : base + cb]
            cell_f = F[base + ca : base + cb]
            if filtered:
                _filtered_pill_cells(cell_g, (dx_p, py, weight), cell_y, g_prof, inv_step, rest)
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
