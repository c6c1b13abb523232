"""Compiled CPU step of K bodies on one surface: c, v and every body advanced together.

:func:`advance_bodies` is the loop of :func:`pde_rotor.kernels.cpu.advance` for the
generalised model (docs/bodies.md): every step it

1. holds the bodies that are fixed or in a stop of their own schedule (the motion's
   ``held``, ``hold``);
2. redraws F, G (filtered for ``consistent``) and the owner map of each body whose pose
   changed since it was last drawn (:func:`draw_body`; bodies may not overlap, so each
   cell belongs to one body at most, and the plate velocity of a cell is its owner's,
   the rates' ``plate_velocity``);
3. takes each moving body's integrals over its plate (:func:`body_integrals`, area
   form with central differences, the ``paper`` scheme; for ``consistent`` the force
   and torque in contour form, :func:`body_contour`);
4. advances c and v by one Euler step of Eqs. (eqc), (eqv) (the rates' ``plate_rates``
   with the owner's plate velocity; behind a no-flux dish wall c on the cut cells of the
   circle, :func:`pde_rotor.kernels.wall.euler_walled_fields`);
5. advances the bodies, Eq. (eq_motion) about X_k (the motion's ``body_loads``,
   ``euler_pose``), forward Euler or Heun's method (the rotor's semantics, see
   :func:`advance_bodies`), and the noise kick of Eq. (noiseav) on omega.

The rotor's loop (:func:`pde_rotor.kernels.cpu.advance`) takes the same step's tail
with the same functions of :mod:`pde_rotor.physics.motion`: the paper's rotor is the
``fixed_axis`` body at the origin.

A body that reaches the dish's edge or another body ends the run: the step, the body
and the reason are returned (see :func:`advance_bodies`), and the solver raises with
them. The physics is :mod:`pde_rotor.physics`; these loops only walk the grid.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ..model.body_schemes import ARC_EDGES
from ..physics.build import CPU, FASTMATH
from ..physics.indicators import PLATE_DISK, PLATE_NONE, PLATE_POLYGON, PLATE_STRIP
from ..physics.motion import MOTION_FIXED, N_INTEGRALS
from .indicators import CornerScratch, PolygonFilter, filtered_plate_row, plate_row
from .spline import ROW_GROUP, spline_columns, spline_rows
from .wall import euler_walled_fields

_plate_rates = CPU.rates.plate_rates
_rate_coefficients = CPU.rates.rate_coefficients
_held = CPU.motion.held
_hold = CPU.motion.hold
_tension_integrand = CPU.tension.tension_integrand
_friction_moments = CPU.motion.friction_moments
_body_loads = CPU.motion.body_loads
_finite_loads = CPU.motion.finite_loads
_euler_pose = CPU.motion.euler_pose
_heun_pose = CPU.motion.heun_pose
_owner_plate = CPU.rates.owner_plate
_body_plate_cell = CPU.indicators.body_plate_cell
_pill_term = CPU.indicators.pill_term
_pill_reach = CPU.indicators.pill_reach
_noise_kick = CPU.motion.noise_kick
_leaves_vessel = CPU.motion.leaves_vessel
_pair_contact = CPU.motion.pair_contact
_wall_contact = CPU.motion.wall_contact
_contact_loads = CPU.motion.contact_loads
_filtered_pill_term = CPU.indicators.filtered_pill_term
_filtered_pill_reach = CPU.indicators.filtered_pill_reach
_edge_sums = CPU.tension.edge_sums
_polygon_band = CPU.tension.polygon_band
_filtered_strip = CPU.indicators.filtered_strip
_arc_node = CPU.tension.arc_node


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
def _orient(k, body, pills, pose, normals, centres):
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


@nb.njit(inline="always", cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def _footprint_row(coords, j0, j1, rx, y_k, reach):
    """[ja, jb): the cells of columns [j0, j1) of a row, rx from X_k, within the footprint
    |r - X_k| < reach (a chord of the disk: scanned in from both ends of the box)."""
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


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def draw_body(F, G, owner, domain, k, body, pills, pose, normals, centres, box, tables, p, scratch,
              taps, moved):  # fmt: skip
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
    the paper's indicator sum). `tables` as for :func:`advance_bodies` (read where the
    record `p`'s ``filtered`` is set); `scratch` (:data:`SCRATCH_ROWS`, n) and `taps`
    (n, unsigned) are scratch. The cells of the last drawn footprint are cleared first
    where X_k `moved` since (else the new footprint is the same cells, all redrawn).

    Returns:
        0, or ``STATUS_EDGE`` (a footprint cell outside the dish), or ``-1 - j`` when
        the footprint meets body j's (the first such cell in row-major order decides).
    """
    coords, lo, hi, _, _ = domain
    _, _, profiles, pill_tab, corner, edges, _, _, _ = tables
    n = coords.size
    if moved:
        _clear_body(F, G, owner, n, k, box)
    _orient(k, body, pills, pose, normals, centres)
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
        ja, jb = _footprint_row(coords, j0, j1, rx, y_k, reach)
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


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def body_integrals(cur, F, owner, coords, k, x_k, y_k, box, p, out):
    """The integrals of body k over its plate, area form (central differences) (compiled).

    out[:] = (int F grad c (x, y), int F (r - X) x grad c, int F, int F (r - X) (x, y),
    int F |r - X|^2, int F (r - X) x v, int F v (x, y)), each times dA (the tension's
    ``tension_integrand`` and the motion's ``friction_moments``), summed over the
    cells body k owns in row-major order (the rotor's order: with X = 0 the torque's
    integrals are those of :func:`pde_rotor.kernels.cpu.rotor_integrals`).
    """
    n = coords.size
    sx = np.uint64(n)  # unsigned offsets: no test for negative indices at each load
    nn = np.uint64(n * n)
    dx = coords[1] - coords[0]
    inv_2dx = 0.5 / dx
    flow = p.flow
    # the sums in locals, which stay in registers (out might alias cur or F)
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = s8 = s9 = 0.0
    for i in range(box[k, 0], box[k, 1]):
        rx = coords[i] - x_k
        for j in range(box[k, 2], box[k, 3]):
            o = np.uint64(i * n + j)
            if owner[o] != k:
                continue
            f = F[o]
            if f == 0.0:
                continue
            ry = coords[j] - y_k
            t0, t1, t2 = _tension_integrand(cur, o, sx, np.uint64(1), f, rx, ry, inv_2dx, p)
            m0, m1, m2, m3, m4, m5, m6 = _friction_moments(cur, o, nn, f, rx, ry, flow)
            s0 += t0
            s1 += t1
            s2 += t2
            s3 += m0
            s4 += m1
            s5 += m2
            s6 += m3
            s7 += m4
            s8 += m5
            s9 += m6
    area = dx * dx
    out[0], out[1], out[2], out[3], out[4] = s0 * area, s1 * area, s2 * area, s3 * area, s4 * area
    out[5], out[6], out[7], out[8], out[9] = s5 * area, s6 * area, s7 * area, s8 * area, s9 * area


