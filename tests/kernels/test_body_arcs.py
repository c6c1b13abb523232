"""The circles of the contour form (:mod:`pde_rotor.kernels.body_arcs`) under the grid's
mirrors: a circle that a mirror of the grid maps onto itself, on a c symmetric under that
mirror, feels no force across the mirror's axis, exactly; a ring's two passes against
its orbits one by one."""

from __future__ import annotations

from typing import Any

import numba as nb
import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.kernels.body_arcs import place_ring, ring_scratch, ring_sum
from pde_rotor.kernels.records import PARAMS
from pde_rotor.model.body_schemes import ARC_EDGES
from pde_rotor.physics.build import CPU, FASTMATH
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


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def _one_pass(coef, lattice, circle, trig, p):
    """A ring's sum orbit by orbit, the tension's ``arc_orbit`` for each in turn."""
    o_x = 0.0
    o_y = 0.0
    for a_l in range(trig.shape[1]):
        a, c = CPU.tension.arc_orbit(coef, lattice, circle, trig[0, a_l], trig[1, a_l], p)
        o_x += a
        o_y += c
    return o_x, o_y


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def _two_passes(coef, lattice, circle, trig, p, scratch):
    """The same ring in :func:`circle_sums`' two passes."""
    place_ring(lattice, circle, trig, scratch)
    axes = CPU.tension.arc_orbit(coef, lattice, circle, trig[0, 0], trig[1, 0], p)
    return ring_sum(coef, trig, scratch, axes, p)


@pytest.mark.parametrize("saturation", [0.0, 0.5], ids=["linear", "saturating"])
def test_a_ring_in_two_passes_has_the_bits_of_its_orbits_one_by_one(saturation: float) -> None:
    """Rings of radius 0.01 to 0.6 about centres anywhere in a cell, the body turned
    anyhow, on random spline coefficients: :func:`place_ring` then :func:`ring_sum` give
    the sums of ``arc_orbit`` orbit by orbit exactly (the shares' products fused into
    the running sum, as a loop of its own avoids, change them by an ulp), for the
    paper's linear law and a saturating one."""
    rng = np.random.default_rng(7)
    n, dx = 64, 0.05
    coef = rng.uniform(0.0, 2.0, n * n)
    p = np.zeros(1, PARAMS).view(np.recarray)[0]
    p.inv_saturation = saturation
    quarter = ARC_EDGES * 32 // 4
    step = 0.5 * np.pi / quarter
    trig = np.array([np.cos(step * np.arange(quarter)), np.sin(step * np.arange(quarter))])
    scratch = ring_scratch(quarter)
    for _ in range(200):
        cx, cy = rng.uniform(-0.4, 0.4, 2)
        phi = rng.uniform(-np.pi, np.pi)
        circle = (cx, cy, rng.uniform(0.01, 0.6), np.cos(phi), np.sin(phi))
        lattice = (0, n, 1.0 / dx)
        assert _two_passes(coef, lattice, circle, trig, p, scratch) == _one_pass(
            coef, lattice, circle, trig, p
        )
