"""The reference's local terms of Eqs. (eqc), (eqv) (pde_rotor/model/rates.py), by hand in
their limits; both references use them, and the compiled steps are tested against those
(tests/model/test_pde.py, tests/solver/test_bodies.py)."""

from __future__ import annotations

import numpy as np

from pde_rotor.config import CamphorConfig, FlowConfig
from pde_rotor.model.rates import camphor_local_rate, flow_local_rate


def test_camphor_evaporates_off_the_plates_and_is_supplied_at_the_pills() -> None:
    camphor = CamphorConfig(evaporation=0.7)
    c = np.array([2.0, 2.0, 3.0])
    plates = np.array([0.0, 1.0, 0.25])
    source = np.array([0.0, 5.0, 1.0])
    rate = camphor_local_rate(camphor, c, plates, source)
    np.testing.assert_allclose(rate, [-1.4, 5.0, -0.7 * 0.75 * 3.0 + 1.0], rtol=1e-15)


def test_the_flow_relaxes_to_the_plate_and_the_bulk_drags_it_to_rest() -> None:
    flow = FlowConfig(enabled=True, drag=4.0, bulk_drag=0.5)
    u = np.array([[1.0], [-2.0]])  # a plate's velocity
    covered = np.ones(1)
    # water moving with a whole plate: only the bulk drag is left
    np.testing.assert_allclose(flow_local_rate(flow, u, covered, covered * u), -0.5 * u)
    # water at rest under the plate: pulled towards u at rate eta
    rest = np.zeros_like(u)
    np.testing.assert_allclose(flow_local_rate(flow, rest, covered, covered * u), 4.0 * u)
    # no plate: the bulk drag alone
    v = np.array([[0.3], [0.1]])
    np.testing.assert_allclose(flow_local_rate(flow, v, 0 * covered, 0 * u), -0.5 * v)
    # two half-covering plates moving apart sum their pulls
    pull = flow_local_rate(flow, rest, covered, 0.5 * u - 0.5 * u)
    np.testing.assert_allclose(pull, 0 * u, atol=1e-15)
