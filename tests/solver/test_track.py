"""A body on a circular track (motion kind ``track``): the compiled step against the numpy
reference, the analytic terminal speed, the circle and the tangent kept to round-off; and
a free body crossing a vessel's inner wall during the run."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from pde_rotor import RotorConfig
from pde_rotor.cli.common import EXIT_CONTACT
from pde_rotor.cli.main import app
from pde_rotor.config import ConfigError, validate_config
from pde_rotor.model.surface import SurfacePDE
from pde_rotor.solver.bodies import BodyContactError
from pde_rotor.solver.simulation import Simulation

RING = {"shape": "annulus", "inner_radius": 0.4, "outer_radius": 2.6}
"""A no-flux annular channel about the origin."""

BOAT = {
    "name": "boat",
    "plate": {"shape": "strip", "length": 0.4, "width": 0.2},
    "pills": [{"x": -0.15, "y": 0.0, "radius": 0.05}],
    "motion": {"kind": "track", "mass": 2e-3, "friction": 0.5},
    "start": {"x": 1.5, "y": 0.0},
}
"""A boat with its camphor at the rear on the track r = 1.5, counterclockwise."""


def track_config(bodies: list[dict[str, Any]], **sections: Any) -> RotorConfig:
    """A coarse annulus with `bodies` (paper scheme, no stops)."""
    data: dict[str, Any] = {
        "grid": {"dx": 0.05, "dt": 2e-4, "domain_radius": 2.6, "vessel": RING},
        "numerics": sections.pop("numerics", {"scheme": "paper"}),
        "protocol": {"t_ini": 1.0, "cycles": 0},
        "bodies": bodies,
        **sections,
    }
    return RotorConfig.model_validate(data)


def on_track(poses: np.ndarray, radius: float, sign: float) -> tuple[float, float]:
    """The largest | |X| - R | and the largest gap of phi from the tangent theta + d pi/2."""
    theta = np.arctan2(poses[:, 1], poses[:, 0])
    off = np.abs(np.hypot(poses[:, 0], poses[:, 1]) - radius).max()
    gap = np.abs(np.remainder(poses[:, 2] - theta - sign * math.pi / 2 + math.pi, 2 * math.pi))
    return float(off), float(np.abs(gap - math.pi).max())


@pytest.mark.parametrize("integrator", ["euler", "heun"])
def test_step_equals_numpy_reference(integrator: str) -> None:
    """One compiled step of two boats on one track, travelling both ways, is the numpy
    reference's (:meth:`SurfacePDE.reference_step`): forces, the poses and velocities."""
    other = {
        **BOAT,
        "name": "back",
        "motion": {**BOAT["motion"], "direction": "clockwise", "speed": 0.7},
        "start": {"x": -1.5 / math.sqrt(2), "y": -1.5 / math.sqrt(2)},
    }
    boat = {**BOAT, "motion": {**BOAT["motion"], "speed": 1.3}}
    config = track_config([boat, other], numerics={"scheme": "paper", "integrator": integrator})
    sim = Simulation(config)
    x, y = sim.pde.cell_coordinates()
    mask = sim.pde.domain.interior_mask
    sim.state.data[0] = mask * (1 + 0.5 * np.sin(1.3 * x + 0.2) * np.cos(0.7 * y + 0.1))
    sim.state.data[1] = mask * 0.3 * np.sin(0.9 * y) * np.cos(0.4 * x)
    sim.state.data[2] = mask * 0.2 * np.cos(1.1 * x) * np.sin(0.5 * y)
    pde: SurfacePDE = sim.pde
    before = sim.state.copy()
    dt = config.grid.dt
    want = pde.reference_step(before, dt)
    sim.run(dt)
    forces = want.bodies.poses[:, 6:12]
    np.testing.assert_allclose(
        sim.bodies.poses[:, 6:12], forces, rtol=1e-9, atol=1e-12 * np.abs(forces).max()
    )
    old = before.bodies.poses[:, :6]
    rates = (sim.bodies.poses[:, :6] - old) / dt
    reference = (want.bodies.poses[:, :6] - old) / dt
    for column in range(6):
        size = np.abs(reference[:, column]).max()
        np.testing.assert_allclose(rates[:, column], reference[:, column], atol=1e-9 * size)
    assert np.all(np.abs(reference[:, 3]) > 0)


