"""pde_rotor.theory.disk: the rest state and the displacement response in closed form
against an independent radial finite-volume solve of Eq. (eqc) in the lab frame
(:mod:`tests.theory.lab_frame`), with and without a dish wall."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pde_rotor.config import ConfigError, RotorConfig
from pde_rotor.theory.disk import (
    CamphorDisk,
    Wall,
    free_disk_displacement_force,
    rest_concentration,
)
from pde_rotor.theory.free_disk import free_disk_force_coefficient

from .lab_frame import radial_lab_frame


def test_config_defaults_make_the_disk(disk):
    cfg = RotorConfig()
    assert disk.radius == cfg.geometry.pill_radius
    assert disk.supply == cfg.camphor.supply
    assert disk.source * disk.area == pytest.approx(cfg.camphor.supply)


def test_a_saturating_tension_is_refused_in_one_line():
    """The onsets are derived for the linear law gamma0 - k c; a saturating law is named."""
    cfg = RotorConfig.model_validate({"camphor": {"saturation": 2.0}})
    with pytest.raises(ConfigError, match=r"^camphor.saturation = 2: .*linear law") as err:
        CamphorDisk.from_config(cfg)
    assert "\n" not in str(err.value)


def test_rest_state_is_the_radial_solve_with_a_sharp_disk(disk):
    """c0 in closed form against finite volumes with F a step (rho on a face), on a dish
    of radius 12 (far enough that its wall changes c0 near the disk by < 1e-10)."""
    wall = Wall(12.0, "absorbing")
    r, rest, _ = radial_lab_frame(disk, 0.0, disk.radius / 100, 0.0, wall)
    near = r < 3.0
    exact = rest_concentration(disk, r[near])
    assert np.max(np.abs(rest[near] - exact)) < 1e-5 * exact.max()
    assert np.allclose(rest_concentration(disk, r[near], wall), exact, atol=1e-9)


@pytest.mark.parametrize("condition", ["absorbing", "no_flux"])
def test_rest_state_in_a_dish_meets_its_wall(disk, condition):
    wall = Wall(1.5, condition)
    r, rest, _ = radial_lab_frame(disk, 0.0, disk.radius / 100, 0.0, wall)
    exact = rest_concentration(disk, r, wall)
    assert np.max(np.abs(rest - exact)) < 1e-5 * exact.max()
    edge = rest_concentration(disk, np.array([wall.radius - 1e-6, wall.radius]), wall)
    if condition == "absorbing":
        assert edge[1] == pytest.approx(0.0, abs=1e-14)
    else:
        assert abs(edge[1] - edge[0]) < 1e-12


def test_rest_state_carries_the_whole_supply_through_the_rim(disk):
    """-2 pi rho D dc0/dr(rho) = s0 from either side of the rim: everything the disk
    supplies leaves through its rim (one-sided second-order differences)."""
    h = 1e-4 * disk.radius
    for side in (-1, 1):
        c = rest_concentration(disk, disk.radius + side * h * np.arange(3))
        slope = side * (-3 * c[0] + 4 * c[1] - c[2]) / (2 * h)
        flux = -2 * math.pi * disk.radius * disk.diffusion * slope
        assert flux == pytest.approx(disk.supply, rel=1e-6)


@pytest.mark.parametrize("condition", ["absorbing", "no_flux"])
@pytest.mark.parametrize("lam", [0.0, 0.3, 0.4j])
def test_dish_force_is_the_lab_frame_radial_solve(disk, condition, lam):
    """Phi(lambda) from Bessel functions with the wall against the lab-frame finite volumes
    (smoothed F = G, delta = rho / 40, 32 cells per delta): agreement to 1e-3 K(0)."""
    wall = Wall(1.5, condition)
    delta = disk.radius / 40
    _, _, numeric = radial_lab_frame(disk, delta, delta / 32, lam, wall)
    exact = free_disk_displacement_force(disk, lam, wall)
    assert abs(numeric - exact) < 1e-3 * free_disk_force_coefficient(disk)


def test_bad_inputs_are_refused_in_one_line():
    cfg = RotorConfig()
    with pytest.raises(ValueError, match="evaporation must be > 0"):
        dataclasses.replace(CamphorDisk.from_config(cfg), evaporation=0.0)
    with pytest.raises(ValueError, match="no_flux"):
        Wall(3.0, "reflecting")
