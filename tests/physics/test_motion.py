"""The compiled equation of motion (pde_rotor.physics.motion) against the numpy one
(pde_rotor.model.motion) and the friction integrals written out."""

from __future__ import annotations

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.kernels.records import make_body_records
from pde_rotor.model.motion import Inertia, accelerations, euler_poses, heun_poses
from pde_rotor.model.setup import Setup
from pde_rotor.physics.build import CPU

PILL = [{"x": 0.0, "y": 0.0}]
BODIES = [
    {
        "name": "free",
        "pills": PILL,
        "motion": {"kind": "free", "mass": 0.02, "inertia": 0.004},
        "external_force": [0.3, -0.1],
        "external_torque": 0.02,
    },
    {
        "name": "axis",
        "pills": PILL,
        "motion": {"kind": "fixed_axis", "inertia": 0.002},
        "start": {"x": 2.0},
        "external_torque": -0.01,
    },
]

motion = CPU.motion


def records() -> tuple[np.ndarray, Inertia]:
    config = RotorConfig.model_validate({"grid": {"domain_radius": 4.0}, "bodies": BODIES})
    setup = Setup(config)
    return make_body_records(setup)[0], Inertia.of(setup.bodies)


@pytest.mark.parametrize("flow", [True, False])
def test_loads_are_the_friction_integrals_and_the_numpy_accelerations(flow: bool) -> None:
    """The friction force and torque from the moments of ``friction_moments`` equal
    -mu int F (u_k - v) dA and -mu int F (r - X) x (u_k - v) dA summed directly over a
    random plate and flow; the tension is s k times its integrals; the accelerations are
    the numpy reference's (external load included)."""
    rng = np.random.default_rng(5)
    n = 12
    buf = np.concatenate(
        [rng.uniform(0, 1, n), rng.normal(size=2 * n) if flow else np.zeros(2 * n)]
    )
    f = rng.uniform(0, 1, n)
    rx, ry = rng.normal(size=n), rng.normal(size=n)
    body, inertia = records()
    pose = (0.5, -0.2, 0.3, 0.7, -0.4, 2.5)
    u, v, omega = pose[3:]
    sums = np.zeros(7)
    for o in range(n):
        sums += motion.friction_moments(buf, o, n, f[o], rx[o], ry[o], flow)
    tension = rng.normal(size=3)
    integrals = (*tension, *sums)
    slip_x = u - omega * ry - buf[n : 2 * n]
    slip_y = v + omega * rx - buf[2 * n :]
    for k in range(2):
        mu = body[k]["friction"]
        loads = motion.body_loads(integrals, pose, body[k], -0.7)
        np.testing.assert_allclose(loads[:3], -0.7 * tension, rtol=1e-15)
        friction = -mu * np.array(
            [np.sum(f * slip_x), np.sum(f * slip_y), np.sum(f * (rx * slip_y - ry * slip_x))]
        )
        np.testing.assert_allclose(loads[3:6], friction, rtol=1e-12, atol=1e-14)
        want = accelerations(np.array([loads[:6]] * 2), inertia, np.array([pose] * 2))[k]
        np.testing.assert_allclose(loads[6:], want, rtol=1e-14)
        assert motion.finite_loads(loads)


@pytest.mark.parametrize("flow", [True, False])
@pytest.mark.parametrize("tension", [True, False])
def test_cell_integrals_are_the_area_integrands_summed(tension: bool, flow: bool) -> None:
    """``cell_integrals`` summed over a grid's interior cells equals the area integrands
    written out with numpy: F grad c by central differences and its moment
    (r - X) x F grad c (0 where `tension` is off: the contour form replaces them), and
    the friction's moments of F (v read only with `flow`)."""
    rng = np.random.default_rng(7)
    n, dx = 9, 0.1
    c = rng.uniform(0, 1, (n, n))
    v = rng.normal(size=(2, n, n)) if flow else np.zeros((2, n, n))
    buf = np.concatenate([c.ravel(), v.ravel()])
    f = rng.uniform(0, 1, (n, n))
    rx, ry = rng.normal(size=n), rng.normal(size=n)
    p = np.zeros(1, dtype=[("inv_saturation", "f8")]).view(np.recarray)[0]
    sums = (0.0,) * 10
    for i in range(1, n - 1):
        for j in range(1, n - 1):
            r = (rx[i], ry[j])
            terms = (tension, flow)
            sums = motion.cell_integrals(
                sums, buf, i * n + j, (n, 1, n * n), f[i, j], r, 0.5 / dx, p, terms
            )
    inner = (slice(1, -1), slice(1, -1))
    dcdx = (c[2:, 1:-1] - c[:-2, 1:-1]) / (2 * dx)
    dcdy = (c[1:-1, 2:] - c[1:-1, :-2]) / (2 * dx)
    fi, x, y = f[inner], rx[1:-1, None], ry[None, 1:-1]
    vx, vy = v[0][inner], v[1][inner]
    grad = [np.sum(fi * dcdx), np.sum(fi * dcdy), np.sum(fi * (x * dcdy - y * dcdx))]
    want = [
        *(grad if tension else [0.0, 0.0, 0.0]),
        np.sum(fi),
        np.sum(fi * x),
        np.sum(fi * y),
        np.sum(fi * (x * x + y * y)),
        np.sum(fi * (x * vy - y * vx)),
        np.sum(fi * vx),
        np.sum(fi * vy),
    ]
    np.testing.assert_allclose(sums, want, rtol=1e-13, atol=1e-14)


def test_euler_and_heun_poses_are_the_numpy_ones() -> None:
    """One Euler and one Heun step of the poses equal the numpy reference's, for a free
    and a fixed_axis body."""
    body, inertia = records()
    rng = np.random.default_rng(6)
    poses = rng.normal(size=(2, 6))
    poses[1, [0, 1, 3, 4]] = [2.0, 0.0, 0.0, 0.0]
    loads = rng.normal(size=(2, 9))
    loads[1, 6:8] = 0.0
    loads_p = rng.normal(size=(2, 9))
    loads_p[1, 6:8] = 0.0
    dt = 1e-3
    held = np.zeros(2, dtype=bool)
    euler = euler_poses(poses, loads[:, 6:], held, inertia, dt)
    predicted = np.array(
        [motion.euler_pose(tuple(poses[k]), tuple(loads[k]), dt, body[k]) for k in range(2)]
    )
    np.testing.assert_allclose(predicted, euler, rtol=1e-15)
    heun = heun_poses(poses, loads[:, 6:], predicted, loads_p[:, 6:], held, inertia, dt)
    got = [
        motion.heun_pose(
            tuple(poses[k]), tuple(loads[k]), tuple(predicted[k]), tuple(loads_p[k]), dt, body[k]
        )
        for k in range(2)
    ]
    np.testing.assert_allclose(np.array(got), heun, rtol=1e-15)
