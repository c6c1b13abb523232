"""The compiled step of K bodies against the numpy reference and the model's symmetries."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.gallery.onsets import (
    free_disk_config,
    kick_growth_rate,
    kick_rotation_rate,
    two_disk_rotor_config,
)
from pde_rotor.model.surface import POSE_COLUMNS, SurfacePDE
from pde_rotor.solver.bodies import BodyContactError
from pde_rotor.solver.simulation import Simulation

HEXAGON = {"shape": "polygon", "n_corners": 6, "radius": 0.5}
COARSE = {"dx": 0.05, "dt": 2e-4}
PAPER_NUMERICS = {"scheme": "paper"}


def surface_config(bodies: list[dict[str, Any]], **sections: Any) -> RotorConfig:
    """A coarse-grid config with `bodies` (paper scheme unless given, no stops unless
    given)."""
    data: dict[str, Any] = {
        "grid": {**COARSE, **sections.pop("grid", {})},
        "numerics": sections.pop("numerics", PAPER_NUMERICS),
        "protocol": sections.pop("protocol", {"t_ini": 1.0, "cycles": 0}),
        "bodies": bodies,
        **sections,
    }
    return RotorConfig.model_validate(data)


def smooth_fields(sim: Simulation, seed: int = 0) -> None:
    """Fill c and v with smooth, nonzero, non-symmetric fields on the dish's interior."""
    x, y = sim.pde.cell_coordinates()
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.5, 1.5, size=6)
    mask = sim.pde.domain.interior_mask
    sim.state.data[0] = mask * (1 + a[0] * np.sin(1.3 * x + a[1]) * np.cos(0.7 * y + a[2]))
    sim.state.data[1] = mask * 0.3 * np.sin(0.9 * y + a[3]) * np.cos(0.4 * x)
    sim.state.data[2] = mask * 0.2 * np.cos(1.1 * x + a[4]) * np.sin(0.5 * y + a[5])


FOUR_BODIES = [
    {
        "name": "hexagon",
        "plate": HEXAGON,
        "pills": [{"x": 0.3, "y": 0.05}, {"x": -0.2, "y": -0.2, "radius": 0.08, "supply": 2.0}],
        "motion": {"kind": "fixed_axis"},
        "start": {"x": -2.0, "y": 1.0, "angle": 0.4, "omega": 3.0},
    },
    {
        "name": "disk",
        "plate": {"shape": "none"},
        "pills": [{"x": 0.0, "y": 0.0}],
        "motion": {"kind": "free", "mass": 1e-5, "inertia": 5e-8, "friction": 1e-4},
        "start": {"x": 1.5, "y": 1.8, "angle": 0.2, "omega": -1.0, "velocity": [0.4, -0.3]},
    },
    {
        "name": "strip",
        "plate": {"shape": "strip", "length": 0.8, "width": 0.3},
        "pills": [{"x": 0.3, "y": 0.0, "radius": 0.06}, {"x": -0.3, "y": 0.0, "radius": 0.06}],
        "motion": {"kind": "free", "mass": 3e-5, "friction": 1e-4},
        "start": {"x": 1.5, "y": -1.5, "angle": 0.7, "omega": 2.0, "velocity": [-0.2, 0.1]},
    },
    {
        "name": "source",
        "plate": {"shape": "disk", "radius": 0.2},
        "pills": [{"x": 0.05, "y": 0.0, "radius": 0.1}],
        "motion": {"kind": "fixed"},
        "start": {"x": -1.5, "y": -2.0},
    },
]


CONSISTENT_BODIES = [
    *FOUR_BODIES[:3],
    {
        **FOUR_BODIES[3],
        "motion": {"kind": "free", "mass": 1e-4, "friction": 1e-4},
        "start": {"x": -1.5, "y": -2.0, "velocity": [0.1, 0.2]},
    },
    {
        "name": "pair",
        "plate": {"shape": "none"},
        "pills": [{"x": 0.3, "y": 0.0, "radius": 0.06}, {"x": -0.3, "y": 0.05, "radius": 0.08}],
        "motion": {"kind": "free", "mass": 3e-5, "inertia": 1e-6, "friction": 1e-4},
        "start": {"x": 0.2, "y": 0.2, "angle": 0.7, "omega": 2.0, "velocity": [-0.2, 0.1]},
    },
]
"""The bodies on the consistent scheme: the four, the disk plate moving, and a free body
floating on two pills."""


