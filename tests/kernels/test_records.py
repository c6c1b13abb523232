"""The kernels' parameter record against the configuration it is built from.

:func:`pde_rotor.kernels.records.make_record` is the one place that packs the
configuration for the compiled kernels. Every physical parameter of the schema must reach
the record with its value, directly (:data:`CONFIG_FIELDS`) or through the derived field
the kernels use instead; a parameter the kernels do not read is named here with the
reason.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.kernels.records import CONFIG_FIELDS, PARAMS, make_record
from pde_rotor.model.pde import TORQUE_SIGN
from pde_rotor.model.setup import Setup

PHYSICAL_SECTIONS = ("geometry", "camphor", "flow", "rotor", "noise", "protocol", "grid")
"""The schema sections that hold the model's parameters (numerics: :func:`test_scheme_fields`)."""

DERIVED: dict[str, str] = {
    "camphor.supply": "source = s0 / (pi rho^2)",
    "rotor.torque": "torque_sign",
    "camphor.saturation": "inv_saturation = 1 / c_sat (0: linear)",
    "noise.sigma": "kick = sqrt(2 dt) sigma / I",
    "geometry.radius": "apothem = R cos(pi/N)",
    "geometry.pill_inset": "pill_distance, Eq. (rc)",
    "protocol.t_ini": "n_ini",
    "protocol.t_stop": "n_stop",
    "protocol.t_release": "n_period",
    "grid.dt": "dt",
}
"""Config keys the kernels read through a derived field (key -> the field)."""

NOT_IN_KERNELS: dict[str, str] = {
    "geometry.phi0": "initial condition, the rotor array",
    "geometry.omega0": "initial condition, the rotor array",
    "geometry.torque": "the geometry section's copy; the kernels use rotor.torque",
    "rotor.phi0": "initial condition, the rotor array",
    "rotor.omega0": "initial condition, the rotor array",
    "noise.seed": "seeds the host's Generator of the normals",
    "grid.domain_radius": "the domain's loop ranges",
    "grid.domain_centre": "the domain's frame (the kernels loop over coords about it)",
    "grid.wall": "the domain's cut cells, passed to the bodies' step as arrays",
    "grid.vessel": "the vessel's cut cells and wet spans, passed to the bodies' step as arrays",
}
"""Config keys of the physical sections that are not kernel parameters (key -> why)."""

VARIED: dict[str, Any] = {
    "geometry": {"n_corners": 5, "asymmetry": 0.03, "smoothing": 0.03, "pill_radius": 0.09},
    "camphor": {
        "diffusion": 0.9,
        "evaporation": 1.1,
        "supply": 1.3,
        "tension_slope": 0.7,
        "saturation": 0.4,
    },
    "flow": {"drag": 1.2, "bulk_drag": 0.8, "viscosity": 0.6},
    "rotor": {"inertia": 2e-5, "friction": 3e-4, "torque": "printed", "external_torque": 1e-6},
    "noise": {"sigma": 1e-7},
    "protocol": {"t_ini": 0.4, "t_stop": 0.2, "t_release": 0.6, "cycles": 3},
}
"""A configuration whose parameters differ from each other and from the defaults."""


def physical_keys(config: RotorConfig) -> list[str]:
    """The dotted keys of every parameter in the physical sections."""
    return [
        f"{section}.{name}"
        for section in PHYSICAL_SECTIONS
        for name in type(getattr(config, section)).model_fields
    ]


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_record_holds_every_parameter_of_the_schema(
    small_config: Callable[..., RotorConfig], scheme: str
) -> None:
    """Each config field of the record equals the config's value; every physical key is
    in the record, derived (with the value the kernels need) or named as not used."""
    cfg = small_config({**VARIED, "numerics": {"scheme": scheme}})
    dt = cfg.grid.dt
    rec = make_record(Setup(cfg))[0]
    assert rec.dtype == PARAMS
    for name, key in CONFIG_FIELDS.items():
        assert rec[name] == cfg.get(key), name
    covered = set(CONFIG_FIELDS.values()) | set(DERIVED) | set(NOT_IN_KERNELS)
    assert set(physical_keys(cfg)) <= covered
    assert not set(DERIVED) & set(CONFIG_FIELDS.values())
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
