"""The CUDA kernel of the GPU ensemble backend (:mod:`pde_rotor.backends.gpu`): E members
of the rotor model advanced in one launch, block m advancing member m.

The same physics as the CPU solver (:mod:`pde_rotor.kernels.cpu`), member by member, from
the same source: the kernel below only maps cells to threads and calls the CUDA build
of the compiled physics (:mod:`pde_rotor.physics`, compiled here as device functions):

* F and G of the member's scheme at the angle phi of the step's start, computed on the
  fly on the support cells (``plate_cell``, ``pill_cell``, or ``filtered_plate``,
  ``filtered_pills`` from the filter tables of the ``consistent`` scheme, shared by all
  members);
* the rotor integrals of Eqs. (eq_motion) and (torque) (``tension_integrand`` and
  ``friction_moments``, or ``polygon_node`` for the contour-form torque of the
  ``consistent`` scheme);
* one forward Euler step of Eqs. (eqc) and (eqv) on the interior cells
  (``cell_rates``), omega = 0 during a stop; without flow v is set to 0 and stays 0;
* then the rotor's step, the tail of every body's step (:mod:`pde_rotor.physics.motion`,
  the rotor is the ``fixed_axis`` body at the origin): the loads of Eqs. (torque) and
  (eq_motion) (``body_loads``, ``finite_loads``), the Euler step (``euler_pose``) plus
  the Euler-Maruyama kick of Eq. (noiseav) (``noise_kick``), except in a stop phase
  (``held``, the stop schedule in integer steps), where omega stays 0;
* the noise: one standard normal per step per member, drawn on the host from a numpy
  Generator seeded like the CPU solver's (``default_rng(noise.seed)``) in step order,
  so both backends use the identical noise sequence.

The parameters of a member are one record (:mod:`pde_rotor.kernels.records`), the
member's row of `params`.

Layout and parallelisation. One thread block advances one member for a whole chunk of
steps in one kernel launch: members are independent, so a step only needs the block's
own threads to agree (``syncthreads``), never a grid-wide barrier or a second kernel.
Each step, the block's threads sweep the member's cells (coalesced along y), compute F
and G on the fly (no indicator arrays in memory), write the new c, v into the other of
two buffers and accumulate the three rotor integrals in registers; a tree reduction in
shared memory (fixed order: bitwise reproducible) and one thread's update of phi and
omega end the step. Per step and member the kernel reads and writes c, v_x, v_y once
(48 bytes per interior cell, 2.2 MB at the paper's 242^2 grid).

All arithmetic is fp64. Importing the module compiles nothing; :func:`advance_kernel`
compiles the kernel on its first launch. With ``NUMBA_ENABLE_CUDASIM=1`` it runs in
numba's CUDA simulator on the CPU (slowly: for tests on tiny grids).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ..physics.build import Physics, make_physics
from ..physics.indicators import PolygonFilter
from .cuda_target import cuda, device_function, float64, kernel

MAX_CORNERS = 24
"""Largest N the kernel's shared geometry table holds (the config allows 3..24)."""


GPU: Physics = make_physics(device_function)
"""The physics (:mod:`pde_rotor.physics`) compiled as CUDA device functions."""

_rotor_table = GPU.indicators.rotor_table
_plate_cell = GPU.indicators.plate_cell
_pill_cell = GPU.indicators.pill_cell
_filtered_plate = GPU.indicators.filtered_plate
_filtered_pills = GPU.indicators.filtered_pills
_cell_rates = GPU.rates.cell_rates
_rate_coefficients = GPU.rates.rate_coefficients
_tension_integrand = GPU.tension.tension_integrand
_friction_moments = GPU.motion.friction_moments
_polygon_node = GPU.tension.polygon_node
_spline_line = GPU.spline.spline_line
_held = GPU.motion.held
_body_loads = GPU.motion.body_loads
_finite_loads = GPU.motion.finite_loads
_euler_pose = GPU.motion.euler_pose
_noise_kick = GPU.motion.noise_kick


