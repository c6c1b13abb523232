"""The compiled step in the vessels (an annular channel, a rectangular tank) against the
numpy reference, and its conservation of camphor with moving bodies and flow."""

from __future__ import annotations

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.model.surface import SurfacePDE
from pde_rotor.solver.simulation import Simulation

VESSELS = {
    "annulus": {"shape": "annulus", "inner_radius": 1.0, "outer_radius": 5.9},
    "annulus_absorbing_inside": {
        "shape": "annulus",
        "inner_radius": 1.0,
        "outer_radius": 5.9,
        "inner_wall": "absorbing",
    },
    "rectangle": {"shape": "rectangle", "half_widths": [4.95, 3.37]},
}
"""The vessels, each about the grid's centre on a grid of half side 6 (a footprint reaches
1.8 from its body at geometry.smoothing = 0.05)."""

STARTS = {
    "annulus": ((-2.4, 2.4), (2.6, -2.2)),
    "annulus_absorbing_inside": ((-2.4, 2.4), (2.6, -2.2)),
    "rectangle": ((-2.0, 1.0), (2.2, -1.2)),
}
"""Where the hexagon and the strip start in each vessel, clear of its walls."""


def seeded(sim: Simulation) -> Simulation:
    """`sim` with a smooth camphor field on its wet cells and a smooth flow inside."""
    pde: SurfacePDE = sim.pde
    x, y = pde.cell_coordinates()
    inside = pde.domain.interior_mask
    sim.state.data[0] = pde.domain.camphor_mask * (1 + 0.5 * np.sin(1.3 * x + 0.2) * np.cos(y))
    sim.state.data[1] = inside * 0.3 * np.sin(0.9 * y + 0.4) * np.cos(0.4 * x)
    sim.state.data[2] = inside * 0.2 * np.cos(1.1 * x + 0.1) * np.sin(0.5 * y + 0.3)
    return sim


def bodies_in(vessel: str, supply: float = 1.0) -> list[dict]:
    """A turning hexagon and a free strip drifting with its start velocity."""
    (hx, hy), (sx, sy) = STARTS[vessel]
    return [
        {
            "name": "hexagon",
            "plate": {"shape": "polygon", "n_corners": 6, "radius": 0.5},
            "pills": [{"x": 0.3, "y": 0.05, "supply": supply}],
            "motion": {"kind": "fixed_axis"},
            "start": {"x": hx, "y": hy, "angle": 0.4, "omega": 3.0},
        },
        {
            "name": "strip",
            "plate": {"shape": "strip", "length": 0.8, "width": 0.3},
            "pills": [{"x": 0.3, "y": 0.0, "radius": 0.06, "supply": supply}],
            "motion": {"kind": "free", "mass": 1e-2},
            "start": {"x": sx, "y": sy, "angle": 0.7, "omega": 2.0, "velocity": [-0.3, 0.2]},
        },
    ]


def vessel_run(vessel: str, supply: float = 1.0, **sections: dict) -> Simulation:
    """A coarse vessel (dx = 0.1) with :func:`bodies_in`, c and v smooth and nonzero up
    to the walls (v only where the cell centre lies inside)."""
    config = RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 6.0, "dx": 0.1, "dt": 1e-3, "vessel": VESSELS[vessel]},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": "paper"},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "bodies": bodies_in(vessel, supply),
            **sections,
        }
    )
    return seeded(Simulation(config))


@pytest.mark.parametrize("vessel", sorted(VESSELS))
def test_vessel_step_equals_numpy_reference(vessel: str) -> None:
    """One compiled step gives the numpy step of c on the vessel's cut cells
    (:meth:`SurfacePDE.camphor_step`) on every cell, and the numpy rate of v, Eq. (eqv);
    nothing moves on the dry cells (an annulus' hole included)."""
    sim = vessel_run(vessel)
    pde: SurfacePDE = sim.pde
    before = sim.state.copy()
    dt = sim.config.grid.dt
    expected = pde.camphor_step(before, dt)
    rate = pde.evolution_rate(before).data
    sim.run(dt)
    after = sim.state.data
    assert np.abs(after[0] - expected).max() <= 1e-12 * np.abs(expected).max()
    computed = (after - before.data) / dt
    assert np.abs(computed[1:] - rate[1:]).max() <= 1e-9 * np.abs(rate).max()
    cells = pde.domain.cut_cells
    assert np.all(after[:, ~cells.mask] == 0.0)
    assert np.all(after[1:, ~cells.flowing] == 0.0)