@nb.njit(cache=True, nogil=True, error_model="numpy")
def spline_box(cur, coef, n, i0, i1, j0, j1, carry):
    """coef = cubic B-spline coefficients of c (cur[:n^2]) on the rows [i0, i1) and
    columns [j0, j1) (compiled): the rows prefiltered in groups of ``ROW_GROUP``, then
    the columns, as the rotor's window (:mod:`pde_rotor.kernels.spline`); `carry` >= n."""
    for r0 in range(i0, i1, ROW_GROUP):
        spline_rows(cur, coef, n, r0, min(i1, r0 + ROW_GROUP), j0, j1, j0, carry)
    spline_columns(coef, n, i0, i1, j0, j1, i0, carry)


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, error_model="numpy")
def body_contour(cur, coords, k, body, pills, pose, normals, centres, tables, p, out):
    """int F_k grad c dA (x, y) and int F_k (r - X_k) x grad c dA in contour form
    (``consistent``; :mod:`pde_rotor.model.body_schemes`) into out[0:3] (compiled).

    The spline of c on the square window of half side ``window_half`` cells about the
    cell of X_k (:func:`spline_box`), then the contour nodes of the tension: a
    polygon's or a strip's edges (``edge_sums``; per (edge, band node) the sum along
    the edge, the pairs added in order, as the rotor's contour torque; a strip's four
    edges of two lengths, its band nodes without a parallel skipped), a disk plate's
    circle about
    X_k, or each pill's circle about its centre, its torque (P - X) x its force
    (``arc_node``, the angles phi + 2 pi l / L). `delta` is the edge width; `tables` as
    for :func:`advance_bodies`.
    """
    quad_s, quad_t, _, pill_tab, _, _, rings, coef, carry = tables
    delta = p.smoothing
    _orient(k, body, pills, pose, normals, centres)  # scratch: a new stepper starts with 0
    b = body[k]
    n = coords.size
    x0 = coords[0]
    inv_dx = 1.0 / (coords[1] - x0)
    x_k, y_k, phi = pose[k, 0], pose[k, 1], pose[k, 2]
    half = b.window_half
    ic = math.floor((x_k - x0) * inv_dx) + 1
    jc = math.floor((y_k - x0) * inv_dx) + 1
    i0, i1 = max(1, ic - half), min(n - 1, ic + half)
    j0, j1 = max(1, jc - half), min(n - 1, jc + half)
    spline_box(cur, coef, n, i0, i1, j0, j1, carry)
    n_s, n_t = quad_s.shape[1], quad_t.shape[1]
    grid = (0, n, x0, inv_dx)
    f_x = 0.0
    f_y = 0.0
    torque = 0.0
    if b.plate == PLATE_POLYGON:
        for j in range(b.n_corners):
            ex, ey = normals[0, j, k], normals[1, j, k]
            for m in range(n_s):
                h, half = _polygon_band(b.size_a, delta, b.tan_half, quad_s, m)
                edge = (x_k, y_k, ex, ey, h, half)
                pair_x, pair_y, pair_t = _edge_sums(coef, grid, edge, quad_s, quad_t, m, p)
                f_x += pair_x
                f_y += pair_y
                torque += pair_t
    elif b.plate == PLATE_STRIP:
        ex, ey = normals[0, 0, k], normals[1, 0, k]
        thinner = min(b.size_a, b.size_b)
        for j in range(4):  # the edges' normals e, z x e, -e, -z x e; sides L/2, W/2
            side, along = (b.size_a, b.size_b) if j % 2 == 0 else (b.size_b, b.size_a)
            for m in range(n_s):
                h = -delta * quad_s[0, m]
                if h <= -thinner:  # no parallel: the gauge is >= -W/2 (L/2) everywhere
                    continue
                edge = (x_k, y_k, ex, ey, side + h, along + h)
                pair_x, pair_y, pair_t = _edge_sums(coef, grid, edge, quad_s, quad_t, m, p)
                f_x += pair_x
                f_y += pair_y
                torque += pair_t
            ex, ey = -ey, ex
    else:
        n_arc = ARC_EDGES * n_t
        step = 2.0 * math.pi / n_arc
        first = b.pill_start
        last = b.pill_start + b.pill_count
        if b.plate == PLATE_DISK:
            first, last = 0, 1
        for q in range(first, last):
            cx, cy, r0, r1 = x_k, y_k, b.ring_start, b.ring_start + b.ring_count
            if b.plate != PLATE_DISK:
                cx, cy = centres[0, q], centres[1, q]
                r0, r1 = pill_tab[q, 4], pill_tab[q, 4] + pill_tab[q, 5]
            q_x = 0.0
            q_y = 0.0
            for m in range(r0, r1):
                h = rings[0, m]
                weight = rings[1, m] * h * step
                for a_l in range(n_arc):
                    angle = phi + step * a_l
                    a, c = _arc_node(
                        coef, grid, cx, cy, h, math.cos(angle), math.sin(angle), weight, p
                    )
                    q_x += a
                    q_y += c
            f_x += q_x
            f_y += q_y
            torque += (cx - x_k) * q_y - (cy - y_k) * q_x
    out[0], out[1], out[2] = f_x, f_y, torque


