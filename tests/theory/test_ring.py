"""The 1D ring theory against sums over images, the infinite line, its own identities and a
direct solve of the moving-source equations."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

from pde_rotor.theory.ring import (
    RingBoats,
    bloch_green,
    drive_force,
    rest_critical_friction,
    rest_hopf_friction,
    rest_pitchfork_friction,
    spacing_dispersion,
    spacing_rates,
    spacing_roots,
    travelling_speed,
    travelling_speeds,
    winding_number,
)
from pde_rotor.theory.ring_solve import RingSolver, fitted_rate, mode_amplitudes

L = 6 * math.pi


def line_green(y: float, speed: float, rate: complex) -> complex:
    root = cmath.sqrt(speed * speed + 4 * rate)
    s_plus, s_minus = (-speed + root) / 2, (-speed - root) / 2
    return (cmath.exp(s_minus * y) if y >= 0 else cmath.exp(s_plus * y)) / root


@pytest.mark.parametrize("phase", [1.0, cmath.exp(2j * math.pi / 3), -1.0])
@pytest.mark.parametrize("y", [0.0, 0.3, 1.7, -0.4, 5.1])
def test_bloch_green_is_the_sum_over_images(phase, y):
    d, v, r = 2.0, 1.3, 1 + 0.2j
    images = sum(phase**p * line_green(y - p * d, v, r) for p in range(-300, 300))
    assert bloch_green(y, d, v, r, phase) == pytest.approx(images, rel=1e-12)
    h = 1e-6
    right = (bloch_green(y + 2 * h, d, v, r, phase) - bloch_green(y + h, d, v, r, phase)) / h
    left = (bloch_green(y - h, d, v, r, phase) - bloch_green(y - 2 * h, d, v, r, phase)) / h
    slope = bloch_green(y, d, v, r, phase, derivative=True)
    expected = 0.5 * (right + left) if y == 0.0 else right
    assert slope == pytest.approx(expected, rel=1e-5, abs=1e-6)


def test_the_slope_jumps_by_one_over_d_at_a_source():
    d, v, r = 3.0, 0.8, 1.0
    up = bloch_green(1e-12, d, v, r, derivative=True)
    down = bloch_green(d - 1e-12, d, v, r, derivative=True)
    assert (up - down).real == pytest.approx(-1.0, rel=1e-9)


def test_a_lone_boat_on_a_long_ring_has_the_line_speed():
    """d >> sqrt(D/a): F(V) = k s0 (1 - e^{s- l}) / sqrt(V^2 + 4aD), the line's result."""
    boats = RingBoats(200.0, 0.3, 1, 0.1)
    v = travelling_speed(boats)
    root = math.sqrt(v * v + 4)
    assert 0.1 * v == pytest.approx((1 - math.exp(-0.5 * (v + root) * 0.3)) / root, rel=1e-12)


def test_n_boats_move_as_one_boat_on_a_ring_of_length_l_over_n():
    many = RingBoats(L, 0.3, 6, 0.1)
    one = RingBoats(L / 6, 0.3, 1, 0.1)
    assert travelling_speed(many) == pytest.approx(travelling_speed(one), rel=1e-12)


def test_symmetric_boats_only_rest_above_the_pitchfork():
    boats = RingBoats(L, 0.3, 2, 0.1, source="centre")
    mu = rest_pitchfork_friction(boats)
    assert drive_force(boats, 0.0) == pytest.approx(0.0, abs=1e-15)
    slower = RingBoats(L, 0.3, 2, 1.01 * mu, source="centre")
    faster = RingBoats(L, 0.3, 2, 0.99 * mu, source="centre")
    assert travelling_speeds(slower) == ()
    assert len(travelling_speeds(faster)) == 1


@pytest.mark.parametrize("count, mu", [(1, 0.05), (3, 0.1), (12, 0.2)])
def test_shift_and_slow_speed_change_of_the_dispersion(count, mu):
    """R_0(0) = 0 (a common shift) and R_0'(0) = F'(V) (a slow change of speed)."""
    boats = RingBoats(L, 0.3, count, mu)
    v = travelling_speed(boats)
    assert abs(spacing_dispersion(boats, v, 0, 0.0)) < 1e-15
    h = 1e-5
    response = (
        (mu * h - spacing_dispersion(boats, v, 0, h))
        - (-mu * h - spacing_dispersion(boats, v, 0, -h))
    ) / (2 * h)
    slope = (drive_force(boats, v + h) - drive_force(boats, v - h)) / (2 * h)
    assert response.real == pytest.approx(slope, rel=1e-6, abs=1e-9)