@pytest.mark.parametrize(
    ("scheme", "flow", "integrator", "saturation", "widths"),
    [
        ("paper", True, "euler", None, 20.0),
        ("paper", False, "euler", None, 20.0),
        ("consistent", True, "euler", None, 20.0),
        ("paper", True, "heun", None, 20.0),
        ("consistent", True, "heun", None, 20.0),
        ("paper", True, "euler", 0.5, 20.0),
        ("consistent", True, "heun", 0.5, 20.0),
        ("paper", True, "euler", None, 4.0),
        ("consistent", True, "euler", None, 4.0),
    ],
)
def test_step_equals_numpy_reference(
    scheme: str, flow: bool, integrator: str, saturation: float | None, widths: float
) -> None:
    """One compiled step of four bodies of every plate shape and motion is the numpy
    reference's step (:meth:`SurfacePDE.reference_step`): the rates of Eqs. (eqc), (eqv),
    the forces and torques and the equation of motion of Eq. (eq_motion), on both
    schemes (consistent: filtered F_k, G_k and the contour forms, each written twice),
    forward Euler and Heun, the linear and the saturating surface tension, and with the
    footprints cut at 4 smoothing widths (``numerics.footprint_widths``: tails of
    3.4e-4 dropped, the same cells by both, and the circles' rules ended there)."""
    bodies = FOUR_BODIES if scheme == "paper" else CONSISTENT_BODIES
    config = surface_config(
        bodies,
        flow={"enabled": flow},
        grid={"domain_radius": 4.0},
        numerics={"scheme": scheme, "integrator": integrator, "footprint_widths": widths},
        camphor={"saturation": saturation},
    )
    sim = Simulation(config)
    smooth_fields(sim)
    if not flow:
        sim.state.data[1:] = 0.0
    pde: SurfacePDE = sim.pde
    before = sim.state.copy()
    dt = config.grid.dt
    want = pde.reference_step(before, dt)
    scale = np.abs(pde.evolution_rate(before).data).max()
    sim.run(dt)
    mask = pde.domain.interior_mask
    computed = (sim.state.data - before.data) / dt
    expected = (want.data - before.data) / dt
    assert np.abs((computed - expected)[:, mask]).max() <= 1e-9 * scale
    moving = [k for k, b in enumerate(pde.bodies) if b.motion != "fixed"]
    forces = want.bodies.poses[:, 6:12]
    recorded = sim.bodies.poses[moving, 6:12]
    np.testing.assert_allclose(
        recorded, forces[moving], rtol=1e-9, atol=1e-12 * np.abs(forces).max()
    )
    # the bodies moved by the reference's step of Eq. (eq_motion) with those forces
    old = before.bodies.poses[:, :6]
    rates = (sim.bodies.poses[:, :6] - old) / dt
    reference = (want.bodies.poses[:, :6] - old) / dt
    for column in range(6):
        size = np.abs(reference[:, column]).max()
        np.testing.assert_allclose(rates[:, column], reference[:, column], atol=1e-9 * size)
    fixed = [k for k, b in enumerate(pde.bodies) if b.motion == "fixed"]
    np.testing.assert_array_equal(sim.bodies.poses[fixed, :6], before.bodies.poses[fixed, :6])
    assert np.all(np.abs(reference[moving, 5]) > 0)  # every moving body is accelerated


@pytest.mark.parametrize("integrator", ["euler", "heun"])
@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_one_body_is_the_rotor(scheme: str, integrator: str) -> None:
    """The paper's rotor written as one fixed_axis body runs as the rotor's own kernel
    does (stops, noise and flow included) to 1e-12, on both schemes and with both
    integrators: on the consistent one the body's filtered F, G and contour torque are
    the rotor's, and Heun's step of the bodies is the rotor's."""
    rotor = RotorConfig.model_validate(
        {
            "numerics": {"scheme": scheme, "integrator": integrator},
            "grid": COARSE,
            "rotor": {"omega0": 100.0},
            "noise": {"sigma": 1e-6, "seed": 3},
            "protocol": {"t_ini": 0.05, "t_stop": 0.02, "t_release": 0.03, "cycles": 3},
        }
    )
    data = rotor.model_dump()
    data["bodies"] = [body.model_dump() for body in rotor.body_list()]
    data["rotor"] = {k: v for k, v in data["rotor"].items() if k not in ("omega0", "phi0")}
    bodies = RotorConfig.model_validate(data)
    a, b = Simulation(rotor), Simulation(bodies)
    for t in (0.06, 0.14):  # in the second stop, then after the third release
        a.run(t)
        b.run(t)
        pose = b.bodies.poses[0]
        assert pose[2] == pytest.approx(a.rotor.phi, rel=1e-12, abs=1e-12)
        assert pose[5] == pytest.approx(a.rotor.omega, rel=1e-12, abs=1e-10)
        assert pose[8] == pytest.approx(a.rotor.torque, rel=1e-9, abs=1e-15)
        assert np.abs(a.state.data - b.state.data).max() <= 1e-12 * np.abs(a.state.data).max()
    assert a.rotor.omega != 0.0  # released at the end: the comparison saw rotation


def test_mirror_pair_stays_mirror_symmetric() -> None:
    """Two rotors mirrored in the y axis (axes at -+d, opposite spins) stay mirror
    images: omega_1 = -omega_2, c(x, y) = c(-x, y), v_x odd and v_y even in x."""
    left = {"plate": HEXAGON, "pills": [{"x": 0.3, "y": 0.1}], "motion": {"kind": "fixed_axis"}}
    right = {
        "plate": HEXAGON,
        "pills": [{"x": -0.3, "y": 0.1}],
        "motion": {"kind": "fixed_axis"},
    }
    config = surface_config(
        [
            {**left, "start": {"x": -1.2, "y": 0.0, "omega": 20.0}},
            {**right, "start": {"x": 1.2, "y": 0.0, "omega": -20.0}},
        ],
        grid={"domain_radius": 2.5},
    )
    sim = Simulation(config)
    sim.run(0.2)
    poses = sim.bodies.poses
    assert poses[0, 5] == pytest.approx(-poses[1, 5], rel=1e-10)
    assert poses[0, 2] == pytest.approx(-poses[1, 2], rel=1e-10)
    c, vx, vy = sim.state.data
    scale = np.abs(sim.state.data).max(axis=(1, 2))
    assert np.abs(c - c[::-1]).max() <= 1e-10 * scale[0]
    assert np.abs(vx + vx[::-1]).max() <= 1e-10 * scale[1]
    assert np.abs(vy - vy[::-1]).max() <= 1e-10 * scale[2]
    assert abs(poses[0, 5]) > 1.0  # it turned