@nb.njit(cache=True, nogil=True)
def support_rows(box, n, slo, shi):
    """slo, shi: per row, the columns [slo, shi) covered by any body's box (the cells
    where F or G may be nonzero; empty rows get slo = shi = 0)."""
    for i in range(n):
        slo[i] = 0
        shi[i] = 0
    for k in range(box.shape[0]):
        for i in range(box[k, 0], box[k, 1]):
            if shi[i] == slo[i]:
                slo[i], shi[i] = box[k, 2], box[k, 3]
            else:
                slo[i] = min(slo[i], box[k, 2])
                shi[i] = max(shi[i], box[k, 3])


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def euler_body_fields(cur, nxt, F, G, owner, domain, coef, dt, pose, flow):
    """One Euler step of Eqs. (eqc), (eqv) on the interior cells, the plate velocity of
    each cell its owner's (:func:`plate_velocity`; none off the bodies) (compiled)."""
    coords, lo, hi, slo, shi = domain
    n = coords.size
    sx = np.uint64(n)
    sy = np.uint64(1)
    nn = np.uint64(n * n)
    for i in range(n):
        x = coords[i]
        for j in range(lo[i], hi[i]):
            o = np.uint64(i * n + j)
            plate = slo[i] <= j < shi[i] and owner[o] >= 0
            f, g, px, py = 0.0, 0.0, 0.0, 0.0
            if plate:
                f, g, px, py = _owner_plate(F, G, owner, pose, o, x, coords[j])
            cc = cur[o]
            ux = cur[o + nn] if flow else 0.0
            uy = cur[o + nn + nn] if flow else 0.0
            rate_c, rate_x, rate_y = _plate_rates(
                cur, o, (sx, sy, nn), f, g, (px, py), coef, flow, plate
            )
            nxt[o] = cc + dt * rate_c
            if flow:
                nxt[o + nn] = ux + dt * rate_x
                nxt[o + nn + nn] = uy + dt * rate_y


