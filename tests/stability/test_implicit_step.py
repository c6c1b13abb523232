"""The Jacobian against the cut-cell step behind a no-flux wall, whose diffusion through
the stiff cells' faces is implicit (:func:`pde_rotor.model.wall.make_wall_step`): one
step from the rest state perturbed by eps moves as (I - dt J_I)^{-1} (I + dt (J - J_I))
says, J_I the implicit faces' part of J, to O(eps^2)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.model.wall import wall_fluxes, wall_rate
from pde_rotor.stability import DiscreteModel, linearise
from tests.stability.conftest import disk_data


def ring_data() -> dict:
    """The disk of :func:`disk_data` in the middle of an annular channel 1 < r < 2.5."""
    data = disk_data("absorbing", radius=2.5)
    data["grid"]["vessel"] = {"shape": "annulus", "inner_radius": 1.0, "outer_radius": 2.5}
    data["bodies"][0]["start"] = {"x": 1.75, "y": 0.0}
    return data


@pytest.mark.parametrize(
    "data",
    [{**disk_data("no_flux", radius=1.5), "flow": {"enabled": True}}, ring_data()],
    ids=["dish-flow", "ring"],
)
def test_one_cut_cell_step_follows_the_split_jacobian(data: dict) -> None:
    config = RotorConfig.model_validate(data)
    model = DiscreteModel(config)
    lin = linearise(model)
    cells = model.pde.domain.cut_cells
    assert cells.implicit_x.any() or cells.implicit_y.any()
    implicit = replace(
        cells,
        aperture_x=np.where(cells.implicit_x, cells.aperture_x, 0.0),
        aperture_y=np.where(cells.implicit_y, cells.aperture_y, 0.0),
    )
    diffusion, dt = config.camphor.diffusion, config.grid.dt

    def j_implicit(c: np.ndarray) -> np.ndarray:
        return wall_rate(wall_fluxes(c, None, implicit, diffusion), cells)

    rng = np.random.default_rng(3)
    x = rng.standard_normal(lin.n_fields)
    x /= np.abs(x).max()
    dc, dv = lin.layout.unpack(x)
    zero = np.zeros(lin.n_dofs)

    def step(eps: float) -> np.ndarray:
        state = model.state(lin.rest.c + eps * dc, eps * dv, model.q0, zero)
        return model.pde.camphor_step(state, dt)

    rate_c, _ = lin.layout.unpack(lin.fields @ x)
    base = step(0.0)
    assert np.abs(base - lin.rest.c).max() < 1e-10  # the rest state is the step's fixed point
    errors, explicit_errors = [], []
    for eps in (1e-3, 1e-4):
        moved = (step(eps) - base) / eps
        # (I - dt J_I) moved = (I + dt (J - J_I)) dc, on the cells that hold c
        residual = moved - dt * j_implicit(moved) - (dc + dt * (rate_c - j_implicit(dc)))
        errors.append(np.abs(residual[model.c_mask]).max())
        forward = moved - (dc + dt * rate_c)
        explicit_errors.append(np.abs(forward[model.c_mask]).max())
    scale = dt * np.abs(rate_c[model.c_mask]).max()
    if config.flow.enabled:  # c v is quadratic: the residual falls tenfold with eps
        assert errors[0] < 1e-3 * scale
        assert errors[1] < errors[0] / 5
    else:  # the step is linear in c: the residual is round-off
        assert max(errors) < 1e-9 * scale
    # forward Euler of the whole J misses the implicit part by O(dt^2 J_I J), not O(eps)
    assert explicit_errors[1] > 100 * errors[1]
