"""Bodies on the GPU (:mod:`pde_rotor.backends.gpu_bodies`) against the CPU, in numba's
CUDA simulator.

The kernel of :mod:`pde_rotor.kernels.cuda_bodies` runs here on the CPU
(``NUMBA_ENABLE_CUDASIM=1``, set below before numba-cuda is imported), on small grids
(dx = 0.1) for a few steps. Checked: a free disk and a fixed_axis hexagon with pills,
stops and noise advance as the CPU's bodies loop advances them, on both schemes, with
forward Euler and Heun, to 1e-10 (poses, velocities, forces, c and v), also with external
forces and torques and the saturating tension law, and so do a strip, a body without a
plate and a fixed body, a disk in an annular channel and boats on a circular track; with
Heun one fixed_axis body is the CPU rotor's Heun, and a free disk's trajectory converges
at second order in dt; a disk at the dish's centre on a mirror-symmetric c feels no
force, bit for bit, as on the CPU; the no-flux dish; an early end at the dish's edge and at an
annulus' inner wall; footprints cut short of saturation (contact at the saturated
radius); an ensemble of members; and
``pde-rotor run --backend gpu`` with a bodies: list.
"""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path
from typing import Any

if "numba.cuda" not in sys.modules:
    os.environ.setdefault("NUMBA_ENABLE_CUDASIM", "1")
    from numba.core import config as numba_config

    numba_config.reload_config()  # numba read its environment when conftest imported it

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

from pde_rotor import RotorConfig
from pde_rotor.backends.gpu_bodies import gpu_bodies_stepper, run_bodies_ensemble
from pde_rotor.cli.main import app
from pde_rotor.model.surface import POSE_COLUMNS
from pde_rotor.solver.bodies import BodyContactError
from pde_rotor.solver.simulation import Simulation

GRID = {"dx": 0.1, "dt": 1e-3, "domain_radius": 3.1}
"""A dish for two bodies whose footprints (the plates grown by 20 delta) stay apart."""

TWO_BODIES: list[dict[str, Any]] = [
    {
        "name": "disk",
        "plate": {"shape": "disk", "radius": 0.2},
        "pills": [{"x": 0.1, "y": 0.0, "radius": 0.06}],
        "motion": {"kind": "free", "mass": 1e-3, "inertia": 1e-4},
        "start": {"x": -1.3, "y": 0.05, "angle": 0.3, "omega": 2.0, "velocity": [0.3, -0.2]},
        "noise_sigma": 1e-6,
    },
    {
        "name": "hexagon",
        "plate": {"shape": "polygon", "n_corners": 6, "radius": 0.3},
        "pills": [{"x": 0.2, "y": 0.05, "radius": 0.06}, {"x": -0.15, "y": -0.1, "radius": 0.06}],
        "motion": {"kind": "fixed_axis"},
        "start": {"x": 1.45, "y": -0.05, "angle": 0.4, "omega": 3.0},
        "protocol": {"t_ini": 0.002, "t_stop": 0.002, "t_release": 0.001, "cycles": 1},
    },
]
"""One free disk (noisy) and one fixed_axis hexagon with two pills and a stop."""

DISK = {**TWO_BODIES[0], "start": {**TWO_BODIES[0]["start"], "x": 0.0}}
"""The free disk alone at the centre of a smaller dish (domain_radius 1.6)."""


@pytest.fixture(autouse=True)
def _every_test_on_the_simulator(fast_simulator: None) -> None:
    """Every test here runs the kernels (:func:`conftest.fast_simulator`)."""


def config(bodies: list[dict[str, Any]], **sections: Any) -> RotorConfig:
    """A bodies config on the small grid, paper scheme and Euler unless given."""
    data: dict[str, Any] = {
        "grid": {**GRID, **sections.pop("grid", {})},
        "geometry": {"smoothing": 0.05},
        "numerics": sections.pop("numerics", {"scheme": "paper"}),
        "protocol": {"t_ini": 1.0, "cycles": 0},
        "noise": {"seed": 7},
        "bodies": bodies,
        **sections,
    }
    return RotorConfig.model_validate(data)