@nb.njit(cache=True, nogil=True)
def _draw_bodies(F, G, owner, domain, surface, bodies, p, scratch, taps, status):
    """Draw every body whose pose changed since it was last drawn (:func:`draw_body`) and
    the rows' support (compiled); `surface` is (wall, first: whether the support rows
    must be redone anyway), `bodies` as for :func:`advance_bodies`.

    Returns:
        True, or False on a contact (the reason and bodies in `status`).
    """
    body, pills, pose, drawn, box, normals, centres, tables = bodies
    redrawn = surface[1]
    for k in range(body.shape[0]):
        moved = pose[k, 0] != drawn[k, 0] or pose[k, 1] != drawn[k, 1]
        if moved or pose[k, 2] != drawn[k, 2]:
            code = draw_body(
                F, G, owner, domain, k, body, pills, pose, normals, centres, box, tables, p,
                scratch, taps, moved,
            )  # fmt: skip
            if code != 0:
                status[0] = STATUS_EDGE if code > 0 else STATUS_OVERLAP
                status[1] = k
                status[2] = -1 - code if code < 0 else -1
                return False
            drawn[k, 0], drawn[k, 1], drawn[k, 2] = pose[k, 0], pose[k, 1], pose[k, 2]
            redrawn = True
    if redrawn:  # the support rows are scratch of each call
        support_rows(box, domain[0].size, domain[3], domain[4])
    return True


