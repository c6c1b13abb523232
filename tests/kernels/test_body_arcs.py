"""The circles of the contour form (:mod:`pde_rotor.kernels.body_arcs`) under the grid's
mirrors: a circle that a mirror of the grid maps onto itself, on a c symmetric under that
mirror, feels no force across the mirror's axis, exactly."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation

FREE = {"kind": "free", "mass": 2e-3, "friction": 0.2, "inertia": 1e-5}


def first_loads(body: dict[str, Any], mirrors: tuple[int, ...], wave: float = 0.0) -> np.ndarray:
    """The tension force and torque (x, y, torque) on `body` at the first step of a
    consistent-scheme run (coarse grid dx = delta = 0.05, dish of radius 2, flow off)
    from a smooth c without symmetry, made exactly symmetric under the grid's `mirrors`
    (0: x -> -x, 1: y -> -y; each a flip of the array, whose middle is the dish's centre),
    plus `wave` times a plane wave that has neither symmetry."""
    cfg = RotorConfig.model_validate(
        {
            "grid": {"dx": 0.05, "dt": 4e-4, "domain_radius": 2.0},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": "consistent"},
            "flow": {"enabled": False},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "bodies": [body],
        }
    )
    sim = Simulation(cfg)
    x, y = sim.pde.cell_coordinates()
    c = 1.0 + 0.5 * np.sin(3.0 * x + 0.3) * np.cos(2.0 * y + 0.1)
    c = c + np.exp(-((x - 0.1) ** 2) - y * y)
    for axis in mirrors:
        c = c + np.flip(c, axis)
    sim.state.data[:] = 0.0
    sim.state.data[0] = c + wave * np.sin(2.0 * x + 3.0 * y)
    sim.run(cfg.grid.dt)
    return sim.bodies.poses[0, 6:9].copy()


@pytest.mark.parametrize(
    "plate", [{"shape": "none"}, {"shape": "disk", "radius": 0.2}], ids=["pill", "disk plate"]
)
def test_a_circle_at_the_dish_centre_on_a_symmetric_field_feels_no_force(
    plate: dict[str, Any],
) -> None:
    """A pill, or a disk plate, at the dish's centre on a c symmetric under both mirrors
    of the grid: its contour force is 0 bit for bit (the nodes in mirror images, read
    about the grid's middle; off by round-off it was 4e-16). The same circle on the same
    c plus a plane wave of amplitude 1e-3 feels a force along both axes."""
    body = {"name": "disk", "plate": plate, "pills": [{"x": 0.0, "y": 0.0}], "motion": FREE}
    force = first_loads(body, (0, 1))
    assert force[0] == 0.0 and force[1] == 0.0
    waved = first_loads(body, (0, 1), wave=1e-3)
    assert np.abs(waved[:2]).min() > 1e-6


def test_a_pill_off_the_body_centre_feels_no_force_across_a_mirror_of_its_circle() -> None:
    """A body at the dish's centre, turned by 0, its one pill 0.3 along its x axis, on a
    c symmetric under y -> -y only: the pill's circle lies on the mirror's axis, so its
    force along y and its torque about the body's centre are 0 bit for bit, while its
    force along x is not."""
    body = {"name": "boat", "plate": {"shape": "none"}, "pills": [{"x": 0.3, "y": 0.0}],
            "motion": FREE}  # fmt: skip
    force_x, force_y, torque = first_loads(body, (1,))
    assert force_y == 0.0 and torque == 0.0
    assert abs(force_x) > 1e-3
