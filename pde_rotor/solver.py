"""Fused explicit Euler solver for c, v, phi and omega (py-pde SolverBase subclass).

One compiled loop advances, every time step dt, all three unknowns of the paper's model:

* camphor c, Eq. (eqc): dc/dt = D lap c - div(c v) - a (1 - F) c + s0/(pi rho^2) G;
* flow v, Eq. (eqv): dv/dt = eta F (omega (-y, x) - v) - eta_b v + D_eta lap v;
* rotor, Eq. (eq_motion): I domega/dt = -mu int F (|r|^2 omega - r x v) dA + T + xi,
  dphi/dt = omega, with the torque T of Eq. (torque) (see :mod:`pde_rotor.model` for the
  sign) and Gaussian white noise xi, Eq. (noiseav), integrated by Euler-Maruyama.

Space: 5-point Laplacian, central differences for div(c v) and grad c (the paper's
"explicit method for the spatial derivative"); time: forward Euler with step dt (the
paper's "Euler method"). Every right-hand side is evaluated at the old time level.

The kernel functions are module-level numba functions compiled once per process (and
cached on disk); :func:`make_fused_stepper` binds them to arrays and parameters.
py-pde has no built-in coupling of ODEs to fields (py-pde issue #533), so
:class:`RotorSolver` replaces ``make_stepper``: py-pde's Controller drives it and its
trackers work unchanged.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numba as nb
import numpy as np
from pde import FieldCollection
from pde.solvers.base import SolverBase

from .geometry import update_indicators
from .model import RotorPDE
from .protocol import StopSchedule, stopped_at


class SimulationDivergedError(FloatingPointError):
    """Raised when the state stops being finite (NaN/Inf); says where and when."""


# indices into the float parameter vector of the kernel
P_DT, P_DX, P_D, P_A, P_SRC, P_K, P_ETA, P_ETAB, P_DETA, P_I, P_MU, P_TSIGN = range(12)


_FAST = {"contract", "arcp", "nsz"}


@nb.njit(cache=True, nogil=True, fastmath=_FAST, inline="always")
def _row_with_flow(cur, nxt, F, G, coords, par, omega, u, x, j0, j1, plate):
    """Euler step of Eqs. (eqc), (eqv) on cells [j0, j1) of row u (compiled).

    `plate` is False on cells outside the support of F and G (F = G = 0 there), which then
    skip reading F and G. Indices are unsigned, so numba emits no negative-index
    wraparound and LLVM vectorises the loop.
    """
    dt, dx = par[P_DT], par[P_DX]
    inv_dx2 = 1.0 / (dx * dx)
    inv_2dx = 0.5 / dx
    diff, evap, src = par[P_D], par[P_A], par[P_SRC]
    eta, eta_b, d_eta = par[P_ETA], par[P_ETAB], par[P_DETA]
    one = np.uint64(1)
    up, um = u + one, u - one
    for j in range(j0, j1):
        jp, jm = j + one, j - one
        cc = cur[0, u, j]
        ux = cur[1, u, j]
        uy = cur[2, u, j]
        lap_c = cur[0, up, j] + cur[0, um, j] + cur[0, u, jp] + cur[0, u, jm]
        div_cv = (
            cur[0, up, j] * cur[1, up, j]
            - cur[0, um, j] * cur[1, um, j]
            + cur[0, u, jp] * cur[2, u, jp]
            - cur[0, u, jm] * cur[2, u, jm]
        )
        lap_x = cur[1, up, j] + cur[1, um, j] + cur[1, u, jp] + cur[1, u, jm]
        lap_y = cur[2, up, j] + cur[2, um, j] + cur[2, u, jp] + cur[2, u, jm]
        rate_c = diff * (lap_c - 4.0 * cc) * inv_dx2 - div_cv * inv_2dx - evap * cc
        rate_x = d_eta * (lap_x - 4.0 * ux) * inv_dx2 - eta_b * ux
        rate_y = d_eta * (lap_y - 4.0 * uy) * inv_dx2 - eta_b * uy
        if plate:
            f = F[u, j]
            rate_c += evap * f * cc + src * G[u, j]
            rate_x += eta * f * (-omega * coords[j] - ux)
            rate_y += eta * f * (omega * x - uy)
        nxt[0, u, j] = cc + dt * rate_c
        nxt[1, u, j] = ux + dt * rate_x
        nxt[2, u, j] = uy + dt * rate_y


@nb.njit(cache=True, nogil=True, fastmath=_FAST, inline="always")
def _row_without_flow(cur, nxt, F, G, par, u, j0, j1, plate):
    """Euler step of Eq. (eqc) with v = 0 on cells [j0, j1) of row u (compiled)."""
    dt, dx = par[P_DT], par[P_DX]
    inv_dx2 = 1.0 / (dx * dx)
    diff, evap, src = par[P_D], par[P_A], par[P_SRC]
    one = np.uint64(1)
    up, um = u + one, u - one
    for j in range(j0, j1):
        cc = cur[0, u, j]
        lap_c = cur[0, up, j] + cur[0, um, j] + cur[0, u, j + one] + cur[0, u, j - one]
        rate_c = diff * (lap_c - 4.0 * cc) * inv_dx2 - evap * cc
        if plate:
            rate_c += evap * F[u, j] * cc + src * G[u, j]
        nxt[0, u, j] = cc + dt * rate_c


@nb.njit(cache=True, nogil=True, fastmath=_FAST)
def _fields_with_flow(cur, nxt, F, G, coords, lo, hi, slo, shi, par, omega):
    """One Euler step of Eqs. (eqc) and (eqv) on all interior cells (compiled).

    Args:
        cur: state (3, n, n) = (c, v_x, v_y) at the old time level.
        nxt: receives the new state on interior cells.
        F, G: plate and pill indicators (zero outside the support).
        coords: cell-centre coordinates.
        lo, hi: interior column ranges per row.
        slo, shi: support column ranges per row (inside the interior ranges).
        par: float parameters (indices P_*).
        omega: plate angular velocity (0 during a stop).
    """
    for i in range(coords.size):
        u = np.uint64(i)
        x = coords[i]
        j0, j1 = np.uint64(lo[i]), np.uint64(hi[i])
        if shi[i] > slo[i]:
            s0, s1 = np.uint64(slo[i]), np.uint64(shi[i])
            _row_with_flow(cur, nxt, F, G, coords, par, omega, u, x, j0, s0, False)
            _row_with_flow(cur, nxt, F, G, coords, par, omega, u, x, s0, s1, True)
            _row_with_flow(cur, nxt, F, G, coords, par, omega, u, x, s1, j1, False)
        else:
            _row_with_flow(cur, nxt, F, G, coords, par, omega, u, x, j0, j1, False)


@nb.njit(cache=True, nogil=True, fastmath=_FAST)
def _fields_without_flow(cur, nxt, F, G, coords, lo, hi, slo, shi, par):
    """One Euler step of Eq. (eqc) with v = 0 (the paper's Fig. 8; compiled).

    Arguments as for :func:`_fields_with_flow`.
    """
    for i in range(coords.size):
        u = np.uint64(i)
        j0, j1 = np.uint64(lo[i]), np.uint64(hi[i])
        if shi[i] > slo[i]:
            s0, s1 = np.uint64(slo[i]), np.uint64(shi[i])
            _row_without_flow(cur, nxt, F, G, par, u, j0, s0, False)
            _row_without_flow(cur, nxt, F, G, par, u, s0, s1, True)
            _row_without_flow(cur, nxt, F, G, par, u, s1, j1, False)
        else:
            _row_without_flow(cur, nxt, F, G, par, u, j0, j1, False)


@nb.njit(cache=True, nogil=True)
def rotor_integrals(c, vx, vy, F, coords, lo, hi, dx, flow):
    """Plate integrals of Eq. (eq_motion) on the support of F (compiled).

    Returns:
        (int F r x grad c dA, int F |r|^2 dA, int F r x v dA), with grad c by central
        differences and r x u = x u_y - y u_x.
    """
    inv_2dx = 0.5 / dx
    cross_grad = 0.0
    moment = 0.0
    cross_v = 0.0
    for i in range(coords.size):
        x = coords[i]
        for j in range(lo[i], hi[i]):
            f = F[i, j]
            if f == 0.0:
                continue
            y = coords[j]
            dcdx = (c[i + 1, j] - c[i - 1, j]) * inv_2dx
            dcdy = (c[i, j + 1] - c[i, j - 1]) * inv_2dx
            cross_grad += f * (x * dcdy - y * dcdx)
            moment += f * (x * x + y * y)
            if flow:
                cross_v += f * (x * vy[i, j] - y * vx[i, j])
    area = dx * dx
    return cross_grad * area, moment * area, cross_v * area


@nb.njit(cache=True, nogil=True)
def advance(
    data,
    spare,
    F,
    G,
    coords,
    lo,
    hi,
    slo,
    shi,
    shape,
    par,
    flow,
    schedule,
    rotor,
    kicks,
    step0,
    n_steps,
):
    """Advance c, v, phi, omega by `n_steps` fused Euler steps (compiled).

    Args:
        data: state (3, n, n) = (c, v_x, v_y), updated in place.
        spare: scratch array of the same shape.
        F, G: indicator arrays (n, n), zero outside the support, updated in place.
        coords: cell-centre coordinates.
        lo, hi: interior column ranges per row.
        slo, shi: support column ranges per row.
        shape: :meth:`RotorShape.as_array`.
        par: float parameters, indices P_*.
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
    dt, inv_inertia, mu, tsign_k = par[P_DT], 1.0 / par[P_I], par[P_MU], par[P_TSIGN] * par[P_K]
    phi, omega = rotor[0], rotor[1]
    cur = data
    nxt = spare
    phi_f = math.nan
    noisy = kicks.size > 0
    if not flow:
        data[1:] = 0.0
        spare[1:] = 0.0
    for s in range(n_steps):
        stopped = stopped_at(step0 + s, schedule)
        if stopped:
            omega = 0.0
        if phi != phi_f:
            update_indicators(F, G, coords, slo, shi, shape, phi)
            phi_f = phi
        cross_grad, moment, cross_v = rotor_integrals(
            cur[0], cur[1], cur[2], F, coords, slo, shi, par[P_DX], flow
        )
        torque = tsign_k * cross_grad
        friction = -mu * (moment * omega - cross_v)
        if not (math.isfinite(torque) and math.isfinite(friction)):
            if s % 2 == 1:
                data[:] = cur
            rotor[0], rotor[1] = phi, omega
            return s
        if flow:
            _fields_with_flow(cur, nxt, F, G, coords, lo, hi, slo, shi, par, omega)
        else:
            _fields_without_flow(cur, nxt, F, G, coords, lo, hi, slo, shi, par)
        if not stopped:
            phi += dt * omega
            omega += dt * (friction + torque) * inv_inertia
            if noisy:
                omega += kicks[s]
        cur, nxt = nxt, cur
        rotor[2], rotor[3], rotor[4] = torque, friction, 1.0 if stopped else 0.0
    if n_steps % 2 == 1:
        data[:] = cur
    rotor[0], rotor[1] = phi, omega
    return -1


@dataclass
class FusedStepper:
    """The compiled kernel bound to one simulation's arrays and parameters.

    Attributes:
        pde: the model (parameters, domain, rotor state).
        dt: time step.
        rng: numpy Generator for the noise; one standard normal is drawn per step, in
            step order, so a run is reproducible whatever the tracker intervals.
    """

    pde: RotorPDE
    dt: float
    rng: np.random.Generator
    schedule: StopSchedule = field(init=False)
    _spare: np.ndarray = field(init=False, repr=False)
    _par: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.schedule = StopSchedule.from_config(self.pde.config.protocol, self.dt)
        self._par = self.pde.kernel_parameters(self.dt)
        self._spare = np.zeros((3, *self.pde.domain.grid.shape))

    def kicks(self, n_steps: int) -> np.ndarray:
        """Euler-Maruyama increments of omega: sqrt(2 dt) sigma / I N(0, 1), Eq. (noiseav)."""
        sigma = self.pde.config.noise.sigma
        if sigma == 0:
            return np.empty(0)
        scale = math.sqrt(2.0 * self.dt) * sigma / self.pde.config.rotor.inertia
        return scale * self.rng.standard_normal(n_steps)

    def __call__(self, data: np.ndarray, step0: int, n_steps: int) -> None:
        """Advance `data` (and the PDE's rotor state) by `n_steps` steps from step `step0`.

        Raises:
            SimulationDivergedError: when the state becomes NaN/Inf, naming the time and field.
        """
        pde = self.pde
        dom = pde.domain
        rotor = pde.rotor.as_array()
        failed = advance(
            data,
            self._spare,
            pde.F,
            pde.G,
            dom.coords,
            dom.interior_lo,
            dom.interior_hi,
            dom.support_lo,
            dom.support_hi,
            pde.shape.as_array(),
            self._par,
            pde.config.flow.enabled,
            self.schedule.as_array(),
            rotor,
            self.kicks(n_steps),
            step0,
            n_steps,
        )
        pde.rotor.update_from(rotor)
        if failed >= 0:
            self._diverged((step0 + failed) * self.dt, data, rotor)
        if not np.isfinite(data).all():
            self._diverged((step0 + n_steps) * self.dt, data, rotor)

    def _diverged(self, t: float, data: np.ndarray, rotor: np.ndarray) -> None:
        names = ["c", "v_x", "v_y"]
        bad = [name for name, arr in zip(names, data, strict=True) if not np.isfinite(arr).all()]
        if not np.isfinite(rotor[:2]).all():
            bad.append("phi/omega")
        where = ", ".join(bad) if bad else "torque"
        msg = (
            f"simulation diverged at t = {t:.6g}: non-finite {where} "
            f"(dt = {self.dt:g}, stability limit {self.pde.config.dt_limit():.4g}; "
            "a large flow can also violate the advection limit dt <= 2 D / |v|^2)"
        )
        raise SimulationDivergedError(msg)


def make_fused_stepper(pde: RotorPDE, dt: float, rng: np.random.Generator) -> FusedStepper:
    """Bind the compiled fused kernel to `pde` (see :class:`FusedStepper`)."""
    return FusedStepper(pde=pde, dt=dt, rng=rng)


class RotorSolver(SolverBase):
    """py-pde solver that advances the rotor model with the fused compiled kernel.

    py-pde's :class:`~pde.solvers.Controller` calls the stepper between tracker times;
    the rotor state lives in ``pde.rotor`` and is advanced in the same compiled loop as
    the fields, every step.
    """

    name = "rotor_fused"

    def __init__(self, pde: RotorPDE, *, rng: np.random.Generator | None = None):
        """
        Args:
            pde: the rotor model.
            rng: Generator for the torque noise; by default seeded from
                ``pde.config.noise.seed``.
        """
        super().__init__(pde, backend="numba")
        self.pde: RotorPDE = pde
        seed = pde.config.noise.seed
        self.rng = rng if rng is not None else np.random.default_rng(seed)

    def make_stepper(
        self, state: FieldCollection, dt: float | None = None
    ) -> Callable[[FieldCollection, float, float], float]:
        """Return stepper(state, t_start, t_end) -> t advancing by whole steps of dt.

        Raises:
            ValueError: if dt exceeds the explicit stability limit (before any step).
        """
        if dt is None:
            dt = self.pde.config.grid.dt
        limit = self.pde.config.dt_limit()
        if dt > limit:
            msg = f"dt = {dt:g} exceeds the explicit stability limit {limit:.4g}"
            raise ValueError(msg)
        stochastic = self.pde.config.noise.sigma > 0
        self.info.update(dt=float(dt), steps=0, dt_adaptive=False, stochastic=stochastic)
        self.info["backend"] = "numba (fused rotor kernel)"
        fused = make_fused_stepper(self.pde, dt, self.rng)
        self.fused = fused

        def stepper(state: FieldCollection, t_start: float, t_end: float) -> float:
            step0 = round(t_start / dt)
            n_steps = max(1, round((t_end - t_start) / dt))
            fused(state.data, step0, n_steps)
            self.info["steps"] += n_steps
            return (step0 + n_steps) * dt

        return stepper
