"""The rest state: the steady camphor field of the bodies held at their start, by one sparse solve.

With every body at rest (q = q0, p = 0) and v = 0, Eq. (eqc) on the grid is affine in c,

    dc/dt = A c + s,    A = D lap_h - a (1 - F),    s = s0 / (pi rho^2) G,

with the discrete Laplacian lap_h of the dish's wall (5-point with c = 0 outside an absorbing
wall; the cut cells' face fluxes behind a no-flux wall, :mod:`pde_rotor.model.wall`) and F,
G of the run's scheme. A and s are read off the reference's rate itself
(:func:`pde_rotor.stability.fields.probe_operator`), so the rest state c0 = -A^{-1} s is
the steady state of exactly the discrete equations the solver steps, on either scheme:
one step from it changes c by round-off only. The flow stays at rest (Eq. (eqv) has no
source while every plate is still), so c0 is the rest state with and without flow.

Balance: summing Eq. (eqc) over the dish, the supply sum_j s_j (1 + pi^2 delta^2 /
(12 rho_j^2)) of the tanh-edged pills equals the sublimation a int (1 - F) c0 dA plus, at
an absorbing wall, the diffusive outflow through it (:attr:`RestState.wall_outflow`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from .fields import FieldLayout, probe_operator
from .system import DiscreteModel


@dataclass
class RestState:
    """The rest state of a config and the camphor operator it solves.

    Attributes:
        model: the discrete model.
        layout: the unknowns (c only: the flow is at rest).
        operator: A, the sparse (n_c, n_c) matrix of Eq. (eqc) at rest.
        source: s on the camphor cells.
        c: (n, n) the rest field c0 (0 off the camphor cells).
    """

    model: DiscreteModel
    layout: FieldLayout
    operator: sp.csr_matrix
    source: np.ndarray
    c: np.ndarray

    @property
    def sublimation(self) -> float:
        """a int (1 - F) c0 dA, the camphor lost to the air per unit time."""
        model = self.model
        f = model.plate_indicator(model.q0)
        evaporation = model.config.camphor.evaporation
        return evaporation * model.camphor_total((1 - f) * self.c)

    @property
    def supply(self) -> float:
        """sum over the grid of the pill sources of Eq. (eqc) (volume-weighted behind a
        no-flux wall)."""
        c_src = np.zeros(self.layout.shape)
        c_src[self.layout.c_mask] = self.source
        return self.model.camphor_total(c_src)

    @property
    def wall_outflow(self) -> float:
        """The camphor leaving through the wall per unit time: supply - sublimation (0 to
        round-off behind a no-flux wall; at an absorbing wall D sum over the last interior
        cells of c0 times their faces to the outside)."""
        model = self.model
        if model.pde.domain.cut_cells is not None:
            return 0.0
        mask = self.layout.c_mask
        outside = np.zeros_like(self.c)
        for axis in (0, 1):
            for shift in (1, -1):
                outside += ~np.roll(mask, shift, axis=axis) & mask
        return model.config.camphor.diffusion * float(np.sum(outside * self.c))


def rest_state(model: DiscreteModel) -> RestState:
    """The steady camphor field of `model`'s bodies held at their start (one sparse LU).

    Args:
        model: the discrete model of a config.

    Returns:
        The rest state, with the operator A and source s it solves.
    """
    layout = FieldLayout(model.shape, model.c_mask, model.v_mask, flow=False)
    q, p = model.q0, np.zeros_like(model.q0)
    zero_v = np.zeros((2, *model.shape))
    zero_c = np.zeros(model.shape)
    base, _ = model.field_rates(zero_c, zero_v, q, p)

    def apply(c: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        rate, _ = model.field_rates(c, zero_v, q, p)
        return rate - base, np.zeros_like(v)

    operator = probe_operator(layout, apply)
    source = base[layout.c_mask]
    c0, _ = layout.unpack(spsolve(operator.tocsc(), -source))
    return RestState(model=model, layout=layout, operator=operator, source=source, c=c0)
