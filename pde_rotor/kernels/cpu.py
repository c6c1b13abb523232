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

from ..model.protocol import stopped_at
from .core import (
    CPU,
    FASTMATH,
    M_CONTOUR,
    M_TAN_HALF,
    M_WINDOW_HI,
    M_WINDOW_LO,
    P_DT,
    P_I,
    P_K,
    P_MU,
    P_TSIGN,
    S_APOTHEM,
    S_DELTA,
    S_N,
)
from .indicators import update_indicators

_cell_rates = CPU.cell_rates
_rate_coefficients = CPU.rate_coefficients
_cell_integrals = CPU.cell_integrals
_contour_node = CPU.contour_node
_spline_line = CPU.spline_line


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
def euler_fields(cur, nxt, F, G, coords, lo, hi, slo, shi, par, omega, flow):
    """One Euler step of Eqs. (eqc) and (eqv) (or (eqc) alone) on all interior cells.

    Args:
        cur: flat state (c, v_x, v_y) at the old time level, 3 n^2 values.
        nxt: receives the new state on interior cells.
        F, G: flat plate and pill indicators (zero outside the support).
        coords: cell-centre coordinates.
        lo, hi: interior column ranges per row.
        slo, shi: support column ranges per row (inside the interior ranges).
        par: float parameters (indices P_* of :mod:`pde_rotor.kernels.core`).
        omega: plate angular velocity (0 during a stop).
        flow: whether v is advanced (False: v = 0, Fig. 8).
    """
    if flow:  # two loops, so that `flow` is a compile-time constant of each
        _euler_rows(cur, nxt, F, G, coords, lo, hi, slo, shi, par, omega, True)
    else:
        _euler_rows(cur, nxt, F, G, coords, lo, hi, slo, shi, par, omega, False)


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH, inline="always")
def _euler_rows(cur, nxt, F, G, coords, lo, hi, slo, shi, par, omega, flow):
    """The rows of :func:`euler_fields`, each split into off-support and support cells."""
    n = coords.size
    sx = np.uint64(n)
    nn = np.uint64(n * n)
    coef = _rate_coefficients(par)
    dt = par[P_DT]
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
def rotor_integrals(cur, F, coords, slo, shi, shape, tab, num, quad_s, quad_t, flow, coef):
    """The integrals of Eq. (eq_motion) over the plate (compiled).

    `tab` must hold the rotor table of the current angle
    (:func:`pde_rotor.kernels.indicators.update_indicators`).
    `num` is :meth:`~pde_rotor.model.schemes.Scheme.as_array`; `coef` (n^2) is scratch for the
    spline coefficients of the contour form.

    Returns:
        (int F r x grad c dA, int F |r|^2 dA, int F r x v dA); the first in area form
        with central differences, or in contour form when num[M_CONTOUR] != 0.
    """
    n = coords.size
    dx = coords[1] - coords[0]
    inv_2dx = 0.5 / dx
    sx, nn = n, n * n
    contour = num[M_CONTOUR] != 0.0
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
        spline_window(cur, coef, n, int(num[M_WINDOW_LO]), int(num[M_WINDOW_HI]))
        cross_grad = 0.0
        n_nodes = int(shape[S_N]) * quad_s.shape[1] * quad_t.shape[1]
        apothem, delta = shape[S_APOTHEM], shape[S_DELTA]
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
                num[M_TAN_HALF],
                quad_s,
                quad_t,
                q,
            )
        return cross_grad, moment * area, cross_v * area
    return cross_grad * area, moment * area, cross_v * area


@nb.njit(cache=True, nogil=True)
def rotor_forces(
    state,
    phi,
    omega,
    indicator_phi,
    F,
    G,
    coords,
    slo,
    shi,
    shape,
    tab,
    num,
    tables,
    par,
    flow,
    coef,
):
    """Torque T, Eq. (torque), and friction torque of Eq. (eq_motion) at `state` (compiled).

    F and G (and the rotor table `tab`) are recomputed for angle `phi` unless they already
    hold it (`indicator_phi` == phi). `tables` is (quad_s, quad_t, plate_tab, edge_tab,
    pill_tab) of the scheme; the other arguments as for :func:`advance`.

    Returns:
        (T, -mu int F (|r|^2 omega - r x v) dA).
    """
    quad_s, quad_t, plate_tab, edge_tab, pill_tab = tables
    if phi != indicator_phi:
        update_indicators(
            F, G, coords, slo, shi, shape, tab, num, plate_tab, edge_tab, pill_tab, phi
        )
    cross_grad, moment, cross_v = rotor_integrals(
        state, F, coords, slo, shi, shape, tab, num, quad_s, quad_t, flow, coef
    )
    return par[P_TSIGN] * par[P_K] * cross_grad, -par[P_MU] * (moment * omega - cross_v)


