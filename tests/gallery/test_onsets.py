"""The fits of the kicked bodies (pde_rotor.gallery.onsets): the disk's orbit about the dish
centre (hopf_rate) and a rate fitted after the next mode of the spectrum has decayed
(gap_window, fitted_rate)."""

from __future__ import annotations

import numpy as np
import pytest

from pde_rotor.gallery.onsets import (
    disk_in_dish_config,
    dragged_orbit,
    fitted_rate,
    gap_window,
    hopf_rate,
)


@pytest.mark.parametrize("lam", [0.05 + 0.3j, -0.2 + 0.8j])
@pytest.mark.parametrize("ratio", [0.0, 0.4, 1.0])
def test_hopf_rate_recovers_the_pair_from_any_mixture(lam: complex, ratio: float) -> None:
    """X + iY = A e^{lambda t} + B e^{conj(lambda) t}: a rotation (B = 0), an ellipse, or
    motion along a line (|B| = |A|) all give back lambda."""
    t = np.linspace(4.0, 24.0, 61)
    z = 1e-3 * np.exp(lam * t) + ratio * 1e-3 * np.exp(0.7j) * np.exp(np.conj(lam) * t)
    fitted = hopf_rate(t, np.stack([z.real, z.imag], axis=1))
    assert fitted == pytest.approx(lam, abs=1e-9)


def test_hopf_rate_of_two_real_rates_is_the_larger() -> None:
    t = np.linspace(0.0, 5.0, 41)
    x = np.exp(0.3 * t) + 0.5 * np.exp(-0.4 * t)
    fitted = hopf_rate(t, np.stack([x, 0.2 * x], axis=1))
    assert fitted == pytest.approx(0.3, abs=1e-9)


def test_dragged_orbit_gives_the_wake_of_its_ellipse() -> None:
    """Dragged along a line through the centre (b = 0), the disk keeps to it after the
    release (the grid's mirror symmetry y -> -y: no angular momentum); dragged along a
    circle (b = a), it leaves turning the same way about the centre."""
    dt = 4e-4
    config = disk_in_dish_config(0.05, dt, 1.75, 1e-4, 0.16, 3.7, 0.5)
    times = np.array([0.5, 1.0])
    line = dragged_orbit(config, 0.5, (0.1, 0.0, 1.0), 2.0, times)
    circle = dragged_orbit(config, 0.5, (0.1, 0.1, 1.0), 2.0, times)
    assert np.all(np.isfinite(line)) and np.all(np.isfinite(circle))
    assert np.all(np.hypot(line[:, 0], line[:, 1]) > 1e-3)  # it moves
    np.testing.assert_allclose(line[:, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(line[:, 3], 0.0, atol=1e-12)
    momentum = circle[:, 0] * circle[:, 3] - circle[:, 1] * circle[:, 2]
    assert np.all(momentum > 0.0)


@pytest.mark.parametrize("lead", [0.4, 0.01, -0.02, -0.5])
def test_gap_window_fit_recovers_the_leading_rate_of_a_mixture(lead: float) -> None:
    """A e^{lambda_1 t} + B e^{lambda_2 t} with B = 5 A (the faster mode kicked harder):
    the window that starts when the second has fallen 1e4 behind gives lambda_1 within the
    stated bound gap B / (A decay); the fixed window [0.5, 1.5] does not, near the onset."""
    second = -1.3
    eigenvalues = np.array([lead, lead, second, second - 0.8], dtype=complex)  # a pair first
    start, end = gap_window(eigenvalues, decay=1e4, span=2.0)
    assert start == pytest.approx(np.log(1e4) / (lead - second))
    assert end == pytest.approx(start + 2.0)
    times = np.arange(0.0, end + 1e-9, 0.05)
    values = 1e-4 * (np.exp(lead * times) + 5.0 * np.exp(second * times))
    rate, error = fitted_rate(times, values, (start, end))
    assert abs(rate - lead) < (lead - second) * 5.0 / 1e4
    assert error < 1e-3
    early, _ = fitted_rate(times, values, (0.5, 1.5))
    if abs(lead) < 0.1:
        assert abs(early - lead) > 0.5


def test_gap_window_needs_a_mode_below_the_leading_one() -> None:
    with pytest.raises(ValueError, match="no eigenvalue below the 1 leading"):
        gap_window(np.array([0.1 + 0.2j, 0.1 - 0.2j]))


def test_gap_window_of_two_slow_modes_lets_a_two_mode_fit_find_both() -> None:
    """A disk free to drift: a slow pair lambda_+ > 0 > lambda_- (the position's coupling)
    and a fast field mode; after the fast one has fallen 1e6 behind the slower of the pair,
    the two-mode fit of position and velocity gives lambda_+."""
    plus, minus, fast = 0.1287, -0.0176, -1.357
    eigenvalues = np.array([plus, plus, minus, minus, fast], dtype=complex)
    start, end = gap_window(eigenvalues, decay=1e6, span=2.0, modes=2)
    assert start == pytest.approx(np.log(1e6) / (minus - fast))
    t = np.arange(start, end + 1e-9, 0.05)
    x = np.exp(plus * t) - np.exp(minus * t) + 3.0 * np.exp(fast * t)
    u = plus * np.exp(plus * t) - minus * np.exp(minus * t) + 3.0 * fast * np.exp(fast * t)
    assert hopf_rate(t, np.stack([x, u], axis=1)).real == pytest.approx(plus, rel=1e-3)
