"""The kernels' parameter records against the configuration they are built from.

:func:`pde_rotor.kernels.records.make_record` and ``make_body_records`` pack the
configuration for the compiled kernels; their config fields are read off the schema
(:mod:`pde_rotor.config.recorded`). Every numeric key of the record sections and of a
body must reach its record with its value, or through the field its marker names; a key
added to the schema in a test reaches the records with no other change.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Annotated, Any

import numpy as np
import pytest
from pydantic import BaseModel, Field

from pde_rotor.config import BodyConfig, CamphorConfig, RotorConfig
from pde_rotor.config.fields import FiniteFloat, NonNegativeFloat, PositiveFloat
from pde_rotor.config.recorded import BuiltInto, NotRecorded, RecordAs, markers
from pde_rotor.kernels.records import (
    BODY,
    BUILT_BODY,
    BUILT_PARAMS,
    PARAMS,
    PARAMS_SECTIONS,
    make_body_records,
    make_record,
)
from pde_rotor.model.pde import TORQUE_SIGN
from pde_rotor.model.setup import Setup

VARIED: dict[str, Any] = {
    "geometry": {"n_corners": 5, "asymmetry": 0.03, "smoothing": 0.03, "pill_radius": 0.09},
    "camphor": {
        "diffusion": 0.9,
        "evaporation": 1.1,
        "supply": 1.3,
        "tension_slope": 0.7,
        "saturation": 0.4,
    },
    "flow": {"enabled": False, "drag": 1.2, "bulk_drag": 0.8, "viscosity": 0.6},
    "rotor": {"inertia": 2e-5, "friction": 3e-4, "torque": "printed", "external_torque": 1e-6},
    "noise": {"sigma": 1e-7},
    "protocol": {"t_ini": 0.4, "t_stop": 0.2, "t_release": 0.6, "cycles": 3},
}
"""A configuration whose parameters differ from each other and from the defaults."""

BODIES: list[dict[str, Any]] = [
    {
        "pills": [{"x": 0.0, "y": 0.0}],
        "motion": {"kind": "free", "mass": 0.02, "inertia": 0.004},
        "external_force": [0.3, -0.1],
        "external_torque": 0.02,
    },
    {"pills": [{"x": 0.0, "y": 0.0}], "start": {"x": 2.0}, "external_torque": -0.01},
]
"""Two bodies whose own keys differ from their defaults."""


def numeric_values(section: BaseModel) -> dict[str, Any]:
    """The record fields the unmarked numeric keys of `section` must give, written out
    (a pair as NAME_x, NAME_y), independently of the layout's code."""
    marked = markers(type(section))
    out: dict[str, Any] = {}
    for key in type(section).model_fields:
        value = getattr(section, key)
        if key in marked or isinstance(value, BaseModel | str | list) or value is None:
            continue
        if isinstance(value, tuple):
            out[f"{key}_x"], out[f"{key}_y"] = value
        elif isinstance(value, bool | int | float):
            out[key] = value
    return out


def assert_marked_keys(section: BaseModel, rec: np.void) -> None:
    """Each marked key of `section` names a field of the record; one derived here holds
    its value."""
    for key, mark in markers(type(section)).items():
        if isinstance(mark, RecordAs):
            value = getattr(section, key)
            assert rec[mark.field] == (value if mark.value is None else mark.value(value)), key
        elif isinstance(mark, BuiltInto):
            assert mark.field in rec.dtype.names, key
        else:
            assert isinstance(mark, NotRecorded) and mark.why, key


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_record_holds_every_parameter_of_the_schema(
    small_config: Callable[..., RotorConfig], scheme: str
) -> None:
    """Each numeric key of the record sections is the field of its name with the
    config's value, or reaches the field its marker names; the built fields hold what
    the kernels need."""
    cfg = small_config({**VARIED, "numerics": {"scheme": scheme}})
    dt = cfg.grid.dt
    rec = make_record(Setup(cfg))[0]
    assert rec.dtype == PARAMS
    for name in PARAMS_SECTIONS:
        section = getattr(cfg, name)
        for field, value in numeric_values(section).items():
            assert rec[field] == value, f"{name}.{field}"
        assert_marked_keys(section, rec)
    assert rec["flow"] is np.False_
    assert rec["external_torque"] == 1e-6
    assert rec["external_force_x"] == rec["external_force_y"] == 0.0
    geo, proto = cfg.geometry, cfg.protocol
    assert rec["dt"] == dt
    assert rec["source"] == cfg.camphor.supply / (math.pi * geo.pill_radius**2)
    assert rec["torque_sign"] == TORQUE_SIGN[cfg.rotor.torque] == 1.0
    assert rec["inv_saturation"] == 1.0 / 0.4
    assert rec["kick"] == math.sqrt(2.0 * dt) * cfg.noise.sigma / cfg.rotor.inertia
    assert rec["apothem"] == geo.radius * math.cos(math.pi / geo.n_corners)
    assert rec["pill_distance"] == geo.radius - geo.pill_radius / math.cos(
        math.pi / geo.n_corners
    ) - geo.pill_inset  # fmt: skip
    assert (rec["n_ini"], rec["n_stop"], rec["n_period"]) == (
        round(proto.t_ini / dt),
        round(proto.t_stop / dt),
        round((proto.t_stop + proto.t_release) / dt),
    )


