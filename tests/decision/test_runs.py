"""Measuring a decision table: the fits on synthetic releases, one tiny real table.

The real table (coarse grid, small domain, two angles, stops up to 1) checks the
physics the model rests on: the rest state after a stop is unstable (λ > 0) with the
same λ in both directions (mirror symmetry), the memory torque opposes the former
rotation and decays, and a free release grows with the amplitude C β/λ that the
Laplace-weighted stop torque predicts.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.decision.runs import (
    SETTLE,
    fit_response,
    measure_table,
    release_amplitude,
    table_steps,
)
from pde_rotor.sweep.spec import RestartEstimator


def test_fit_response_recovers_rate_and_amplitude() -> None:
    times = np.arange(1, 80) * 0.01
    transient = np.exp(-40 * times)
    free = 0.003 * np.exp(13.0 * times) - 0.002 * transient
    kicked = free + 0.01 * (0.8 * np.exp(13.0 * times) + 0.5 * transient)
    rate, response, samples = fit_response(times, free, kicked, 0.01)
    assert rate == pytest.approx(13.0, rel=1e-4)
    assert response == pytest.approx(0.8, rel=1e-3)
    assert samples == np.count_nonzero((times >= SETTLE) & (np.abs(kicked) < 3.0))
    assert release_amplitude(times, free, 13.0) == pytest.approx(0.003, rel=1e-3)


def test_fit_response_refuses_a_short_window() -> None:
    times = np.arange(1, 30) * 0.01
    free = np.exp(30.0 * times)  # leaves the linear range before SETTLE
    with pytest.raises(RuntimeError, match="fit window"):
        fit_response(times, free, free + 1e-3, 1e-3)
    assert np.isnan(release_amplitude(times, free, 30.0))


def test_tiny_table_physics(small_config: Callable[..., RotorConfig]) -> None:
    config = small_config({"geometry": {"asymmetry": 1e-4}})
    estimator = RestartEstimator(warmup=4.0)
    table = measure_table(
        config, n_angles=2, t_max=1.0, interval=0.004, checks=(0.5, 1.0), estimator=estimator
    )
    rates = table.attrs["growth_rate_by_direction"]
    assert np.all(rates > 0)  # no rest state (the paper's choice of mu)
    assert rates[0] == pytest.approx(rates[1], rel=0.03)  # mirror symmetry
    memory = table.memory_torque()
    window = (table.time > 0.1) & (table.time < 1.0)
    assert np.all(memory[window] > 0)  # against the former rotation: an inversion
    assert np.all(np.diff(memory[window]) < 0)
    for name in ("ccw", "cw"):
        measured = table.attrs[f"check_amplitude_{name}"]
        predicted = table.attrs[f"check_predicted_{name}"]
        finite = np.isfinite(measured)
        assert finite.any()
        np.testing.assert_allclose(measured[finite], predicted[finite], rtol=0.15)
    assert table_steps(config, 2, 1.0, 2, estimator) > 0