@nb.njit(cache=True, nogil=True)
def advance(
    data,
    spare,
    stage,
    F,
    G,
    coords,
    lo,
    hi,
    slo,
    shi,
    shape,
    par,
    num,
    quad_s,
    quad_t,
    plate_tab,
    edge_tab,
    pill_tab,
    flow,
    schedule,
    rotor,
    kicks,
    step0,
    n_steps,
):
    """Advance c, v, phi, omega by `n_steps` fused steps, Euler or Heun (compiled).

    Forward Euler (the paper's method) when `stage` is empty. Otherwise Heun's method
    (explicit trapezoidal rule, second order): a predictor Euler step of fields and rotor
    from (y, phi, omega), F and G and the rotor integrals recomputed at the predicted
    angle and state, a second Euler step from there into `stage`, and the average
    y + dt (f(y) + f(y~)) / 2 (:func:`heun_average`); phi and omega likewise. The noise
    kick is additive, added once per step (stochastic Heun for additive noise).

    Args:
        data: flat state (c, v_x, v_y), 3 n^2 values, updated in place.
        spare: scratch array of the same shape.
        stage: scratch of the same shape for Heun's method, or empty for Euler.
        F, G: flat indicator arrays (n^2), zero outside the support, updated in place.
        coords: cell-centre coordinates.
        lo, hi: interior column ranges per row.
        slo, shi: support column ranges per row.
        shape: :meth:`RotorShape.as_array`.
        par: float parameters, indices P_* of :mod:`pde_rotor.kernels.core`.
        num: :meth:`~pde_rotor.model.schemes.Scheme.as_array`.
        quad_s, quad_t: the scheme's quadrature rules (:class:`~pde_rotor.model.schemes.Scheme`).
        plate_tab, edge_tab, pill_tab: the scheme's filter tables
            (:meth:`~pde_rotor.model.schemes.Scheme.table_arrays`).
        flow: whether the flow is on (False: v is set to 0 and stays 0, Fig. 8).
        schedule: :meth:`StopSchedule.as_array`.
        rotor: [phi, omega, torque, friction, stopped], updated in place.
        kicks: Euler-Maruyama noise increments of omega, one per step (may be empty).
        step0: global index of the first step (t = step0 dt).
        n_steps: number of steps.

    Returns:
        -1 on success, else the index of the step at which phi, omega or T stopped
        being finite (the state is then left at the start of that step).
    """
    dt, inv_inertia = par[P_DT], 1.0 / par[P_I]
    tables = (quad_s, quad_t, plate_tab, edge_tab, pill_tab)
    phi, omega = rotor[0], rotor[1]
    cur = data
    nxt = spare
    nn = coords.size * coords.size
    tab = np.empty((4, int(shape[S_N])))
    coef = np.zeros(nn) if num[M_CONTOUR] != 0.0 else np.zeros(0)
    phi_f = math.nan
    noisy = kicks.size > 0
    heun = stage.size > 0
    if not flow:
        data[nn:] = 0.0
        spare[nn:] = 0.0
    for s in range(n_steps):
        stopped = stopped_at(step0 + s, schedule)
        if stopped:
            omega = 0.0
        torque, friction = rotor_forces(
            cur, phi, omega, phi_f, F, G, coords, slo, shi, shape, tab, num, tables, par, flow, coef
        )
        phi_f = phi
        if not (math.isfinite(torque) and math.isfinite(friction)):
            if s % 2 == 1:
                data[:] = spare
            rotor[0], rotor[1] = phi, omega
            return s
        euler_fields(cur, nxt, F, G, coords, lo, hi, slo, shi, par, omega, flow)
        rate_omega = (friction + torque) * inv_inertia
        if heun:
            phi_p, omega_p = phi, 0.0
            if not stopped:
                phi_p = phi + dt * omega
                omega_p = omega + dt * rate_omega
            torque_p, friction_p = rotor_forces(
                nxt,
                phi_p,
                omega_p,
                phi_f,
                F,
                G,
                coords,
                slo,
                shi,
                shape,
                tab,
                num,
                tables,
                par,
                flow,
                coef,
            )
            phi_f = phi_p
            euler_fields(nxt, stage, F, G, coords, lo, hi, slo, shi, par, omega_p, flow)
            heun_average(cur, stage, nxt, coords.size, lo, hi, flow)
            if not stopped:
                phi += 0.5 * dt * (omega + omega_p)
                omega += 0.5 * dt * (rate_omega + (friction_p + torque_p) * inv_inertia)
                if noisy:
                    omega += kicks[s]
        elif not stopped:
            phi += dt * omega
            omega += dt * rate_omega
            if noisy:
                omega += kicks[s]
        cur, nxt = nxt, cur
        rotor[2], rotor[3], rotor[4] = torque, friction, 1.0 if stopped else 0.0
    if n_steps % 2 == 1:
        data[:] = spare
    rotor[0], rotor[1] = phi, omega
    return -1
