"""The bodies: list: its schema, its one-line errors, the shorthand rotor, and the hashes of
configs without it, which stored sweep runs are keyed by."""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path
from typing import Any

import pytest
import yaml
from typer.testing import CliRunner

from pde_rotor.cli.common import EXIT_BAD_INPUT
from pde_rotor.cli.main import app
from pde_rotor.config import (
    FREE_FRICTION,
    SHORTHAND_KEYS,
    ConfigError,
    RotorConfig,
    allowed_values,
    dump_config,
    key_text,
    load_config,
    parse_yaml,
    validate_config,
)
from pde_rotor.config.fields import PAPER_FRICTION
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep import shipped_base
from pde_rotor.theory import (
    CamphorDisk,
    free_disk_critical_friction,
    free_disk_growth_rate,
    free_disk_steady_speed,
)

ROOT = Path(__file__).parents[2]
BODY_CONFIGS = sorted((ROOT / "configs" / "bodies").glob("*.yaml"))
RUN_CONFIGS = [*sorted((ROOT / "configs").glob("*.yaml")), *map(shipped_base, ("paper", "coarse"))]
SECTIONS = ("geometry", "camphor", "flow", "rotor", "noise", "protocol", "grid", "numerics")
"""The sections a config had before bodies existed (solver and output change no result)."""
GRID_KEYS = ("domain_radius", "dx", "dt")
"""The grid's keys before domain_centre existed."""

PILL = {"pills": [{}]}
"""A body of one paper-size pill at its origin (no plate, fixed_axis)."""


def as_before(config: RotorConfig) -> dict[str, Any]:
    """The JSON mapping of a config's physics as it was before bodies and domain_centre:
    each section's own dump, the grid with its three keys."""
    data = {name: getattr(config, name).model_dump(mode="json") for name in SECTIONS}
    data["grid"] = {key: getattr(config.grid, key) for key in GRID_KEYS}
    return data


@pytest.mark.parametrize("path", [None, *RUN_CONFIGS], ids=lambda p: p.name if p else "default")
def test_configs_without_bodies_keep_their_hash_and_physics(path: Path | None) -> None:
    """config_hash and physics of a config without bodies are computed from the sections
    it had before the keys existed; its dump names neither bodies nor domain_centre."""
    config = load_config(path) if path else RotorConfig()
    data = as_before(config)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"))
    assert config.config_hash() == hashlib.sha256(text.encode()).hexdigest()[:16]
    assert config.physics() == {**data, "numerics": config.numerics.acting()}
    dumped = yaml.safe_load(dump_config(config))
    assert "bodies" not in dumped
    assert set(dumped["grid"]) == set(GRID_KEYS)


def test_bodies_and_dish_centre_enter_hash_and_physics() -> None:
    """A config with bodies, a moved body, a moved dish or a no-flux wall is another run;
    the absorbing wall written out is the default's run."""
    base = RotorConfig()
    one = validate_config({"bodies": [PILL]})
    moved = validate_config({"bodies": [{**PILL, "start": {"x": 0.5}}]})
    centred = validate_config({"grid": {"domain_centre": [0.25, 0.0]}})
    walled = validate_config({"grid": {"wall": "no_flux"}, "bodies": [PILL]})
    hashes = {c.config_hash() for c in (base, one, moved, centred, walled)}
    assert len(hashes) == 5
    assert walled.physics()["grid"]["wall"] == "no_flux"
    absorbing = validate_config({"grid": {"wall": "absorbing"}, "bodies": [PILL]})
    assert absorbing.config_hash() == one.config_hash()
    assert one.physics()["bodies"][0]["pills"] == [
        {"x": 0.0, "y": 0.0, "radius": 0.1, "supply": None}
    ]
    assert centred.physics()["grid"]["domain_centre"] == [0.25, 0.0]


