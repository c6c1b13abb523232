"""Contact (``contact:``): the spring and dashpot between footprints and from the walls,
against the numpy reference, the force balance it must reach, the damped oscillator's
decay per step and the refusal of forward Euler where the spring would ring up."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from pde_rotor import RotorConfig
from pde_rotor.config import ConfigError, load_config, validate_config
from pde_rotor.config.contact import CONTACT_MODES
from pde_rotor.model.surface import POSE_COLUMNS, SurfacePDE
from pde_rotor.solver.bodies import BodyContactError, make_bodies_stepper
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.plan import Sweep

ROOT = Path(__file__).resolve().parents[2]

RING = {"shape": "annulus", "inner_radius": 0.4, "outer_radius": 2.6}
GRID = {"dx": 0.05, "dt": 2e-4, "domain_radius": 2.6, "vessel": RING}
CONTACT = {"enabled": True, "stiffness": 100.0, "range": 0.1}
DAMPED = {**CONTACT, "damping": 0.03}
"""CONTACT with the dashpot forward Euler needs for the free disk below (mu A = 3e-4)."""

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
    """One compiled step of two boats whose footprints are within the contact range, one
    of them moving, and a free disk moving within range of the outer wall, the dashpot
    on, is the numpy reference's step, and the recorded contact force is the
    reference's."""
    half = math.asin(1.88 / 2 / 1.5)  # chord 1.88: footprints (0.92 each) 0.04 apart
    bodies = [
        {**BOAT, "name": "a", "start": at(0.0), "motion": {**BOAT["motion"], "speed": 0.4}},
        {**BOAT, "name": "b", "start": at(2 * half)},
        {
            "name": "disk",
            "pills": [{"x": 0.0, "y": 0.0}],
            "motion": {"kind": "free", "mass": 1e-3},
            "start": {"x": 0.0, "y": -1.94, "velocity": [0.3, -0.2]},
        },
    ]
    numerics = {"scheme": "paper", "integrator": integrator}
    config = contact_config(bodies, numerics=numerics, contact=DAMPED)
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
    contact = [POSE_COLUMNS.index("contact_x"), POSE_COLUMNS.index("contact_y")]
    recorded = want.bodies.poses[:, contact]
    assert np.abs(recorded).min(axis=1).max() > 0.1  # every body is pushed
    np.testing.assert_allclose(
        sim.bodies.poses[:, contact], recorded, rtol=0, atol=1e-12 * np.abs(recorded).max()
    )
    # the dashpot acts: without it the contact forces at the step's start differ (Heun's
    # config: Euler without the dashpot is refused)
    spring = contact_config(bodies, numerics={"scheme": "paper", "integrator": "heun"})
    undamped = SurfacePDE(spring).reference_step(before, dt).bodies.poses[:, contact]
    assert np.abs(undamped - recorded).max() > 1e-3 * np.abs(recorded).max()
    # the contact dominates: without it the step differs by far more than that
    off = contact_config(bodies, numerics=numerics, contact={"enabled": False})
    plain = SurfacePDE(off).reference_step(before, dt)
    moved = (plain.bodies.poses[:, 3:5] - old[:, 3:5]) / dt
    assert np.abs(moved - reference[:, 3:5]).max() > 1e3 * 1e-9 * np.abs(reference).max()


def pushed_disks(force: float) -> list[dict[str, Any]]:
    """Two camphor-free disks (radius 0.2) on the track r = 1.5 of RING, 1.6 rad apart,
    pushed towards each other by the tangential force `force`."""
    disk = {"shape": "disk", "radius": 0.2}
    return [
        {
            "name": name,
            "plate": disk,
            "motion": {"kind": "track", "mass": 2e-3, "friction": 1.0, "direction": way,
                       "force": force},
            "start": at(angle),
        }
        for name, way, angle in (("ccw", "counterclockwise", -0.8), ("cw", "clockwise", 0.8))
    ]  # fmt: skip


def pushed_rest(force: float, **sections: Any) -> tuple[float, float, float]:
    """(g, kappa (ell - g) cos(dtheta / 2), largest |w|): the footprints' gap, the spring's
    force along the track and the faster arc speed of :func:`pushed_disks` after t = 1
    without flow (dtheta the disks' angle apart)."""
    config = contact_config(pushed_disks(force), flow={"enabled": False}, **sections)
    sim = Simulation(config)
    sim.run(1.0)
    poses = sim.bodies.poses
    reach = config.body_list()[0].reach(config.geometry.smoothing)
    chord = float(np.hypot(*(poses[0, :2] - poses[1, :2])))
    gap = chord - 2 * reach
    along = config.contact.stiffness * (config.contact.range - gap) * chord_cosine(chord)
    return gap, along, float(np.abs(poses[:, 5]).max() * 1.5)


