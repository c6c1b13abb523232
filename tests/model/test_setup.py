"""The configuration is made into the model's objects once, in :mod:`pde_rotor.model.setup`.

The setup makes each object at most once and its objects are the ones the run reads
(the PDE's, the stepper's record, the trackers' schedule); nothing else in the package
makes them from a configuration (an AST scan of every module).
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np

from pde_rotor.config import validate_config
from pde_rotor.kernels.records import make_body_records, make_record
from pde_rotor.model.geometry import RotorShape
from pde_rotor.model.pde import RotorPDE
from pde_rotor.model.protocol import StopSchedule
from pde_rotor.model.setup import Setup, as_setup
from pde_rotor.model.surface import SurfacePDE
from pde_rotor.trackers import InversionTracker, TimeSeriesTracker

PACKAGE = Path(__file__).resolve().parents[2] / "pde_rotor"

BUILDER = PACKAGE / "model" / "setup.py"
ALLOWED = (BUILDER, PACKAGE / "config", PACKAGE / "cli")
"""Where a configuration may be made into model objects: the builder; the config
package (which validates) and the command line (which reads the user's files)."""

MADE_BY_THE_SETUP = {"from_config", "body_list"}
"""Calls that turn a configuration (or its sections) into model objects or resolved
bodies: only the builder (and the config package itself) makes them."""

PILL = [{"x": 0.0, "y": 0.0}]
PROTOCOL = {"t_ini": 0.002, "t_stop": 0.001, "t_release": 0.001, "cycles": 2}
BODIES = [
    {
        "name": "boat",
        "pills": PILL,
        "motion": {"kind": "free", "mass": 0.5, "inertia": 0.008},
        "protocol": PROTOCOL,
    },
    {"name": "wheel", "pills": PILL, "motion": {"kind": "fixed_axis", "inertia": 0.004},
     "start": {"x": 1.5}},
]  # fmt: skip


def calls_outside_the_builder(
    package: Path = PACKAGE, allowed: tuple[Path, ...] = ALLOWED
) -> list[str]:
    """Every call of :data:`MADE_BY_THE_SETUP` in a module of `package` outside `allowed`."""
    found = []
    for path in sorted(package.rglob("*.py")):
        if any(path == place or place in path.parents for place in allowed):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Call):
                continue
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if name in MADE_BY_THE_SETUP:
                found.append(f"{path.relative_to(package)}:{node.lineno} {name}")
    return found


def test_nothing_below_the_builder_makes_model_objects_from_the_config() -> None:
    """No module outside the builder, the config package and the CLI calls a
    ``from_config`` or resolves the bodies of a configuration."""
    assert calls_outside_the_builder() == []


def test_the_scan_finds_a_call(tmp_path: Path) -> None:
    """The scan is not blind: a module below the builder that calls
    ``StopSchedule.from_config`` or resolves the bodies is named; the builder is not."""
    for folder in ("solver", "model"):
        (tmp_path / folder).mkdir()
    late = "def f(config):\n    return StopSchedule.from_config(config.protocol, 1e-4)\n"
    (tmp_path / "solver" / "late.py").write_text(late, encoding="utf-8")
    (tmp_path / "model" / "bodies.py").write_text("x = config.body_list()\n", encoding="utf-8")
    builder = tmp_path / "model" / "setup.py"
    builder.write_text(late, encoding="utf-8")
    found = calls_outside_the_builder(tmp_path, (builder,))
    assert found == ["model/bodies.py:1 body_list", "solver/late.py:2 from_config"]


def test_each_object_is_made_once_and_on_first_use() -> None:
    """Nothing is made before it is asked for, and asking again returns the same object."""
    setup = Setup(validate_config({"numerics": {"scheme": "paper"}}))
    assert setup.made() == ()
    shape = setup.shape
    assert setup.made() == ("shape",)
    assert setup.shape is shape
    assert setup.scheme is setup.scheme
    assert setup.schedule is setup.schedule
    assert set(setup.made()) == {"shape", "scheme", "schedule"}


