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
integrals: the physics core (:mod:`pde_rotor.kernels.core`) in the scheme of ``numerics.scheme``
(:mod:`pde_rotor.model.schemes`). These loops only walk the grid and call the core; the GPU
backend calls the same core from its threads. :mod:`pde_rotor.solver.rotor` binds them to a
simulation and to py-pde.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from .core import CPU, FASTMATH
from .indicators import update_indicators

_cell_rates = CPU.cell_rates
_rate_coefficients = CPU.rate_coefficients
_cell_integrals = CPU.cell_integrals
_contour_node = CPU.contour_node
_spline_line = CPU.spline_line
_stopped_at = CPU.stopped_at
_rotor_torques = CPU.rotor_torques
_angular_acceleration = CPU.angular_acceleration
_euler_rotor = CPU.euler_rotor
_heun_rotor = CPU.heun_rotor
_noise_kick = CPU.noise_kick


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, inline="always")
def _euler_row(cur, nxt, F, G, y_of, coef, dt, omega, x, base, sx, nn, j0, j1, flow, plate):
    """Euler step of the cells [j0, j1) of one row (offset `base`) (compiled)."""
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
            cur, o, sx, sy, nn, f, g, omega, x, y_of[j], coef, flow, plate
        )
        nxt[o] = cc + dt * rate_c
        if flow:
            ox = o + nn
            nxt[ox] = ux + dt * rate_x
            nxt[ox + nn] = uy + dt * rate_y


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def euler_fields(cur, nxt, F, G, domain, params, omega):
    """One Euler step of Eqs. (eqc) and (eqv) (or (eqc) alone) on all interior cells.

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
    coef = _rate_coefficients(p)
    if p.flow:  # two loops, so that `flow` is a compile-time constant of each
        _euler_rows(cur, nxt, F, G, domain, coef, p.dt, omega, True)
    else:
        _euler_rows(cur, nxt, F, G, domain, coef, p.dt, omega, False)


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, inline="always")
def _euler_rows(cur, nxt, F, G, domain, coef, dt, omega, flow):
    """The rows of :func:`euler_fields`, each split into off-support and support cells."""
    coords, lo, hi, slo, shi = domain
    n = coords.size
    sx = np.uint64(n)
    nn = np.uint64(n * n)
    for i in range(n):
        x = coords[i]
        base = np.uint64(i * n)
        j0, j1 = np.uint64(lo[i]), np.uint64(hi[i])
        if shi[i] > slo[i]:
            s0, s1 = np.uint64(slo[i]), np.uint64(shi[i])
            _euler_row(
                cur, nxt, F, G, coords, coef, dt, omega, x, base, sx, nn, j0, s0, flow, False
            )
            _euler_row(cur, nxt, F, G, coords, coef, dt, omega, x, base, sx, nn, s0, s1, flow, True)
            _euler_row(
                cur, nxt, F, G, coords, coef, dt, omega, x, base, sx, nn, s1, j1, flow, False
            )
        else:
            _euler_row(
                cur, nxt, F, G, coords, coef, dt, omega, x, base, sx, nn, j0, j1, flow, False
            )


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def heun_average(cur, stage, nxt, n, lo, hi, flow):
    """nxt = (cur + stage) / 2 on the interior cells of c (and v with `flow`) (compiled).

    With stage = y~ + dt f(y~), y~ = y + dt f(y), this is Heun's y + dt (f(y) + f(y~)) / 2.
    """
    nn = n * n
    for ch in range(3 if flow else 1):
        for i in range(n):
            row = ch * nn + i * n
            for j in range(lo[i], hi[i]):
                nxt[row + j] = 0.5 * (cur[row + j] + stage[row + j])


@nb.njit(cache=True, nogil=True)
def spline_window(cur, coef, n, lo, hi):
    """coef[window] = cubic B-spline coefficients of c (cur[:n^2]) on rows, columns [lo, hi)."""
    for i in range(lo, hi):
        for j in range(lo, hi):
            coef[i * n + j] = cur[i * n + j]
    for i in range(lo, hi):
        _spline_line(coef, i * n + lo, 1, hi - lo)
    for j in range(lo, hi):
        _spline_line(coef, lo * n + j, n, hi - lo)


@nb.njit(cache=True, nogil=True)
def rotor_integrals(cur, F, domain, params, tab, tables, coef):
    """The integrals of Eq. (eq_motion) over the plate (compiled).

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
    quad_s, quad_t = tables[0], tables[1]
    flow = p.flow
    n = coords.size
    dx = coords[1] - coords[0]
    inv_2dx = 0.5 / dx
    sx, nn = n, n * n
    contour = p.contour
    cross_grad = 0.0
    moment = 0.0
    cross_v = 0.0
    for i in range(n):
        x = coords[i]
        for j in range(slo[i], shi[i]):
            o = i * n + j
            f = F[o]
            if f == 0.0:
                continue
            grad, mom, vel = _cell_integrals(cur, o, sx, 1, nn, f, x, coords[j], inv_2dx, flow)
            cross_grad += grad
            moment += mom
            cross_v += vel
    area = dx * dx
    if contour:
        spline_window(cur, coef, n, p.window_lo, p.window_hi)
        cross_grad = 0.0
        n_nodes = p.n_corners * quad_s.shape[1] * quad_t.shape[1]
        apothem, delta, tan_half = p.apothem, p.smoothing, p.tan_half
        for q in range(n_nodes):
            cross_grad += _contour_node(
                coef,
                0,
                n,
                coords[0],
                1.0 / dx,
                tab,
                apothem,
                delta,
                tan_half,
                quad_s,
                quad_t,
                q,
            )
        return cross_grad, moment * area, cross_v * area
    return cross_grad * area, moment * area, cross_v * area