def smooth_fields(sim: Simulation) -> None:
    """Smooth, non-symmetric c and v on the dish's interior (gradients under every body)."""
    x, y = sim.pde.cell_coordinates()
    mask = sim.pde.domain.interior_mask
    sim.state.data[0] = mask * (1 + 0.5 * np.sin(1.3 * x + 0.2) * np.cos(0.7 * y + 0.1))
    sim.state.data[1] = mask * 0.3 * np.sin(0.9 * y) * np.cos(0.4 * x)
    sim.state.data[2] = mask * 0.2 * np.cos(1.1 * x) * np.sin(0.5 * y)


def pair(cfg: RotorConfig) -> tuple[Simulation, Simulation]:
    """The CPU's and the GPU's simulation of `cfg` from the same smooth fields."""
    cpu = Simulation(cfg)
    gpu = Simulation(cfg, stepper=gpu_bodies_stepper)
    smooth_fields(cpu)
    smooth_fields(gpu)
    return cpu, gpu


def assert_same(cpu: Simulation, gpu: Simulation, tol: float = 1e-10) -> None:
    """Poses, velocities, forces and the held flags agree to `tol`, c and v to `tol`
    relative."""
    np.testing.assert_allclose(gpu.bodies.poses, cpu.bodies.poses, rtol=0, atol=tol)
    scale = np.abs(cpu.state.data).max()
    assert np.abs(gpu.state.data - cpu.state.data).max() <= tol * scale


@pytest.mark.parametrize("integrator", ["euler", "heun"])
@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_two_bodies_agree_with_the_cpu(scheme: str, integrator: str) -> None:
    """A free disk and a fixed_axis hexagon, flow on, the hexagon through a stop and the
    disk kicked by noise: after each of two calls (the indicators kept between them) the
    GPU's poses, velocities, forces, c and v are the CPU's to 1e-10, with forward Euler
    and with Heun's method."""
    cpu, gpu = pair(config(TWO_BODIES, numerics={"scheme": scheme, "integrator": integrator}))
    for t in (0.003, 0.006):  # in the hexagon's stop, then after its release
        cpu.run(t)
        gpu.run(t)
        assert_same(cpu, gpu)
    assert cpu.bodies.poses[0, 6] != 0.0 and cpu.bodies.poses[1, 8] != 0.0  # forces seen
    assert cpu.bodies.poses[1, 5] != 0.0  # the hexagon turns again after its stop


LOADED: list[dict[str, Any]] = [
    {**TWO_BODIES[0], "external_force": [0.02, -0.01], "external_torque": 3e-4},
    {**TWO_BODIES[1], "external_torque": -2e-4},
]
"""The two bodies with external loads: a force and a torque on the disk, a torque on the
hexagon."""


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_external_loads_and_saturating_tension_agree_with_the_cpu(scheme: str) -> None:
    """With external forces and torques and the saturating tension law (c_sat = 0.5, so
    that the surface pressure c / (1 + c / c_sat) is far from c) the GPU's run is the
    CPU's to 1e-10, Heun's method; and the loads and the law change the run (against
    the same run without them, the disk's velocity differs by more than 1e-6)."""
    cfg = config(
        LOADED,
        numerics={"scheme": scheme, "integrator": "heun"},
        camphor={"saturation": 0.5},
    )
    cpu, gpu = pair(cfg)
    cpu.run(0.004)
    gpu.run(0.004)
    assert_same(cpu, gpu)
    plain, _ = pair(config(TWO_BODIES, numerics={"scheme": scheme, "integrator": "heun"}))
    plain.run(0.004)
    assert np.abs(cpu.bodies.poses[0, 3:6] - plain.bodies.poses[0, 3:6]).max() > 1e-6
    assert abs(cpu.bodies.poses[0, 6] - plain.bodies.poses[0, 6]) > 1e-9  # the tension law


STRIP_AND_PILLS: list[dict[str, Any]] = [
    {
        "name": "strip",
        "plate": {"shape": "strip", "length": 0.6, "width": 0.2},
        "pills": [{"x": 0.2, "y": 0.0, "radius": 0.06}],
        "motion": {"kind": "free", "mass": 1e-3, "inertia": 1e-4},
        "start": {"x": 1.7, "y": 0.1, "angle": 0.7, "omega": 2.0, "velocity": [-0.2, 0.1]},
    },
    {
        "name": "pair",
        "plate": {"shape": "none"},
        "pills": [{"x": 0.2, "y": 0.0, "radius": 0.06}, {"x": -0.2, "y": 0.05, "radius": 0.08}],
        "motion": {"kind": "free", "mass": 1e-3, "inertia": 1e-4},
        "start": {"x": -1.4, "y": -0.1, "angle": 0.3, "omega": -1.0, "velocity": [0.1, 0.2]},
    },
]
"""The other plates: a free strip and a free body floating on two pills (no plate)."""


