"""Config files: YAML round trip, --set overrides, and one-line errors for every bad input."""

from __future__ import annotations

import math
import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from pydantic import BaseModel
from typer.testing import CliRunner

from pde_rotor.cli.common import EXIT_BAD_INPUT
from pde_rotor.cli.main import app
from pde_rotor.config import (
    CALIBRATED_SIGMA,
    PAPER_SCHEME_SIGMA,
    PAPER_STEADY_OMEGA,
    TIME_KEYS,
    BodyConfig,
    ConfigError,
    FieldError,
    GridConfig,
    NumericsConfig,
    RotorConfig,
    apply_overrides,
    bodies,
    dump_config,
    load_config,
    parse_yaml,
    validate_config,
)
from pde_rotor.config.stable import DUMPED_KEYS
from pde_rotor.model.protocol import StopSchedule
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep import shipped_base

CONFIGS = sorted((Path(__file__).parents[2] / "configs").glob("*.yaml"))
COARSE_YAML = "grid: {dx: 0.05, dt: 4.0e-4}\ngeometry: {smoothing: 0.05}\n"

# (YAML text or None, --set overrides, key path named in the error, allowed text named)
BAD_INPUTS: dict[str, tuple[str | None, list[str], str, str]] = {
    "unknown section": ("protcol: {t_stop: 1.0}\n", [], "protcol", "allowed keys"),
    "unknown key": ("protocol: {t_stp: 1.0}\n", [], "protocol.t_stp", "t_stop"),
    "unknown key via --set": (None, ["grid.ddx=0.1"], "grid.ddx", "dx"),
    "section is a number": ("protocol: 5\n", [], "protocol", "t_stop"),
    "section is a list": ("grid: [1, 2]\n", [], "grid", "dx"),
    "negative t_stop": (None, ["protocol.t_stop=-1"], "protocol.t_stop", "0 <= t_stop <= 100000"),
    "zero t_release": (
        None,
        ["protocol.t_release=0"],
        "protocol.t_release",
        "0 < t_release <= 100000",
    ),
    "negative cycles": (None, ["protocol.cycles=-3"], "protocol.cycles", "0 <= cycles <= 100000"),
    "fractional cycles": (None, ["protocol.cycles=2.5"], "protocol.cycles", "integer"),
    "cycles as text": (None, ["protocol.cycles=many"], "protocol.cycles", "integer"),
    "negative radius": (None, ["geometry.radius=-0.5"], "geometry.radius", "radius > 0"),
    "zero pill radius": (None, ["geometry.pill_radius=0"], "geometry.pill_radius", "> 0"),
    "negative pill inset": (None, ["geometry.pill_inset=-0.1"], "geometry.pill_inset", ">= 0"),
    "two corners": (None, ["geometry.n_corners=2"], "geometry.n_corners", "3 <= n_corners"),
    "too many corners": (None, ["geometry.n_corners=25"], "geometry.n_corners", "<= 24"),
    "R_c <= 0": (None, ["geometry.pill_radius=0.45"], "geometry.pill_radius", "R_c"),
    "pills outside plate": (None, ["geometry.asymmetry=0.5"], "geometry.asymmetry", "0.4283"),
    "negative smoothing": (None, ["geometry.smoothing=-0.01"], "geometry.smoothing", "> 0"),
    "infinite asymmetry": (None, ["geometry.asymmetry=.inf"], "geometry.asymmetry", "finite"),
    "nan radius": (None, ["geometry.radius=.nan"], "geometry.radius", "finite"),
    "grid too coarse": (None, ["grid.dx=0.2"], "grid.dx", "dx <= 2 * smoothing"),
    "negative dx": (None, ["grid.dx=-0.05"], "grid.dx", "dx > 0"),
    "dt above stability limit": (None, ["grid.dt=1e-3"], "grid.dt", "dt <= 0.0006"),
    "zero dt": (None, ["grid.dt=0"], "grid.dt", "dt > 0"),
    "domain smaller than plate": (None, ["grid.domain_radius=0.5"], "grid.domain_radius", "> "),
    "domain cuts the support of F": (
        None,
        ["grid.domain_radius=1.5"],
        "grid.domain_radius",
        "domain_radius >= 1.655",
    ),
    "dx as text": (None, ["grid.dx=fine"], "grid.dx", "number"),
    "dx as boolean": (None, ["grid.dx=true"], "grid.dx", "number"),
    "t_stop not a multiple of dt": (
        None,
        ["protocol.t_stop=0.0005"],
        "protocol.t_stop",
        "multiple of grid.dt",
    ),
    "t_ini not a multiple of dt": (None, ["protocol.t_ini=1.0001"], "protocol.t_ini", "k * dt"),
    "interval not a multiple of dt": (
        None,
        ["output.movie_interval=0.0101"],
        "output.movie_interval",
        "multiple of grid.dt",
    ),
    "nothing to simulate": (
        None,
        ["protocol.t_ini=0", "protocol.cycles=0"],
        "protocol.t_ini",
        "> 0",
    ),
    "negative seed": (None, ["noise.seed=-1"], "noise.seed", "seed >= 0"),
    "negative sigma": (None, ["noise.sigma=-0.1"], "noise.sigma", "sigma >= 0"),
    "sigma that drowns the rotation": (None, ["noise.sigma=1e300"], "noise.sigma", "per step"),
    "asymmetry of astronomic size": (
        None,
        ["geometry.asymmetry=1e300"],
        "geometry.asymmetry",
        "|asymmetry| < pi/N = 0.5236",
    ),
    "asymmetry of a whole period": (
        None,
        ["geometry.asymmetry=1.0471975511965976"],
        "geometry.asymmetry",
        "pi/N",
    ),
    "unknown backend": (None, ["solver.backend=tpu"], "solver.backend", "cpu, gpu, auto"),
    "unknown torque convention": (None, ["rotor.torque=mine"], "rotor.torque", "physical"),
    "zero inertia": (None, ["rotor.inertia=0"], "rotor.inertia", "1e-08 <= inertia"),
    "flow switch not boolean": (None, ["flow.enabled=sometimes"], "flow.enabled", "true or false"),
    "commit fraction above 1": (
        None,
        ["output.commit_fraction=1.5"],
        "output.commit_fraction",
        "commit_fraction <= 1",
    ),
    "movie fps zero": (None, ["output.movie_fps=0"], "output.movie_fps", "movie_fps"),
    "negative diffusion": (None, ["camphor.diffusion=-1"], "camphor.diffusion", "0 < diffusion"),
    "--set without '='": (None, ["protocol.t_stop"], "protocol.t_stop", "KEY.PATH=VALUE"),
    "--set without key": (None, ["=1.5"], "--set", "KEY.PATH=VALUE"),
    "--set without value": (None, ["protocol.t_stop="], "protocol.t_stop", "missing value"),
    "--set bad key path": (None, ["protocol..t_stop=1"], "protocol..t_stop", "dotted key path"),
    "--set into a value": (None, ["grid.dx.fine=1"], "grid.dx", "not a section"),
    "--set unparsable value": (None, ["protocol.t_stop=[1"], "protocol.t_stop", "invalid YAML"),
    "unparsable YAML": ("protocol: {t_stop: 1\n", [], "invalid YAML", "line"),
    "tab in YAML": ("protocol:\n\tt_stop: 1\n", [], "invalid YAML", "line 2"),
    "duplicate key": ("protocol:\n  t_stop: 1\n  t_stop: 2\n", [], "duplicate key", "t_stop"),
    "top level is a list": ("- 1\n- 2\n", [], "top level", "geometry"),
    "empty file": ("", [], "empty", "write {}"),
    "a sweep file": (
        "name: s\nbase: coarse\naxes: {protocol.t_stop: [1.0]}\nsamples: 2\nseed: 1\n",
        [],
        "is a sweep file",
        "pde-rotor sweep FILE --dry-run",
    ),
    "only comments": ("# all defaults?\n\n", [], "only comments", "write {}"),
}