@pytest.mark.parametrize("vessel", ["annulus", "rectangle"])
def test_vessel_conserves_camphor_with_moving_bodies_and_flow(vessel: str) -> None:
    """With no-flux walls, no sublimation and no supply, the camphor in the vessel (sum
    of kappa c dA) stays what it was to round-off while the bodies turn and move and the
    flow advects it."""
    sim = vessel_run(vessel, supply=0.0, camphor={"evaporation": 0.0})
    domain = sim.pde.domain
    start = domain.camphor_total(sim.state.data[0])
    x0 = sim.bodies.poses[1, :2].copy()
    sim.run(0.2)
    assert np.abs(sim.state.data[1:]).max() > 0.01
    assert np.hypot(*(sim.bodies.poses[1, :2] - x0)) > 0.02
    assert abs(domain.camphor_total(sim.state.data[0]) / start - 1) < 1e-12


SPAN = (1.2, 3.8, 2.5)
"""The channel R1 < r < R2 and the track radius of the spanning boat."""


def spanning_run(supply: float, **sections: dict) -> Simulation:
    """A boat that spans the channel SPAN (a strip 0.6 long and 5 wide, its plate 1.2 past
    each wall, a pill at its rear 1.1 inside them) sailing at 0.3 on the coarse grid
    (dx = 0.1), c and v smooth and nonzero up to the walls."""
    inner, outer, radius = SPAN
    boat = {
        "name": "boat",
        "plate": {"shape": "strip", "length": 0.6, "width": 5.0},
        "pills": [{"x": -0.15, "y": 0.0, "radius": 0.08, "supply": supply}],
        "motion": {"kind": "track", "mass": 1.0, "spans": True, "speed": 0.3},
        "start": {"x": 0.6 * radius, "y": 0.8 * radius},
    }
    vessel = {"shape": "annulus", "inner_radius": inner, "outer_radius": outer}
    config = RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 6.4, "dx": 0.1, "dt": 1e-3, "vessel": vessel},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": "paper"},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "bodies": [boat],
            **sections,
        }
    )
    return seeded(Simulation(config))


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_spanning_boat_step_equals_numpy_reference(scheme: str) -> None:
    """One compiled step of a boat whose plate crosses both walls gives the numpy step of
    c on the cut cells, the numpy rate of v and the numpy integrals over the wet cells
    (:meth:`SurfacePDE.body_forces`: tension and friction, recorded at the step's start),
    on either scheme (``consistent``: the filtered plate and pill, the wet-cell integrals
    in place of its contour form)."""
    sim = spanning_run(1.0, numerics={"scheme": scheme})
    pde: SurfacePDE = sim.pde
    before = sim.state.copy()
    dt = sim.config.grid.dt
    expected = pde.camphor_step(before, dt)
    rate = pde.evolution_rate(before).data
    forces = pde.body_forces(before)[0]
    sim.run(dt)
    after = sim.state.data
    assert np.abs(after[0] - expected).max() <= 1e-12 * np.abs(expected).max()
    computed = (after - before.data) / dt
    assert np.abs(computed[1:] - rate[1:]).max() <= 1e-9 * np.abs(rate).max()
    recorded = sim.bodies.poses[0, 6:12]
    assert np.abs(recorded - forces).max() <= 1e-10 * np.abs(forces).max()
    assert np.abs(forces[:2]).max() > 0.1


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_spanning_boat_conserves_camphor_and_supplies_it_all_to_the_water(scheme: str) -> None:
    """With no-flux walls and no sublimation the camphor in the channel stays what it was
    to round-off while the spanning boat sails and stirs the water; with its pill on, the
    camphor grows by exactly its supply, sum of the source over every cell (at the pose
    of the step's start) times dA and dt per step: none of it falls on the dry cells its
    plate covers, on either scheme (``consistent``: the filtered pill)."""
    numerics = {"scheme": scheme}
    sim = spanning_run(0.0, camphor={"evaporation": 0.0}, numerics=numerics)
    domain = sim.pde.domain
    start = domain.camphor_total(sim.state.data[0])
    x0 = sim.bodies.poses[0, :2].copy()
    sim.run(0.1)
    assert np.hypot(*(sim.bodies.poses[0, :2] - x0)) > 0.02
    assert abs(domain.camphor_total(sim.state.data[0]) / start - 1) < 1e-12
    fed = spanning_run(
        2.0, camphor={"evaporation": 0.0}, flow={"enabled": False}, numerics=numerics
    )
    pde: SurfacePDE = fed.pde
    start = pde.domain.camphor_total(fed.state.data[0])
    dt = fed.config.grid.dt
    supplied = 0.0
    for step in range(20):
        _, source = pde.body_fields(fed.state.bodies)[0]
        supplied += dt * float(np.sum(source)) * pde.domain.cell_area
        fed.run((step + 1) * dt)
    gained = pde.domain.camphor_total(fed.state.data[0]) - start
    assert supplied > 20 * dt * 1.9
    assert abs(gained / supplied - 1) < 1e-12