@pytest.mark.parametrize("path", BODY_CONFIGS, ids=[p.name for p in BODY_CONFIGS])
def test_body_configs_validate_and_round_trip(path: Path, tmp_path: Path) -> None:
    """configs/bodies/*.yaml: valid (``pde-rotor check`` exits 0), YAML -> model -> YAML
    -> model gives the same model, and the bodies are there."""
    config = load_config(path)
    assert config.bodies
    again_path = tmp_path / "again.yaml"
    again_path.write_text(dump_config(config))
    assert load_config(again_path) == config
    result = CliRunner().invoke(app, ["check", str(path)], catch_exceptions=False)
    assert result.exit_code == 0, result.stderr


def test_body_configs_are_the_systems_they_name() -> None:
    """Two paper rotors, one stopped and one not; a free disk of one pill without plate;
    two pills at (+-l, 0) on a fixed axis; the paper rotor with a fixed one-pill source."""
    paper = RotorConfig().body_list()[0]
    by_name = {p.stem: load_config(p).body_list() for p in BODY_CONFIGS}
    stopped, running = by_name["two_rotors"]
    for rotor in (stopped, running, by_name["rotor_and_source"][0]):
        assert rotor.plate == paper.plate
        assert [(p.x, p.y) for p in rotor.pills] == [
            (round(p.x, 6), round(p.y, 6) + 0.0) for p in paper.pills
        ]
        assert rotor.motion == paper.motion
    assert stopped.protocol is not None and running.protocol is None
    (disk,) = by_name["free_disk"]
    assert (disk.plate.shape, disk.motion.kind, len(disk.pills)) == ("none", "free", 1)
    (arm,) = by_name["two_disk_rotor"]
    assert arm.plate.shape == "none" and arm.motion.kind == "fixed_axis"
    assert [(p.x, p.y) for p in arm.pills] == [(0.5, 0.0), (-0.5, 0.0)]
    source = by_name["rotor_and_source"][1]
    assert source.motion.kind == "fixed" and len(source.pills) == 1


def test_shorthand_is_one_fixed_axis_body() -> None:
    """Without bodies, body_list is the paper's rotor: the polygon of the geometry, N
    pills at R_c from the origin at the corners shifted by Delta, the rotor's dynamics
    and start, the run's protocol and noise."""
    config = validate_config({"geometry": {"asymmetry": 0.1}, "noise": {"sigma": 1e-7}})
    (body,) = config.body_list()
    geo = config.geometry
    assert body.name == "body0"
    assert (body.plate.shape, body.plate.n_corners, body.plate.radius) == (
        "polygon",
        geo.n_corners,
        geo.radius,
    )
    assert len(body.pills) == geo.n_corners
    for j, pill in enumerate(body.pills, start=1):
        assert math.hypot(pill.x, pill.y) == pytest.approx(geo.pill_distance, rel=1e-14)
        angle = 2 * math.pi * j / geo.n_corners + geo.asymmetry
        assert math.atan2(pill.y, pill.x) % (2 * math.pi) == pytest.approx(
            angle % (2 * math.pi), abs=1e-14
        )
        assert (pill.radius, pill.supply) == (geo.pill_radius, config.camphor.supply)
    assert body.motion.kind == "fixed_axis"
    assert (body.motion.inertia, body.motion.friction) == (
        config.rotor.inertia,
        config.rotor.friction,
    )
    assert (body.start.x, body.start.y, body.start.angle, body.start.omega) == (
        0.0,
        0.0,
        config.rotor.phi0,
        config.rotor.omega0,
    )
    assert body.protocol == config.protocol
    assert body.noise_sigma == config.noise.sigma
    assert body.reach(geo.smoothing) == geo.support_radius