def test_a_disk_on_a_symmetric_field_feels_no_force_as_on_the_cpu() -> None:
    """The free disk (a disk plate, its pill off the centre) at the dish's centre, turned
    by 0, on a c symmetric under both mirrors of the grid: on the GPU as on the CPU its
    plate's circle feels a contour force of 0 bit for bit, each thread's orbits of four
    mirror-image nodes adding up to 0 (tests/kernels/test_body_arcs.py)."""
    disk = {**DISK, "start": {"x": 0.0, "y": 0.0, "omega": 2.0}}
    cfg = config([disk], grid={"domain_radius": 1.6}, numerics={"scheme": "consistent"})
    for stepper in (None, gpu_bodies_stepper):
        sim = Simulation(cfg) if stepper is None else Simulation(cfg, stepper=stepper)
        smooth_fields(sim)
        c = sim.state.data[0]
        c = c + c[::-1, :]
        sim.state.data[0] = c + c[:, ::-1]
        sim.run(cfg.grid.dt)
        assert np.all(sim.bodies.poses[0, 6:8] == 0.0)
        assert sim.bodies.poses[0, 11] != 0.0  # the step did take the disk's integrals


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_strip_and_plateless_bodies_agree_with_the_cpu(scheme: str) -> None:
    """A strip (its filtered quadrant table and four edges in contour form) and a body
    without a plate (its pills' F, and their circles in contour form) as on the CPU."""
    cpu, gpu = pair(
        config(STRIP_AND_PILLS, grid={"domain_radius": 3.6}, numerics={"scheme": scheme})
    )
    cpu.run(0.003)
    gpu.run(0.003)
    assert_same(cpu, gpu)
    assert np.all(cpu.bodies.poses[:, 8] != 0.0)


def test_a_fixed_body_stays_and_feeds_the_fields_as_on_the_cpu() -> None:
    """A fixed body (its start velocities dropped) never moves; its sources and plate act
    on the fields as on the CPU."""
    fixed = {**DISK, "motion": {"kind": "fixed"}, "noise_sigma": None}
    fixed["start"] = {"x": 0.0, "y": 0.05, "angle": 0.3}
    cpu, gpu = pair(config([fixed], grid={"domain_radius": 1.6}))
    cpu.run(0.002)
    gpu.run(0.002)
    assert_same(cpu, gpu)
    np.testing.assert_array_equal(gpu.bodies.poses[0, :6], [0.0, 0.05, 0.3, 0.0, 0.0, 0.0])
    assert gpu.bodies.poses[0, 12] == 1.0


@pytest.mark.parametrize("integrator", ["euler", "heun"])
def test_no_flux_dish_agrees_with_the_cpu(integrator: str) -> None:
    """Behind the no-flux wall (cut cells, implicit clusters) the GPU's step is the CPU's,
    with Euler and with Heun (whose average covers the runs of cut cells)."""
    cpu, gpu = pair(
        config(
            [DISK],
            grid={"wall": "no_flux", "domain_radius": 1.6},
            numerics={"scheme": "paper", "integrator": integrator},
        )
    )
    cpu.run(0.003)
    gpu.run(0.003)
    assert_same(cpu, gpu)


VESSEL = {
    "shape": "annulus",
    "inner_radius": 0.5,
    "outer_radius": 4.0,
    "inner_wall": "no_flux",
    "outer_wall": "no_flux",
}
"""An annular channel whose two no-flux walls hold the camphor in (cut cells of both
circles)."""


def vessel_pair(integrator: str) -> tuple[Simulation, Simulation]:
    """The CPU's and the GPU's run of the free disk in the channel :data:`VESSEL`."""
    disk = {**DISK, "start": {**DISK["start"], "x": 2.2, "y": 0.1}}
    numerics = {"scheme": "paper", "integrator": integrator}
    return pair(config([disk], grid={"domain_radius": 4.0, "vessel": VESSEL}, numerics=numerics))