def write_config(tmp_path: Path, text: str | None) -> Path:
    """A config file: the coarse grid, or the given text."""
    path = tmp_path / "config.yaml"
    path.write_text(COARSE_YAML if text is None else text)
    return path


def schema_has(path: str) -> bool:
    """Whether the dotted key path names a section or a field of :class:`RotorConfig`."""
    model: Any = RotorConfig
    for part in path.split("."):
        if not (isinstance(model, type) and issubclass(model, BaseModel)):
            return False
        if part not in model.model_fields:
            return False
        model = model.model_fields[part].annotation
    return True


def offending_values(text: str | None, overrides: list[str]) -> dict[str, Any]:
    """The values the bad input sets, by dotted key path (sections and their keys of the
    YAML text, each well-formed ``KEY=VALUE`` override), parsed as the loader does."""
    values: dict[str, Any] = {}
    try:
        data = parse_yaml(text) if text else None
    except ConfigError:
        data = None
    if isinstance(data, dict):
        for section, body in data.items():
            values[section] = body
            if isinstance(body, dict):
                values.update({f"{section}.{k}": v for k, v in body.items()})
    for override in overrides:
        key, sep, raw = override.partition("=")
        try:
            parsed = parse_yaml(raw)
        except ConfigError:
            continue
        if sep and key and raw:
            values[key] = parsed
    return values