def test_body_reaching_the_edge_ends_the_run_naming_it() -> None:
    """A free body driven at the rim stops the run with its name, time and place."""
    config = surface_config(
        [
            {
                "name": "boat",
                "plate": {"shape": "none"},
                "pills": [{"x": 0.0, "y": 0.0}],
                "motion": {"kind": "free", "mass": 1e-5, "friction": 1e-4},
                "start": {"x": 1.3, "y": 0.0, "velocity": [5.0, 0.0]},
            }
        ],
        grid={"domain_radius": 2.0},
    )
    sim = Simulation(config)
    with pytest.raises(BodyContactError, match=r"body boat reached the dish's edge at t = ") as err:
        sim.run(1.0)
    t_end = float(str(err.value).split("at t = ")[1].split(" ")[0])
    assert 0 < t_end < 1.0
    # the footprint (rho + 20 delta = 0.6) met the rim (L - dx) within the last step
    x_end = 1.3 + 5.0 * t_end
    assert x_end + 0.6 == pytest.approx(2.0, abs=0.1)


def test_far_apart_rotors_turn_like_single_rotors() -> None:
    """Two rotors many diffusion lengths apart (sqrt(D/a) = 1) turn as each would alone
    in the same dish, to 1e-3 in omega."""
    one = {"plate": HEXAGON, "pills": [{"x": 0.3, "y": 0.05}], "motion": {"kind": "fixed_axis"}}
    starts = [{"x": -4.0, "y": 0.0, "omega": 30.0}, {"x": 4.0, "y": 0.0, "omega": -10.0}]
    grid = {"domain_radius": 5.5, "dx": 0.05, "dt": 2e-4}
    pair = Simulation(surface_config([{**one, "start": s} for s in starts], grid=grid))
    pair.run(0.6)
    for k, start in enumerate(starts):
        alone = Simulation(surface_config([{**one, "start": start}], grid=grid))
        alone.run(0.6)
        assert pair.bodies.poses[k, 5] == pytest.approx(alone.bodies.poses[0, 5], rel=1e-3)
        assert math.isfinite(alone.bodies.poses[0, 5])


def free_disk_growth(dx: float, dt: float, mu: float) -> float:
    """The simulated growth rate of a free camphor disk's velocity after a kick, no flow
    (:mod:`pde_rotor.gallery.onsets`, as benchmarks/free_disk_onset.py)."""
    relax, fit = 6.0, (0.5, 1.5)
    config = free_disk_config(dx, dt, 4.0, 2e-3, mu, relax + fit[1] + 0.1, relax)
    return kick_growth_rate(config, relax, 1e-4, fit)


@pytest.mark.parametrize(
    ("dx", "dt", "tolerance"),
    [(0.05, 4e-4, 0.1), pytest.param(0.025, 1e-4, 0.02, marks=pytest.mark.slow)],
)
def test_free_disk_starts_moving_below_the_critical_friction(
    dx: float, dt: float, tolerance: float
) -> None:
    """A free camphor disk (no plate, no flow) at rest: a kick grows below mu_c and decays
    above it, and the friction where the simulated growth rate changes sign is the
    linear stability's closed form (docs/bodies.md) to 10 % on the coarse grid, 2 % on
    the paper's (measured: -7 % and -0.9 %)."""
    from pde_rotor.theory import CamphorDisk, free_disk_critical_friction

    mu_c = free_disk_critical_friction(CamphorDisk.from_config(RotorConfig()))
    below, above = 0.9 * mu_c, 1.05 * mu_c
    lam_below = free_disk_growth(dx, dt, below)
    lam_above = free_disk_growth(dx, dt, above)
    assert lam_below > 0 > lam_above
    simulated = below - lam_below * (above - below) / (lam_above - lam_below)
    assert simulated == pytest.approx(mu_c, rel=tolerance)