def test_bodies_inherit_the_run_values_they_leave_out() -> None:
    """Left out, a pill's supply is camphor.supply, inertia the rotor's, friction the
    rotor's for a fixed_axis body and a camphor disk's own for a free one, noise_sigma the
    run's for a fixed_axis body and 0 for the others, the name body{k}; given, each is the
    body's own."""
    config = validate_config(
        {
            "grid": {"domain_radius": 6.0},
            "camphor": {"supply": 1.5},
            "rotor": {"inertia": 2e-5, "friction": 2e-4},
            "noise": {"sigma": 1e-7},
            "bodies": [
                PILL,
                {
                    **PILL,
                    "motion": {"kind": "free", "mass": 1e-4},
                    "start": {"x": 2},
                },
                {**PILL, "motion": {"kind": "fixed"}, "start": {"x": -2}},
                {
                    "name": "own",
                    "pills": [{"supply": 0.5}],
                    "motion": {"kind": "fixed_axis", "inertia": 3e-5, "friction": 1e-5},
                    "noise_sigma": 2e-7,
                    "start": {"y": 2},
                },
            ],
        }
    )
    axis, free, fixed, own = config.body_list()
    assert [b.name for b in (axis, free, fixed, own)] == ["body0", "body1", "body2", "own"]
    assert [b.pills[0].supply for b in (axis, free, fixed, own)] == [1.5, 1.5, 1.5, 0.5]
    assert (axis.motion.inertia, axis.motion.friction) == (2e-5, 2e-4)
    assert (free.motion.inertia, free.motion.friction) == (2e-5, FREE_FRICTION)
    assert (own.motion.inertia, own.motion.friction) == (3e-5, 1e-5)
    assert [b.noise_sigma for b in (axis, free, fixed, own)] == [1e-7, 0.0, 0.0, 2e-7]
    assert config.bodies is not None and config.bodies[0].pills[0].supply is None


def test_a_free_body_defaults_to_a_camphor_disks_friction() -> None:
    """A free camphor disk of the paper's pill, friction left out, self-propels at a steady
    speed of a small fraction of a cell per step (below its onset mu_c, within a factor
    of two of it); the paper rotor's friction, 1e-4, lies three orders of magnitude below
    mu_c, where the disk runs away."""
    disk_body = {**PILL, "motion": {"kind": "free", "mass": 6.3e-6, "inertia": 3.1e-8}}
    config = validate_config({"grid": {"domain_radius": 5.0}, "bodies": [disk_body]})
    (body,) = config.body_list()
    assert body.motion.friction == FREE_FRICTION != config.rotor.friction
    disk = CamphorDisk.from_config(config)
    assert disk.radius == body.pills[0].radius
    onset = free_disk_critical_friction(disk)
    assert onset / 2 < FREE_FRICTION < onset
    assert free_disk_growth_rate(disk, FREE_FRICTION, 6.3e-6) > 0
    speed = free_disk_steady_speed(disk, FREE_FRICTION)
    assert 0 < speed * config.grid.dt / config.grid.dx < 0.01
    assert 1e-3 * onset > PAPER_FRICTION


def test_a_light_free_body_sets_the_time_step_limit() -> None:
    """A free body's translational friction rate mu pi e^2 / m bounds the explicit step
    (e the body's extent): with a small enough mass it is the limit, 2 m / (mu pi e^2)."""
    mass, rho = 1e-10, 0.1
    body = {**PILL, "motion": {"kind": "free", "mass": mass, "inertia": 1e-8, "friction": 1e-4}}
    config = validate_config({"grid": {"dt": 1e-6}, "bodies": [body]})
    friction = config.rotor.friction
    assert config.dt_limit() == pytest.approx(2 * mass / (friction * math.pi * rho**2), rel=1e-14)
    with pytest.raises(ConfigError, match=r"^grid\.dt = 0\.0001: above the explicit stability"):
        validate_config({"bodies": [body]})