def names_value(named: str, value: Any) -> bool:
    """Whether the text an error gives for a value (``'many'``, ``Infinity``, ``0.0``,
    ``[1, 2]``) is that value."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return named in (repr(value), str(value).lower(), yaml.safe_dump(value).strip())
    return float(named) == value or (math.isnan(value) and named == "NaN")


def as_file(text: str | None, overrides: list[str]) -> tuple[str, list[str]]:
    """The bad input as a config file: the overrides that are ``KEY=VALUE`` with a YAML
    value go into the coarse config's text; the others (malformed ``--set``) stay
    overrides."""
    if text is not None:
        return text, overrides
    data, rest = yaml.safe_load(COARSE_YAML), []
    for override in overrides:
        key, sep, raw = override.partition("=")
        parts = key.split(".")
        try:
            value = parse_yaml(raw)
        except ConfigError:
            rest.append(override)
            continue
        if not (sep and raw and len(parts) == 2 and all(parts)):
            rest.append(override)
            continue
        data.setdefault(parts[0], {})[parts[1]] = value
    return yaml.safe_dump(data), rest


@pytest.mark.parametrize("case", list(BAD_INPUTS), ids=list(BAD_INPUTS))
def test_bad_input_names_its_key_and_value_here_and_in_check(tmp_path, case):
    """One ConfigError, one line, that starts with the offending key and, where the input
    sets a key of the schema to a bad value, gives that value (``protocol.cycles = 2.5:``);
    ``pde-rotor check`` on a file holding the input exits 2 with that one line."""
    text, overrides, key, _ = BAD_INPUTS[case]
    path = write_config(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_config(path, overrides)
    message = str(info.value)
    assert "\n" not in message
    assert key in message
    values = offending_values(text, overrides)
    if key in values and schema_has(key):
        assert message.startswith(f"{key} = "), message
        named = message.removeprefix(f"{key} = ").split(": ", 1)[0]
        assert names_value(named, values[key]), (named, values[key])

    file_text, sets = as_file(text, overrides)
    bad = tmp_path / "bad.yaml"
    bad.write_text(file_text)
    args = ["check", str(bad)] + [arg for s in sets for arg in ("--set", s)]
    result = CliRunner().invoke(app, args, catch_exceptions=False)
    assert result.exit_code == EXIT_BAD_INPUT
    assert result.stdout == ""
    assert result.stderr.startswith("error: ") and result.stderr.count("\n") == 1
    assert key in result.stderr


@pytest.mark.parametrize("case", list(BAD_INPUTS), ids=list(BAD_INPUTS))
def test_bad_input_gives_one_line_naming_key_and_allowed(tmp_path, case):
    text, overrides, key, allowed = BAD_INPUTS[case]
    path = write_config(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_config(path, overrides)
    message = str(info.value)
    assert "\n" not in message
    assert key in message
    assert allowed in message


def test_explicit_empty_mapping_is_every_default(tmp_path):
    """An empty file is refused (above); ``{}`` asks for the paper's defaults on purpose."""
    path = write_config(tmp_path, "{}  # every default\n")
    assert load_config(path) == RotorConfig()