@pytest.mark.parametrize("integrator", ["euler", "heun"])
def test_annular_vessel_agrees_with_the_cpu(integrator: str) -> None:
    """In an annular channel (the spans of cut cells of two circles in a row) the GPU's
    run is the CPU's, with Euler and with Heun."""
    cpu, gpu = vessel_pair(integrator)
    cpu.run(0.003)
    gpu.run(0.003)
    assert_same(cpu, gpu)
    assert cpu.bodies.poses[0, 6] != 0.0


TRACK_BOATS = [
    {
        "name": name,
        "plate": {"shape": "strip", "length": 0.4, "width": 0.2},
        "pills": [{"x": -0.12, "y": 0.0, "radius": 0.06}],
        "motion": {
            "kind": "track",
            "mass": 1e-3,
            "friction": 0.5,
            "direction": way,
            "speed": 0.4,
            "force": 0.01,
        },
        "start": {"x": x, "y": 0.1},
        "external_force": [0.02, -0.01],
    }
    for name, way, x in (("ccw", "counterclockwise", 2.25), ("cw", "clockwise", -2.25))
]
"""Two boats on the track r = hypot(2.25, 0.1) in the channel :data:`VESSEL`, each way round,
with a tangential and a projected external force."""


@pytest.mark.parametrize("integrator", ["euler", "heun"])
def test_track_boats_agree_with_the_cpu(integrator: str) -> None:
    """Boats on a circular track (motion kind track) run on the GPU as on the CPU, with
    Euler and with Heun."""
    numerics = {"scheme": "paper", "integrator": integrator}
    cfg = config(TRACK_BOATS, grid={"domain_radius": 4.0, "vessel": VESSEL}, numerics=numerics)
    cpu, gpu = pair(cfg)
    cpu.run(0.003)
    gpu.run(0.003)
    assert_same(cpu, gpu)
    assert np.all(cpu.bodies.poses[:, 6] != 0.0)


SPANNING_BOAT = {
    "name": "boat",
    "plate": {"shape": "strip", "length": 0.4, "width": 3.2},
    "pills": [{"x": -0.12, "y": 0.0, "radius": 0.08}],
    "motion": {"kind": "track", "mass": 1e-2, "friction": 0.5, "spans": True, "speed": 0.3},
    "start": {"x": 1.5, "y": 2.0},
}
"""A boat on the track r = 2.5 that spans the channel 1.2 < r < 3.8, its plate 0.3 past
each wall, its pill 1.3 inside them."""


@pytest.mark.parametrize(("scheme", "integrator"), [("paper", "euler"), ("consistent", "heun")])
def test_a_spanning_boat_agrees_with_the_cpu(scheme: str, integrator: str) -> None:
    """A boat that spans its channel (its force and friction over the wet cells, its
    footprint past both walls, no wall contact) runs on the GPU as on the CPU, on either
    scheme and with either integrator."""
    ring = {**VESSEL, "inner_radius": 1.2, "outer_radius": 3.8}
    numerics = {"scheme": scheme, "integrator": integrator}
    grid = {"domain_radius": 5.5, "vessel": ring}
    cpu, gpu = pair(config([SPANNING_BOAT], grid=grid, numerics=numerics))
    cpu.run(0.003)
    gpu.run(0.003)
    assert_same(cpu, gpu)
    assert cpu.bodies.poses[0, 6] != 0.0


