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


@pytest.mark.parametrize("case", list(BAD), ids=list(BAD))
def test_bad_vessel_is_one_line_naming_its_key(case: str) -> None:
    data, start, named = BAD[case]
    with pytest.raises(ConfigError) as info:
        validate_config(data)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(start), message
    assert named in message, message