@pytest.mark.parametrize(
    ("dx", "dt", "radius", "factors", "fit", "tolerance"),
    [
        (0.05, 4e-4, 2.0, (0.92, 1.0), (3.0, 11.0), (0.08, 0.05)),
        pytest.param(
            1 / 30, 2e-4, 3.0, (0.96, 1.0), (4.0, 24.0), (0.02, 0.05), marks=pytest.mark.slow
        ),
    ],
)
def test_disk_in_a_no_flux_dish_leaves_rest_through_a_hopf_onset(
    dx: float,
    dt: float,
    radius: float,
    factors: tuple[float, float],
    fit: tuple[float, float],
    tolerance: tuple[float, float],
) -> None:
    """A free camphor disk at the centre of a no-flux dish (Koyano, Suematsu & Kitahata
    2019; no flow): a kick grows below and decays above the linear stability's Hopf onset
    (docs/bodies.md), turning about the centre, and the friction where the fitted growth
    rate changes sign, and the frequency there, are mu_c and omega_c to within
    `tolerance`: on the coarse grid in a dish of radius 2 (measured: -5.2 % and +0.5 %), on a
    grid of dx = 1/30 in the dish of radius 3 (measured: -0.3 % and +2.2 %)."""
    from pde_rotor.gallery.onsets import disk_in_dish_config, kick_hopf_rate
    from pde_rotor.theory import CamphorDisk, Wall, dish_hopf_onset

    mass, relax = 1e-4, 6.0
    mu_c, omega_c = dish_hopf_onset(
        CamphorDisk.from_config(RotorConfig()), Wall(radius, "no_flux"), mass
    )
    mus = [factor * mu_c for factor in factors]
    rates = [
        kick_hopf_rate(
            disk_in_dish_config(dx, dt, radius, mass, mu, relax + fit[1] + 0.1, relax),
            relax,
            1e-4,
            fit,
        )
        for mu in mus
    ]
    assert rates[0].real > 0 > rates[1].real
    assert rates[0].imag > 0 and rates[1].imag > 0
    weight = rates[0].real / (rates[0].real - rates[1].real)
    simulated = mus[0] + weight * (mus[1] - mus[0])
    omega = rates[0].imag + weight * (rates[1].imag - rates[0].imag)
    assert simulated == pytest.approx(mu_c, rel=tolerance[0])
    assert omega == pytest.approx(omega_c, rel=tolerance[1])


def test_two_disk_rotor_starts_turning_below_its_critical_friction() -> None:
    """The two-disk rotor of Koyano et al. (PRE 2017), l = 0.5, no flow: a kick to omega
    grows at 0.9 mu_c(l) and decays at 1.05 mu_c(l) of the linear stability
    (docs/bodies.md), and the sign change lies within 10 % of mu_c on the coarse grid
    (measured: -6 %; -0.2 % on the paper grid)."""
    from pde_rotor.theory import CamphorDisk, rotor_critical_friction

    half_length, inertia, relax, fit = 0.5, 1e-4, 6.0, (0.5, 1.5)
    mu_c = rotor_critical_friction(CamphorDisk.from_config(RotorConfig()), half_length, 0.025)
    rates = []
    for mu in (0.9 * mu_c, 1.05 * mu_c):
        config = two_disk_rotor_config(0.05, 4e-4, 3.0, half_length, inertia, mu, 8.0, relax)
        rates.append(kick_rotation_rate(config, relax, 1e-3, fit))
    assert rates[0] > 0 > rates[1]
    simulated = 0.9 * mu_c - rates[0] * 0.15 * mu_c / (rates[1] - rates[0])
    assert simulated == pytest.approx(mu_c, rel=0.1)


def test_free_body_momentum_balances_the_forces_of_the_fields() -> None:
    """A free strip with pills, moving and turning through its own camphor and flow: over
    every step m dU = (tension + friction force) dt and I domega = (torque + friction
    torque) dt with the forces the step recorded, and those forces are the numpy
    reference's of the state the step started from, at the start and after 150 steps."""
    strip = {
        "name": "strip",
        "plate": {"shape": "strip", "length": 0.8, "width": 0.3},
        "pills": [{"x": 0.3, "y": 0.05, "radius": 0.06}],
        "motion": {"kind": "free", "mass": 2e-4, "inertia": 4e-6, "friction": 1e-4},
        "start": {"x": -0.3, "y": 0.2, "angle": 0.3, "omega": 4.0, "velocity": [0.3, -0.2]},
    }
    config = surface_config([strip], grid={"domain_radius": 2.5})
    sim = Simulation(config)
    dt = config.grid.dt
    body = sim.pde.bodies[0]
    for start in (0, 150):
        sim.run(start * dt)
        before = sim.state.copy()
        reference = sim.pde.body_forces(before)[0]
        sim.run((start + 1) * dt)
        pose = sim.bodies.poses[0]
        np.testing.assert_allclose(pose[6:12], reference, rtol=1e-9, atol=1e-14)
        old = before.bodies.poses[0]
        f_x, f_y, torque, d_x, d_y, friction = pose[6:12]
        assert body.mass * (pose[3] - old[3]) == pytest.approx((f_x + d_x) * dt, rel=1e-10)
        assert body.mass * (pose[4] - old[4]) == pytest.approx((f_y + d_y) * dt, rel=1e-10)
        assert body.inertia * (pose[5] - old[5]) == pytest.approx(
            (torque + friction) * dt, rel=1e-10
        )
    assert abs(sim.bodies.poses[0, 0] - (-0.3)) > 1e-3  # it moved


BOAT = {
    "name": "boat",
    "plate": {"shape": "strip", "length": 0.6, "width": 0.3},
    "pills": [{"x": 0.05, "y": 0.0}],
    "motion": {"kind": "free", "mass": 0.05, "inertia": 0.005, "friction": 1.0},
}
"""A camphor boat: a strip plate with its pill 0.05 ahead of its centre, so it sails
backwards (-x in its frame) at a steady speed of about 0.09 (mu = 1, no flow)."""


