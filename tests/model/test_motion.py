"""The numpy equation of motion (pde_rotor.model.motion) against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.model.motion import Inertia, accelerations, euler_poses, held_bodies, heun_poses
from pde_rotor.model.setup import Setup

PILL = [{"x": 0.0, "y": 0.0}]
BODIES = [
    {"name": "free", "pills": PILL, "motion": {"kind": "free", "mass": 0.5, "inertia": 0.008}},
    {
        "name": "axis",
        "pills": PILL,
        "motion": {"kind": "fixed_axis", "inertia": 0.004},
        "start": {"x": 2.0},
    },
    {"name": "fixed", "pills": PILL, "motion": {"kind": "fixed"}, "start": {"x": -2.0}},
]


def three_bodies() -> Inertia:
    config = RotorConfig.model_validate({"grid": {"domain_radius": 4.0}, "bodies": BODIES})
    return Inertia.of(Setup(config).bodies)


def test_accelerations_are_the_loads_over_mass_and_inertia() -> None:
    """dU/dt = (f + f_fr) / m for the free body only, domega/dt = (T + T_fr) / I for the
    turning ones, 0 for the fixed one."""
    inertia = three_bodies()
    forces = np.array([[1.0, 2.0, 3.0, -0.5, -1.0, -1.0]] * 3)
    accel = accelerations(forces, inertia, np.zeros((3, 6)))
    np.testing.assert_allclose(accel, [[1.0, 2.0, 250.0], [0.0, 0.0, 500.0], [0.0, 0.0, 0.0]])


@pytest.mark.parametrize("dt", [0.1, 0.01])
def test_heun_is_exact_and_euler_first_order_under_constant_loads(dt: float) -> None:
    """Under constant accelerations a Heun step is the exact parabola
    x + u dt + a dt^2 / 2 (its rates at the predicted pose are the same accelerations);
    Euler misses it by a dt^2 / 2; held bodies keep their pose."""
    inertia = three_bodies()
    poses = np.array([[0.1, 0.2, 0.3, 1.0, -1.0, 2.0]] * 3)
    accel = np.array([[4.0, -2.0, 6.0]] * 3)
    held = np.array([False, False, True])
    euler = euler_poses(poses, accel, held, inertia, dt)
    heun = heun_poses(poses, accel, euler, accel, held, inertia, dt)
    exact = poses[0, :3] + poses[0, 3:] * dt + 0.5 * accel[0] * dt**2
    np.testing.assert_allclose(heun[0, :3], exact, rtol=1e-14)
    np.testing.assert_allclose(heun[0, 3:], poses[0, 3:] + accel[0] * dt, rtol=1e-14)
    np.testing.assert_allclose(exact - euler[0, :3], 0.5 * accel[0] * dt**2, rtol=1e-9)
    assert heun[1, 2] == pytest.approx(0.3 + 2.0 * dt + 3.0 * dt**2, rel=1e-14)
    assert (heun[1, [0, 1, 3, 4]] == poses[1, [0, 1, 3, 4]]).all()  # a fixed axis
    np.testing.assert_array_equal(heun[2], poses[2])


def test_held_bodies_are_the_fixed_ones_and_those_in_a_stop() -> None:
    """A body is held in the steps of its own stops and always when fixed."""
    protocol = {"t_ini": 0.001, "t_stop": 0.001, "t_release": 0.002, "cycles": 1}
    bodies = [{**BODIES[0], "protocol": protocol}, BODIES[2]]
    config = RotorConfig.model_validate(
        {"grid": {"domain_radius": 4.0, "dt": 1e-4}, "bodies": bodies}
    )
    setup = Setup(config)
    found, schedules = setup.bodies, setup.body_schedules
    steps = [held_bodies(found, schedules, step).tolist() for step in (9, 10, 19, 20)]
    assert steps == [[False, True], [True, True], [True, True], [False, True]]