@nb.njit(cache=True, nogil=True)
def _loads(cur, F, owner, domain, bodies, p, integrals, loads, status):
    """Each moving body's loads at its pose on the state `cur` into loads[k] (compiled):
    its integrals (:func:`body_integrals`, and :func:`body_contour` for the contour form)
    and the motion's ``body_loads``.

    With contact on, the contact forces are added (:func:`_contact`).

    Returns:
        True, or False where a body's footprint crosses a wall of the vessel (the motion's
        ``leaves_vessel``; ``STATUS_EDGE``, also with contact on, whose spring was then
        too weak) or its accelerations are not finite (the body in `status`).
    """
    body, pills, pose, _, box, normals, centres, tables = bodies
    coords = domain[0]
    sign_k = p.torque_sign * p.tension_slope
    for k in range(body.shape[0]):
        b = body[k]
        if b.motion == MOTION_FIXED:
            continue
        if _leaves_vessel(pose[k, 0], pose[k, 1], b.reach, p):
            status[0] = STATUS_EDGE
            status[1] = k
            status[2] = -1
            return False
        body_integrals(cur, F, owner, coords, k, pose[k, 0], pose[k, 1], box, p, integrals)
        if p.contour:
            body_contour(
                cur, coords, k, body, pills, pose, normals, centres, tables, p,
                integrals,
            )  # fmt: skip
        state = (pose[k, 0], pose[k, 1], pose[k, 2], pose[k, 3], pose[k, 4], pose[k, 5])
        out = _body_loads(integrals, state, b, sign_k)
        for m in range(9):
            loads[k, m] = out[m]
        if not _finite_loads(out):
            status[0] = STATUS_FINITE
            status[1] = k
            return False
    if p.contact_range > 0.0:
        _contact(body, pose, p, loads)
    return True


@nb.njit(cache=True, nogil=True)
def _contact(body, pose, p, loads):
    """Add each moving body's contact force with every other body and the walls to its
    accelerations in `loads` (compiled; the motion's ``pair_contact``, ``wall_contact``,
    ``contact_loads``)."""
    for k in range(body.shape[0]):
        b = body[k]
        if b.motion == MOTION_FIXED:
            continue
        x, y = pose[k, 0], pose[k, 1]
        f_x, f_y = _wall_contact(x, y, b.reach, p)
        for j in range(body.shape[0]):
            if j != k:
                g = _pair_contact(x, y, b.reach, pose[j, 0], pose[j, 1], body[j].reach, p)
                f_x += g[0]
                f_y += g[1]
        state = (x, y, pose[k, 2], pose[k, 3], pose[k, 4], pose[k, 5])
        out = _contact_loads(loads[k], state, f_x, f_y, b)
        for m in range(6, 9):
            loads[k, m] = out[m]


@nb.njit(cache=True, nogil=True)
def _fields(cur, nxt, F, G, owner, domain, wall, p, pose, rhs):
    """One Euler step of the fields from `cur` into `nxt` with the bodies at `pose`
    (compiled): behind the no-flux wall :func:`~pde_rotor.kernels.wall.euler_walled_fields`,
    else :func:`euler_body_fields`."""
    coef = _rate_coefficients(p)
    if wall[0].size > 0:
        euler_walled_fields(cur, nxt, (F, G, owner), domain, wall, coef, p.dt, pose, p.flow, rhs)
    else:
        euler_body_fields(cur, nxt, F, G, owner, domain, coef, p.dt, pose, p.flow)


@nb.njit(cache=True, nogil=True)
def _average(cur, stage, nxt, domain, wall, flow):
    """nxt = (cur + stage) / 2 where a step writes (compiled): c on the interior cells (on
    the runs of cut cells of each row behind a no-flux wall or in a vessel), v on the
    interior cells with `flow`."""
    coords, lo, hi, _, _ = domain
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


@nb.njit(cache=True, nogil=True)
def _set_poses(pose, poses):
    """pose[:, :6] = the (K, 6) `poses`."""
    for k in range(pose.shape[0]):
        for m in range(6):
            pose[k, m] = poses[k, m]