def boat_speed(
    scheme: str, dx: float, dt: float, heading: float, offset: tuple[float, float]
) -> float:
    """The boat's mean speed over [3, 5] (distance over time) on `scheme`, started at
    rest 0.8 from the dish centre so that it sails through the centre along `heading`
    (radians), shifted by `offset` cells; delta = dx, no flow."""
    start = {
        "x": 0.8 * math.cos(heading) + offset[0] * dx,
        "y": 0.8 * math.sin(heading) + offset[1] * dx,
        "angle": heading,
    }
    config = surface_config(
        [{**BOAT, "start": start}],
        grid={"dx": dx, "dt": dt, "domain_radius": 3.0},
        geometry={"smoothing": dx},
        flow={"enabled": False},
        numerics={"scheme": scheme},
        protocol={"t_ini": 5.0, "cycles": 0},
    )
    sim = Simulation(config)
    positions = []
    for t in (3.0, 5.0):
        sim.run(round(t / dt) * dt)
        positions.append(sim.bodies.poses[0, :2].copy())
    return float(np.linalg.norm(positions[1] - positions[0]) / 2.0)


@pytest.mark.parametrize(
    ("scheme", "dx", "dt"),
    [
        ("consistent", 1 / 30, 2e-4),
        pytest.param("paper", 1 / 30, 2e-4, marks=pytest.mark.slow),
        pytest.param("paper", 0.025, 1e-4, marks=pytest.mark.slow),
    ],
)
def test_free_body_steady_speed_does_not_depend_on_where_it_starts(
    scheme: str, dx: float, dt: float
) -> None:
    """A free camphor boat's steady speed is the same to 1 % whatever its heading on the
    lattice (0, 30, 45, 90 degrees) and its sub-cell start (measured spread: consistent
    scheme 0.13 % at dx = 1/30, 0.28 % at 0.05; paper scheme 0.74 % at 1/30, 0.43 % at
    0.025, 1.5 % at 0.05)."""
    starts = [
        (0.0, (0.0, 0.0)),
        (0.0, (0.37, 0.71)),
        (math.radians(30.0), (0.0, 0.0)),
        (math.radians(45.0), (0.5, 0.5)),
        (math.radians(90.0), (0.2, 0.9)),
    ]
    speeds = np.array([boat_speed(scheme, dx, dt, heading, offset) for heading, offset in starts])
    assert np.all(speeds > 0.05)  # it sails
    assert np.ptp(speeds) < 0.01 * speeds.mean()


def test_two_disk_rotor_turns_fastest_at_an_intermediate_size() -> None:
    """Koyano et al.'s omega(l) (PRE 2017; configs/bodies/two_disk_rotor_size.yaml,
    mu = 0.15, no flow), coarse grid: below the linear stability's critical size the
    rotor slows down towards rest, omega peaks between the onset and the far-apart
    regime, and far apart each disk runs near the free disk's steady speed U*(mu)
    (omega l within 10 %; measured -5 % at dx = 0.05; the paper grid in
    gallery/bodies_rotor_size.py)."""
    from pde_rotor.config import load_config
    from pde_rotor.gallery.onsets import rotation_samples, sized_rotor
    from pde_rotor.theory import (
        CamphorDisk,
        free_disk_steady_speed,
        rotor_critical_half_length,
    )

    base = load_config(
        "configs/bodies/two_disk_rotor_size.yaml",
        ["grid.dx=0.05", "grid.dt=4e-4", "geometry.smoothing=0.05"],
    )
    disk = CamphorDisk.from_config(base)
    l_c = rotor_critical_half_length(disk, 0.15, 0.05)
    below = rotation_samples(
        sized_rotor(base, 0.8 * l_c, 0.8 * l_c + 2.0), np.array([2.0, 7.0, 12.0])
    )
    assert below[0] > below[1] > below[2] > 0 and below[2] < 0.5 * below[0]  # slowing to rest
    omega = {}
    for half_length in (0.8, 1.1, 2.5):
        config = sized_rotor(base, half_length, half_length + 2.0)
        omega[half_length] = rotation_samples(config, np.array([12.0]))[0]
    assert omega[1.1] > omega[0.8] > 0.5
    assert omega[1.1] > omega[2.5] > 0.5
    assert omega[2.5] * 2.5 == pytest.approx(free_disk_steady_speed(disk, 0.15), rel=0.1)


def held_force(scheme: str, x: float, body: dict[str, Any] | None = None) -> float:
    """f_x on a free body (a camphor disk unless given) held at (x, 0) for 2 time units
    (coarse grid, L = 2)."""
    held = {
        **(body or {"name": "disk", "pills": [{"x": 0.0, "y": 0.0}]}),
        "motion": {"kind": "free", "mass": 1e-3, "friction": 1e-4},
        "start": {"x": x, "y": 0.0},
        "protocol": {"t_ini": 0.0, "t_stop": 2.0, "t_release": 1.0, "cycles": 1},
    }
    config = surface_config(
        [held],
        grid={"domain_radius": 2.0, "dt": 4e-4},
        numerics={"scheme": scheme},
        protocol={"t_ini": 2.0, "cycles": 0},
    )
    sim = Simulation(config)
    sim.run(2.0)
    return float(sim.bodies.poses[0, POSE_COLUMNS.index("force_x")])


def lattice_force(scheme: str, body: dict[str, Any] | None = None) -> tuple[float, float]:
    """(Phi, the lattice force) of a body held a quarter cell off the dish centre: the
    absorbing edge's pull f = (Phi + Phi3 x^2) x, fitted from holds at one and two
    cells, where the lattice force vanishes by symmetry, taken off the quarter cell's."""
    dx = COARSE["dx"]
    one, two, quarter = (held_force(scheme, m * dx, body) for m in (1.0, 2.0, 0.25))
    phi = (8.0 * one - two) / (6.0 * dx)
    phi3 = (two - 2.0 * one) / (6.0 * dx**3)
    x = 0.25 * dx
    return phi, abs(quarter - (phi + phi3 * x * x) * x)


