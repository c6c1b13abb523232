"""Contact (``contact:``): the soft spring between footprints and from the walls, against
the numpy reference and the force balance it must reach."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.config import ConfigError, validate_config
from pde_rotor.model.surface import SurfacePDE
from pde_rotor.solver.bodies import BodyContactError
from pde_rotor.solver.simulation import Simulation

RING = {"shape": "annulus", "inner_radius": 0.4, "outer_radius": 2.6}
GRID = {"dx": 0.05, "dt": 2e-4, "domain_radius": 2.6, "vessel": RING}
CONTACT = {"enabled": True, "stiffness": 100.0, "range": 0.1}

BOAT = {
    "plate": {"shape": "strip", "length": 0.4, "width": 0.2},
    "pills": [{"x": -0.15, "y": 0.0, "radius": 0.05}],
    "motion": {"kind": "track", "mass": 2e-3, "friction": 0.5},
}


def contact_config(bodies: list[dict[str, Any]], **sections: Any) -> RotorConfig:
    """The annulus RING on a coarse grid (smoothing 0.025: footprints 20 delta = 0.5
    beyond the plates), contact on unless given."""
    data: dict[str, Any] = {
        "grid": GRID,
        "geometry": {"smoothing": 0.025},
        "numerics": sections.pop("numerics", {"scheme": "paper"}),
        "protocol": {"t_ini": 1.0, "cycles": 0},
        "contact": sections.pop("contact", CONTACT),
        "bodies": bodies,
        **sections,
    }
    return RotorConfig.model_validate(data)


def at(angle: float, radius: float = 1.5) -> dict[str, float]:
    return {"x": radius * math.cos(angle), "y": radius * math.sin(angle)}


@pytest.mark.parametrize("integrator", ["euler", "heun"])
def test_step_with_contact_equals_numpy_reference(integrator: str) -> None:
    """One compiled step of two boats whose footprints are within the contact range and a
    free disk within range of the outer wall is the numpy reference's step."""
    half = math.asin(1.88 / 2 / 1.5)  # chord 1.88: footprints (0.92 each) 0.04 apart
    bodies = [
        {**BOAT, "name": "a", "start": at(0.0)},
        {**BOAT, "name": "b", "start": at(2 * half)},
        {
            "name": "disk",
            "pills": [{"x": 0.0, "y": 0.0}],
            "motion": {"kind": "free", "mass": 1e-3},
            "start": {"x": 0.0, "y": -1.94, "velocity": [0.3, -0.2]},
        },
    ]
    config = contact_config(bodies, numerics={"scheme": "paper", "integrator": integrator})
    sim = Simulation(config)
    x, y = sim.pde.cell_coordinates()
    mask = sim.pde.domain.interior_mask
    sim.state.data[0] = mask * (1 + 0.5 * np.sin(1.3 * x + 0.2) * np.cos(0.7 * y + 0.1))
    pde: SurfacePDE = sim.pde
    before = sim.state.copy()
    dt = config.grid.dt
    want = pde.reference_step(before, dt)
    sim.run(dt)
    old = before.bodies.poses[:, :6]
    rates = (sim.bodies.poses[:, :6] - old) / dt
    reference = (want.bodies.poses[:, :6] - old) / dt
    for column in range(6):
        size = np.abs(reference[:, column]).max()
        np.testing.assert_allclose(rates[:, column], reference[:, column], atol=1e-9 * size)
    # the contact dominates: without it the step differs by far more than that
    off = contact_config(bodies, contact={"enabled": False})
    plain = SurfacePDE(off).reference_step(before, dt)
    moved = (plain.bodies.poses[:, 3:5] - old[:, 3:5]) / dt
    assert np.abs(moved - reference[:, 3:5]).max() > 1e3 * 1e-9 * np.abs(reference).max()


def test_boats_pushed_together_stop_where_the_spring_balances_the_push() -> None:
    """Two camphor-free disks on one track pushed towards each other by the tangential
    force f_t come to rest where the spring's force along the track balances it,
    kappa (ell - g) cos(dtheta / 2) = f_t (g the footprints' gap, dtheta their angle
    apart); without contact their footprints meet and end the run."""
    force = 0.1
    disk = {"shape": "disk", "radius": 0.2}
    bodies = [
        {
            "name": name,
            "plate": disk,
            "motion": {"kind": "track", "mass": 2e-3, "friction": 1.0, "direction": way,
                       "force": force},
            "start": at(angle),
        }
        for name, way, angle in (("ccw", "counterclockwise", -0.8), ("cw", "clockwise", 0.8))
    ]  # fmt: skip
    config = contact_config(bodies, flow={"enabled": False})
    sim = Simulation(config)
    sim.run(1.0)
    poses = sim.bodies.poses
    reach = config.body_list()[0].reach(config.geometry.smoothing)
    chord = float(np.hypot(*(poses[0, :2] - poses[1, :2])))
    gap = chord - 2 * reach
    dtheta = 2 * math.asin(chord / 3.0)
    assert 0 < gap < CONTACT["range"]
    speed = np.abs(poses[:, 5]).max() * 1.5
    assert speed < 1e-4 * force / (1.0 * math.pi * 0.2**2)  # 1e-4 of the free speed f / (mu A)
    along = CONTACT["stiffness"] * (CONTACT["range"] - gap) * math.cos(dtheta / 2)
    assert along == pytest.approx(force, rel=1e-3)
    off = Simulation(contact_config(bodies, flow={"enabled": False}, contact={"enabled": False}))
    with pytest.raises(BodyContactError, match="touched"):
        off.run(1.0)


def test_a_free_disk_thrown_at_the_inner_wall_bounces_off() -> None:
    """A free disk thrown at the annulus' inner wall with contact on is pushed back by the
    wall's spring and the run goes on (without contact it ends there)."""
    disk = {
        "name": "thrown",
        "plate": {"shape": "disk", "radius": 0.1},
        "motion": {"kind": "free", "mass": 1e-3, "friction": 0.01},
        "start": {"x": 0.0, "y": 1.5, "velocity": [0.0, -2.0]},
    }
    sim = Simulation(contact_config([disk], flow={"enabled": False}))
    sim.run(0.5)  # the footprint (0.6) meets the wall's range near t = 0.2
    assert sim.bodies.poses[0, 4] > 1.0  # moving outwards again, nearly as fast
    off = Simulation(contact_config([disk], flow={"enabled": False}, contact={"enabled": False}))
    with pytest.raises(BodyContactError, match="reached a wall of the annulus"):
        off.run(0.5)


@pytest.mark.parametrize(
    ("data", "start"),
    [
        ({"contact": {"enabled": True}}, "contact.enabled = true: acts between the bodies"),
        (
            {
                "grid": GRID,
                "geometry": {"smoothing": 0.025},
                "contact": {"enabled": True, "stiffness": 1e5},
                "bodies": [{**BOAT, "start": at(0.0)}],
            },
            "contact.stiffness = 100000.0: is too stiff",
        ),
    ],
)
def test_bad_contact_input_is_one_line_naming_its_key(data: dict[str, Any], start: str) -> None:
    """Contact without bodies, or a spring the step cannot resolve, is refused."""
    with pytest.raises(ConfigError) as err:
        validate_config(data)
    assert str(err.value).startswith(start), str(err.value)