def test_the_objects_are_those_of_the_config() -> None:
    """The shape, schedule and bodies equal what their own constructors make of the
    config's sections; without ``bodies:`` the one body is the rotor's fixed_axis body."""
    config = validate_config({"geometry": {"asymmetry": 0.1}})
    setup = Setup(config)
    assert setup.dt == config.grid.dt
    assert setup.shape == RotorShape.from_config(config.geometry)
    assert setup.schedule == StopSchedule.from_config(config.protocol, config.grid.dt)
    (rotor,) = setup.bodies
    assert rotor.motion == "fixed_axis"
    assert rotor.start == (0.0, 0.0, config.rotor.phi0)
    assert rotor.inertia == config.rotor.inertia
    assert setup.body_schedules == (setup.schedule,)


def test_bodies_with_and_without_their_own_schedule() -> None:
    """Each body's schedule counts its own protocol in steps of the setup's dt."""
    config = validate_config({"grid": {"domain_radius": 3.0, "dx": 0.05, "dt": 1e-4},
                              "bodies": BODIES})  # fmt: skip
    setup = Setup(config)
    boat, wheel = setup.body_schedules
    assert wheel is None
    assert (boat.n_ini, boat.n_stop, boat.n_period, boat.cycles) == (20, 10, 20, 2)
    assert boat == StopSchedule.from_config(config.bodies[0].protocol, 1e-4)
    assert [b.name for b in setup.bodies] == ["boat", "wheel"]


def test_another_step_shares_every_object_but_the_schedules() -> None:
    """:meth:`Setup.at`: the schedules in the new step, the shape, bodies and schemes the
    same objects, made by one of the two setups only."""
    setup = Setup(validate_config({"numerics": {"scheme": "paper"}}))
    half = setup.at(setup.dt / 2)
    assert setup.at(setup.dt) is setup
    assert half.dt == setup.dt / 2
    assert half.schedule.n_ini == 2 * setup.schedule.n_ini
    assert half.shape is setup.shape
    assert half.scheme is setup.scheme
    assert half.bodies is setup.bodies
    assert half.at(setup.dt / 4).shape is setup.shape


def test_a_config_or_its_setup() -> None:
    """The public calls take either; a setup is passed on, a config made into one."""
    config = validate_config({"numerics": {"scheme": "paper"}})
    setup = Setup(config)
    assert as_setup(setup) is setup
    made = as_setup(config)
    assert isinstance(made, Setup) and made.config is config
    pde = RotorPDE(setup)
    assert pde.setup is setup and pde.shape is setup.shape and pde.scheme is setup.scheme


def test_the_run_reads_the_setups_objects() -> None:
    """The PDE, the record and the trackers of one run use one setup's objects: the
    record's schedule and apothem are the setup's, the trackers' schedule is its own."""
    config = validate_config(
        {"numerics": {"scheme": "paper"}, "grid": {"domain_radius": 1.5, "dx": 0.05}}
    )
    setup = Setup(config)
    pde = RotorPDE(setup)
    rec = make_record(pde.setup)[0]
    schedule = setup.schedule
    assert (rec["n_ini"], rec["n_stop"], rec["n_period"]) == (
        schedule.n_ini,
        schedule.n_stop,
        schedule.n_period,
    )
    assert rec["apothem"] == setup.shape.apothem
    series = TimeSeriesTracker(setup, 0.1)
    events = InversionTracker(setup, 0.1, 0.5)
    assert series.setup is setup and series.schedule is schedule
    assert events.setup is setup and events.schedule is schedule


def test_the_bodies_records_read_the_setups_schedules() -> None:
    """A body's stop schedule in its record is the setup's (at the kernels' step); a
    body without one never stops."""
    config = validate_config({"grid": {"domain_radius": 3.0, "dx": 0.05, "dt": 1e-4},
                              "bodies": BODIES})  # fmt: skip
    setup = Setup(config)
    pde = SurfacePDE(setup)
    assert pde.bodies is setup.bodies and pde.body_scheme is setup.body_scheme
    records, _ = make_body_records(setup.at(5e-5))
    boat = setup.at(5e-5).body_schedules[0]
    assert (records[0]["n_ini"], records[0]["n_stop"], records[0]["n_period"]) == (
        boat.n_ini,
        boat.n_stop,
        boat.n_period,
    )
    assert boat.n_ini == 2 * setup.body_schedules[0].n_ini
    assert records[1]["n_period"] == 1 and records[1]["cycles"] == 0
    np.testing.assert_array_equal(records["cycles"], [2, 0])