@pytest.mark.parametrize("count, mu", [(3, 0.1), (6, 0.05), (12, 0.2)])
def test_newton_finds_every_root_the_winding_number_counts(count, mu):
    boats = RingBoats(L, 0.3, count, mu)
    v = travelling_speed(boats)
    for m in range(count):
        top = v * 2 * math.pi * (m + count) / L + 3.0
        found = spacing_roots(boats, v, m)
        assert len(found) == winding_number(boats, v, m, (-0.98, 3.0, top))
        for z in found:
            assert abs(spacing_dispersion(boats, v, m, z)) < 1e-9


def test_modes_m_and_n_minus_m_are_conjugate():
    boats = RingBoats(L, 0.3, 6, 0.1)
    rates = spacing_rates(boats)
    for m in range(1, 6):
        assert rates[m] == pytest.approx(rates[6 - m].conjugate(), rel=1e-9)


@pytest.mark.parametrize("count", [1, 4])
def test_the_rest_state_loses_stability_at_the_critical_friction(count):
    """No root in the right half-plane just above mu_c, one (or a pair) just below."""
    boats = RingBoats(L, 0.3, count, 1.0, source="centre")
    mu_c = rest_critical_friction(boats)
    for factor, unstable in ((1.01, False), (0.99, True)):
        b = RingBoats(L, 0.3, count, factor * mu_c, source="centre")
        counts = [winding_number(b, 0.0, m, (1e-6, 8.0, 8.0)) for m in range(count)]
        assert (sum(counts) > 0) is unstable, (factor, counts)


def test_a_hopf_crossing_is_a_root_on_the_imaginary_axis():
    boats = RingBoats(L, 0.3, 6, 1.0, source="centre")
    mu, omega = rest_hopf_friction(boats, 3)
    at = RingBoats(L, 0.3, 6, mu, source="centre")
    assert abs(spacing_dispersion(at, 0.0, 3, 1j * omega)) < 1e-10


def test_the_direct_solve_reaches_the_travelling_speed():
    boats = RingBoats(L, 0.3, 3, 0.1)
    solver = RingSolver(boats, 256, boats.spacing * np.arange(3))
    run = solver.run(25.0, 0.05, every=50)
    assert run.velocities[-1] == pytest.approx(np.full(3, travelling_speed(boats)), rel=1e-4)


def test_the_direct_solve_decays_a_spacing_mode_at_the_theory_rate():
    boats = RingBoats(L, 0.3, 3, 0.1)
    solver = RingSolver(boats, 256, boats.spacing * np.arange(3))
    solver.run(20.0, 0.04, every=100)
    solver.positions = solver.positions + 1e-4 * np.array([0.3, -1.0, 0.7])
    run = solver.run(40.0, 0.04, every=10)
    late = run.times > run.times[0] + 10
    measured = fitted_rate(run.times[late], mode_amplitudes(run, boats.spacing)[late, 1])
    theory = spacing_rates(boats)[1]
    assert measured.real == pytest.approx(theory.real, rel=0.02)
    assert measured.imag == pytest.approx(theory.imag, rel=0.03)


def test_symmetric_boats_below_the_pitchfork_start_to_move_at_the_theory_rate():
    boats = RingBoats(L, 0.3, 1, 1.0, source="centre")
    mu = 0.8 * rest_pitchfork_friction(boats)
    b = RingBoats(L, 0.3, 1, mu, source="centre")
    theory = spacing_roots(b, 0.0, 0)[0]
    solver = RingSolver(b, 256, np.zeros(1))
    solver.run(12.0, 0.02, every=1000)
    solver.positions = solver.positions + 1e-6
    run = solver.run(8.0, 0.02, every=5)
    late = run.times > run.times[0] + 3
    rate = np.polyfit(run.times[late], np.log(np.abs(run.velocities[late, 0])), 1)[0]
    assert theory.imag == pytest.approx(0.0, abs=1e-9)
    assert rate == pytest.approx(theory.real, rel=0.02)


def test_bad_boats_are_refused_with_the_key():
    with pytest.raises(ValueError, match="boat_length"):
        RingBoats(L, 5.0, 4, 0.1)
    with pytest.raises(ValueError, match="source"):
        RingBoats(L, 0.3, 4, 0.1, source="front")  # type: ignore[arg-type]
