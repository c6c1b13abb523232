"""pde_rotor.theory.dish: the Hopf onset of a disk in a no-flux dish and the drift in an
absorbing one, as roots of the characteristic equation found independently."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from pde_rotor.theory.dish import dish_drift_rate, dish_hopf_onset, dish_hopf_rate
from pde_rotor.theory.disk import Wall, free_disk_displacement_force
from pde_rotor.theory.free_disk import free_disk_critical_friction


def test_walls_push_and_pull(disk):
    """A no-flux wall holds the disk at the centre (F(0) < 0, camphor piles up at the
    wall); an absorbing one pulls it away (F(0) > 0), so the centre has no Hopf onset."""
    assert free_disk_displacement_force(disk, 0.0, Wall(2.0, "no_flux")) < 0
    assert free_disk_displacement_force(disk, 0.0, Wall(2.0, "absorbing")) > 0
    with pytest.raises(ValueError, match="does not hold"):
        dish_hopf_onset(disk, Wall(2.0, "absorbing"))
    mu_c = free_disk_critical_friction(disk)
    assert dish_drift_rate(disk, Wall(3.0, "absorbing"), 2 * mu_c) > 0
    assert math.isnan(dish_drift_rate(disk, Wall(3.0, "no_flux"), 2 * mu_c))


def test_hopf_onset_is_a_pair_of_imaginary_roots(disk):
    """At (mu_c, omega_c) lambda = i omega_c solves m lambda^2 + mu A lambda - Phi(lambda) = 0,
    and the root moves into Re lambda > 0 as mu falls below mu_c."""
    wall = Wall(2.0, "no_flux")
    mass = 1e-3
    mu_c, omega = dish_hopf_onset(disk, wall, mass)

    def chi(lam: complex, mu: float) -> complex:
        return mass * lam**2 + mu * disk.area * lam - free_disk_displacement_force(disk, lam, wall)

    assert abs(chi(1j * omega, mu_c)) < 1e-12
    for factor, sign in ((0.99, 1), (1.01, -1)):

        def parts(z, mu=factor * mu_c):
            value = chi(complex(z[0], z[1]), mu)
            return [value.real, value.imag]

        root = fsolve(parts, [0.0, omega], xtol=1e-13)
        assert abs(chi(complex(*root), factor * mu_c)) < 1e-12
        assert np.sign(root[0]) == sign


def test_hopf_rate_follows_the_pair_from_the_onset(disk):
    """dish_hopf_rate solves the characteristic equation, is i omega_c at mu_c, and its
    real part falls through 0 there (the same root fsolve finds from i omega_c)."""
    wall = Wall(3.0, "no_flux")
    mass = 1e-4
    mu_c, omega = dish_hopf_onset(disk, wall, mass)
    assert dish_hopf_rate(disk, wall, mu_c, mass) == pytest.approx(1j * omega, abs=1e-10)
    rates = [dish_hopf_rate(disk, wall, f * mu_c, mass) for f in (0.97, 0.99, 1.01, 1.03)]
    assert rates[0].real > rates[1].real > 0 > rates[2].real > rates[3].real
    for factor, lam in zip((0.97, 0.99, 1.01, 1.03), rates, strict=True):
        force = free_disk_displacement_force(disk, lam, wall)
        assert abs(mass * lam**2 + factor * mu_c * disk.area * lam - force) < 1e-12
        assert lam.imag > 0


def test_dish_onset_tends_to_the_free_disk(disk):
    """As the wall recedes the Hopf frequency falls to 0 and mu_c tends to the free disk's."""
    mu_c = free_disk_critical_friction(disk)
    far = [dish_hopf_onset(disk, Wall(radius, "no_flux")) for radius in (3.0, 5.0, 8.0)]
    assert far[0][1] > far[1][1] > far[2][1]
    assert far[2][1] < 1e-2
    assert far[2][0] == pytest.approx(mu_c, rel=1e-5)
