"""The local terms of Eqs. (eqc) and (eqv) in numpy: the reference's one copy of them.

Both references, the paper's rotor (:meth:`pde_rotor.model.pde.RotorPDE.evolution_rate`)
and K bodies on one surface (:meth:`pde_rotor.model.surface.SurfacePDE.evolution_rate`),
add these to their transport terms (D lap c - div(c v), D_eta lap v), so that a term of
the rates is written once here, beside its compiled twin in
:mod:`pde_rotor.physics.rates` (``local_rate``, ``plate_rates``).
"""

from __future__ import annotations

import numpy as np

from ..config import CamphorConfig, FlowConfig


def camphor_local_rate(
    camphor: CamphorConfig, c: np.ndarray, plates: np.ndarray, source: np.ndarray
) -> np.ndarray:
    """-a (1 - F) c + s of Eq. (eqc): evaporation where no plate covers the water, and the
    pills' supply.

    Args:
        camphor: the camphor section (a: ``evaporation``).
        c: the surface concentration.
        plates: F, the plates' indicator summed over the bodies.
        source: the pills' supply density summed over the bodies (s0 / (pi rho^2) G).
    """
    return -camphor.evaporation * (1 - plates) * c + source


def flow_local_rate(
    flow: FlowConfig, v: np.ndarray, plates: np.ndarray, plate_flow: np.ndarray
) -> np.ndarray:
    """eta F (u - v) - eta_b v of Eq. (eqv): the plates drag the water towards their
    velocity u, the bulk drags it to rest.

    Args:
        flow: the flow section (eta: ``drag``, eta_b: ``bulk_drag``).
        v: the surface flow, shape (2, ...).
        plates: F, the plates' indicator summed over the bodies.
        plate_flow: sum_k F_k u_k, the plates' velocities weighted by their indicators,
            shape (2, ...).
    """
    return flow.drag * (plate_flow - plates * v) - flow.bulk_drag * v
