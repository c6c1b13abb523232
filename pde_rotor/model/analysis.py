"""Analysis of the model that needs no time stepping: the stopped plate's steady state.

A stopped plate (omega = 0) has v -> 0, Eq. (eqv), and c relaxes to the solution of the
linear problem of Eq. (eqc),

    D lap c - a (1 - F) c + s0 / (pi rho^2) G = 0,  c = 0 on and outside the circle,

discretised exactly as in the solver (5-point Laplacian on the interior cells). Its
torque, Eq. (torque), vanishes for a symmetric rotor in the continuum; on the Cartesian
grid it does not (the lattice breaks the hexagon's rotation symmetry), and for Delta != 0
it is the asymmetry torque that selects the favoured direction. Both are computed here by
a sparse direct solve, without time stepping.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from ..config import RotorConfig
from .pde import RotorPDE


def stopped_concentration(pde: RotorPDE, phi: float) -> np.ndarray:
    """Steady c of a plate held at angle `phi` (solves the discrete Eq. (eqc) with v = 0).

    Args:
        pde: the model (its configuration fixes every parameter).
        phi: plate angle [rad].

    Returns:
        c on the grid, shape (n, n), zero outside the disk.
    """
    cfg = pde.config
    F, G = pde.indicators(phi)
    mask = pde.domain.interior_mask
    n = mask.shape[0]
    second = sp.diags([1.0, -2.0, 1.0], [-1, 0, 1], shape=(n, n))
    eye = sp.identity(n)
    laplace = (sp.kron(second, eye) + sp.kron(eye, second)).tocsr() / pde.domain.dx**2
    # c = 0 outside the interior cells: keep their rows and columns only
    inside = np.flatnonzero(mask)
    ii, jj = np.nonzero(mask)
    decay = cfg.camphor.evaporation * (1.0 - F[ii, jj])
    matrix = cfg.camphor.diffusion * laplace[inside][:, inside] - sp.diags(decay)
    source = cfg.camphor.supply / (np.pi * cfg.geometry.pill_radius**2) * G[ii, jj]
    c = np.zeros(mask.shape)
    c[ii, jj] = spsolve(matrix.tocsc(), -source)
    return c


def stopped_torque(config: RotorConfig, phis: np.ndarray) -> np.ndarray:
    """Torque T, Eq. (torque), on a plate held at each angle of `phis` in steady state.

    Args:
        config: run configuration (geometry, camphor, grid and torque convention).
        phis: plate angles [rad].

    Returns:
        T for each angle. For Delta = 0 this is the spurious lattice torque (zero in the
        continuum); for Delta != 0 it adds the asymmetry torque.
    """
    pde = RotorPDE(config)
    state = pde.initial_state()
    torques = np.empty(len(phis))
    for n, phi in enumerate(phis):
        state.rotor.phi, state.rotor.omega = float(phi), 0.0
        state[0].data[:] = stopped_concentration(pde, float(phi))
        torques[n], _ = pde.rotor_torques(state)
    return torques
