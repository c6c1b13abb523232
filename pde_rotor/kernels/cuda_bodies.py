"""The CUDA kernel of K camphor bodies on one surface: E members in one launch, block m
advancing member m (the loop of :func:`pde_rotor.kernels.bodies.advance_bodies` on the
GPU, with Heun's method besides forward Euler).

The physics is :mod:`pde_rotor.physics` (indicators, rates, tension, motion), compiled
as CUDA device functions (:data:`pde_rotor.kernels.cuda.GPU`); this module holds no
physics of its own and only maps cells, bodies and sums to the threads of a block. Each
evaluation of the right-hand side (:func:`_stage`: once per Euler step, twice per Heun step):

1. every body whose pose changed since it was drawn is redrawn, one body after the other
   in their order (:func:`pde_rotor.kernels.cuda_body_draw.draw_body`): its old
   footprint cleared, then, split among the threads, the footprint's cells checked (a
   cell outside the dish ends the run, as does a cell another body owns; the first such
   row decides, as on the CPU) and F_k, G_k and the owner written per cell
   (``body_plate_cell``, or for ``consistent`` ``filtered_plate``,
   ``filtered_pill_term``, ``filtered_strip``; the pills' terms ``pill_term``,
   ``filtered_pill_term``, on the cells the CPU gives them);
2. the integrals of each moving body (:mod:`pde_rotor.kernels.cuda_body_sums`: the
   cells of its box it owns, area form, ``tension_integrand`` and ``friction_moments``;
   for ``consistent`` the tension force and torque in contour form: the spline of c on
   the body's window, then its edges' or circles' nodes, ``edge_sums``, ``arc_orbit``;
   c read through the surface pressure of a saturating tension law), each a fixed-order
   tree reduction in shared memory, and its loads (``body_loads``: tension, friction and
   external load, the accelerations; ``finite_loads``);
3. one Euler step of Eqs. (eqc), (eqv) from one buffer into another
   (:func:`_euler_fields`: ``plate_rates`` with the owner's plate velocity,
   ``owner_plate``; behind a no-flux dish wall ``cut_cell_inflow`` and ``local_rate``
   on the cut cells, then the implicit clusters, :func:`_walled_fields`).

A step first holds the bodies that are fixed or in a stop of their own schedule
(``held``, ``hold``), then moves the others: forward Euler (``euler_pose``), or Heun:
the predictor's Euler step of fields and bodies, the right-hand side again at the
predicted poses and fields into a stage buffer, the fields' trapezoid
(:func:`_average`) and the bodies' (``heun_pose``, the forces recorded those of the
step's start), as the CPU's :func:`pde_rotor.kernels.bodies.advance_bodies`. The noise
kick (``noise_kick``) follows, once per step, for the bodies not held, from K standard
normals per step drawn on the host.

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

from collections.abc import Callable

from ..physics.motion import MOTION_FIXED
from .bodies import STATUS_EDGE, STATUS_FINITE, STATUS_OVERLAP
from .cuda import GPU
from .cuda_body_draw import draw_body
from .cuda_body_sums import N_SUMS, contour_sums, owned_sums
from .cuda_target import cuda, device_function, float64, int64, kernel

_plate_rates = GPU.rates.plate_rates
_rate_coefficients = GPU.rates.rate_coefficients
_cut_cell_inflow = GPU.rates.cut_cell_inflow
_local_rate = GPU.rates.local_rate
_owner_plate = GPU.rates.owner_plate
_held = GPU.motion.held
_hold = GPU.motion.hold
_body_loads = GPU.motion.body_loads
_finite_loads = GPU.motion.finite_loads
_euler_pose = GPU.motion.euler_pose
_heun_pose = GPU.motion.heun_pose
_noise_kick = GPU.motion.noise_kick
_leaves_vessel = GPU.motion.leaves_vessel
_pair_contact = GPU.motion.pair_contact
_wall_contact = GPU.motion.wall_contact
_contact_loads = GPU.motion.contact_loads


@device_function
def _lanes():
    """(first row, row stride, first column offset, column stride) of this thread: the
    rows split among groups of up to 32 threads, each row's cells among a group's."""
    tid = cuda.threadIdx.x
    lanes = min(cuda.blockDim.x, 32)
    return tid // lanes, cuda.blockDim.x // lanes, tid % lanes, lanes


@device_function
def _cell_plate(state, pose, m, o, x, y):
    """(plate, F, G, plate velocity x, y) of cell o of member m at (x, y): its owner's
    (``owner_plate``), or zeros where no body owns it."""
    _, F, G, owner = state
    if owner[m, o] >= 0:
        f, g, px, py = _owner_plate(F[m], G[m], owner[m], pose[m], o, x, y)
        return True, f, g, px, py
    return False, 0.0, 0.0, 0.0, 0.0


@device_function
def _step_flow(buf, src, dst, o, nn, dt, rate):
    """v of cell o from buf[src:] into buf[dst:] by an Euler step of `rate` (x, y)."""
    buf[dst + o + nn] = buf[src + o + nn] + dt * rate[0]
    buf[dst + o + 2 * nn] = buf[src + o + 2 * nn] + dt * rate[1]


@device_function
def _euler_fields(src, dst, m, state, surface, bodies, p):
    """One Euler step of Eqs. (eqc), (eqv) on the interior cells from buf[src:] into
    buf[dst:], the plate terms those of each cell's owner (all threads)."""
    buf = state[0]
    coords, interior = surface
    n = coords.size
    nn = n * n
    coef = _rate_coefficients(p)
    row0, rows, col0, lanes = _lanes()
    for i in range(row0, n, rows):
        x = coords[i]
        for j in range(interior[0, i] + col0, interior[1, i], lanes):
            o = i * n + j
            plate, f, g, px, py = _cell_plate(state, bodies[2], m, o, x, coords[j])
            rate_c, rate_x, rate_y = _plate_rates(
                buf, src + o, (n, 1, nn), f, g, (px, py), coef, p.flow, plate
            )
            buf[dst + o] = buf[src + o] + p.dt * rate_c
            if p.flow:
                _step_flow(buf, src, dst, o, nn, p.dt, (rate_x, rate_y))
    cuda.syncthreads()