def test_missing_file(tmp_path):
    with pytest.raises(ConfigError, match="not found"):
        load_config(tmp_path / "nope.yaml")


@pytest.mark.parametrize("path", CONFIGS, ids=[p.name for p in CONFIGS])
def test_shipped_configs_round_trip(path, tmp_path):
    """YAML -> model -> YAML -> model gives the same model and the same YAML text."""
    config = load_config(path)
    text = dump_config(config, {"config_hash": config.config_hash()})
    again_path = tmp_path / "again.yaml"
    again_path.write_text(text)
    again = load_config(again_path)
    assert again == config
    assert dump_config(again, {"config_hash": again.config_hash()}) == text
    assert again.config_hash() == config.config_hash()


def test_paper_resolution_configs_carry_the_calibrated_noise():
    """One value: every config at the paper's grid uses CALIBRATED_SIGMA, coarse ones do not.

    CALIBRATED_SIGMA is calibrated at the paper's dx and dt; every shipped config on
    another grid must state its own sigma (quickstart and no_flow are coarse).
    """
    root = Path(__file__).resolve().parents[2] / "configs"
    paper = [*sorted(root.glob("paper_fig*.yaml")), shipped_base("paper")]
    for path in paper:
        config = load_config(path)
        assert (config.grid.dx, config.grid.dt) == (0.025, 1e-4), path
        assert config.noise.sigma == CALIBRATED_SIGMA, path
    coarse = [path for path in CONFIGS if load_config(path).grid != RotorConfig().grid]
    assert {path.name for path in coarse} >= {"quickstart.yaml", "no_flow.yaml"}
    for path in coarse:
        assert load_config(path).noise.sigma != CALIBRATED_SIGMA, path
    sweeps = yaml.safe_load((root / "sweeps" / "predictions.yaml").read_text())
    assert PAPER_SCHEME_SIGMA in sweeps["axes"]["noise.sigma"]  # its stored report's
    calibration = yaml.safe_load((root / "sweeps" / "science_calibration.yaml").read_text())
    assert CALIBRATED_SIGMA in calibration["axes"]["noise.sigma"]


def test_hash_follows_physics_not_recording():
    base = RotorConfig()
    quiet = validate_config({"output": {"movie": False, "progress": False}})
    assert quiet.config_hash() == base.config_hash()
    other = validate_config({"protocol": {"t_stop": 1.0}})
    assert other.config_hash() != base.config_hash()


def sections() -> dict[str, type[BaseModel]]:
    """The sections of the schema (every top-level key but the bodies list)."""
    return {
        name: field.annotation
        for name, field in RotorConfig.model_fields.items()
        if isinstance(field.annotation, type) and issubclass(field.annotation, BaseModel)
    }


def test_dump_holds_every_key():
    """Every key of every section that the committed stores were written with; the keys
    added since (the dish centre and wall, the vessel, the tension law, external loads)
    are left out at their defaults (configs from before they existed dump and hash as
    before: tests/config/test_stable.py); set, they are dumped."""
    data = yaml.safe_load(dump_config(RotorConfig()))
    assert set(data) == set(sections()) - {"contact"}  # a later section, at its default
    for section, model in sections().items():
        if section not in data:
            continue
        later = set(model.model_fields) - DUMPED_KEYS[model.__name__]
        assert set(data[section]) == set(model.model_fields) - later
    assert {"domain_centre", "wall", "vessel"} <= set(GridConfig.model_fields) - set(data["grid"])
    assert "saturation" not in data["camphor"] and "external_torque" not in data["rotor"]
    moved = validate_config(
        {"grid": {"domain_centre": [0.5, 0.0], "wall": "no_flux"}, "bodies": [{"pills": [{}]}]}
    )
    data = yaml.safe_load(dump_config(moved))
    assert data["grid"]["domain_centre"] == [0.5, 0.0]
    assert data["grid"]["wall"] == "no_flux"
    assert set(data["bodies"][0]) == set(BodyConfig.model_fields) & DUMPED_KEYS["BodyConfig"]
    touching = validate_config({"contact": {"enabled": True}, "bodies": [{"pills": [{}]}]})
    assert yaml.safe_load(dump_config(touching))["contact"] == {"enabled": True}


