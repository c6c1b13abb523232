"""The rotor model's Euler step composed from py-pde's compiled operators (benchmark reference).

The same equations as the fused solver (:mod:`pde_rotor.kernels.cpu`), Eqs. (eqc), (eqv),
(eq_motion) and (torque) of Koyano et al. (Chaos 2020), built the way a py-pde user
would: ``grid.make_operator`` for laplace, divergence, vector_laplace and gradient, array
expressions for the rest, F and G evaluated with tanh on the whole grid (the scheme
``paper``). No stop schedule and no noise. benchmarks/bench_solver.py times it against
the fused solver and compares their states.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numba as nb
import numpy as np

from pde_rotor.model.pde import BOUNDARY, TORQUE_SIGN, RotorPDE


def make_operator_stepper(
    pde: RotorPDE, dt: float
) -> Callable[[np.ndarray, np.ndarray, int], None]:
    """Euler stepper of `pde` composed from py-pde's compiled operators.

    Args:
        pde: the model (parameters, shape, domain).
        dt: time step.

    Returns:
        step(data, rotor, n_steps): advances data (3, n, n) and rotor [phi, omega].
    """
    grid = pde.domain.grid
    laplace = grid.make_operator("laplace", BOUNDARY)
    divergence = grid.make_operator("divergence", BOUNDARY)
    vector_laplace = grid.make_operator("vector_laplace", BOUNDARY)
    gradient = grid.make_operator("gradient", BOUNDARY)
    x, y = pde.cell_coordinates()
    mask = pde.domain.interior_mask.astype(float)
    cfg, shape = pde.config, pde.shape
    diff, evap = cfg.camphor.diffusion, cfg.camphor.evaporation
    src = cfg.camphor.supply / (math.pi * shape.pill_radius**2)
    eta, eta_b, d_eta = cfg.flow.drag, cfg.flow.bulk_drag, cfg.flow.viscosity
    tsign_k = TORQUE_SIGN[cfg.rotor.torque] * cfg.camphor.tension_slope
    mu, inertia, area = cfg.rotor.friction, cfg.rotor.inertia, pde.domain.cell_area
    n_corners, apothem, rho = shape.n_corners, shape.apothem, shape.pill_radius
    r_c, asym, inv_delta = shape.pill_distance, shape.asymmetry, 1.0 / shape.smoothing

    @nb.njit(cache=False)
    def step(data: np.ndarray, rotor: np.ndarray, n_steps: int) -> None:
        for _ in range(n_steps):
            phi, omega = rotor[0], rotor[1]
            proj = np.full(x.shape, -np.inf)
            G = np.zeros(x.shape)
            for k in range(n_corners):
                a_edge = phi + 2.0 * np.pi * (k + 0.5) / n_corners
                proj = np.maximum(proj, x * np.cos(a_edge) + y * np.sin(a_edge))
                a_pill = phi + 2.0 * np.pi * (k + 1) / n_corners + asym
                dist = np.sqrt((x - r_c * np.cos(a_pill)) ** 2 + (y - r_c * np.sin(a_pill)) ** 2)
                G += 0.5 * (1.0 + np.tanh((rho - dist) * inv_delta))
            F = 0.5 * (1.0 + np.tanh((apothem - proj) * inv_delta))
            c, v = data[0], data[1:]
            grad = gradient(c)
            cross_grad = np.sum(F * (x * grad[1] - y * grad[0])) * area
            cross_v = np.sum(F * (x * v[1] - y * v[0])) * area
            moment = np.sum(F * (x * x + y * y)) * area
            c_rate = diff * laplace(c) - divergence(c * v) - evap * (1.0 - F) * c + src * G
            v_rate = np.empty_like(v)
            v_rate[0] = eta * F * (-omega * y - v[0]) - eta_b * v[0]
            v_rate[1] = eta * F * (omega * x - v[1]) - eta_b * v[1]
            v_rate += d_eta * vector_laplace(v)
            data[0] += dt * mask * c_rate
            data[1:] += dt * mask * v_rate
            rotor[0] = phi + dt * omega
            rotor[1] = (
                omega + dt * (tsign_k * cross_grad - mu * (moment * omega - cross_v)) / inertia
            )

    return step