@pytest.mark.parametrize(
    ("integrator", "widths"), [("euler", 20.0), ("heun", 20.0), ("euler", 6.0)]
)
def test_contact_agrees_with_the_cpu(integrator: str, widths: float) -> None:
    """With contact on (spring and dashpot), two boats whose footprints are within its
    range of each other and of both walls run on the GPU as on the CPU, with Euler and
    with Heun, their recorded contact forces too; with the footprints drawn to 6 delta
    (``numerics.footprint_widths``) contact still acts at the 20-delta contact radius."""
    half = math.asin(3.3 / 2 / 2.25)  # chord 3.3: the footprints (1.628 each) 0.044 apart
    boats = [
        {**TRACK_BOATS[0], "start": {"x": 2.25, "y": 0.0}},
        {
            **TRACK_BOATS[1],
            "start": {"x": 2.25 * math.cos(2 * half), "y": 2.25 * math.sin(2 * half)},
        },
    ]
    numerics = {"scheme": "paper", "integrator": integrator, "footprint_widths": widths}
    contact = {"enabled": True, "stiffness": 100.0, "range": 0.2, "damping": 0.1}
    grid = {"domain_radius": 4.0, "vessel": VESSEL}
    cpu, gpu = pair(config(boats, grid=grid, numerics=numerics, contact=contact))
    cpu.run(0.003)
    gpu.run(0.003)
    assert_same(cpu, gpu)  # with the recorded contact forces
    assert np.abs(cpu.bodies.poses[:, POSE_COLUMNS.index("contact_x")]).min() > 0.1
    plain, _ = pair(config(boats, grid=grid, numerics=numerics))
    plain.run(0.003)
    assert np.abs(plain.bodies.poses[:, 3:6] - cpu.bodies.poses[:, 3:6]).max() > 1e-3


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_a_cut_footprint_agrees_with_the_cpu(scheme: str) -> None:
    """The two bodies with their footprints drawn to 4 smoothing widths
    (``numerics.footprint_widths``; tails of 3.4e-4 dropped) run on the GPU as on the
    CPU to 1e-10, and the cut is seen (c differs from the saturated footprint's run by
    more than 1e-8 of its size)."""
    numerics = {"scheme": scheme, "footprint_widths": 4.0}
    cpu, gpu = pair(config(TWO_BODIES, numerics=numerics))
    cpu.run(0.003)
    gpu.run(0.003)
    assert_same(cpu, gpu)
    full, _ = pair(config(TWO_BODIES, numerics={"scheme": scheme}))
    full.run(0.003)
    assert np.abs(full.state.data - cpu.state.data).max() > 1e-8 * np.abs(full.state.data).max()


def rotor_configs(integrator: str, scheme: str) -> tuple[RotorConfig, RotorConfig]:
    """The paper's rotor (small plate, noise, two stops) and the same rotor written as one
    fixed_axis body."""
    rotor = RotorConfig.model_validate(
        {
            "grid": {"dx": 0.1, "dt": 1e-3, "domain_radius": 1.6},
            "geometry": {"radius": 0.3, "pill_radius": 0.06, "pill_inset": 0.03, "smoothing": 0.05},
            "numerics": {"scheme": scheme, "integrator": integrator},
            "rotor": {"omega0": 50.0},
            "noise": {"sigma": 1e-5, "seed": 3},
            "protocol": {"t_ini": 0.003, "t_stop": 0.002, "t_release": 0.001, "cycles": 2},
        }
    )
    data = rotor.model_dump()
    data["bodies"] = [body.model_dump() for body in rotor.body_list()]
    data["rotor"] = {k: v for k, v in data["rotor"].items() if k not in ("omega0", "phi0")}
    data["geometry"] = {"smoothing": rotor.geometry.smoothing}
    return rotor, RotorConfig.model_validate(data)


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_one_body_with_heun_is_the_rotors_heun(scheme: str) -> None:
    """The rotor as one fixed_axis body, integrated by Heun on the GPU through two stops
    with noise, follows the CPU rotor's Heun to 1e-10 (phi, omega, torque, c, v), on both
    schemes."""
    rotor, body = rotor_configs("heun", scheme)
    a = Simulation(rotor)
    b = Simulation(body, stepper=gpu_bodies_stepper)
    for t in (0.004, 0.009):  # in the first stop, then after the second release
        a.run(t)
        b.run(t)
        pose = b.bodies.poses[0]
        assert pose[2] == pytest.approx(a.rotor.phi, rel=1e-10, abs=1e-12)
        assert pose[5] == pytest.approx(a.rotor.omega, rel=1e-10, abs=1e-10)
        assert pose[8] == pytest.approx(a.rotor.torque, rel=1e-9, abs=1e-15)
        assert np.abs(a.state.data - b.state.data).max() <= 1e-10 * np.abs(a.state.data).max()
    assert a.rotor.omega != 0.0


def free_disk_x(integrator: str, dt: float) -> np.ndarray:
    """x, y, phi, u, v, omega of a free disk at t = 0.004 after a start with smooth fields."""
    cfg = config(
        [{**DISK, "noise_sigma": 0.0}],
        grid={"dt": dt, "domain_radius": 1.6},
        numerics={"scheme": "paper", "integrator": integrator},
    )
    sim = Simulation(cfg, stepper=gpu_bodies_stepper)
    smooth_fields(sim)
    sim.run(0.004)
    return sim.bodies.poses[0, :6].copy()


