"""The straight channel's exact 2D steady state against the 1D ring theory it reduces to."""

from __future__ import annotations

import math

import pytest

from pde_rotor.theory.ring import RingBoats, drive_force, travelling_speed
from pde_rotor.theory.ring_channel import ChannelBoats, channel_force, channel_speed

L = 6 * math.pi


def boats(width: float, plate: float, count: int = 1, rho: float = 0.05) -> ChannelBoats:
    """Boats 0.3 long with the pill touching the rear edge (sigma = -0.15 + rho)."""
    return ChannelBoats(L, count, width, 0.3, plate, rho, -0.15 + rho, 0.1)


@pytest.mark.parametrize("count", [1, 4])
def test_a_boat_spanning_the_channel_feels_the_width_average_at_any_width(count):
    """b = w leaves only the m = 0 mode: the force does not depend on w."""
    narrow = channel_force(boats(0.1, 0.1, count), 1.3)
    wide = channel_force(boats(1.9, 1.9, count), 1.3)
    assert wide == pytest.approx(narrow, rel=1e-12)


@pytest.mark.parametrize("speed", [0.4, 1.8])
def test_a_point_source_spanning_the_channel_is_the_1d_theory(speed):
    """b = w, the pill centred on the rear end: the 1D drive k s0 [G(rear) - G(front)] as
    rho -> 0. The disk smears the source over the kink of G at the rear end, an error of
    first order in rho (1.2 to 1.4 % at rho = 0.01), which Richardson's step removes."""
    one_d = drive_force(RingBoats(L, 0.3, 1, 0.1, source="rear"), speed)
    big, small = (
        channel_force(ChannelBoats(L, 1, 0.2, 0.3, 0.2, rho, -0.15, 0.1), speed)
        for rho in (0.02, 0.01)
    )
    assert small == pytest.approx(one_d, rel=0.02)
    assert 2 * small - big == pytest.approx(one_d, rel=2e-5)


def test_a_narrow_boat_is_pulled_harder_and_the_excess_vanishes_as_it_spans_the_channel():
    """b < w: the pill's peak across the channel adds to the rear edge's pull, less as w -> b."""
    forces = [channel_force(boats(w, 0.1), 1.5) for w in (1.9, 0.5, 0.2, 0.1)]
    assert forces == sorted(forces, reverse=True)
    assert forces[0] > 2 * forces[-1]


def test_the_speed_balances_the_friction():
    channel = boats(0.1, 0.1)
    v = channel_speed(channel, 0.1, 10.0)
    assert channel_force(channel, v) == pytest.approx(channel.friction * v, rel=1e-8)
    point = RingBoats(L, 0.3, 1, 0.1, source="rear")
    assert v < travelling_speed(point)  # the source 0.05 ahead of the rear end pulls less


def test_a_plate_wider_than_the_channel_is_refused():
    with pytest.raises(ValueError, match="boat_width"):
        boats(0.1, 0.2)
