"""The dish measures on synthetic positions and velocities with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from pde_rotor.collective import dish


def uniform_in_disk(rng: np.random.Generator, shape: tuple[int, ...], radius: float):
    r = radius * np.sqrt(rng.uniform(size=shape))
    a = rng.uniform(0, 2 * math.pi, size=shape)
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=-1)


@pytest.mark.parametrize("radius", [0.7, 3.0])
def test_pair_density_is_normalised_with_the_known_mean(radius: float) -> None:
    """p(r) integrates to 1 and its mean is 128 R / (45 pi), that of two uniform points."""
    total = integrate.quad(dish.disk_pair_density, 0, 2 * radius, args=(radius,))[0]
    mean = integrate.quad(lambda r: r * dish.disk_pair_density(r, radius), 0, 2 * radius)[0]
    assert total == pytest.approx(1.0, rel=1e-10)
    assert mean == pytest.approx(128 * radius / (45 * math.pi), rel=1e-10)
    edges = np.linspace(0, 2 * radius, 9)
    assert dish.bin_probabilities(edges, radius).sum() == pytest.approx(1.0, rel=1e-10)


def test_uncorrelated_centres_give_g_one_at_every_distance() -> None:
    """Uniform centres in the disk: g = 1 within the counting noise, out to r = 2 R (no
    1/r^2 fall at large r: the finite-size normalisation)."""
    rng = np.random.default_rng(7)
    radius = 4.0
    positions = uniform_in_disk(rng, (400, 30), radius)
    edges = np.linspace(0, 1.6 * radius, 9)
    g = dish.pair_correlation(positions, radius, edges)
    expected = 400 * 435 * dish.bin_probabilities(edges, radius)
    np.testing.assert_allclose(g, 1.0, atol=5 / np.sqrt(expected.min()))


def test_a_lattice_has_its_peak_and_no_pairs_closer() -> None:
    """Bodies on a square lattice of spacing a: g = 0 below a, the peak at a."""
    a = 1.0
    grid = np.array([(i, j) for i in range(-2, 3) for j in range(-2, 3)], float) * a
    edges = np.linspace(0.05, 1.55, 16)
    g = dish.pair_correlation(grid[None], 3.0, edges)
    below = edges[1:] <= 0.95 * a
    assert (g[below] == 0).all()
    assert np.argmax(g) == np.searchsorted(edges, a) - 1


def test_records_with_nan_are_left_out() -> None:
    rng = np.random.default_rng(3)
    positions = uniform_in_disk(rng, (3, 5), 2.0)
    edges = np.linspace(0, 4, 5)
    spoilt = np.concatenate([positions, np.full((1, 5, 2), np.nan)])
    np.testing.assert_array_equal(
        dish.pair_correlation(spoilt, 2.0, edges), dish.pair_correlation(positions, 2.0, edges)
    )


def test_speed_and_order_of_a_flock_and_a_mill() -> None:
    rng = np.random.default_rng(5)
    positions = uniform_in_disk(rng, (1, 40), 3.0)
    flock = np.tile([0.3, -0.4], (1, 40, 1))
    np.testing.assert_allclose(dish.mean_speed(flock), 0.5)
    np.testing.assert_allclose(dish.polar_order(flock), 1.0)
    mill = 2.0 * np.stack([-positions[..., 1], positions[..., 0]], axis=-1)  # omega = 2
    np.testing.assert_allclose(dish.rotational_order(positions, mill), 1.0)
    np.testing.assert_allclose(dish.rotational_order(positions, -mill), -1.0)
    r = np.hypot(positions[..., 0], positions[..., 1])
    np.testing.assert_allclose(dish.mean_speed(mill), 2.0 * r.mean(axis=-1))
    ring = np.array(
        [[[math.cos(a), math.sin(a)] for a in np.linspace(0, 2 * math.pi, 8, endpoint=False)]]
    )
    circling = np.stack([-ring[..., 1], ring[..., 0]], axis=-1)
    assert dish.polar_order(circling)[0] == pytest.approx(0.0, abs=1e-12)
    assert dish.polar_order(np.zeros((1, 4, 2)))[0] == 0.0