def test_heun_converges_at_second_order_in_dt() -> None:
    """The free disk's pose and velocities at t = 0.004 for dt, dt/2, dt/4 on the GPU
    kernels: the differences shrink four-fold with Heun (second order; forward Euler's
    two-fold, which shows that the measure tells the orders apart, is checked on the
    CPU by ``tests/solver/test_bodies.py``, and the two backends' Euler agree to 1e-10)."""
    x1, x2, x4 = (free_disk_x("heun", dt) for dt in (1e-3, 5e-4, 2.5e-4))
    assert np.abs(x1 - x2).max() / np.abs(x2 - x4).max() > 3.5


def test_a_body_at_the_dish_edge_ends_the_run_as_on_the_cpu() -> None:
    """A disk thrown at the dish's edge ends both runs at the same step, same message."""
    disk = {**DISK, "start": {"x": 0.0, "velocity": [40.0, 0.0]}, "noise_sigma": 0.0}
    cfg = config([disk], grid={"domain_radius": 1.6})
    cpu, gpu = pair(cfg)
    messages = []
    for sim in (cpu, gpu):
        with pytest.raises(BodyContactError, match="reached the dish's edge") as err:
            sim.run(0.02)
        messages.append(str(err.value))
    assert messages[0] == messages[1]
    assert_same(cpu, gpu)


def test_a_body_crossing_the_inner_wall_ends_the_run_as_on_the_cpu() -> None:
    """A disk thrown at the annulus' inner wall ends both runs at the same step, with the
    same message (the wall is caught during the run, not only at the start)."""
    disk = {**DISK, "start": {"x": 2.2, "y": 0.0, "velocity": [-40.0, 0.0]}, "noise_sigma": 0.0}
    cfg = config([disk], grid={"domain_radius": 4.0, "vessel": VESSEL})
    cpu, gpu = pair(cfg)
    messages = []
    for sim in (cpu, gpu):
        with pytest.raises(BodyContactError, match="reached a wall of the annulus") as err:
            sim.run(0.05)
        messages.append(str(err.value))
    assert messages[0] == messages[1]
    assert_same(cpu, gpu)


def test_an_ensemble_runs_each_member_as_its_own_run() -> None:
    """Two members (different seeds, start angles) of one ensemble: each member's record
    at its end is the GPU run of its own config alone (the stepper under the Controller)."""
    base = config([DISK], grid={"domain_radius": 1.6})
    data = base.model_dump()
    data["bodies"][0]["start"]["angle"] = 1.0
    other = RotorConfig.model_validate({**data, "noise": {"seed": 11}})
    result = run_bodies_ensemble([base, other], 0.004, record_interval=0.002)
    np.testing.assert_allclose(result.t, [0.0, 0.002, 0.004])
    assert np.isnan(result.ended_at).all()
    for m, cfg in enumerate((base, other)):
        alone = Simulation(cfg, stepper=gpu_bodies_stepper)
        alone.run(0.004)
        np.testing.assert_allclose(result.poses[m, -1], alone.bodies.poses, rtol=0, atol=1e-14)
    assert result.poses[0, -1, 0, 2] != result.poses[1, -1, 0, 2]


def test_cli_run_with_bodies_on_the_gpu(tmp_path: Path) -> None:
    """``pde-rotor run CONFIG --backend gpu`` with a bodies: list writes the CPU run's
    files, and its bodies.nc is the CPU's to 1e-10."""
    cfg = config([DISK], grid={"domain_radius": 1.6})
    data = cfg.model_dump(mode="json")
    data["protocol"] = {"t_ini": 0.004, "cycles": 0}
    data["output"] = {"timeseries_interval": 0.002, "event_interval": 0.002}
    path = tmp_path / "bodies.yaml"
    path.write_text(yaml.safe_dump(data))
    runs = {}
    for backend in ("cpu", "gpu"):
        out = tmp_path / backend
        done = CliRunner().invoke(app, ["run", str(path), "--out", str(out), "--backend", backend])
        assert done.exit_code == 0, done.output
        runs[backend] = out
    files = {p.name for p in runs["cpu"].iterdir()}
    assert files == {p.name for p in runs["gpu"].iterdir()}
    with (
        xr.open_dataset(runs["cpu"] / "bodies.nc") as a,
        xr.open_dataset(runs["gpu"] / "bodies.nc") as b,
    ):
        assert a.attrs["backend"] == "cpu" and b.attrs["backend"] == "gpu"
        for name in a.data_vars:
            np.testing.assert_allclose(b[name].values, a[name].values, rtol=0, atol=1e-10)
