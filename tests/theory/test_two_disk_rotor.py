"""pde_rotor.theory.two_disk_rotor: the onset of the two-disk rotor against the balance
of supply and sublimation, the free disk's limit and the friction moment in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.theory import two_disk_rotor
from pde_rotor.theory.free_disk import free_disk_critical_friction, free_disk_force_coefficient
from pde_rotor.theory.two_disk_rotor import (
    rotor_critical_friction,
    rotor_critical_half_length,
    rotor_friction_moment,
    rotor_grid,
    rotor_growth_rate,
    rotor_torque_coefficient,
)


def test_rotor_rest_field_balances_supply_and_sublimation(disk):
    """Integrating Eq. (eqc) at rest: int a (1 - F) c0 dA = S int G dA."""
    grid = rotor_grid(disk, 0.5, 0.01, 0.005)
    rest = two_disk_rotor._rest_field(disk, grid)
    weights = 4 * np.outer(two_disk_rotor._trapezoid(grid.x), two_disk_rotor._trapezoid(grid.y))
    lost = np.sum(weights * disk.evaporation * (1 - grid.indicator) * rest)
    supplied = np.sum(weights * disk.source * grid.indicator)
    assert lost == pytest.approx(supplied, rel=1e-3)


def test_far_apart_rotor_is_two_free_disks(disk):
    """For l >> sqrt(D/a) each disk moves like a free disk at speed omega l:
    K_rot -> 2 l^2 K(0) (here with the smoothed disks' extra area pi^2 delta^2 / 12)."""
    half_length, delta = 4.0, disk.radius / 10
    torque = rotor_torque_coefficient(disk, half_length, smoothing=delta)
    area_factor = 1 + math.pi**2 * delta**2 / (12 * disk.radius**2)
    free = 2 * half_length**2 * free_disk_force_coefficient(disk) * area_factor
    assert torque == pytest.approx(free, rel=1.5e-3)


def test_rotor_critical_friction_rises_to_the_free_disks(disk):
    """mu_c(l) grows with l toward the free disk's (the rotor has a critical size at
    frictions between its contact value and the free disk's)."""
    delta = disk.radius / 10
    values = [rotor_critical_friction(disk, length, delta) for length in (0.2, 0.5, 2.0)]
    assert values[0] < values[1] < values[2] < free_disk_critical_friction(disk)
    assert values[2] == pytest.approx(free_disk_critical_friction(disk), rel=1e-2)


def test_rotor_friction_moment_is_the_smoothed_one_in_the_limit(disk):
    moment = two_disk_rotor._grid_friction_moment(disk, 0.5, disk.radius / 40)
    assert moment == pytest.approx(rotor_friction_moment(disk, 0.5), rel=2e-3)


def test_paper_friction_has_no_critical_rotor_size(disk):
    """At the paper's mu = 1e-4 every two-disk rotor turns: mu_c at contact is far above."""
    with pytest.raises(ValueError, match="no critical size"):
        rotor_critical_half_length(disk, RotorConfig().rotor.friction, smoothing=0.02)


def test_rotor_growth_rate_vanishes_at_the_critical_friction(disk):
    """I lambda = K_rot(lambda) - mu J has its root at 0 exactly at mu_c(l), and grows
    below it (at the simulation's delta, where the grid is cheap)."""
    delta, length = RotorConfig().geometry.smoothing, 0.5
    mu_c = rotor_critical_friction(disk, length, delta)
    inertia = RotorConfig().rotor.inertia
    assert abs(rotor_growth_rate(disk, length, mu_c, inertia, delta)) < 1e-6
    assert rotor_growth_rate(disk, length, 0.9 * mu_c, inertia, delta) > 0