def test_body_keys_read_and_set_by_index(tmp_path: Path) -> None:
    """``--set bodies[k].key=value`` changes body k (an index one past the end adds one);
    RotorConfig.get reads the same paths; the protocols of bodies are times too."""
    path = ROOT / "configs" / "bodies" / "two_rotors.yaml"
    config = load_config(path, ["bodies[1].start.x=2.0", "bodies[1].start.y=-0.5"])
    assert (config.get("bodies[1].start.x"), config.get("bodies[1].start.y")) == (2.0, -0.5)
    more = load_config(
        path,
        ["bodies[2].pills=[{radius: 0.1}]", "bodies[2].motion.kind=fixed", "bodies[2].start.y=2.8"],
    )
    assert len(more.body_list()) == 3 and more.body_list()[2].motion.kind == "fixed"
    assert "bodies[0].protocol.t_stop" in config.time_keys()
    with pytest.raises(ConfigError, match=r"bodies\[5\] is not an entry of the 2 in bodies"):
        load_config(path, ["bodies[5].start.x=1"])
    with pytest.raises(ConfigError, match=r"bodies is a list, not a section"):
        load_config(path, ["bodies.start.x=1"])


def test_schema_paths_are_written_as_the_user_writes_them() -> None:
    """Error locations become ``bodies[1].plate.radius`` (tags of discriminated sections
    left out) and the allowed values of a body's key are named."""
    assert key_text(("bodies", 1, "plate", "disk", "radius")) == "bodies[1].plate.radius"
    assert key_text(("bodies", 0, "motion", "free", "mass")) == "bodies[0].motion.mass"
    assert key_text(("grid", "domain_centre", 1)) == "grid.domain_centre[1]"
    assert allowed_values(("bodies", 0, "plate")) == (
        "a section with shape: one of polygon, disk, strip, none"
    )
    assert allowed_values(("bodies", 0, "motion", "free", "mass")) == "number, mass > 0"
    assert allowed_values(("bodies", 0, "plate", "polygon", "n_corners")) == (
        "integer, 3 <= n_corners <= 24"
    )
    assert allowed_values(("bodies",)).startswith("a list of sections with keys name, plate")


def two(body: dict[str, Any], first: dict[str, Any] | None = None) -> dict[str, Any]:
    """A config with a pill at the origin and `body` (a large dish)."""
    return {"grid": {"domain_radius": 5.0}, "bodies": [first or PILL, body]}