@nb.njit(cache=True, nogil=True)
def rotor_forces(state, phi, omega, indicator_phi, F, G, domain, params, tab, tables, coef):
    """Torque T, Eq. (torque), and friction torque of Eq. (eq_motion) at `state` (compiled).

    F and G (and the rotor table `tab`) are recomputed for angle `phi` unless they already
    hold it (`indicator_phi` == phi); the other arguments as for :func:`advance`.

    Returns:
        (T, -mu int F (|r|^2 omega - r x v) dA).
    """
    if phi != indicator_phi:
        update_indicators(F, G, domain, params, tab, tables, phi)
    cross_grad, moment, cross_v = rotor_integrals(state, F, domain, params, tab, tables, coef)
    return _rotor_torques(cross_grad, moment, cross_v, omega, params[0])


@nb.njit(cache=True, nogil=True)
def advance(data, spare, stage, F, G, domain, params, tables, rotor, xi, step0, n_steps):
    """Advance c, v, phi, omega by `n_steps` fused steps, Euler or Heun (compiled).

    Forward Euler (the paper's method) when `stage` is empty. Otherwise Heun's method
    (explicit trapezoidal rule, second order): a predictor Euler step of fields and rotor
    from (y, phi, omega), F and G and the rotor integrals recomputed at the predicted
    angle and state, a second Euler step from there into `stage`, and the average
    y + dt (f(y) + f(y~)) / 2 (:func:`heun_average`); phi and omega likewise. The noise
    kick is additive, added once per step (stochastic Heun for additive noise). The
    stop schedule, the torques and the rotor's update are the physics core's.

    Args:
        data: flat state (c, v_x, v_y), 3 n^2 values, updated in place.
        spare: scratch array of the same shape.
        stage: scratch of the same shape for Heun's method, or empty for Euler.
        F, G: flat indicator arrays (n^2), zero outside the support, updated in place.
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
        step0: global index of the first step (t = step0 dt).
        n_steps: number of steps.

    Returns:
        -1 on success, else the index of the step at which phi, omega or T stopped
        being finite (the state is then left at the start of that step).
    """
    p = params[0]
    dt = p.dt
    phi, omega = rotor[0], rotor[1]
    cur = data
    nxt = spare
    n = domain[0].size
    nn = n * n
    tab = np.empty((4, p.n_corners))
    coef = np.zeros(nn) if p.contour else np.zeros(0)
    phi_f = math.nan
    noisy = p.kick != 0.0
    heun = stage.size > 0
    if not p.flow:
        data[nn:] = 0.0
        spare[nn:] = 0.0
    for s in range(n_steps):
        stopped = _stopped_at(step0 + s, p.n_ini, p.n_stop, p.n_period, p.cycles)
        if stopped:
            omega = 0.0
        torque, friction = rotor_forces(
            cur, phi, omega, phi_f, F, G, domain, params, tab, tables, coef
        )
        phi_f = phi
        if not (math.isfinite(torque) and math.isfinite(friction)):
            if s % 2 == 1:
                data[:] = spare
            rotor[0], rotor[1] = phi, omega
            return s
        euler_fields(cur, nxt, F, G, domain, params, omega)
        accel = _angular_acceleration(torque, friction, p)
        if heun:
            phi_p, omega_p = phi, 0.0
            if not stopped:
                phi_p, omega_p = _euler_rotor(phi, omega, accel, dt)
            torque_p, friction_p = rotor_forces(
                nxt, phi_p, omega_p, phi_f, F, G, domain, params, tab, tables, coef
            )
            phi_f = phi_p
            euler_fields(nxt, stage, F, G, domain, params, omega_p)
            heun_average(cur, stage, nxt, n, domain[1], domain[2], p.flow)
            if not stopped:
                accel_p = _angular_acceleration(torque_p, friction_p, p)
                phi, omega = _heun_rotor(phi, omega, accel, omega_p, accel_p, dt)
        elif not stopped:
            phi, omega = _euler_rotor(phi, omega, accel, dt)
        if noisy and not stopped:
            omega = _noise_kick(omega, xi[s], p)
        cur, nxt = nxt, cur
        rotor[2], rotor[3], rotor[4] = torque, friction, 1.0 if stopped else 0.0
    if n_steps % 2 == 1:
        data[:] = spare
    rotor[0], rotor[1] = phi, omega
    return -1
