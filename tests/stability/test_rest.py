"""The rest state: the steady state of the discrete Eq. (eqc), and its camphor balance."""

from __future__ import annotations

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.stability import DiscreteModel, rest_state
from tests.stability.conftest import disk_data, rotor_data


@pytest.mark.parametrize(
    "data",
    [
        rotor_data("consistent"),
        rotor_data("paper", flow=False),
        disk_data("no_flux", radius=1.5),
        disk_data("absorbing", radius=1.5),
    ],
    ids=["rotor-consistent", "rotor-paper", "disk-no-flux", "disk-absorbing"],
)
def test_one_euler_step_from_the_rest_state_changes_c_by_round_off(data: dict) -> None:
    config = RotorConfig.model_validate(data)
    model = DiscreteModel(config)
    rest = rest_state(model)
    zero_v = np.zeros((2, *model.shape))
    rate, v_rate = model.field_rates(rest.c, zero_v, model.q0, np.zeros_like(model.q0))
    step = config.grid.dt * rate
    assert rest.c.max() > 0.1
    assert np.abs(step).max() < 1e-13 * rest.c.max()
    assert np.abs(v_rate).max() == 0.0


@pytest.mark.parametrize(
    "data", [rotor_data("consistent"), rotor_data("paper"), disk_data("no_flux", radius=1.5)]
)
def test_supply_equals_sublimation_plus_the_wall_outflow(data: dict) -> None:
    model = DiscreteModel(RotorConfig.model_validate(data))
    rest = rest_state(model)
    balance = rest.sublimation + rest.wall_outflow
    assert rest.supply == pytest.approx(balance, rel=1e-10)
    # the sampled tanh sources hold the pills' analytic total to the grid's error (dx = 2
    # delta for the disk: 0.5 %)
    assert rest.supply == pytest.approx(model.source_total(), rel=1e-2)


def test_behind_a_no_flux_wall_all_supply_sublimates() -> None:
    model = DiscreteModel(RotorConfig.model_validate(disk_data("no_flux", radius=1.5)))
    rest = rest_state(model)
    assert rest.wall_outflow == 0.0
    assert rest.sublimation == pytest.approx(rest.supply, rel=1e-10)
    evaporation = model.config.camphor.evaporation
    # a int (1 - F) c dA = sum s_j (1 + pi^2 delta^2 / 12 rho^2), the grid's error apart
    assert rest.sublimation == pytest.approx(model.source_total(), rel=1e-2)
    assert evaporation == 1.0
