"""The Jacobian against the step: a small perturbation advanced by the reference's forward
Euler step moves as (1 + dt J) says, to the order of the perturbation."""

from __future__ import annotations

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.stability import DiscreteModel, linearise
from tests.stability.conftest import disk_data, rotor_data


def euler_step(lin, x: np.ndarray, dt: float) -> np.ndarray:
    """One forward Euler step of the full nonlinear reference from rest + x (positions)."""
    model = lin.model
    n, m = lin.n_fields, lin.n_dofs
    c, v = lin.layout.unpack(x[:n])
    q = model.q0.copy()
    q[lin.active] += x[n : n + lin.active.size]
    p = x[n + lin.active.size :]
    rate_c, rate_v = model.field_rates(lin.rest.c + c, v, q, p)
    acc = model.accelerations(lin.rest.c + c, v, q, p)
    rates = np.concatenate([lin.layout.pack(rate_c, rate_v), p[lin.active], acc])
    assert p.size == m
    return x + dt * rates


@pytest.mark.parametrize(
    "data",
    [
        rotor_data("consistent", flow=True),
        rotor_data("paper", flow=True),
        rotor_data("consistent", flow=False),
        {**disk_data("absorbing", radius=1.5), "flow": {"enabled": True}},
    ],
    ids=["rotor-consistent-flow", "rotor-paper-flow", "rotor-no-flow", "disk-flow"],
)
def test_steps_of_a_small_perturbation_follow_the_jacobian(data: dict) -> None:
    # at phi = 0 the plate's mirror symmetry on the lattice makes the rest state a fixed
    # point of the free rotor (elsewhere the lattice torque moves it: docs/stability.md)
    config = RotorConfig.model_validate(
        {**data, "rotor": {"phi0": 0.0}} if "bodies" not in data else data
    )
    lin = linearise(DiscreteModel(config), positions=True)
    assert np.abs(lin.rest_acceleration).max() < 1e-9
    dt = config.grid.dt
    rng = np.random.default_rng(1)
    direction = rng.standard_normal(lin.size)
    direction /= np.abs(direction).max()
    errors = []
    for eps in (1e-3, 1e-4):
        x = eps * direction
        linear = eps * direction
        base = np.zeros(lin.size)
        for _ in range(3):
            x = euler_step(lin, x, dt)
            base = euler_step(lin, base, dt)
            linear = linear + dt * lin.matvec(linear)
        errors.append(np.abs((x - base) - linear).max() / eps)
    # the error of the linear prediction is of the order of the perturbation: it falls
    # tenfold with it (the paper scheme, smooth in phi), at least fourfold with the
    # consistent scheme's tables, which are linear interpolants in the plate's angle
    assert errors[0] < 1e-3
    assert errors[1] < errors[0] / 4


def test_field_operator_is_the_reference_on_a_random_field(rotor_config: RotorConfig) -> None:
    lin = linearise(DiscreteModel(rotor_config))
    model = lin.model
    rng = np.random.default_rng(2)
    x = rng.standard_normal(lin.n_fields)
    c, v = lin.layout.unpack(x)
    zero_p = np.zeros(lin.n_dofs)
    zero_v = np.zeros((2, *model.shape))
    base = lin.layout.pack(*model.field_rates(lin.rest.c, zero_v, model.q0, zero_p))
    # rates are affine in c and in v separately: probe each alone
    rate_c = lin.layout.pack(*model.field_rates(lin.rest.c + c, zero_v, model.q0, zero_p))
    rate_v = lin.layout.pack(*model.field_rates(lin.rest.c, v, model.q0, zero_p))
    expected = (rate_c - base) + (rate_v - base)
    assert np.abs(lin.fields @ x - expected).max() < 1e-10 * np.abs(expected).max()


def test_comoving_frame_drops_only_the_stiffness() -> None:
    """A disk far from the wall: its rest force hardly depends on where it is, so the
    co-moving and the full linearisations share their leading eigenvalue."""
    config = RotorConfig.model_validate(disk_data("absorbing", radius=3.0))
    lin = linearise(DiscreteModel(config))
    assert not lin.positions
    active = lin.with_positions(True).active
    assert [lin.model.dofs[i].coordinate for i in active] == ["x", "y"]  # a round disk's angle
    stiffness = np.abs(lin.stiffness[:2, :2]).max()
    assert stiffness < 1e-2 * np.abs(lin.coordinate_rows[:2, :2]).max()
