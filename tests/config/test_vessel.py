"""grid.vessel: left out it is the dish of before (dump and hash unchanged); set, it is part
of the run's hash, and each bad vessel is refused in one line naming its key."""

from __future__ import annotations

import pytest
import yaml

from pde_rotor.config import ConfigError, RotorConfig, dump_config, validate_config

PILL = {"pills": [{}]}
"""A body of one paper-size pill at its origin."""

RING = {"shape": "annulus", "inner_radius": 1.5, "outer_radius": 3.0}
TANK = {"shape": "rectangle", "half_widths": [3.0, 2.0]}


def test_a_vessel_left_out_is_not_dumped_and_a_set_one_enters_the_hash() -> None:
    """The default dumps no vessel key (so every config and hash of before stays as it
    was); an annulus and a tank are runs of their own, told apart by every key."""
    plain = validate_config({"bodies": [PILL]})
    assert "vessel" not in yaml.safe_load(dump_config(plain))["grid"]
    assert "vessel" not in yaml.safe_load(dump_config(RotorConfig()))["grid"]
    at = {"bodies": [{**PILL, "start": {"x": 2.2}}]}
    ring = validate_config({"grid": {"vessel": RING}, **at})
    leaky = validate_config({"grid": {"vessel": {**RING, "inner_wall": "absorbing"}}, **at})
    tank = validate_config({"grid": {"vessel": TANK}, **at})
    moved = validate_config(at)
    hashes = {c.config_hash() for c in (ring, leaky, tank, moved)}
    assert len(hashes) == 4
    assert ring.grid.vessel.inner_wall == "no_flux"  # a default: left out of the dump
    assert "inner_wall" not in ring.physics()["grid"]["vessel"]
    assert leaky.physics()["grid"]["vessel"]["inner_wall"] == "absorbing"
    assert validate_config(yaml.safe_load(dump_config(tank))) == tank


BAD = {
    "without bodies": ({"grid": {"vessel": RING}}, "grid.vessel = 'annulus'", "bodies: list"),
    "with a dish wall": (
        {"grid": {"vessel": RING, "wall": "no_flux"}, "bodies": [{**PILL, "start": {"x": 2.2}}]},
        "grid.wall = 'no_flux'",
        "leave it out",
    ),
    "outside the grid": (
        {"grid": {"vessel": {**TANK, "half_widths": [3.5, 2.0]}}, "bodies": [PILL]},
        "grid.domain_radius = 3",
        "domain_radius >= 3.5",
    ),
    "rings the wrong way": (
        {"grid": {"vessel": {**RING, "inner_radius": 3.0}}, "bodies": [PILL]},
        "grid.vessel.annulus.inner_radius = 3",
        "R1 < R2",
    ),
    "too narrow": (
        {"grid": {"vessel": {**RING, "inner_radius": 2.95}}, "bodies": [PILL]},
        "grid.vessel = 'annulus'",
        "width >= 0.1",
    ),
    "a body over the hole": (
        {"grid": {"vessel": RING}, "bodies": [PILL]},
        "bodies[0].start = [0.0, 0.0]",
        "inside every wall",
    ),
    "an unknown shape": (
        {"grid": {"vessel": {"shape": "hexagon"}}, "bodies": [PILL]},
        "grid.vessel",
        "annulus",
    ),
}


SPAN_RING = {"shape": "annulus", "inner_radius": 2.0, "outer_radius": 4.0}
"""A ring channel 2 wide about r = 3, on the default grid (dx = 0.025, delta = 0.025)."""


def spanning_boat(**changes: object) -> dict:
    """A strip 3 wide across the channel SPAN_RING on the track r = 3, a pill at its rear."""
    boat = {
        "plate": {"shape": "strip", "length": 0.3, "width": 3.0},
        "pills": [{"x": -0.1, "radius": 0.05}],
        "motion": {"kind": "track", "mass": 1.0, "spans": True},
        "start": {"x": 3.0},
    }
    return {**boat, **changes}


def spanning(vessel: dict | None = None, **sections: object) -> dict:
    """The config of :func:`spanning_boat` in `vessel` (SPAN_RING) with `sections`."""
    grid = {"domain_radius": 5.2, "vessel": vessel or SPAN_RING}
    return {"grid": grid, "bodies": [spanning_boat()], "numerics": {"scheme": "paper"}, **sections}


def test_a_spanning_boat_may_cross_the_walls_that_would_refuse_another() -> None:
    """The boat's footprint (radius 2.10) reaches past both walls of its channel: allowed
    with motion.spans, refused without it (the footprint must lie inside every wall)."""
    config = validate_config(spanning())
    assert config.body_list()[0].motion.spans
    plain = spanning()
    plain["bodies"] = [spanning_boat(motion={"kind": "track", "mass": 1.0})]
    with pytest.raises(ConfigError, match="inside every wall"):
        validate_config(plain)


def test_a_spanning_boat_runs_on_either_backend_and_scheme() -> None:
    """The GPU's bodies kernel takes the wet-cell integrals as the CPU's does, and both
    take them in place of the consistent scheme's contour form: a boat that spans its
    channel is a valid config on either backend and either scheme."""
    for backend in ("cpu", "gpu"):
        for scheme in ("paper", "consistent"):
            config = validate_config(
                spanning(solver={"backend": backend}, numerics={"scheme": scheme})
            )
            assert (config.solver.backend, config.numerics.scheme) == (backend, scheme)
            assert config.body_list()[0].motion.spans


SPAN_BAD = {
    "in a tank": (
        spanning({"shape": "rectangle", "half_widths": [4.0, 4.0]}),
        "bodies[0].motion.spans = true",
        "no_flux walls",
    ),
    "through an absorbing wall": (
        spanning({**SPAN_RING, "outer_wall": "absorbing"}),
        "bodies[0].motion.spans = true",
        "no_flux walls",
    ),
    "its pill near a wall": (
        {
            "grid": {"domain_radius": 5.2, "vessel": {**SPAN_RING, "outer_radius": 3.5}},
            "bodies": [spanning_boat()],
            "numerics": {"scheme": "paper"},
        },
        "bodies[0].pills[0]",
        "falls on wet cells",
    ),
    "past the grid": (
        {**spanning(), "grid": {"domain_radius": 5.0, "vessel": SPAN_RING}},
        "grid.domain_radius = 5",
        "domain_radius >= 5.128",
    ),
    "off the annulus' centre": (
        {
            "grid": {"domain_radius": 5.2, "vessel": SPAN_RING},
            "bodies": [
                spanning_boat(
                    motion={"kind": "track", "mass": 1.0, "spans": True, "centre": [0.1, 0.0]}
                )
            ],
            "numerics": {"scheme": "paper"},
        },
        "bodies[0].motion.centre",
        "that centre",
    ),
}


@pytest.mark.parametrize("case", [*BAD, *SPAN_BAD], ids=[*BAD, *SPAN_BAD])
def test_bad_vessel_or_spanning_boat_is_one_line_naming_its_key(case: str) -> None:
    data, start, named = {**BAD, **SPAN_BAD}[case]
    with pytest.raises(ConfigError) as info:
        validate_config(data)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(start), message
    assert named in message, message