def test_consistent_scheme_removes_the_lattice_force_on_a_held_disk() -> None:
    """A free camphor disk held off the dish centre feels the absorbing edge's pull
    f = (Phi + Phi3 x^2) x (Phi is the linear stability's Phi(0) of docs/bodies.md to
    10 %) plus a lattice force that depends on its sub-cell position; held a quarter
    cell off a cell corner, that lattice force is at least four times smaller on the
    consistent scheme than on the paper scheme (measured: 9 times at dx = 0.05)."""
    from pde_rotor.theory import CamphorDisk, Wall, free_disk_displacement_force

    pull = free_disk_displacement_force(
        CamphorDisk.from_config(RotorConfig()), 0.0, Wall(2.0, "absorbing")
    )
    lattice = {}
    for scheme in ("paper", "consistent"):
        phi, lattice[scheme] = lattice_force(scheme)
        assert phi == pytest.approx(pull, rel=0.1)
    assert lattice["consistent"] < lattice["paper"] / 4


def test_consistent_scheme_removes_the_lattice_force_on_a_held_strip() -> None:
    """A strip plate (0.6 x 0.3) with a pill at its centre, held a quarter cell off the
    dish centre along its length: its lattice force (less the edge's pull, fitted as
    for the disk; both schemes' pulls agree to 10 %) is a hundred times smaller on the
    consistent scheme than on the paper scheme (measured at dx = 0.05: 1.3e-7 against
    1.8e-4, with pulls Phi = 2.05e-3 and 2.07e-3)."""
    strip = {
        "name": "strip",
        "plate": {"shape": "strip", "length": 0.6, "width": 0.3},
        "pills": [{"x": 0.0, "y": 0.0}],
    }
    pulls, lattice = {}, {}
    for scheme in ("paper", "consistent"):
        pulls[scheme], lattice[scheme] = lattice_force(scheme, strip)
    assert pulls["consistent"] == pytest.approx(pulls["paper"], rel=0.1)
    assert lattice["consistent"] < lattice["paper"] / 100


def test_heun_converges_at_second_order_for_a_free_body() -> None:
    """A free camphor disk with an off-centre pill, moving and turning through its own
    camphor and flow: its pose at t = 0.04 from three steps dt, 2e-4, 1e-4 and 5e-5,
    converges at order 2 with Heun's method (the differences of successive poses shrink
    by 4) and at order 1 with forward Euler (by 2). A disk, whose F is smooth in its
    pose: a polygon's or strip's F has kinks along the corner bisectors, which cells
    cross as the body moves, and which spoil the order in time at the 1e-11 level."""
    disk = {
        "name": "disk",
        "plate": {"shape": "disk", "radius": 0.3},
        "pills": [{"x": 0.15, "y": 0.05, "radius": 0.1}],
        "motion": {"kind": "free", "mass": 0.05, "inertia": 0.005, "friction": 1.0},
        "start": {"x": 0.1, "y": -0.2, "angle": 0.3, "omega": 2.0, "velocity": [0.3, -0.1]},
    }

    def pose_at(integrator: str, dt: float) -> np.ndarray:
        config = surface_config(
            [disk],
            grid={"dt": dt, "domain_radius": 2.0},
            numerics={"scheme": "paper", "integrator": integrator},
        )
        sim = Simulation(config)
        sim.run(0.04)
        return sim.bodies.poses[0, :6].copy()

    for integrator, order in (("heun", 2), ("euler", 1)):
        poses = [pose_at(integrator, dt) for dt in (2e-4, 1e-4, 5e-5)]
        ratio = np.abs(poses[0] - poses[1]) / np.abs(poses[1] - poses[2])
        np.testing.assert_allclose(ratio, 2.0**order, rtol=0.03)


def test_external_force_without_camphor_drives_a_free_disk_at_terminal_velocity() -> None:
    """Without camphor and flow a free disk under a constant external force obeys
    m dU/dt = f_ext - mu A U, A = int F dA: it reaches U = f_ext / (mu A) (25 relaxation
    times m / (mu A)) along the force, without turning (but for the lattice's first
    moment of F); an external torque alone turns a fixed_axis disk at
    omega = T_ext / (mu J), J = int F |r - X|^2 dA."""
    force, torque, mu = (0.03, -0.04), 2e-3, 1.0
    disk = {"shape": "disk", "radius": 0.3}
    bodies = [
        {
            "name": "pushed",
            "plate": disk,
            "motion": {"kind": "free", "mass": 0.002, "inertia": 1e-3, "friction": mu},
            "start": {"x": -0.5, "y": 0.5},
            "external_force": list(force),
        },
        {
            "name": "turned",
            "plate": disk,
            "motion": {"kind": "fixed_axis", "inertia": 1e-4, "friction": mu},
            "start": {"x": 0.8, "y": -0.8},
            "external_torque": torque,
        },
    ]
    config = surface_config(bodies, grid={"domain_radius": 2.0}, flow={"enabled": False})
    sim = Simulation(config)
    x, y = sim.pde.cell_coordinates()
    area = sim.pde.domain.cell_area
    sim.run(0.2)
    owner = sim.pde.owner
    a_eff = float(np.sum(sim.pde.F[owner == 0]) * area)
    pose = sim.bodies.poses[1]
    rx, ry = x - pose[0], y - pose[1]
    polar = float(np.sum((sim.pde.F * (rx**2 + ry**2))[owner == 1]) * area)
    assert 0.002 / (mu * a_eff) < 0.2 / 25 and 1e-4 / (mu * polar) < 0.2 / 25
    np.testing.assert_allclose(sim.bodies.poses[0, 3:5], np.array(force) / (mu * a_eff), rtol=1e-3)
    assert abs(sim.bodies.poses[0, 5]) * 0.3 < 1e-3 * np.hypot(*force) / (mu * a_eff)
    assert pose[5] == pytest.approx(torque / (mu * polar), rel=1e-3)
    assert np.abs(sim.state.data).max() == 0.0