# config data, the key the one-line error starts with, a text it names
BAD_BODIES: dict[str, tuple[dict[str, Any], str, str]] = {
    "empty list": ({"bodies": []}, "bodies = []", "at least one body"),
    "footprint below 3 widths": (
        {"numerics": {"footprint_widths": 2.5}, "bodies": [PILL]},
        "numerics.footprint_widths = 2.5",
        "3 <= footprint_widths <= 20",
    ),
    "footprint beyond saturation": (
        {"numerics": {"footprint_widths": 21}, "bodies": [PILL]},
        "numerics.footprint_widths = 21",
        "3 <= footprint_widths <= 20",
    ),
    "footprint as text": (
        {"numerics": {"footprint_widths": "short"}, "bodies": [PILL]},
        "numerics.footprint_widths = 'short'",
        "number",
    ),
    "footprint of the shorthand rotor": (
        {"numerics": {"footprint_widths": 8}},
        "numerics.footprint_widths = 8",
        "bodies: list only",
    ),
    "bodies not a list": ({"bodies": 5}, "bodies = 5", "a list of sections"),
    "body not a section": ({"bodies": [3]}, "bodies[0] = 3", "keys name, plate"),
    "unknown body key": ({"bodies": [{**PILL, "mass": 1}]}, "bodies[0].mass", "allowed keys"),
    "unknown plate shape": (
        {"bodies": [{**PILL, "plate": {"shape": "hexagon"}}]},
        "bodies[0].plate.shape = 'hexagon'",
        "polygon, disk, strip, none",
    ),
    "plate without shape": (
        {"bodies": [{**PILL, "plate": {"radius": 0.3}}]},
        "bodies[0].plate.shape: missing",
        "polygon, disk, strip, none",
    ),
    "key of another shape": (
        {"bodies": [{**PILL, "plate": {"shape": "disk", "n_corners": 6}}]},
        "bodies[0].plate.n_corners: unknown key",
        "shape, radius",
    ),
    "negative plate radius": (
        {"bodies": [{**PILL, "plate": {"shape": "disk", "radius": -1}}]},
        "bodies[0].plate.radius = -1",
        "radius > 0",
    ),
    "strip without width": (
        {"bodies": [{**PILL, "plate": {"shape": "strip", "length": 1.0}}]},
        "bodies[0].plate.width: missing",
        "width > 0",
    ),
    "too few corners": (
        {"bodies": [{**PILL, "plate": {"shape": "polygon", "n_corners": 2}}]},
        "bodies[0].plate.n_corners = 2",
        "3 <= n_corners <= 24",
    ),
    "pill radius as text": (
        {"bodies": [{"pills": [{"radius": "big"}]}]},
        "bodies[0].pills[0].radius = 'big'",
        "number",
    ),
    "pill outside its disk": (
        {"bodies": [{"plate": {"shape": "disk", "radius": 0.3}, "pills": [{"x": 0.25}]}]},
        "bodies[0].pills[0] = [0.25, 0.0]",
        "sticks out of the disk plate",
    ),
    "pill outside its strip": (
        {
            "bodies": [
                {"plate": {"shape": "strip", "length": 1, "width": 0.3}, "pills": [{"y": 0.1}]}
            ]
        },
        "bodies[0].pills[0] = [0.0, 0.1]",
        "strip plate",
    ),
    "pill outside its polygon": (
        {"bodies": [{"plate": {"shape": "polygon"}, "pills": [{}, {"x": -0.45}]}]},
        "bodies[0].pills[1] = [-0.45, 0.0]",
        "polygon plate",
    ),
    "body without plate and pills": ({"bodies": [{}]}, "bodies[0].pills = []", "at least one"),
    "free body without mass": (
        {"bodies": [{**PILL, "motion": {"kind": "free"}}]},
        "bodies[0].motion.mass: missing",
        "mass > 0",
    ),
    "unknown motion kind": (
        {"bodies": [{**PILL, "motion": {"kind": "orbit"}}]},
        "bodies[0].motion.kind = 'orbit'",
        "fixed, fixed_axis, free",
    ),
    "mass of a fixed_axis body": (
        {"bodies": [{**PILL, "motion": {"kind": "fixed_axis", "mass": 1}}]},
        "bodies[0].motion.mass: unknown key",
        "kind, inertia, friction",
    ),
    "inertia out of range": (
        {"bodies": [{**PILL, "motion": {"kind": "fixed_axis", "inertia": 1.0}}]},
        "bodies[0].motion.inertia = 1",
        "inertia <= 0.01",
    ),
    "velocity of a fixed_axis body": (
        {"bodies": [{**PILL, "start": {"velocity": [1, 0]}}]},
        "bodies[0].start.velocity = [1.0, 0.0]",
        "motion kind free",
    ),
    "turning fixed body": (
        {"bodies": [{**PILL, "motion": {"kind": "fixed"}, "start": {"omega": 1}}]},
        "bodies[0].start.omega = 1",
        "does not turn",
    ),
    "stops of a fixed body": (
        {"bodies": [{**PILL, "motion": {"kind": "fixed"}, "protocol": {}}]},
        "bodies[0].protocol = {...}",
        "never stopped",
    ),
    "noise on a fixed body": (
        {"bodies": [{**PILL, "motion": {"kind": "fixed"}, "noise_sigma": 1e-7}]},
        "bodies[0].noise_sigma = 1e-07",
        "no torque noise",
    ),
    "bad name": ({"bodies": [{**PILL, "name": "a b"}]}, "bodies[0].name = 'a b'", "letters"),
    "two bodies one name": (
        two({**PILL, "name": "body0", "start": {"x": 2.0}}),
        "bodies[1].name = 'body0'",
        "bodies[0]",
    ),
    "overlapping footprints": (
        two({**PILL, "start": {"x": 1.0}}),
        "bodies[1].start = [1.0, 0.0]",
        "overlaps body 'body0'",
    ),
    "body at the rim": (
        two({**PILL, "start": {"x": 0.0, "y": 4.5}}),
        "bodies[1].start = [0.0, 4.5]",
        "|start - grid.domain_centre| < 4.375",
    ),
    "body outside a moved dish": (
        {"grid": {"domain_centre": [2.5, 0.0]}, "bodies": [PILL]},
        "grid.domain_centre = [2.5, 0.0]",
        "moves the dish off body 'body0' at start [0, 0]",
    ),
    "body outside the dish wherever it lies": (
        {"grid": {"domain_centre": [2.5, 0.0]}, "bodies": [{**PILL, "start": {"x": -2.6}}]},
        "bodies[0].start = [-2.6, 0.0]",
        "from the dish centre",
    ),
    "bare bodies line": ({"bodies": None}, "bodies = null", "a bare `bodies:` line"),
    "two pills on one spot": (
        {"bodies": [{"plate": {"shape": "disk", "radius": 0.3}, "pills": [{"x": 0.1}] * 2}]},
        "bodies[0].pills[1] = [0.1, 0.0]",
        "overlaps pills[0] of body 'body0'",
    ),
    "overlapping floating pills": (
        {"bodies": [{"pills": [{}, {"x": 0.15}]}]},
        "bodies[0].pills[1] = [0.15, 0.0]",
        "less than the sum of their radii 0.2",
    ),
    "overlapping pills of the shorthand": (
        {"geometry": {"n_corners": 12}},
        "geometry.pill_radius = 0.1",
        "pills of neighbouring corners overlap",
    ),
    "absurd start angle": (
        {"bodies": [{**PILL, "start": {"angle": 1e300}}]},
        "bodies[0].start.angle = 1e+300",
        "-10000 <= angle <= 10000",
    ),
    "infinite start angle": (
        {"bodies": [{**PILL, "start": {"angle": math.inf}}]},
        "bodies[0].start.angle = Infinity",
        "finite",
    ),
    "absurd rotor angle": ({"rotor": {"phi0": -1e300}}, "rotor.phi0 = -1e+300", "phi0 <= 10000"),
    "absurd start velocity": (
        {
            "bodies": [
                {**PILL, "motion": {"kind": "free", "mass": 1}, "start": {"velocity": [1e9, 0]}}
            ]
        },
        "bodies[0].start.velocity[0] = 1000000000.0",
        "-1000 <= velocity <= 1000",
    ),
    "velocity of one number": (
        {"bodies": [{**PILL, "motion": {"kind": "free", "mass": 1}, "start": {"velocity": [1]}}]},
        "bodies[0].start.velocity = [1]",
        "expected 2 values, got 1 (allowed: [number, number])",
    ),
    "own noise that drowns the rotation": (
        {"bodies": [{**PILL, "noise_sigma": 1.0}]},
        "bodies[0].noise_sigma = 1",
        "sigma < 0.124",
    ),
    "inherited noise that drowns the rotation": (
        {"noise": {"sigma": 1.0}, "bodies": [PILL]},
        "noise.sigma = 1",
        "body 'body0'",
    ),
    "body protocol off the steps": (
        {"bodies": [{**PILL, "protocol": {"t_stop": 0.00015}}]},
        "bodies[0].protocol.t_stop = 0.00015",
        "multiple of grid.dt",
    ),
    "negative body stop": (
        {"bodies": [{**PILL, "protocol": {"t_stop": -1}}]},
        "bodies[0].protocol.t_stop = -1",
        "0 <= t_stop",
    ),
    "dish centre of three numbers": (
        {"grid": {"domain_centre": [1, 2, 3]}},
        "grid.domain_centre = [1, 2, 3]",
        "[number, number]",
    ),
    "no-flux wall for the single rotor": (
        {"grid": {"wall": "no_flux"}},
        "grid.wall = 'no_flux'",
        "bodies: list only",
    ),
    "unknown wall": (
        {"grid": {"wall": "reflecting"}, "bodies": [PILL]},
        "grid.wall = 'reflecting'",
        "no_flux",
    ),
    "dish centre off the rotor": (
        {"grid": {"domain_centre": [2.5, 0.0]}},
        "grid.domain_centre = [2.5, 0.0]",
        "|domain_centre| <",
    ),
    **{
        f"shorthand key {key}": (
            {key.split(".")[0]: {key.split(".")[1]: value}, "bodies": [PILL]},
            f"{key} = {value}",
            "geometry: shorthand",
        )
        for key in SHORTHAND_KEYS
        for value in [{"geometry.n_corners": 4, "geometry.radius": 0.45}.get(key, 0.02)]
    },
}