def chord_cosine(chord: float) -> float:
    """cos(dtheta / 2) for two points of the circle r = 1.5 a `chord` apart."""
    return math.cos(math.asin(chord / 3.0))


def test_boats_pushed_together_stop_where_the_spring_balances_the_push() -> None:
    """Two camphor-free disks on one track pushed towards each other by the tangential
    force f_t come to rest where the spring's force along the track balances it,
    kappa (ell - g) cos(dtheta / 2) = f_t (g the footprints' gap, dtheta their angle
    apart); without contact their footprints meet and end the run."""
    force = 0.1
    gap, along, speed = pushed_rest(force)
    assert 0 < gap < CONTACT["range"]
    assert speed < 1e-4 * force / (1.0 * math.pi * 0.2**2)  # 1e-4 of the free speed f / (mu A)
    assert along == pytest.approx(force, rel=1e-3)
    off = contact_config(pushed_disks(force), flow={"enabled": False}, contact={"enabled": False})
    with pytest.raises(BodyContactError, match="touched"):
        Simulation(off).run(1.0)


def test_a_free_disk_thrown_at_the_inner_wall_bounces_off() -> None:
    """A free disk thrown at the annulus' inner wall with contact on is pushed back by the
    wall's spring (its dashpot damping the bounce by a few per cent) and the run goes on
    (without contact it ends there)."""
    disk = {
        "name": "thrown",
        "plate": {"shape": "disk", "radius": 0.1},
        "motion": {"kind": "free", "mass": 1e-3, "friction": 0.01},
        "start": {"x": 0.0, "y": 1.5, "velocity": [0.0, -2.0]},
    }
    sim = Simulation(contact_config([disk], flow={"enabled": False}, contact=DAMPED))
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
        (
            {
                "grid": GRID,
                "geometry": {"smoothing": 0.025},
                "contact": {"enabled": True},
                "bodies": [{**BOAT, "start": at(0.0)}],
            },
            "contact.damping = 0.0: lets forward Euler ring the contact spring up "
            "(numerics.integrator = euler, contact.stiffness = 100, grid.dt = 0.0002, least "
            "friction mu A = 0.04: lambda (kappa dt - gamma) > mu A for lambda = 4) (allowed: "
            "contact.damping >= 0.01, numerics.integrator: heun, or grid.dt <= 0.0001)",
        ),
        (
            {
                "grid": GRID,
                "geometry": {"smoothing": 0.025},
                "contact": {"enabled": True, "damping": 5.0},
                "bodies": [{**BOAT, "start": at(0.0)}],
            },
            "contact.damping = 5.0: is too strong for dt = 0.0002",
        ),
    ],
)
def test_bad_contact_input_is_one_line_naming_its_key(data: dict[str, Any], start: str) -> None:
    """Contact without bodies, a spring the step cannot resolve, forward Euler with too
    little damping for the spring, or a dashpot the step cannot resolve, is refused."""
    with pytest.raises(ConfigError) as err:
        validate_config(data)
    assert str(err.value).startswith(start), str(err.value)


def test_euler_is_refused_exactly_below_the_damping_that_stops_the_ringing() -> None:
    """Forward Euler with contact is accepted from gamma = kappa dt - mu A / lambda up
    (the boat's mu A = 0.5 * 0.08) and refused just below it; Heun's method is accepted
    without a dashpot; the check reads before any compute (validation only)."""
    least = CONTACT["stiffness"] * GRID["dt"] - 0.5 * 0.4 * 0.2 / CONTACT_MODES
    for damping, accepted in ((least, True), (0.99 * least, False)):
        data = {
            "grid": GRID,
            "geometry": {"smoothing": 0.025},
            "contact": {**CONTACT, "damping": damping},
            "bodies": [{**BOAT, "start": at(0.0)}],
        }
        if accepted:
            validate_config(data)
        else:
            with pytest.raises(ConfigError, match=r"^contact\.damping = "):
                validate_config(data)
    validate_config({**data, "numerics": {"integrator": "heun"}, "contact": CONTACT})