@pytest.mark.parametrize(("scheme", "bound"), [("paper", 2e-17), ("consistent", 1e-16)])
def test_a_disk_held_at_the_dish_centre_feels_no_force(scheme: str, bound: float) -> None:
    """A free camphor disk held at the dish's centre, which the dish's and the grid's
    mirrors map onto itself, feels no force but round-off, on both schemes: its window
    of cells and its nodes have their mirror images (a window or a node off by one would
    leave a force many orders larger). What is left is the run's c, mirror-symmetric only
    to 1.9e-16: the paper scheme's sums 5e-18, the consistent scheme's contour 2.5e-17
    (its nodes mirror images about the grid's middle, exact on a symmetric c:
    tests/kernels/test_body_arcs.py; read about cell 0 and each at its own angle they
    left 4e-16)."""
    disk = {
        "name": "disk",
        "plate": {"shape": "none"},
        "pills": [{"x": 0.0, "y": 0.0, "radius": 0.1}],
        "motion": {"kind": "free", "mass": 2e-3, "friction": 0.2, "inertia": 1e-5},
        "protocol": {"t_ini": 0.0, "t_stop": 0.4, "t_release": 1.0, "cycles": 1},
    }
    cfg = RotorConfig.model_validate(
        {
            "grid": {"dx": 0.05, "dt": 4e-4, "domain_radius": 2.0},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": 0.4, "cycles": 0},
            "bodies": [disk],
        }
    )
    sim = Simulation(cfg)
    sim.run(0.04)
    force = sim.bodies.poses[0, 6:8]
    assert np.abs(sim.state.data[0]).max() > 0.1  # the disk has spread its camphor
    assert np.abs(force).max() <= bound


def test_spline_window_wanted_where_the_taps_lie_keeps_the_whole_windows_bits() -> None:
    """The contour form's spline of c (``body_sums.spline_box``) wanted only on the inner
    part of its window gives there the same coefficients, bit for bit, as the whole
    window wanted (each line's recursions still run over the whole window), and leaves
    the columns before and after the wanted ones as they were (they are not computed:
    the forward recursions stop at the last wanted coefficient)."""
    from pde_rotor.kernels.body_sums import spline_box

    n = 64
    x = np.arange(n) * 0.05
    rng = np.random.default_rng(3)
    a = rng.uniform(0.5, 1.5, 4)
    c = 1 + a[0] * np.sin(1.3 * x[:, None] + a[1]) * np.cos(0.7 * x[None, :] + a[2])
    cur = np.concatenate([(c + 0.01 * rng.standard_normal((n, n))).ravel(), np.zeros(2 * n * n)])
    window, taps = (3, 61, 5, 60), (20, 33, 18, 40)
    whole = np.full(n * n, np.nan)
    spline_box(cur, whole, n, window, window, np.zeros(n))
    part = np.full(n * n, np.nan)
    spline_box(cur, part, n, window, taps, np.zeros(n))
    rows, columns = slice(taps[0], taps[1]), slice(taps[2], taps[3])
    wanted = part.reshape(n, n)[rows, columns]
    assert np.isfinite(wanted).all()
    assert np.array_equal(wanted, whole.reshape(n, n)[rows, columns])
    assert np.isnan(part.reshape(n, n)[:, : taps[2]]).all()
    assert np.isnan(part.reshape(n, n)[:, taps[3] :]).all()


def test_pill_cells_in_two_passes_are_the_cell_terms_bit_for_bit() -> None:
    """A pill's weighted filtered G on a row's cells (``body_draw._filtered_pill_cells``:
    where each cell reads the profile, then the reads) adds what the physics'
    ``filtered_pill_term`` gives cell by cell, bit for bit, 0 beyond the profile's
    end, which the row crosses."""
    import numba as nb

    from pde_rotor.kernels.body_draw import _filtered_pill_cells
    from pde_rotor.model.filtering import PROFILE_REFINEMENT, disk_profile
    from pde_rotor.physics.build import CPU

    term = CPU.indicators.filtered_pill_term

    @nb.njit
    def both(g, pill, ys, profile, inv_step):
        rows = g.copy()
        _filtered_pill_cells(rows, pill, ys, profile, inv_step, (np.empty(ys.size),
                             np.empty(ys.size, np.uint64)))  # fmt: skip
        cells = g.copy()
        for j in range(ys.size):
            cells[j] += pill[2] * term(pill[0], ys[j] - pill[1], profile, inv_step)
        return rows, cells

    dx = 0.05
    profile = disk_profile(0.05, 0.025, dx, ("sharpened", 0.95))
    inv_step = PROFILE_REFINEMENT / dx
    ys = dx * np.arange(-30, 31) + 0.013
    g = np.random.default_rng(5).uniform(0.0, 1.0, ys.size)
    for dx_p in (0.0, 0.21, 0.6, 2.0):
        rows, cells = both(g, (dx_p, 0.02, 4.0), ys, profile, inv_step)
        np.testing.assert_array_equal(rows, cells)
        if dx_p < 0.5:
            assert (rows != g).any() and (rows == g).any()  # the profile ends on the row