def test_shipped_paper_configs_follow_the_paper():
    """Figs. 4 and 6: Delta 0 / 1e-4, t_stop 0.5 / 2, t_ini = t_release = 10, M = 100."""
    expected = {
        "paper_fig4a.yaml": (0.0, 0.5),
        "paper_fig4b.yaml": (0.0, 2.0),
        "paper_fig6a.yaml": (1e-4, 0.5),
        "paper_fig6b.yaml": (1e-4, 2.0),
    }
    paper = RotorConfig()
    for name, (delta, t_stop) in expected.items():
        config = load_config(CONFIGS[0].parent / name)
        assert config.geometry.asymmetry == delta
        assert config.protocol.t_stop == t_stop
        assert config.protocol.t_ini == config.protocol.t_release == 10
        assert config.protocol.cycles == 100
        assert config.grid == paper.grid
        assert config.geometry.smoothing == paper.geometry.smoothing
        assert config.flow.enabled


NO_FLOW_TINY = [
    "grid.domain_radius=1.75",
    "protocol.t_ini=0.04",
    "protocol.t_stop=0.02",
    "protocol.t_release=0.04",
    "protocol.cycles=1",
    "output.movie=false",
]
"""configs/no_flow.yaml shrunk to the small domain and one cycle: 250 steps in all."""


@pytest.mark.parametrize("flow", [False, True], ids=["as shipped", "flow switched on"])
def test_no_flow_config_keeps_v_zero_while_c_evolves(flow):
    """configs/no_flow.yaml run (shrunk): v is exactly 0 while the plate turns, is
    stopped and turns again, and c changes; the same run with the flow switched on
    moves the water (the check can see a flow)."""
    switch = ["flow.enabled=true"] if flow else []  # as shipped: the file's own setting
    config = load_config(CONFIGS[0].parent / "no_flow.yaml", [*NO_FLOW_TINY, *switch])
    sim = Simulation(config)
    c_start = sim.state.data[0].copy()
    flows, stops = [], []
    for t in (0.02, 0.05, config.protocol.t_end):
        sim.run(t)
        flows.append(np.abs(sim.state.data[1:]).max())
        stops.append(sim.rotor.stopped)
        assert np.abs(sim.state.data[0] - c_start).max() > 0.1
    assert stops == [False, True, False]
    if flow:
        assert min(flows) > 0
    else:
        assert max(flows) == 0.0


def test_quickstart_is_coarse_and_has_cycles():
    config = load_config(CONFIGS[0].parent / "quickstart.yaml")
    assert config.grid.dx > RotorConfig().grid.dx
    assert config.protocol.cycles >= 2
    assert config.output.movie
    # every stop starts and ends on a whole step: t / dt is an integer for the times
    # the config states, so the stop schedule in steps ends exactly at t_end
    p, dt = config.protocol, config.grid.dt
    for m in range(p.cycles):
        for t in (p.t_ini + m * p.period, p.t_ini + m * p.period + p.t_stop):
            assert t / dt == pytest.approx(round(t / dt), abs=1e-6), t
    schedule = StopSchedule.from_config(p, dt)
    assert (schedule.n_ini + p.cycles * schedule.n_period) * dt == pytest.approx(p.t_end)


def test_overrides_apply_in_order_and_parse_yaml_values(tmp_path):
    path = write_config(tmp_path, None)
    config = load_config(
        path,
        [
            "protocol.t_stop=1.5",
            "protocol.t_stop=2",
            "geometry.asymmetry=1e-4",
            "flow.enabled=false",
            "noise.seed=null",
        ],
    )
    assert config.protocol.t_stop == 2.0
    assert config.geometry.asymmetry == 1e-4
    assert config.flow.enabled is False
    assert config.noise.seed is None