def test_shipped_configs_with_contact_are_accepted() -> None:
    """Every shipped bodies config and every point of every shipped sweep with contact on
    passes the checks."""
    count = 0
    for path in sorted((ROOT / "configs" / "bodies").glob("*.yaml")):
        count += load_config(path).contact.enabled
    for path in sorted((ROOT / "configs" / "sweeps").glob("*.yaml")):
        base = yaml.safe_load(path.read_text()).get("base", {})
        if isinstance(base, dict) and base.get("contact", {}).get("enabled"):
            for run in Sweep.load(path).runs():
                count += RotorConfig.model_validate(run.config).contact.enabled
    assert count >= 2


def step_map(integrator: str, beta: float, omega2: float, dt: float) -> tuple[float, float]:
    """(trace, determinant) of one step's 2 x 2 map of x'' + beta x' + omega^2 x = 0:
    sum and product of R(s_i dt) over the roots s_i of s^2 + beta s + omega^2 (R(z) =
    1 + z for Euler, 1 + z + z^2 / 2 for Heun). The determinant is the factor by which a
    step multiplies the squared amplitude, 1 - beta dt + (omega dt)^2 for Euler."""
    roots = np.roots([1.0, beta, omega2]) * dt
    growth = 1 + roots if integrator == "euler" else 1 + roots + roots**2 / 2
    return float(np.sum(growth).real), float(np.prod(growth).real)


@pytest.mark.parametrize("integrator", ["euler", "heun"])
def test_damped_contact_of_two_free_disks_decays_as_the_damped_oscillator(
    integrator: str,
) -> None:
    """Two camphor-free free disks pressed together along x by external forces +-f
    oscillate about the gap g* = ell - f / kappa as x'' + beta x' + omega^2 x = 0 with
    beta = (mu A + 2 gamma) / m, omega^2 = 2 kappa / m (spring, dashpot and friction are
    linear along the line of centres): x_{n+1} = tr x_n - det x_{n-1}, and the fitted
    trace and det (the squared amplitude's factor per step) are the analytic ones (Euler:
    det = 1 - beta dt + (omega dt)^2, above 1 without the dashpot); the oscillation dies
    out."""
    mass, force, mu, damping = 1e-3, 2.0, 0.05, 0.05
    grid = {"dx": 0.05, "dt": 2e-4, "domain_radius": 1.6}
    start = 0.6 + 0.5 * 0.095  # footprints (0.6) 0.095 apart, g* = 0.08
    bodies = [
        {
            "name": name,
            "plate": {"shape": "disk", "radius": 0.1},
            "motion": {"kind": "free", "mass": mass, "friction": mu},
            "start": {"x": sign * start, "y": 0.0},
            "external_force": [-sign * force, 0.0],
        }
        for name, sign in (("left", -1.0), ("right", 1.0))
    ]
    config = RotorConfig.model_validate(
        {
            "grid": grid,
            "geometry": {"smoothing": 0.025},
            "numerics": {"scheme": "paper", "integrator": integrator},
            "flow": {"enabled": False},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "contact": {**CONTACT, "damping": damping},
            "bodies": bodies,
        }
    )
    sim = Simulation(config)
    dt = grid["dt"]
    step = make_bodies_stepper(sim.pde, dt, np.random.default_rng(0))
    rest = CONTACT["range"] - force / CONTACT["stiffness"]
    gaps = []
    for n in range(300):
        step(sim.state.data, sim.bodies, n, 1)
        gaps.append(sim.bodies.poses[1, 0] - sim.bodies.poses[0, 0] - 1.2 - rest)
    x = np.array(gaps)
    assert np.abs(sim.bodies.poses[:, 1]).max() < 1e-15  # the motion stays on the x axis
    area = float(np.sum(sim.pde.F[sim.pde.owner == 0]) * sim.pde.domain.cell_area)
    beta = (mu * area + 2 * damping) / mass
    omega2 = 2 * CONTACT["stiffness"] / mass
    fit, *_ = np.linalg.lstsq(np.stack([x[1:-1], -x[:-2]], axis=1), x[2:], rcond=None)
    np.testing.assert_allclose(fit, step_map(integrator, beta, omega2, dt), rtol=0, atol=1e-7)
    assert np.abs(x[-30:]).max() < 0.2 * np.abs(x[:30]).max()
    assert step_map("euler", mu * area / mass, omega2, dt)[1] > 1  # undamped Euler rings