@device_function
def _walled_fields(src, dst, m, state, surface, bodies, wall, rhs, p):
    """One step of Eqs. (eqc), (eqv) behind the no-flux dish wall (all threads): the
    explicit part on the runs of cut cells of each row (``cut_cell_inflow``,
    ``local_rate``), v on the cells that flow, then A c' = kappa c' on each cluster of
    implicit faces by its L D L^T factors
    (:func:`pde_rotor.kernels.wall.implicit_clusters`), the rows of one level in
    parallel (those of different clusters), the levels in turn."""
    buf = state[0]
    coords = surface[0]
    volume, pass_x, pass_y, open_x, open_y, row_start, span_lo, span_hi, flowing = wall[:9]
    faces = (open_x, open_y, pass_x, pass_y)
    index, levels, factor = wall[9:]
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    nn = n * n
    coef = _rate_coefficients(p)
    dt = p.dt
    flow = p.flow
    rm = rhs[m]
    row0, rows, col0, lanes = _lanes()
    for i in range(row0, n, rows):
        x = coords[i]
        for s in range(row_start[i], row_start[i + 1]):
            for j in range(span_lo[s] + col0, span_hi[s], lanes):
                o = i * n + j
                plate, f, g, px, py = _cell_plate(state, bodies[2], m, o, x, coords[j])
                cc = buf[src + o]
                kappa = volume[o]
                q = _cut_cell_inflow(buf[src:], o, (n, 1, nn), faces, coef, flow)
                r = kappa * cc + dt * (q + kappa * _local_rate(cc, f, g, coef, plate))
                rm[o] = r
                buf[dst + o] = r / kappa
                if flow and flowing[o]:
                    _, rate_x, rate_y = _plate_rates(
                        buf, src + o, (n, 1, nn), f, g, (px, py), coef, flow, plate
                    )
                    _step_flow(buf, src, dst, o, nn, dt, (rate_x, rate_y))
    cuda.syncthreads()
    span = index.shape[1]
    for t in range(levels.size - 1):  # forward substitution, one level at a time
        for g in range(levels[t] + tid, levels[t + 1], n_threads):
            y = rm[index[g, 0]]
            for e in range(1, span):
                rm[index[g, e]] -= factor[g, e] * y
        cuda.syncthreads()
    for t in range(levels.size - 2, -1, -1):  # back substitution, last level first
        for g in range(levels[t] + tid, levels[t + 1], n_threads):
            o = index[g, 0]
            x = rm[o] * factor[g, 0]
            for e in range(span - 1, 0, -1):
                x -= factor[g, e] * buf[dst + index[g, e]]
            buf[dst + o] = x
        cuda.syncthreads()