def test_edge_pair_in_two_passes_is_the_tensions_edge_sums_bit_for_bit() -> None:
    """A straight edge's band node (``body_sums._edge_pair``: the nodes' taps and
    weights first, then their sums in order) gives the tension's ``edge_sums`` bit for
    bit, for a strip's long and short edges at each band node, the linear and the
    saturating law."""
    import numba as nb

    from pde_rotor.kernels.body_sums import _edge_pair
    from pde_rotor.model.schemes import sech2_gauss
    from pde_rotor.physics.build import CPU

    edge_sums = CPU.tension.edge_sums

    @nb.njit
    def both(coef, grid, edge, quad_s, quad_t, m, p):
        scratch = (np.empty(quad_t.shape[1], np.uint64), np.empty((10, quad_t.shape[1])))
        got = _edge_pair(coef, grid, edge, (quad_s, quad_t), m, p, scratch)
        return got, edge_sums(coef, grid, edge, quad_s, quad_t, m, p)

    n = 64
    coef = np.random.default_rng(6).uniform(0.0, 2.0, n * n)
    grid = (0, n, -1.6, 20.0)
    quad_s = np.ascontiguousarray(np.stack(sech2_gauss(6)))
    quad_t = np.ascontiguousarray(np.stack(np.polynomial.legendre.leggauss(32)))
    for saturation in (0.0, 2.0):
        p = np.zeros(1, dtype=[("inv_saturation", "f8")]).view(np.recarray)[0]
        p.inv_saturation = saturation
        for m in range(quad_s.shape[1]):
            h = -0.025 * quad_s[0, m]
            for side, along in ((0.15, 0.075), (0.075, 0.15)):
                edge = (0.11, -0.07, math.cos(0.4), math.sin(0.4), side + h, along + h)
                got, want = both(coef, grid, edge, quad_s, quad_t, m, p)
                assert got == want
                assert all(abs(v) > 0.0 for v in got)


TAIL_DISKS = [
    {
        "name": f"disk{k}",
        "plate": {"shape": "none"},
        "pills": [{"radius": 0.1}],
        "motion": {"kind": "free", "mass": 1e-3, "inertia": 5e-6, "friction": 0.1},
        "start": {"x": x, "y": y},
    }
    for k, (x, y) in enumerate([(-0.61, 0.013), (0.6, -0.02), (0.03, 1.2)])
]
"""Three free camphor disks (rho = 0.1 = 4 delta) as close as their contact radii allow
(0.6 each), off the cells' centres."""


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
@pytest.mark.parametrize("widths", [6.0, 10.0])
def test_a_cut_footprint_errs_by_its_tail(scheme: str, widths: float) -> None:
    """Three free disks pushed apart by each other's camphor, run for 0.3 (1 500 steps)
    with footprints cut at w smoothing widths and at the saturated 20: the camphor each
    disk leaves out beyond rho + w delta is int 2 pi r g dr = pi (rho + w delta) delta
    t_w at most (t_w the tail there: 1 / (1 + e^(2 w)) on the paper scheme, the largest
    |G_eps|, |F_eps| of the filtered profiles beyond on the consistent one), a part
    (rho + w delta) delta / rho^2 t_w < t_w of its supply, so c, the velocities and
    the tension forces change by about t_w relative. Bound: 5 t_w; and the cut changes
    the run (a difference above t_w / 1000)."""
    runs = {}
    for w in (20.0, widths):
        cfg = surface_config(
            TAIL_DISKS,
            grid={"domain_radius": 2.5},
            numerics={"scheme": scheme, "footprint_widths": w},
        )
        sim = Simulation(cfg)
        sim.run(0.3)
        runs[w] = (sim.bodies.poses.copy(), np.asarray(sim.state.data[0]).copy())
    (full, c_full), (cut, c_cut) = runs[20.0], runs[widths]
    tail = 1.0 / (1.0 + math.exp(2.0 * widths))
    if scheme == "consistent":
        scheme_of = sim.pde.body_scheme
        beyond = int((0.1 + widths * 0.025) / scheme_of.profile_step)
        filt = scheme_of.filters[0]
        tail = max(np.abs(filt.pill_g[0][beyond:]).max(), np.abs(filt.pill_f[0][beyond:]).max())
    bound = 5 * tail
    errors = [
        np.abs(c_cut - c_full).max() / np.abs(c_full).max(),
        np.abs(cut[:, 3:5] - full[:, 3:5]).max() / np.abs(full[:, 3:5]).max(),
        np.abs(cut[:, 6:8] - full[:, 6:8]).max() / np.abs(full[:, 6:8]).max(),
    ]
    assert max(errors) <= bound, (errors, tail)
    assert max(errors) > tail / 1000, (errors, tail)
    assert np.abs(full[:, 3:5]).max() > 0.01  # the disks move