@pytest.mark.parametrize("case", list(BAD_BODIES), ids=list(BAD_BODIES))
def test_bad_body_input_is_one_line_naming_its_key(case: str, tmp_path: Path) -> None:
    """One ConfigError line that starts with the key path as the user writes it and names
    what is allowed; ``pde-rotor check`` on the file exits 2 with that one line."""
    data, start, named = BAD_BODIES[case]
    with pytest.raises(ConfigError) as info:
        validate_config(data)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(start), message
    assert named in message, message
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(data))
    result = CliRunner().invoke(app, ["check", str(bad)], catch_exceptions=False)
    assert result.exit_code == EXIT_BAD_INPUT
    assert result.stderr == f"error: {message}\n"


def test_list_indices_in_overrides_and_flow_mappings_are_explained(tmp_path: Path) -> None:
    """``--set bodies[-1]...`` says that indices count from 0; a key with an index inside
    a YAML flow mapping (``{bodies[0].start.x: 1}``, invalid YAML) says to quote it or to
    write it in block style, and both of those read."""
    config = tmp_path / "two.yaml"
    config.write_text(yaml.safe_dump(two({**PILL, "start": {"x": 2.0}})))
    result = CliRunner().invoke(app, ["check", str(config), "--set", "bodies[-1].start.x=1"])
    assert result.exit_code == EXIT_BAD_INPUT
    assert result.stderr.count("\n") == 1
    assert "[-1] counts from the end" in result.stderr, result.stderr
    assert "e.g. bodies[0]" in result.stderr
    with pytest.raises(ConfigError, match=r"must be quoted.*block style"):
        parse_yaml("set: {bodies[0].start.x: 1.0}")
    quoted = parse_yaml('set: {"bodies[0].start.x": 1.0}')
    block = parse_yaml("set:\n  bodies[0].start.x: 1.0\n")
    assert quoted == block == {"set": {"bodies[0].start.x": 1.0}}


def test_bodies_run_every_scheme_and_integrator_and_a_moved_dish_is_refused() -> None:
    """Bodies run on either scheme with every plate and with either integrator; the rotor
    of geometry: refuses a moved dish in one line."""
    path = ROOT / "configs" / "bodies" / "two_rotors.yaml"
    consistent = load_config(path, ["numerics.scheme=consistent"])
    assert Simulation(consistent).pde.body_scheme.consistent  # polygons: implemented
    data = yaml.safe_load(path.read_text())
    data["numerics"]["scheme"] = "consistent"
    data["bodies"][1]["plate"] = {"shape": "strip", "length": 1.0, "width": 0.8}
    assert Simulation(validate_config(data)).pde.body_scheme.filters[1].strip is not None
    heun = load_config(path, ["numerics.integrator=heun"])
    assert Simulation(heun).config.numerics.integrator == "heun"
    centred = validate_config({"grid": {"domain_centre": [0.5, 0.0]}})
    with pytest.raises(ConfigError, match=r"^grid\.domain_centre = \[0\.5, 0\.0\]"):
        Simulation(centred)