@device_function
def _average(cur, stage, dst, buf, surface, wall, p):
    """buf[dst:] = (buf[cur:] + buf[stage:]) / 2 on the cells the step writes (Heun's
    trapezoid, :func:`pde_rotor.kernels.cpu.heun_average`; all threads)."""
    coords, interior = surface
    row_start, span_lo, span_hi = wall[5], wall[6], wall[7]
    walled = wall[0].size > 0
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    n = coords.size
    nn = n * n
    for i in range(tid, n, n_threads):
        if walled:  # c on the runs of cut cells of the row
            for s in range(row_start[i], row_start[i + 1]):
                for j in range(span_lo[s], span_hi[s]):
                    o = i * n + j
                    buf[dst + o] = 0.5 * (buf[cur + o] + buf[stage + o])
        else:
            for j in range(interior[0, i], interior[1, i]):
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
    redrawn, the integrals and loads of the moving ones (the motion's ``body_loads``)
    into loads[m, k, stage] (at `stage` 0 their forces also into the pose's columns
    6..11), and the fields' Euler step into buf[dst:].

    Returns:
        0, or the reason the run ends (``STATUS_*``), the bodies in flags[2], flags[3].
    """
    body, _, pose, drawn, _ = bodies
    loads = scratch[2]
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
            code = draw_body(k, m, moved, state, surface, bodies, scratch, tables, p, red)
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
        if not b.spans and _leaves_vessel(pose[m, k, 0], pose[m, k, 1], b.contact, p):
            if tid == 0:
                flags[2] = k
                flags[3] = -1
            cuda.syncthreads()
            return STATUS_EDGE
        owned_sums(src, k, m, state, surface, bodies, wall[0], p, red)
        if tid == 0:
            for q in range(N_SUMS):
                ints[q] = red[q * n_threads] * area
        cuda.syncthreads()
        if p.contour and not b.spans:
            contour_sums(src, k, m, state, surface, bodies, scratch, tables, p, red)
            if tid == 0:
                ints[0] = red[0]
                ints[1] = red[n_threads]
                ints[2] = red[2 * n_threads]
        cuda.syncthreads()
        if tid == 0:
            here = (pose[m, k, 0], pose[m, k, 1], pose[m, k, 2], pose[m, k, 3], pose[m, k, 4],
                    pose[m, k, 5])  # fmt: skip
            out = _body_loads(ints, here, b, sign_k)
            if stage == 0:
                pose[m, k, 6], pose[m, k, 7], pose[m, k, 8] = out[0], out[1], out[2]
                pose[m, k, 9], pose[m, k, 10], pose[m, k, 11] = out[3], out[4], out[5]
            for q in range(9):
                loads[m, k, stage, q] = out[q]
            if not _finite_loads(out):
                flags[1] = STATUS_FINITE
                flags[2] = k
                flags[3] = -1
        cuda.syncthreads()
        if flags[1] != 0:
            return STATUS_FINITE
    if p.contact_range > 0.0:
        if tid == 0:
            _contact(m, stage, bodies, loads, p)
        cuda.syncthreads()
    if wall[0].size > 0:
        _walled_fields(src, dst, m, state, surface, bodies, wall, rhs, p)
    else:
        _euler_fields(src, dst, m, state, surface, bodies, p)
    return 0


@device_function
def _contact(m, stage, bodies, loads, p):
    """Add each moving body's contact force with every other body and the walls (not for
    a body that spans its channel, whose plate crosses them by design) to its
    accelerations in loads[m, k, stage] (one thread; the motion's ``pair_contact``,
    ``wall_contact`` at the poses' positions and velocities, ``contact_loads``); at
    `stage` 0 the force into the pose's columns 13, 14."""
    body, _, pose, _, _ = bodies
    n_bodies = body.shape[1]
    for k in range(n_bodies):
        b = body[m][k]
        if b.motion == MOTION_FIXED:
            continue
        here = (pose[m, k, 0], pose[m, k, 1], pose[m, k, 3], pose[m, k, 4])
        f_x, f_y = (0.0, 0.0) if b.spans else _wall_contact(here, b.contact, p)
        for j in range(n_bodies):
            if j != k:
                there = (pose[m, j, 0], pose[m, j, 1], pose[m, j, 3], pose[m, j, 4])
                g = _pair_contact(here, b.contact, there, body[m][j].contact, p)
                f_x += g[0]
                f_y += g[1]
        state = (here[0], here[1], pose[m, k, 2], here[2], here[3], pose[m, k, 5])
        out = _contact_loads(loads[m, k, stage], state, f_x, f_y, b)
        for q in range(6, 9):
            loads[m, k, stage, q] = out[q]
        if stage == 0:
            pose[m, k, 13], pose[m, k, 14] = f_x, f_y


@device_function
def _hold_bodies(step, m, bodies, scratch):
    """Which bodies are held this step (the motion's ``held``: fixed, or in a stop of
    their own schedule): the pose's column 12, their velocities 0 (``hold``); each
    body's pose and velocities at the step's start into start[m] (one thread)."""
    body, _, pose, _, _ = bodies
    start = scratch[3]
    for k in range(body.shape[1]):
        is_held = _held(step, body[m][k])
        pose[m, k, 12] = 1.0 if is_held else 0.0
        here = (pose[m, k, 0], pose[m, k, 1], pose[m, k, 2], pose[m, k, 3], pose[m, k, 4],
                pose[m, k, 5])  # fmt: skip
        here = _hold(here, is_held)
        for q in range(6):
            pose[m, k, q] = here[q]
            start[m, k, q] = here[q]


@device_function
def _move(m, phase, bodies, scratch, dt):
    """Move the bodies that are not held (one thread): `phase` 0, the motion's
    ``euler_pose`` from the start with the start's loads (Euler's step and Heun's
    predictor); 1, ``heun_pose`` from the start with the start's loads and the predicted
    pose (in the pose) and its loads (loads[m, k, 1])."""
    body, _, pose, _, _ = bodies
    loads, start = scratch[2], scratch[3]
    for k in range(body.shape[1]):
        if pose[m, k, 12] != 0.0:
            continue
        b = body[m][k]
        first = (start[m, k, 0], start[m, k, 1], start[m, k, 2], start[m, k, 3],
                 start[m, k, 4], start[m, k, 5])  # fmt: skip
        if phase == 0:
            moved = _euler_pose(first, loads[m, k, 0], dt, b)
        else:
            guess = (pose[m, k, 0], pose[m, k, 1], pose[m, k, 2], pose[m, k, 3],
                     pose[m, k, 4], pose[m, k, 5])  # fmt: skip
            moved = _heun_pose(first, loads[m, k, 0], guess, loads[m, k, 1], dt, b)
        for q in range(6):
            pose[m, k, q] = moved[q]


@device_function
def _kick(m, s, bodies, xi):
    """The noise kick of Eq. (noiseav) on omega of every body not held, after the step
    (the motion's ``noise_kick``; one thread)."""
    body, _, pose, _, _ = bodies
    n_bodies = body.shape[1]
    for k in range(n_bodies):
        b = body[m][k]
        if pose[m, k, 12] == 0.0 and b.kick != 0.0:
            here = (pose[m, k, 0], pose[m, k, 1], pose[m, k, 2], pose[m, k, 3], pose[m, k, 4],
                    pose[m, k, 5])  # fmt: skip
            pose[m, k, 5] = _noise_kick(here, xi[m, s * n_bodies + k], b)[5]


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
        arrays: (pills (E, P, 7), pose (E, K, 15) updated, drawn (E, K, 3) and box
            (E, K, 4) of the last drawing, kept between launches), as for
            :func:`pde_rotor.kernels.bodies.advance_bodies`.
        scratch: (normals (E, K, 2, C), centres (E, 2, P), loads (E, K, 2, 9) (the
            motion's ``body_loads`` at the start and at Heun's predicted pose), start
            (E, K, 6), spline coefficients (E, 2 n^2): the coefficients, then the rows'
            prefiltered c).
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
            _hold_bodies(step, m, bodies, scratch)
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
            _kick(m, s, bodies, xi)
        cuda.syncthreads()


_KERNELS: dict[int, Callable] = {}


def bodies_kernel(threads_per_block: int) -> Callable:
    """The bodies' kernel for a block size (compiled on its first launch); launch it with
    E blocks and ``N_SUMS * threads_per_block * 8`` bytes of dynamic shared memory."""
    if threads_per_block not in _KERNELS:
        _KERNELS[threads_per_block] = kernel(_advance_bodies, (threads_per_block,))
    return _KERNELS[threads_per_block]