@nb.njit(cache=True, nogil=True)
def advance_bodies(
    data, spare, stage, F, G, owner, domain, wall, params, bodies, xi, status, step0, n_steps,
):  # fmt: skip
    """Advance c, v and every body by `n_steps` steps, forward Euler or Heun (compiled).

    Each step, every body k:

    1. held (``fixed``, or in a stop of its own schedule: the motion's ``held``): U = 0,
       omega = 0 (``hold``), and the column ``stopped`` of its pose is 1;
    2. F, G and the owner map redrawn where a pose changed (:func:`_draw_bodies`);
    3. the loads of each moving body at the state y and pose P (:func:`_loads`, the
       motion's ``body_loads``), recorded in its pose's force columns;
    4. the fields' Euler step y~ = y + dt f(y, P) (:func:`_fields`).

    Forward Euler (`stage` empty): 5. P <- ``euler_pose`` of every body not held.

    Heun (`stage` of the data's shape), the rotor's semantics
    (:func:`pde_rotor.kernels.cpu.advance`):

    5. the predicted poses P~ = ``euler_pose`` (P for a held body, whose velocities stay 0);
    6. F, G and the owner map redrawn at P~ (a contact there ends the run as at step 2);
    7. the loads at (y~, P~) (step 3, not recorded);
    8. a second Euler step of the fields from (y~, P~) into `stage`, y~ + dt f(y~, P~);
    9. the fields' average y + dt (f(y, P) + f(y~, P~)) / 2 = (y + stage) / 2 on the
       cells a step writes (:func:`_average`);
    10. every body not held: P <- ``heun_pose`` (the trapezoid of X, phi with the
        velocities at P and P~, of U, omega with the accelerations at both).

    Then, both integrators: the noise kick of Eq. (noiseav) on omega of every body not
    held (``noise_kick``, once per step, after the average), and on to the next step.
    Every step ends with finite accelerations, or the run ends.

    Args:
        data: flat state (c, v_x, v_y), 3 n^2 values, updated in place.
        spare: scratch of the same shape.
        stage: scratch of the same shape for Heun's method, or empty for Euler.
        F, G, owner: flat indicator arrays and the owner map (-1: no body), updated.
        domain: (coords, lo, hi, slo, shi); slo, shi are rewritten from the bodies' boxes.
        wall: the cut cells of a no-flux dish wall (:meth:`pde_rotor.model.wall.CutCells.arrays`;
            empty, :data:`pde_rotor.kernels.wall.NO_WALL`, for the absorbing wall).
        params: the run's parameter record (:func:`pde_rotor.kernels.records.make_record`).
        bodies: (body, pills, pose, drawn, box, normals, centres, tables):
            the bodies' records (``BODY``), their pills (P, 7): body-frame x, y, radius,
            relative source density, and polar form: distance from X and the angle as
            two terms (the paper's corner angle 2 pi j / N and the shift Delta, added in
            the rotor's order); the (K, 13) poses
            (:data:`pde_rotor.model.surface.POSE_COLUMNS`), updated in place; (K, 3) x,
            y, phi at which each body was last drawn (nan: never); (K, 4) int rows and
            columns of each body's last drawn footprint; scratch (2, max N, K) and
            (2, P); the ``consistent`` scheme's arrays
            (:func:`pde_rotor.kernels.records.make_body_tables`), read where the
            record's ``filtered`` and ``contour`` are set.
        xi: K standard normals per step for the noise (read where a body's kick != 0).
        status: (3,) ints: on an early end, the reason (``STATUS_*``) and the bodies.
        step0: global index of the first step; n_steps: number of steps.

    Returns:
        -1 on success, else the index of the step at which the run ended (state and
        poses left at the start of that step; the reason in `status`).
    """
    p = params[0]
    dt = p.dt
    body, _, pose, _, _, _, _, _ = bodies
    n_bodies = body.shape[0]
    coords = domain[0]
    n = coords.size
    nn = n * n
    cur = data
    nxt = spare
    heun = stage.size > 0
    integrals = np.zeros(N_INTEGRALS)
    loads = np.zeros((n_bodies, 9))
    loads_p = np.zeros((n_bodies, 9))
    start = np.zeros((n_bodies, 6))
    predicted = np.zeros((n_bodies, 6))
    rhs = np.zeros(nn if wall[0].size > 0 else 0)
    scratch = np.empty((SCRATCH_ROWS, n))
    taps = np.empty(n, np.uint64)
    if not p.flow:
        data[nn:] = 0.0
        spare[nn:] = 0.0
        if heun:
            stage[nn:] = 0.0
    for s in range(n_steps):
        for k in range(n_bodies):
            is_held = _held(step0 + s, body[k])
            pose[k, 12] = 1.0 if is_held else 0.0
            state = (pose[k, 0], pose[k, 1], pose[k, 2], pose[k, 3], pose[k, 4], pose[k, 5])
            state = _hold(state, is_held)
            for m in range(6):
                start[k, m] = state[m]
        _set_poses(pose, start)
        ok = _draw_bodies(F, G, owner, domain, (wall, s == 0), bodies, p, scratch, taps, status)
        if ok:
            ok = _loads(cur, F, owner, domain, bodies, p, integrals, loads, status)
        if not ok:
            if s % 2 == 1:
                data[:] = spare
            return s
        for k in range(n_bodies):
            for m in range(6):
                pose[k, 6 + m] = loads[k, m]
        _fields(cur, nxt, F, G, owner, domain, wall, p, pose, rhs)
        for k in range(n_bodies):
            b = body[k]
            state = (start[k, 0], start[k, 1], start[k, 2], start[k, 3], start[k, 4], start[k, 5])
            load = (loads[k, 0], loads[k, 1], loads[k, 2], loads[k, 3], loads[k, 4],
                    loads[k, 5], loads[k, 6], loads[k, 7], loads[k, 8])  # fmt: skip
            if pose[k, 12] == 0.0:
                state = _euler_pose(state, load, dt, b)
            for m in range(6):
                predicted[k, m] = state[m]
        _set_poses(pose, predicted)
        if heun:
            ok = _draw_bodies(F, G, owner, domain, (wall, False), bodies, p, scratch, taps, status)
            if ok:
                ok = _loads(nxt, F, owner, domain, bodies, p, integrals, loads_p, status)
            if not ok:
                _set_poses(pose, start)
                if s % 2 == 1:
                    data[:] = spare
                return s
            _fields(nxt, stage, F, G, owner, domain, wall, p, pose, rhs)
            _average(cur, stage, nxt, domain, wall, p.flow)
            for k in range(n_bodies):
                if pose[k, 12] != 0.0:
                    continue
                state = (start[k, 0], start[k, 1], start[k, 2], start[k, 3], start[k, 4],
                         start[k, 5])  # fmt: skip
                load = (loads[k, 0], loads[k, 1], loads[k, 2], loads[k, 3], loads[k, 4],
                        loads[k, 5], loads[k, 6], loads[k, 7], loads[k, 8])  # fmt: skip
                guess = (predicted[k, 0], predicted[k, 1], predicted[k, 2], predicted[k, 3],
                         predicted[k, 4], predicted[k, 5])  # fmt: skip
                load_p = (loads_p[k, 0], loads_p[k, 1], loads_p[k, 2], loads_p[k, 3],
                          loads_p[k, 4], loads_p[k, 5], loads_p[k, 6], loads_p[k, 7],
                          loads_p[k, 8])  # fmt: skip
                state = _heun_pose(state, load, guess, load_p, dt, body[k])
                for m in range(6):
                    pose[k, m] = state[m]
        for k in range(n_bodies):
            b = body[k]
            if pose[k, 12] == 0.0 and b.kick != 0.0:
                state = (pose[k, 0], pose[k, 1], pose[k, 2], pose[k, 3], pose[k, 4], pose[k, 5])
                pose[k, 5] = _noise_kick(state, xi[s * n_bodies + k], b)[5]
        cur, nxt = nxt, cur
    if n_steps % 2 == 1:
        data[:] = spare
    return -1