@pytest.mark.parametrize("integrator", ["euler", "heun"])
def test_tangential_force_without_camphor_gives_the_terminal_speed(integrator: str) -> None:
    """Without camphor and flow a track disk under the tangential force f_t obeys
    m dw/dt = d f_t - mu A w (A = int F dA; the plate turns rigidly about the centre, whose
    first moment of F vanishes but for the lattice): it reaches w = d f_t / (mu A) after
    25 relaxation times m / (mu A), on its circle and along its tangent to round-off, both
    directions of travel."""
    mu, force, radius = 1.0, 0.02, 1.5
    disk = {"shape": "disk", "radius": 0.3}
    bodies = [
        {
            "name": name,
            "plate": disk,
            "motion": {
                "kind": "track",
                "mass": 2e-3,
                "friction": mu,
                "direction": way,
                "force": force,
            },
            "start": {"x": radius * math.cos(angle), "y": radius * math.sin(angle)},
        }
        for name, way, angle in (("ccw", "counterclockwise", 0.3), ("cw", "clockwise", 3.5))
    ]
    config = track_config(
        bodies, flow={"enabled": False}, numerics={"scheme": "paper", "integrator": integrator}
    )
    sim = Simulation(config)
    area = sim.pde.domain.cell_area
    sim.run(0.2)
    for k, sign in enumerate((1.0, -1.0)):
        a_eff = float(np.sum(sim.pde.F[sim.pde.owner == k]) * area)
        assert 2e-3 / (mu * a_eff) < 0.2 / 25
        pose = sim.bodies.poses[k]
        theta = math.atan2(pose[1], pose[0])
        speed = -pose[3] * math.sin(theta) + pose[4] * math.cos(theta)
        assert speed == pytest.approx(sign * force / (mu * a_eff), rel=2e-3)
        assert pose[5] == pytest.approx(speed / radius, rel=1e-12)
        off, gap = on_track(sim.bodies.poses[k : k + 1], radius, sign)
        assert off < 1e-13
        assert gap < 1e-12
        assert sign * (theta - [0.3, 3.5 - 2 * math.pi][k]) > 0.0  # it went its way
    assert np.abs(sim.state.data).max() == 0.0


def test_boats_keep_to_the_track_and_sail_forwards() -> None:
    """Boats with camphor at the rear sail along their direction of travel (w d > 0),
    on the circle and along the tangent to round-off, in the flow."""
    other = {**BOAT, "name": "two", "start": {"x": -1.5, "y": 0.0}}
    config = track_config([BOAT, other])
    sim = Simulation(config)
    sim.run(0.2)
    poses = sim.bodies.poses
    off, gap = on_track(poses, 1.5, 1.0)
    assert off < 1e-13
    assert gap < 1e-12
    assert np.all(poses[:, 5] > 0)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"start": {"x": 1.5, "y": 0.0, "velocity": [0.0, 1.0]}}, "bodies[0].start.velocity"),
        ({"start": {"x": 1.5, "y": 0.0, "omega": 1.0}}, "bodies[0].start.omega"),
        ({"external_torque": 1e-3}, "bodies[0].external_torque"),
        ({"noise_sigma": 1e-3}, "bodies[0].noise_sigma"),
        ({"start": {"x": 1.5, "y": 0.0, "angle": 0.3}}, "bodies[0].start.angle"),
        ({"motion": {**BOAT["motion"], "radius": 1.2}}, "bodies[0].start"),
        ({"start": {"x": 0.0, "y": 0.0}}, "bodies[0].start"),
    ],
)
def test_inconsistent_track_input_is_refused_naming_the_key(
    change: dict[str, Any], key: str
) -> None:
    """A start velocity or spin, an external torque, torque noise, a start angle off the
    tangent or a start off the given radius are refused naming the key."""
    data = {
        "grid": {"dx": 0.05, "dt": 2e-4, "domain_radius": 2.6, "vessel": RING},
        "bodies": [{**BOAT, **change}],
    }
    with pytest.raises(ConfigError) as err:
        validate_config(data)
    message = str(err.value)
    assert "\n" not in message
    assert message.startswith(key + " = "), message


def test_start_angle_and_velocity_follow_the_track() -> None:
    """The start angle is the tangent theta + d pi/2 and U(0) = d speed e_theta."""
    boat = {
        **BOAT,
        "motion": {**BOAT["motion"], "direction": "clockwise", "speed": 0.5},
        "start": {"x": 0.0, "y": 1.5},
    }
    sim = Simulation(track_config([boat]))
    pose = sim.bodies.poses[0]
    np.testing.assert_allclose(pose[:6], [0.0, 1.5, 0.0, 0.5, 0.0, -0.5 / 1.5], atol=1e-15)


def test_a_free_body_crossing_the_inner_wall_ends_the_run_naming_it(tmp_path: Path) -> None:
    """A free disk launched at the inner wall of the annulus ends the run where its
    footprint crosses that wall (not only at the start), with one line naming the body
    and the wall; from the CLI with the contact exit code."""
    disk = {
        "name": "pushed",
        "plate": {"shape": "none"},
        "pills": [{"x": 0.0, "y": 0.0}],
        "motion": {"kind": "free", "mass": 1e-5, "friction": 1e-4},
        "start": {"x": 0.0, "y": 1.5, "velocity": [0.0, -5.0]},
    }
    config = track_config([disk])
    sim = Simulation(config)
    with pytest.raises(
        BodyContactError, match=r"^body pushed reached a wall of the annulus"
    ) as err:
        sim.run(0.5)
    reach = config.body_list()[0].reach(config.geometry.smoothing)
    y = float(str(err.value).split("y = ")[1].split(";")[0])  # where the footprint crossed
    assert y - reach < RING["inner_radius"] < y - reach + config.grid.dx / 4
    path = tmp_path / "inner.yaml"
    path.write_text(yaml.safe_dump(config.model_dump(mode="json")))
    result = CliRunner().invoke(app, ["run", str(path), "--out", str(tmp_path / "run"), "-q"])
    assert result.exit_code == EXIT_CONTACT
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1
    assert "reached a wall of the annulus" in lines[0]