def _advance(buf, domain, params, tables, state, span):
    """Advance every member by `n_steps` fused Euler steps; block m advances member m.

    The arrays and counters travel as three tuples (a kernel's arguments are flattened
    on launch, so tuples of device arrays and of integers cost nothing): `domain` is
    (coords, interior, rows, support), `state` is (rotor, xi, records, status, coef),
    `span` is (step0, n_steps, parity0, record_every, record0).

    Args:
        buf: two state buffers (2, E, 3, n, n) of (c, v_x, v_y), flattened; buffer
            `parity0` holds the state at step0, the result ends in buffer
            (parity0 + n_steps) % 2.
        domain: the grid's arrays, below.
        params: (E,) parameter records, one per member
            (:func:`pde_rotor.kernels.records.make_record`).
        tables: (quad_s, quad_t, plate, edge, pill), the common quadrature rules of the
            contour torque and filter tables (:meth:`Scheme.kernel_tables`).
        state: the members' arrays, below.
        span: the steps of this launch, below.

    The tuples' entries:
        coords: (n,) cell-centre coordinates.
        interior: (2, n) column range [lo, hi) of interior cells per row.
        rows: [i0, i1), the rows holding interior cells.
        support: (E, 2, n) column range of each member's support of F and G per row
            (inside the interior ranges).
        rotor: (E, 5) [phi, omega, torque, friction, stopped], updated.
        xi: (E, n_steps) standard normals of the noise (read where the member's
            ``kick`` != 0).
        records: (E, R, 6) receives the rotor and the total camphor int c dA after each
            step that ends on a multiple of `record_every`, at row
            (step + 1) // record_every - record0.
        status: (E,) -1, or the step at which the member's state stopped being finite
            (the member is then left at the start of that step and not advanced again).
        coef: (2 E n^2) scratch for the spline coefficients of c (contour form only):
            member m's at 2 m n^2, its rows' prefiltered c after them.
        step0: global index of the first step.
        n_steps: number of steps.
        parity0: buffer holding the state at step0.
        record_every: steps between records.
        record0: record number of row 0 of `records`.
    """
    coords, interior, rows, support = domain
    rotor, xi, records, status, coef = state
    step0, n_steps, parity0, record_every, record0 = span
    m = cuda.blockIdx.x
    tid = cuda.threadIdx.x
    n_threads = cuda.blockDim.x
    if status[m] >= 0:
        return
    red = cuda.shared.array(0, float64)  # 4 * n_threads partial sums
    tab = cuda.shared.array((4, MAX_CORNERS), float64)  # edge normals, pill centres
    rot = cuda.shared.array(6, float64)  # phi, omega, torque, friction, stopped, failed

    p = params[m]
    quad_s, quad_t, plate_tab, edge_tab, pill_tab = tables
    rates = _rate_coefficients(p)
    dt, dx = p.dt, p.dx
    inv_2dx = 0.5 / dx
    area = dx * dx
    n_corners = p.n_corners
    apothem, rho, r_c = p.apothem, p.pill_radius, p.pill_distance
    asym, delta = p.asymmetry, p.smoothing
    inv_delta = 1.0 / delta
    filtered = p.filtered
    t_n, t_x0 = p.table_n, p.table_x0
    t_inv, p_inv = p.table_inv_step, p.profile_inv_step
    crease, e_u0, e_inv = p.crease, p.edge_u0, p.edge_inv_step
    corner_end = p.corner_end
    contour = p.contour
    tan_half = p.tan_half
    plate_filter = PolygonFilter(
        n_corners, apothem, tan_half, crease, corner_end, edge_tab, e_u0, e_inv, plate_tab,
        t_n, t_x0, t_inv,
    )  # fmt: skip
    polygon = (apothem, delta, tan_half)
    w_lo = p.window_lo
    width = p.window_hi - w_lo
    n_nodes = n_corners * quad_s.shape[1] * quad_t.shape[1] if contour else 0
    flow = p.flow
    noisy = p.kick != 0.0
    i0, i1 = rows[0], rows[1]
    lanes = min(n_threads, 32)  # a warp sweeps a row, coalesced along y
    group = tid // lanes
    lane = tid % lanes
    n_groups = n_threads // lanes
    n = coords.size
    nn = n * n
    x0 = coords[0]
    inv_dx = 1.0 / dx
    n_members = status.size

    if tid == 0:
        for q in range(5):
            rot[q] = rotor[m, q]
        rot[5] = 0.0
    cuda.syncthreads()

    for s in range(n_steps):
        step = step0 + s
        p_cur = (parity0 + s) % 2
        p_nxt = 1 - p_cur
        stopped = _held(step, p)
        phi = rot[0]
        omega = rot[1]
        if stopped:
            omega = 0.0
        if tid == 0:
            _rotor_table(phi, n_corners, r_c, asym, tab)
        cuda.syncthreads()

        cross_grad = 0.0
        moment = 0.0
        cross_v = 0.0
        camphor = 0.0
        bad = False
        cur = (p_cur * n_members + m) * 3 * nn  # offset of the member's c in buf
        nxt = (p_nxt * n_members + m) * 3 * nn
        for i in range(i0 + group, i1, n_groups):
            x = coords[i]
            s_lo = support[m, 0, i]
            s_hi = support[m, 1, i]
            for j in range(interior[0, i] + lane, interior[1, i], lanes):
                on_support = s_lo <= j and j < s_hi
                y = coords[j]
                o = cur + i * n + j
                f = 0.0
                g = 0.0
                if on_support:
                    if filtered:
                        f = _filtered_plate(x, y, tab, plate_filter)
                        g = _filtered_pills(x, y, tab, n_corners, pill_tab, p_inv)
                    else:
                        f = _plate_cell(x, y, tab, n_corners, apothem, inv_delta)
                        g = _pill_cell(x, y, tab, n_corners, rho, inv_delta)
                    if f != 0.0:
                        cross_grad += _tension_integrand(buf, o, n, 1, f, x, y, inv_2dx, p)[2]
                        moments = _friction_moments(buf, o, nn, f, x, y, flow)
                        moment += moments[3]
                        cross_v += moments[4]
                rate_c, rate_x, rate_y = _cell_rates(
                    buf, o, (n, 1, nn), f, g, omega, (x, y), rates, flow, on_support
                )
                o_new = nxt + i * n + j
                new_c = buf[o] + dt * rate_c
                buf[o_new] = new_c
                camphor += new_c
                if not math.isfinite(new_c):
                    bad = True
                if flow:
                    new_x = buf[o + nn] + dt * rate_x
                    new_y = buf[o + 2 * nn] + dt * rate_y
                    buf[o_new + nn] = new_x
                    buf[o_new + 2 * nn] = new_y
                    if not (math.isfinite(new_x) and math.isfinite(new_y)):
                        bad = True
        if contour:  # the contour form replaces the area form of int F r x grad c dA
            o_coef = 2 * m * nn
            o_rows = o_coef + nn  # the rows' coefficients, which the columns filter
            for q in range(tid, width, n_threads):
                o = (w_lo + q) * n + w_lo
                _spline_line(buf, cur + o, coef, o_rows + o, 1, width)
            cuda.syncthreads()
            for q in range(tid, width, n_threads):
                o = w_lo * n + w_lo + q
                _spline_line(coef, o_rows + o, coef, o_coef + o, n, width)
            cuda.syncthreads()
            cross_grad = 0.0
            for q in range(tid, n_nodes, n_threads):
                cross_grad += _polygon_node(
                    coef, (o_coef, n, x0, inv_dx), tab, polygon, quad_s, quad_t, q, p
                )[2]

        # block reduction of the rotor integrals in a fixed order
        red[tid] = cross_grad
        red[n_threads + tid] = moment
        red[2 * n_threads + tid] = cross_v
        red[3 * n_threads + tid] = camphor
        if bad:
            rot[5] = 1.0
        cuda.syncthreads()
        half = n_threads // 2
        while half > 0:
            if tid < half:
                red[tid] += red[tid + half]
                red[n_threads + tid] += red[n_threads + tid + half]
                red[2 * n_threads + tid] += red[2 * n_threads + tid + half]
                red[3 * n_threads + tid] += red[3 * n_threads + tid + half]
            cuda.syncthreads()
            half //= 2

        if tid == 0:
            total_grad = red[0] if contour else red[0] * area
            total_moment = red[n_threads] * area
            total_v = red[2 * n_threads] * area
            integrals = (0.0, 0.0, total_grad, 0.0, 0.0, 0.0, total_moment, total_v, 0.0, 0.0)
            pose = (0.0, 0.0, phi, 0.0, 0.0, omega)
            loads = _body_loads(integrals, pose, p, p.torque_sign * p.tension_slope)
            if not _finite_loads(loads) or rot[5] != 0.0:
                status[m] = step
                rot[1] = omega
                rot[5] = 1.0
            else:
                if not stopped:
                    pose = _euler_pose(pose, loads, dt, p)
                    if noisy:
                        pose = _noise_kick(pose, xi[m, s], p)
                rot[0] = pose[2]
                rot[1] = pose[5]
                rot[2] = loads[2]
                rot[3] = loads[5]
                rot[4] = 1.0 if stopped else 0.0
                if (step + 1) % record_every == 0:
                    row_out = (step + 1) // record_every - record0
                    for q in range(5):
                        records[m, row_out, q] = rot[q]
                    records[m, row_out, 5] = red[3 * n_threads] * area
        cuda.syncthreads()
        if rot[5] != 0.0:
            # diverged: leave the member at the start of this step in both buffers
            for i in range(i0 + group, i1, n_groups):
                for j in range(interior[0, i] + lane, interior[1, i], lanes):
                    for ch in range(3):
                        buf[nxt + ch * nn + i * n + j] = buf[cur + ch * nn + i * n + j]
            break

    cuda.syncthreads()
    if tid == 0:
        for q in range(5):
            rotor[m, q] = rot[q]


_KERNELS: dict[tuple[int, int], Callable] = {}


def advance_kernel(threads_per_block: int, min_blocks_per_sm: int = 0) -> Callable:
    """The kernel for a block size and launch bound (compiled on its first launch).

    Args:
        threads_per_block: threads per block (the launch bound the compiler may assume).
        min_blocks_per_sm: if > 0, ask the compiler to fit this many blocks on one
            multiprocessor (fewer registers per thread, possibly spills); 0: its choice.
    """
    key = (threads_per_block, min_blocks_per_sm)
    if key not in _KERNELS:
        bounds = (threads_per_block, min_blocks_per_sm) if min_blocks_per_sm else None
        _KERNELS[key] = kernel(_advance, bounds)
    return _KERNELS[key]