def test_overrides_do_not_mutate_input():
    data = {"grid": {"dx": 0.05}}
    apply_overrides(data, ["grid.dx=0.025"])
    assert data == {"grid": {"dx": 0.05}}


def test_exponent_floats_are_floats():
    assert parse_yaml("a: 1e-4\nb: -2E+3\nc: 1.0e-5") == {"a": 1e-4, "b": -2000.0, "c": 1e-5}


def test_provenance_block_is_ignored_on_load(tmp_path):
    config = validate_config({"protocol": {"t_stop": 1.0}})
    path = tmp_path / "run.yaml"
    path.write_text(dump_config(config, {"pde_rotor_version": "0", "seed": 5}))
    assert load_config(path) == config


def test_stability_limit_is_the_boundary():
    """dt exactly at the limit is accepted; one part in 1e9 above it is refused.

    The limit cannot exceed the von Neumann bound of the explicit 5-point diffusion
    step, dx^2 / (4 D); the flow and reaction terms only lower it. Every time of the
    config is first made a multiple of the limit, so that dt = limit passes the
    whole-step rule and only the stability limit decides.
    """
    base = RotorConfig()
    limit = base.dt_limit()
    assert 0 < limit <= base.grid.dx**2 / (4 * base.camphor.diffusion)
    data = base.model_dump(mode="json")
    for key in TIME_KEYS:
        section, name = key.split(".")
        if data[section][name] is not None:
            data[section][name] = round(data[section][name] / limit) * limit
    data["grid"]["dt"] = limit
    assert validate_config(data).grid.dt == limit
    data["grid"]["dt"] = limit * (1 + 1e-9)
    with pytest.raises(ConfigError, match=r"grid\.dt = .*stability limit"):
        validate_config(data)


def test_pill_asymmetry_limit_is_sharp():
    """The largest allowed |Delta| puts the pill exactly on the edge (clearance = rho)."""
    geometry = RotorConfig().geometry
    limit = geometry.max_asymmetry()
    at_limit = geometry.model_copy(update={"asymmetry": limit})
    assert at_limit.edge_clearance() == pytest.approx(geometry.pill_radius, abs=1e-12)
    validate_config({"geometry": {"asymmetry": 0.999 * limit}})
    with pytest.raises(ConfigError, match=r"geometry\.asymmetry"):
        validate_config({"geometry": {"asymmetry": -1.001 * limit}})


def test_noise_limit_is_a_kick_of_the_steady_omega():
    """sigma is refused where its kick per step, sqrt(2 dt) sigma / I, reaches the steady
    omega; the paper's sigma = 0.1 passes at dt = 1e-4 (kick 141), not at dt = 4e-4 (283)."""
    config = RotorConfig()
    limit = PAPER_STEADY_OMEGA * config.rotor.inertia / math.sqrt(2 * config.grid.dt)
    validate_config({"noise": {"sigma": 0.999 * limit}})
    with pytest.raises(ConfigError, match=r"noise\.sigma = .*sqrt\(2 dt\) sigma / I"):
        validate_config({"noise": {"sigma": 1.001 * limit}})
    validate_config({"noise": {"sigma": 0.1}})
    coarse = {"grid": {"dx": 0.05, "dt": 4e-4}, "geometry": {"smoothing": 0.05}}
    with pytest.raises(ConfigError, match=r"allowed: sigma < 0\.0622"):
        validate_config({**coarse, "noise": {"sigma": 0.1}})


def test_asymmetry_limit_is_half_a_period_for_any_corner_count():
    """|Delta| < pi/N even where the pills would still fit (small pills near the centre, N = 3)."""
    small = {"n_corners": 3, "pill_radius": 0.02, "pill_inset": 0.36}  # pills near the centre
    validate_config({"geometry": {**small, "asymmetry": 0.999 * math.pi / 3}})
    with pytest.raises(ConfigError, match=r"pi/N = 1\.047"):
        validate_config({"geometry": {**small, "asymmetry": -math.pi / 3}})


