"""Compiled CPU kernels of the fused time step: c, v, phi and omega advanced together.

One compiled loop, :func:`advance`, advances every time step dt all three unknowns of
the paper's model:

* camphor c, Eq. (eqc): dc/dt = D lap c - div(c v) - a (1 - F) c + s0/(pi rho^2) G;
* flow v, Eq. (eqv): dv/dt = eta F (omega (-y, x) - v) - eta_b v + D_eta lap v;
* rotor, Eq. (eq_motion): I domega/dt = -mu int F (|r|^2 omega - r x v) dA + T + xi,
  dphi/dt = omega, with the torque T of Eq. (torque) (see :mod:`pde_rotor.model.pde` for the
  sign) and Gaussian white noise xi, Eq. (noiseav), integrated by Euler-Maruyama.

Time: forward Euler with step dt (the paper's "Euler method"), every right-hand side at
the old time level; or, with ``numerics.integrator: heun``, Heun's second-order method
(predictor Euler step of fields and rotor, F, G and the torque recomputed at the predicted
angle, trapezoidal average; docs/model.md, "Time integration"). Space and the rotor
integrals: the compiled physics (:mod:`pde_rotor.physics`) in the scheme of ``numerics.scheme``
(:mod:`pde_rotor.model.schemes`). These loops only walk the grid and call the physics; the GPU
backend calls the same core from its threads. :mod:`pde_rotor.solver.rotor` binds them to a
simulation and to py-pde.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ..physics.build import CPU, FASTMATH
from .indicators import SCRATCH_ROWS, indicator_row
from .spline import (
    ROW_GROUP,
    node_pressure,
    node_scratch,
    place_nodes,
    spline_columns,
    spline_rows,
    spline_window,
)

_cell_rates = CPU.rates.cell_rates
_rate_coefficients = CPU.rates.rate_coefficients
_tension_integrand = CPU.tension.tension_integrand
_friction_moments = CPU.motion.friction_moments
_polygon_band = CPU.tension.polygon_band
_rotor_table = CPU.indicators.rotor_table
_held = CPU.motion.held
_hold = CPU.motion.hold
_body_loads = CPU.motion.body_loads
_finite_loads = CPU.motion.finite_loads
_euler_pose = CPU.motion.euler_pose
_heun_pose = CPU.motion.heun_pose
_noise_kick = CPU.motion.noise_kick


_LOOP = {"cache": True, "nogil": True, "fastmath": FASTMATH, "error_model": "numpy"}
"""numba options of the loops: fastmath without reassociation
(:data:`pde_rotor.physics.build.FASTMATH`)."""
_PARALLEL = {**_LOOP, "parallel": True}
"""... and of the loops shared among threads (numba ``prange``)."""


@nb.njit(inline="always", **_LOOP)
def _euler_cells(bufs, row, j0, j1, coef, dt, omega, flow, plate):
    """Euler step of the cells [j0, j1) of one row (compiled): `bufs` is (cur, nxt, F, G,
    coords), `row` (x, the row's offset, the strides sx and nn of the rates' ``strides``)."""
    cur, nxt, F, G, y_of = bufs
    x, base, sx, nn = row
    sy = np.uint64(1)
    f = 0.0
    g = 0.0
    for j in range(j0, j1):
        o = base + j
        # loaded before any store, so that these are the loads cell_rates makes too
        cc = cur[o]
        ux = cur[o + nn] if flow else 0.0
        uy = cur[o + nn + nn] if flow else 0.0
        if plate:
            f = F[o]
            g = G[o]
        rate_c, rate_x, rate_y = _cell_rates(
            cur, o, (sx, sy, nn), f, g, omega, (x, y_of[j]), coef, flow, plate
        )
        nxt[o] = cc + dt * rate_c
        if flow:
            ox = o + nn
            nxt[ox] = ux + dt * rate_x
            nxt[ox + nn] = uy + dt * rate_y


@nb.njit(inline="always", **_LOOP)
def _euler_row(bufs, i, domain, coef, dt, omega, flow):
    """One Euler step of Eqs. (eqc) and (eqv) (or (eqc) alone) on the interior cells of
    row i: the cells before, on and after the support (where F, G may be nonzero), an
    empty support where the row has none (no branch around the loops, which would keep
    numba's reference counts in the loop over rows); `bufs` is (cur, nxt, F, G), `domain`
    as for :func:`advance`."""
    cur, nxt, F, G = bufs
    coords, lo, hi, slo, shi = domain
    n = coords.size
    cells = (cur, nxt, F, G, coords)
    row = (coords[i], np.uint64(i * n), np.uint64(n), np.uint64(n * n))
    j0, j1 = np.uint64(lo[i]), np.uint64(hi[i])
    plate = shi[i] > slo[i]
    s0 = np.uint64(slo[i]) if plate else j0
    s1 = np.uint64(shi[i]) if plate else j0
    _euler_cells(cells, row, j0, s0, coef, dt, omega, flow, False)
    _euler_cells(cells, row, s0, s1, coef, dt, omega, flow, True)
    _euler_cells(cells, row, s1, j1, coef, dt, omega, flow, False)


@nb.njit(inline="always", **_LOOP)
def _row_integrals(cur, F, i, coords, j0, j1, p, inv_2dx, area, sums):
    """Row i's sums of the integrands of Eq. (eq_motion) over its support cells [j0, j1)
    (the torque's of ``tension_integrand``, F r x grad c, and of ``friction_moments``,
    F |r|^2 and F r x v, without dA; the rotor is the body at X = 0) into sums[i]; the
    first only with `area` (a compile-time constant: without it, the torque's contour
    form replaces the area form, whose sum is 0 and whose gradients LLVM drops); `p` is
    the parameter record (its ``flow`` selects the flow's moment), `inv_2dx` is
    1 / (2 dx)."""
    n = coords.size
    x = coords[i]
    cross_grad = 0.0
    moment = 0.0
    cross_v = 0.0
    for j in range(j0, j1):
        o = i * n + j
        f = F[o]
        if f == 0.0:
            continue
        y = coords[j]
        if area:
            cross_grad += _tension_integrand(cur, o, n, 1, f, x, y, inv_2dx, p)[2]
        moments = _friction_moments(cur, o, n * n, f, x, y, p.flow)
        moment += moments[3]
        cross_v += moments[4]
    sums[i, 0] = cross_grad
    sums[i, 1] = moment
    sums[i, 2] = cross_v


@nb.njit(inline="always", **_LOOP)
def _euler_rows(bufs, i0, i1, domain, coef, dt, omega, flow):
    """:func:`_euler_row` of the rows [i0, i1), `flow` a compile-time constant; `bufs` is
    (cur, nxt, F, G)."""
    for i in range(i0, i1):
        _euler_row(bufs, i, domain, coef, dt, omega, flow)


# Called, not inlined: a prange body stays small and fast to compile. numba's (private)
# ``_nrt=False``: no reference counting of the arrays, which in these nested loops numba
# would not prune (a fifth of the Euler update); the block allocates nothing.
@nb.njit(_nrt=False, **_LOOP)
def _sweep_block(bufs, domain, params, tables, plate, work, b, blocks):
    """The rows of block b of `blocks` (groups of :data:`.spline.ROW_GROUP` rows, every
    `blocks`-th group): see :func:`sweep_rows`; `work` is (coef, sums, scratch
    (:data:`.indicators.SCRATCH_ROWS`, n), taps (n, unsigned))."""
    p = params[0]  # read here: numba cannot pass a record into a prange loop's body
    cur, _, F, G = bufs
    tab, turned, omega = plate
    coef, sums, scratch, taps = work
    coords, _, _, slo, shi = domain
    n = coords.size
    rates = _rate_coefficients(p)
    dt = p.dt
    inv_2dx = 0.5 / (coords[1] - coords[0])
    w_lo, w_hi = p.window_lo, p.window_hi
    for g in range(b, (n + ROW_GROUP - 1) // ROW_GROUP, blocks):
        i0 = g * ROW_GROUP
        i1 = min(n, i0 + ROW_GROUP)
        for i in range(i0, i1):
            j0, j1 = slo[i], shi[i]
            if turned and j1 > j0:
                indicator_row(F, G, i, coords, j0, j1, p, tab, tables, (scratch, taps))
            if p.contour:  # two calls, so that `area` is a compile-time constant of each
                _row_integrals(cur, F, i, coords, j0, j1, p, inv_2dx, False, sums)
            else:
                _row_integrals(cur, F, i, coords, j0, j1, p, inv_2dx, True, sums)
        if p.flow:  # two loops, so that `flow` is a compile-time constant of each
            _euler_rows(bufs, i0, i1, domain, rates, dt, omega, True)
        else:
            _euler_rows(bufs, i0, i1, domain, rates, dt, omega, False)
        if p.contour and max(i0, w_lo) < min(i1, w_hi):
            r0, r1 = max(i0, w_lo), min(i1, w_hi)
            spline_rows(cur, coef, n, r0, r1, w_lo, w_hi, (p.taps_lo, w_hi), scratch[3])


@nb.njit(**_PARALLEL)
def sweep_rows(bufs, domain, params, tables, plate, out, threads):
    """One pass over the rows of the grid: all of a step's work that goes row by row.

    `bufs` is (cur, nxt, F, G): the flat state now and after the step, the flat
    indicators; `plate` is (tab, turned, omega): the rotor table, whether the plate
    turned, its angular velocity; `out` is (coef, sums); `domain`, `params` and `tables`
    as for :func:`advance`.

    For each row i: F and G of its support cells at the angle of the rotor table `tab`
    if the plate `turned` (:func:`pde_rotor.kernels.indicators.indicator_row`), the
    row's sums of the integrands of Eq. (eq_motion) on `cur` into sums[i] (n, 3), the
    Euler step of Eqs. (eqc), (eqv) of its interior cells from `cur` into `nxt` with the
    angular velocity `omega` and, with the contour torque, the row's part of the spline
    window of c into `coef` (:func:`.spline.spline_rows`). A row reads F and G of its
    own cells only, so all of this fits in one pass. The rows go in groups of
    :data:`.spline.ROW_GROUP`, every `threads`-th group to one block of a numba
    ``prange`` (one block per thread of ``numba.set_num_threads``); each row's results
    are the same however the rows are shared.
    """
    coef, sums = out
    n = domain[0].size
    blocks = min(threads, n // ROW_GROUP)
    if blocks <= 1:  # no parallel region to start
        for b in range(blocks):
            work = (coef, sums, np.empty((SCRATCH_ROWS, n)), np.empty(n, np.uint64))
            _sweep_block(bufs, domain, params, tables, plate, work, b, 1)
    else:
        for b in nb.prange(blocks):
            work = (coef, sums, np.empty((SCRATCH_ROWS, n)), np.empty(n, np.uint64))
            _sweep_block(bufs, domain, params, tables, plate, work, np.int64(b), blocks)


@nb.njit(**_LOOP)
def _window_columns(coef, n, lo, hi, taps_lo, taps_hi):
    """The spline window's columns (x) [taps_lo, taps_hi) over its rows [lo, hi) (those
    the contour's taps read, :func:`.spline.spline_columns`)."""
    carry = np.empty(taps_hi - taps_lo)
    spline_columns(coef, n, lo, hi, taps_lo, taps_hi, (taps_lo, hi), carry)


@nb.njit(_nrt=False, **_LOOP)  # called, not inlined: a prange body stays small
def _contour_block(coef, coords, params, tab, quad_s, quad_t, sums, scratch, b, blocks):
    """Block b of the contour nodes: the sum over the nodes along the edge of each
    (edge j, band node m) of every `blocks`-th pair into sums[j M + m], in two passes
    over a pair's nodes: where each node reads the spline (:func:`place_nodes`, SIMD),
    then the 16-tap sums ``spline_sum`` times the torque's weights, added in
    order (the torque of the tension's ``edge_node``, node by node)."""
    p = params[0]
    n = coords.size
    x0 = coords[0]
    inv_dx = 1.0 / p.dx
    n_s, n_t = quad_s.shape[1], quad_t.shape[1]
    apothem, delta, tan_half = p.apothem, p.smoothing, p.tan_half
    taps, weights = scratch
    sx, sy = np.uint64(n), np.uint64(1)
    grid = (0, n, x0, inv_dx)
    for pair in range(b, p.n_corners * n_s, blocks):
        j = pair // n_s
        m = pair - j * n_s
        h, half = _polygon_band(apothem, delta, tan_half, quad_s, m)
        edge = (0.0, 0.0, tab[0, j], tab[1, j], h, half)
        place_nodes(grid, edge, quad_s, quad_t, m, taps, weights)
        total = 0.0
        for k_t in range(n_t):
            total += weights[9, k_t] * node_pressure(coef, taps, weights, k_t, sx, sy, p)
        sums[pair] = total


@nb.njit(**_PARALLEL)
def contour_torque(coef, coords, params, tab, tables, sums, threads):
    """int F r x grad c dA in contour form (compiled), after :func:`sweep_rows` has filled
    the rows of the spline window of c into `coef`: the window's columns
    (:func:`.spline.spline_columns`, 0.002 ms, on the calling thread: shared among threads
    they would cost a parallel loop's start and their cache lines' moves from core to
    core), then the nodes of the tension's ``edge_node`` (:func:`_contour_block`)
    in `threads` blocks of (edge, band node) pairs; `sums` (N M) receives the pairs'
    sums, added in order (the same for any number of threads)."""
    p = params[0]
    quad_s, quad_t = tables[0], tables[1]
    n = coords.size
    pairs = p.n_corners * quad_s.shape[1]
    _window_columns(coef, n, p.window_lo, p.window_hi, p.taps_lo, p.taps_hi)
    blocks = min(threads, pairs)
    if blocks <= 1:  # no parallel region to start
        for b in range(1):
            scratch = node_scratch(quad_t.shape[1])
            _contour_block(coef, coords, params, tab, quad_s, quad_t, sums, scratch, b, 1)
    else:
        for b in nb.prange(blocks):
            scratch = node_scratch(quad_t.shape[1])
            _contour_block(
                coef, coords, params, tab, quad_s, quad_t, sums, scratch, np.int64(b), blocks
            )
    total = 0.0
    for pair in range(pairs):
        total += sums[pair]
    return total


@nb.njit(**_LOOP)  # called, not inlined: a prange body stays small, fast to compile
def _average_rows(cur, stage, nxt, domain, flow, b, blocks):
    """nxt = (cur + stage) / 2 on the interior cells of every `blocks`-th row from b."""
    coords, lo, hi, _, _ = domain
    n = coords.size
    for ch in range(3 if flow else 1):
        for i in range(b, n, blocks):
            row = ch * n * n + i * n
            for j in range(lo[i], hi[i]):
                nxt[row + j] = 0.5 * (cur[row + j] + stage[row + j])


@nb.njit(**_PARALLEL)
def heun_average(cur, stage, nxt, domain, flow, threads):
    """nxt = (cur + stage) / 2 on the interior cells of c (and v with `flow`) (compiled),
    the rows in `threads` blocks.

    With stage = y~ + dt f(y~), y~ = y + dt f(y), this is Heun's y + dt (f(y) + f(y~)) / 2.
    """
    if threads <= 1:  # no parallel region to start
        for b in range(threads):
            _average_rows(cur, stage, nxt, domain, flow, b, threads)
    else:
        for b in nb.prange(threads):
            _average_rows(cur, stage, nxt, domain, flow, np.int64(b), threads)


@nb.njit(inline="always", **_LOOP)
def _total_integrals(sums, coords):
    """The integrals of Eq. (eq_motion) from the rows' sums (n, 3), added row by row in
    order, times dA: (int F r x grad c dA in area form, int F |r|^2 dA, int F r x v dA)."""
    cross_grad = 0.0
    moment = 0.0
    cross_v = 0.0
    for i in range(sums.shape[0]):
        cross_grad += sums[i, 0]
        moment += sums[i, 1]
        cross_v += sums[i, 2]
    dx = coords[1] - coords[0]
    area = dx * dx
    return cross_grad * area, moment * area, cross_v * area


@nb.njit(inline="always", **_LOOP)
def _step(bufs, domain, params, tables, tab, pose, turned, work, threads):
    """A step's pass over the grid at the rotor's `pose` (angle phi, angular velocity
    omega; the motion's pose of the body at X = 0): F and G anew if
    the plate `turned` since they were computed, the Euler step of the fields from `cur`
    into `nxt` (`bufs` = (cur, nxt, F, G), :func:`sweep_rows`) and the torques on `cur`
    (the contour form by :func:`contour_torque`), in `threads` blocks. `tab` is the rotor
    table, `work` (coef, row sums, pair sums) scratch.

    Returns:
        The rotor's loads, Eqs. (torque), (eq_motion) (the motion's ``body_loads`` of the
        body at X = 0).
    """
    p = params[0]
    phi, omega = pose[2], pose[5]
    coef, sums, pair_sums = work
    if turned:
        _rotor_table(phi, p.n_corners, p.pill_distance, p.asymmetry, tab)
    sweep_rows(bufs, domain, params, tables, (tab, turned, omega), (coef, sums), threads)
    cross_grad, moment, cross_v = _total_integrals(sums, domain[0])
    if p.contour:
        cross_grad = contour_torque(coef, domain[0], params, tab, tables, pair_sums, threads)
    integrals = (0.0, 0.0, cross_grad, 0.0, 0.0, 0.0, moment, cross_v, 0.0, 0.0)
    return _body_loads(integrals, pose, p, p.torque_sign * p.tension_slope)


@nb.njit(**_LOOP)
def advance(states, maps, domain, params, tables, rotor, xi, steps, threads):
    """Advance c, v, phi, omega by `n_steps` fused steps, Euler or Heun (compiled).

    Forward Euler (the paper's method) when `stage` is empty. Otherwise Heun's method
    (explicit trapezoidal rule, second order): a predictor Euler step of fields and rotor
    from (y, phi, omega), F and G and the rotor integrals recomputed at the predicted
    angle and state, a second Euler step from there into `stage`, and the average
    y + dt (f(y) + f(y~)) / 2 (:func:`heun_average`); phi and omega likewise. The noise
    kick is additive, added once per step (stochastic Heun for additive noise). The
    rotor is the ``fixed_axis`` body at the origin: the step's tail (stop, loads,
    finiteness, step, kick) is the motion's (:mod:`pde_rotor.physics.motion`), the same
    as every body's (:func:`pde_rotor.kernels.bodies.advance_bodies`).

    The grid's work is shared among `threads` blocks, run on numba's threads (numba
    ``prange``; the caller sets their number with ``numba.set_num_threads``): rows,
    spline columns and contour nodes. Every sum is taken over fixed parts (rows, node
    pairs) in a fixed order, so the result has the same bits for any number of threads.

    Args:
        states: (data, spare, stage): the flat state (c, v_x, v_y), 3 n^2 values,
            updated in place; scratch of the same shape; scratch of the same shape for
            Heun's method, or empty for Euler.
        maps: (F, G): flat indicator arrays (n^2), zero outside the support, updated in
            place.
        domain: (coords, lo, hi, slo, shi): cell-centre coordinates, the interior and
            the support column ranges [lo, hi) per row.
        params: the run's parameter record, the (1,) array of
            :func:`pde_rotor.kernels.records.make_record` (an array, which numba's
            dispatcher types faster than a bare record); without ``flow`` v is set to 0
            and stays 0 (Fig. 8).
        tables: (quad_s, quad_t, plate, edge, pill): the scheme's quadrature rules and
            filter tables (:class:`~pde_rotor.model.schemes.Scheme`).
        rotor: [phi, omega, torque, friction, stopped], updated in place.
        xi: one standard normal per step for the noise (read where ``kick`` != 0).
        steps: (step0, n_steps): global index of the first step (t = step0 dt), number
            of steps.
        threads: blocks the grid's work is split into (1: one thread, no parallel region).

    Returns:
        -1 on success, else the index of the step at which phi, omega or T stopped
        being finite (the state is then left at the start of that step).
    """
    data, spare, stage = states
    F, G = maps
    step0, n_steps = steps
    p = params[0]
    dt = p.dt
    pose = (0.0, 0.0, rotor[0], 0.0, 0.0, rotor[1])
    cur = data
    nxt = spare
    n = domain[0].size
    nn = n * n
    tab = np.empty((4, p.n_corners))
    work = (
        np.zeros(nn) if p.contour else np.zeros(0),
        np.zeros((n, 3)),
        np.zeros(p.n_corners * tables[0].shape[1]),
    )
    phi_f = math.nan
    noisy = p.kick != 0.0
    heun = stage.size > 0
    if not p.flow:
        data[nn:] = 0.0
        spare[nn:] = 0.0
    for s in range(n_steps):
        stopped = _held(step0 + s, p)
        pose = _hold(pose, stopped)
        loads = _step(
            (cur, nxt, F, G), domain, params, tables, tab, pose, pose[2] != phi_f, work, threads
        )
        phi_f = pose[2]
        if not _finite_loads(loads):
            if s % 2 == 1:
                data[:] = spare
            rotor[0], rotor[1] = pose[2], pose[5]
            return s
        if heun:
            predicted = pose if stopped else _euler_pose(pose, loads, dt, p)
            turned = predicted[2] != phi_f
            loads_p = _step(
                (nxt, stage, F, G), domain, params, tables, tab, predicted, turned, work, threads
            )
            phi_f = predicted[2]
            heun_average(cur, stage, nxt, domain, p.flow, threads)
            if not stopped:
                pose = _heun_pose(pose, loads, predicted, loads_p, dt, p)
        elif not stopped:
            pose = _euler_pose(pose, loads, dt, p)
        if noisy and not stopped:
            pose = _noise_kick(pose, xi[s], p)
        cur, nxt = nxt, cur
        rotor[2], rotor[3], rotor[4] = loads[2], loads[5], 1.0 if stopped else 0.0
    if n_steps % 2 == 1:
        data[:] = spare
    rotor[0], rotor[1] = pose[2], pose[5]
    return -1


@nb.njit(**_LOOP)
def euler_fields(cur, nxt, F, G, domain, params, omega):
    """One Euler step of Eqs. (eqc) and (eqv) (or (eqc) alone) on all interior cells,
    row by row as the time step's :func:`sweep_rows` (compiled; tests and profiles).

    Args:
        cur: flat state (c, v_x, v_y) at the old time level, 3 n^2 values.
        nxt: receives the new state on interior cells.
        F, G: flat plate and pill indicators (zero outside the support).
        domain: (coords, lo, hi, slo, shi) as for :func:`advance`.
        params: the parameter record as for :func:`advance`; without ``flow`` only c is
            advanced (v = 0, Fig. 8).
        omega: plate angular velocity (0 during a stop).
    """
    p = params[0]
    rates = _rate_coefficients(p)
    n = domain[0].size
    if p.flow:  # as in _sweep_block
        _euler_rows((cur, nxt, F, G), 0, n, domain, rates, p.dt, omega, True)
    else:
        _euler_rows((cur, nxt, F, G), 0, n, domain, rates, p.dt, omega, False)


@nb.njit(**_LOOP)
def rotor_integrals(cur, F, domain, params, tab, tables, coef):
    """The integrals of Eq. (eq_motion) over the plate, as the time step takes them
    (compiled; tests and profiles).

    `tab` must hold the rotor table of the current angle
    (:func:`pde_rotor.kernels.indicators.update_indicators`); `domain`, `params` and
    `tables` as for :func:`advance`; `coef` (n^2) is scratch for the spline coefficients
    of the contour form.

    Returns:
        (int F r x grad c dA, int F |r|^2 dA, int F r x v dA); the first in area form
        with central differences, or in contour form with the record's ``contour``.
    """
    p = params[0]
    coords, _, _, slo, shi = domain
    n = coords.size
    inv_2dx = 0.5 / (coords[1] - coords[0])
    sums = np.zeros((n, 3))
    for i in range(n):
        _row_integrals(cur, F, i, coords, slo[i], shi[i], p, inv_2dx, True, sums)
    cross_grad, moment, cross_v = _total_integrals(sums, coords)
    if p.contour:
        spline_window(cur, coef, n, p.window_lo, p.window_hi, p.taps_lo, p.taps_hi)
        pair_sums = np.zeros(p.n_corners * tables[0].shape[1])
        for b in range(1):  # as contour_torque calls it
            scratch = node_scratch(tables[1].shape[1])
            _contour_block(
                coef, coords, params, tab, tables[0], tables[1], pair_sums, scratch, b, 1
            )
        cross_grad = 0.0
        for pair in range(pair_sums.size):
            cross_grad += pair_sums[pair]
    return cross_grad, moment, cross_v
