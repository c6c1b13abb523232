"""The ring measures on synthetic trajectories with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor.collective import ring


def evenly(n: int, t: np.ndarray, omega: float = 0.7) -> np.ndarray:
    """(T, N) angles of N evenly spaced bodies turning together at omega."""
    return omega * t[:, None] + 2 * math.pi * np.arange(n)[None, :] / n


def test_angles_about_the_centre() -> None:
    theta = ring.ring_angles(np.array([3.0, 2.0, 1.0]), np.array([1.0, 2.0, 1.0]), (2.0, 1.0))
    np.testing.assert_allclose(theta, [0.0, math.pi / 2, math.pi])


def test_angular_velocity_of_a_rigid_rotation() -> None:
    """Bodies turning rigidly at omega about the centre, at several radii."""
    rng = np.random.default_rng(2)
    dx, dy = rng.normal(size=(2, 3, 5))
    omega = -1.3
    omegas, arc = ring.angular_velocity(dx, dy, -omega * dy, omega * dx)
    np.testing.assert_allclose(omegas, omega)
    np.testing.assert_allclose(arc, omega * np.hypot(dx, dy))


@pytest.mark.parametrize("n", [1, 2, 7, 16])
def test_evenly_spaced_bodies(n: int) -> None:
    theta = evenly(n, np.linspace(0, 5, 11))
    np.testing.assert_allclose(ring.gaps(theta), 2 * math.pi / n)
    np.testing.assert_allclose(ring.spacing_spread(theta), 0.0, atol=1e-12)
    np.testing.assert_allclose(ring.lattice_order(theta), 1.0)
    order, m = ring.cluster_order(theta)
    if n == 1:
        assert np.isnan(order).all() and np.isnan(m).all()
    else:
        np.testing.assert_allclose(order, 0.0, atol=1e-12)
    assert ring.gap_mobility(theta) == pytest.approx(0.0, abs=1e-12)


def test_gaps_belong_to_their_bodies_and_sum_to_the_ring() -> None:
    theta = np.array([[0.5, 6.0, 2.0]])  # order 0.5 -> 2.0 -> 6.0 -> 0.5
    np.testing.assert_allclose(ring.gaps(theta), [[1.5, 0.5 + 2 * math.pi - 6.0, 4.0]])
    rng = np.random.default_rng(1)
    np.testing.assert_allclose(ring.gaps(rng.uniform(0, 9, (4, 6))).sum(axis=-1), 2 * math.pi)


@pytest.mark.parametrize("m", [1, 2, 3])
def test_m_tight_clusters(m: int) -> None:
    """12 bodies in m clusters evenly placed: cluster order 1 at m, spread from the gaps."""
    per = 12 // m
    width = 1e-3
    theta = np.array([2 * math.pi * c / m + width * j for c in range(m) for j in range(per)])[
        None, :
    ]
    order, found = ring.cluster_order(theta)
    assert found[0] == m
    assert order[0] == pytest.approx(1.0, abs=1e-4)
    gaps = np.array([width] * (per - 1) + [2 * math.pi / m - (per - 1) * width])
    gaps = np.tile(gaps, m)
    assert ring.spacing_spread(theta)[0] == pytest.approx(gaps.std() / gaps.mean())


def test_density_wave_and_static_clusters_by_the_gap_mobility() -> None:
    """Gaps g (1 + A cos(2 pi m k / N - W t)): spread and mobility both A / sqrt(2); the
    same gaps frozen in time: mobility 0."""
    n, a, m = 12, 0.4, 2
    t = np.linspace(0, 2 * math.pi, 400, endpoint=False)
    k = np.arange(n)
    g = 2 * math.pi / n * (1 + a * np.cos(2 * math.pi * m * k[None, :] / n - t[:, None]))
    theta = np.concatenate([np.zeros((len(t), 1)), np.cumsum(g, axis=1)[:, :-1]], axis=1)
    spread = ring.spacing_spread(theta)
    np.testing.assert_allclose(spread, a / math.sqrt(2), rtol=1e-9)
    assert ring.gap_mobility(theta) == pytest.approx(a / math.sqrt(2), rel=1e-9)
    assert ring.ring_mode(1.0, 1.0, spread.mean(), ring.gap_mobility(theta)) == "density wave"
    frozen = np.repeat(theta[:1], 50, axis=0)
    assert ring.gap_mobility(frozen) == pytest.approx(0.0, abs=1e-12)
    assert ring.ring_mode(1.0, -1.0, spread.mean(), 0.0) == "clusters"


def test_modes_by_their_thresholds() -> None:
    stop = ring.STOP_SPEED
    assert ring.ring_mode(0.5 * stop, 0.5 * stop, 1.0, 1.0) == "stop"
    assert ring.ring_mode(float("nan"), float("nan"), 0.0, 0.0) == "stop"
    assert ring.ring_mode(2 * stop, -2 * stop, 0.5 * ring.UNIFORM_SPREAD, 9.0) == "uniform"
    net = ring.NET_SPEED * 2 * stop
    assert ring.ring_mode(2 * stop, 1.01 * net, 0.0, 0.0) == "uniform"
    assert ring.ring_mode(2 * stop, -0.99 * net, 0.0, 0.0) == "oscillation"
    assert ring.MODES[:4] == ("uniform", "clusters", "density wave", "stop")  # stored codes
    assert set(ring.MODES) == {"uniform", "clusters", "density wave", "stop", "oscillation"}


def test_rocking_bodies_oscillate_and_sailing_ones_do_not() -> None:
    """Boats rocking about evenly spaced places, w_k = A sin(W t + pi k): they move, go
    nowhere (the mean signed speed 0, by the record times' symmetry) and keep a tiny spread:
    oscillation; the same boats with a drift V > A: uniform."""
    n, a, w = 8, 0.05, 2.0
    t = np.linspace(0.0, 2 * math.pi / w * 10, 2000, endpoint=False)
    k = np.arange(n)
    r = 4.0
    for drift, mode in ((0.0, "oscillation"), (3 * a, "uniform")):
        s = drift * t[:, None] - a / w * np.cos(w * t[:, None] + math.pi * k[None, :])
        theta = 2 * math.pi * k[None, :] / n + s / r
        speed = drift + a * np.sin(w * t[:, None] + math.pi * k[None, :])
        spread = ring.spacing_spread(theta).mean()
        found = ring.ring_mode(np.abs(speed).mean(), speed.mean(), spread, ring.gap_mobility(theta))
        assert found == mode
        assert spread < ring.UNIFORM_SPREAD