def body_keys() -> list[str]:
    """Every key of a body as docs/usage.md writes it (``bodies[k].plate.radius``)."""
    keys = []
    for name in bodies.BodyConfig.model_fields:
        parts = {
            "plate": [bodies.PolygonPlate, bodies.DiskPlate, bodies.StripPlate, bodies.NoPlate],
            "motion": [bodies.FixedMotion, bodies.FixedAxisMotion, bodies.FreeMotion],
            "pills": [bodies.PillConfig],
            "start": [bodies.StartConfig],
            "protocol": [],
        }.get(name)
        if not parts:
            keys.append(f"bodies[k].{name}")
        prefix = "pills[j]" if name == "pills" else name
        keys += [f"bodies[k].{prefix}.{key}" for model in parts or [] for key in model.model_fields]
    return keys


def test_usage_doc_lists_every_key():
    """docs/usage.md's reference table names every key of the schema, and its section on
    bodies every key of a body."""
    doc = (Path(__file__).parents[2] / "docs" / "usage.md").read_text()
    for section, model in sections().items():
        for key in model.model_fields:
            assert f"`{section}.{key}`" in doc
    for key in body_keys():
        assert f"`{key}`" in doc, key


def test_field_error_survives_pickling():
    """A worker process (dask, a process pool) sends a config error back whole."""
    err = FieldError("grid.dx", 0.3, "grid.dx: too coarse")
    back = pickle.loads(pickle.dumps(err))
    assert (type(back), back.path, back.value, str(back)) == (FieldError, "grid.dx", 0.3, str(err))


def test_acting_numerics_are_those_of_the_scheme():
    """The paper scheme ignores the consistent scheme's settings (its point values use no
    prefilter and no contour quadrature), so they leave its acting numerics, and with them
    a sweep run's key, unchanged; for the consistent scheme every setting acts."""
    paper = NumericsConfig(scheme="paper")
    retuned = NumericsConfig(scheme="paper", pill_filter_width=1.2, contour_nodes=64)
    assert paper.acting() == retuned.acting() == {"scheme": "paper", "integrator": "euler"}
    consistent = NumericsConfig()
    assert consistent.acting() == consistent.model_dump(mode="json")
    assert NumericsConfig(pill_filter_width=1.2).acting() != consistent.acting()


def test_a_cut_footprint_acts_on_both_schemes_and_the_default_on_no_hash():
    """``numerics.footprint_widths`` changes the drawn F_k, G_k on either scheme, so a
    cut one is acting on ``paper`` too and changes the config hash; at its default, set
    or left out, it is in no dump: the hash is that of a config without the key."""
    bodies = [{"pills": [{}]}]
    plain = validate_config({"numerics": {"scheme": "paper"}, "bodies": bodies})
    saturated = validate_config(
        {"numerics": {"scheme": "paper", "footprint_widths": 20.0}, "bodies": bodies}
    )
    cut = validate_config(
        {"numerics": {"scheme": "paper", "footprint_widths": 8}, "bodies": bodies}
    )
    assert plain.config_hash() == saturated.config_hash() != cut.config_hash()
    assert "footprint_widths" not in plain.physics()["numerics"]
    assert cut.physics()["numerics"]["footprint_widths"] == 8.0
    assert NumericsConfig(footprint_widths=6).acting() != NumericsConfig().acting()


def test_physics_differences_name_the_settings_that_change_a_result():
    """Keys with both values; what changes no result (output, solver) and ignored keys
    are left out; equal configs differ in nothing."""
    from pde_rotor.config import physics_differences

    base = RotorConfig()
    other = validate_config(
        {"grid": {"dx": 0.05}, "protocol": {"t_stop": 3.0}, "solver": {"backend": "auto"}}
    )
    assert physics_differences(base, base) == {}
    assert physics_differences(base, other) == {
        "grid.dx": (base.grid.dx, 0.05),
        "protocol.t_stop": (base.protocol.t_stop, 3.0),
    }
    assert list(physics_differences(base, other, ignore={"protocol.t_stop"})) == ["grid.dx"]