def test_linear_law_records_no_saturation(small_config: Callable[..., RotorConfig]) -> None:
    """The linear law (``camphor.saturation`` null) is 1 / c_sat = 0 in the record."""
    cfg = small_config()
    assert make_record(Setup(cfg))[0]["inv_saturation"] == 0.0


def test_body_records_hold_every_key_of_a_body() -> None:
    """Each numeric key of a body is the field of its name in its ``BODY`` record, with
    its value; the run record holds the same fields, those of the shorthand's rotor."""
    cfg = RotorConfig.model_validate({"grid": {"domain_radius": 4.0}, "bodies": BODIES})
    records = make_body_records(Setup(cfg))[0]
    assert records.dtype == BODY
    for body, rec in zip(cfg.body_list(), records, strict=True):
        values = numeric_values(body)
        assert values
        for field, value in values.items():
            assert rec[field] == value, field
        assert_marked_keys(body, rec)
    assert set(BODY.names) - {name for name, _ in BUILT_BODY} <= set(PARAMS.names)


class DummyCamphor(CamphorConfig):
    """The camphor section with two new keys: a plain rate and a derived scalar."""

    dummy_rate: NonNegativeFloat = Field(0.0, description="a new scalar of the law")
    dummy_scale: Annotated[
        PositiveFloat | None, RecordAs("inv_dummy_scale", lambda v: 0.0 if v is None else 1 / v)
    ] = Field(None, description="a new derived scalar")


class DummyBody(BodyConfig):
    """A body with a new constant load and a new pair."""

    dummy_load: FiniteFloat = Field(0.0, description="a new per-body constant")
    dummy_pair: tuple[FiniteFloat, FiniteFloat] = Field((0.0, 0.0), description="new")


class DummyConfig(RotorConfig):
    """The schema with the new keys."""

    camphor: DummyCamphor = Field(default_factory=DummyCamphor)
    bodies: list[DummyBody] | None = None


def test_a_key_added_to_the_schema_reaches_the_records(
    small_config: Callable[..., RotorConfig],
) -> None:
    """A key added to a section or to a body is a field of the run's or the bodies'
    records with its value, with no edit of the records' module: the records are read
    off the schema."""
    base = small_config().model_dump(mode="json")
    cfg = DummyConfig.model_validate({**base, "camphor": {"dummy_rate": 0.7, "dummy_scale": 4.0}})
    rec = make_record(Setup(cfg))[0]
    assert (rec["dummy_rate"], rec["inv_dummy_scale"]) == (0.7, 0.25)
    assert set(PARAMS.names) < set(rec.dtype.names)
    assert {name for name, _ in BUILT_PARAMS} < set(rec.dtype.names)
    bodies = [{**BODIES[0], "dummy_load": 0.125, "dummy_pair": [1.5, -2.5]}, BODIES[1]]
    cfg = DummyConfig.model_validate({"grid": {"domain_radius": 4.0}, "bodies": bodies})
    records = make_body_records(Setup(cfg))[0]
    assert list(records["dummy_load"]) == [0.125, 0.0]
    assert (records["dummy_pair_x"][0], records["dummy_pair_y"][0]) == (1.5, -2.5)
    assert records["external_torque"][0] == 0.02


def test_scheme_fields(small_config: Callable[..., RotorConfig]) -> None:
    """The scheme's fields: contour torque and filtered F, G for ``consistent`` (with the
    layout of its tables), neither for ``paper``."""
    for name in ("paper", "consistent"):
        cfg = small_config({"numerics": {"scheme": name}})
        setup = Setup(cfg)
        scheme = setup.scheme
        rec = make_record(setup)[0]
        consistent = name == "consistent"
        assert rec["contour"] == rec["filtered"] == consistent
        assert rec["tan_half"] == math.tan(math.pi / cfg.geometry.n_corners)
        assert (rec["window_lo"], rec["window_hi"]) == scheme.window
        assert (rec["taps_lo"], rec["taps_hi"]) == scheme.taps
        if consistent:
            tables = scheme.tables
            assert rec["table_n"] == tables.plate_n
            assert rec["table_x0"] == tables.plate_x0
            assert rec["table_inv_step"] == 1.0 / tables.plate_step
            assert rec["profile_inv_step"] == 1.0 / tables.pill_step
            assert rec["edge_u0"] == tables.edge_u0
            assert rec["edge_inv_step"] == 1.0 / tables.edge_step
            assert rec["crease"] > 0.0
            assert rec["corner_end"] == tables.corner_end


def test_kick_follows_the_solver_step(small_config: Callable[..., RotorConfig]) -> None:
    """The noise factor and the schedule's step counts use the step the kernels take."""
    cfg = small_config({"noise": {"sigma": 1e-7}})
    dt = cfg.grid.dt / 2
    rec = make_record(Setup(cfg).at(dt))[0]
    assert rec["dt"] == dt
    assert rec["kick"] == cfg.kick_scale(dt) == math.sqrt(2.0 * dt) * 1e-7 / cfg.rotor.inertia
    assert rec["n_ini"] == round(cfg.protocol.t_ini / dt)
    assert np.isfinite(rec["kick"])
