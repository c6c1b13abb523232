"""The reduced decision model against closed forms on a synthetic table.

Stop curves T_d(t) = -d M e^{-t/τ} + T_a (memory against the former direction d, a
constant asymmetry torque) have the Laplace-weighted bias
β_d(t) = (-d M e^{-t/τ} λ/(λ + 1/τ) + T_a) / I in closed form; the escape probability,
the estimators' P, the critical stop and the calibration follow from it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from pde_rotor.config import RotorConfig
from pde_rotor.decision.table import (
    DecisionTable,
    diffusion_of,
    escape_probability,
    load_table,
    sigma_of,
)

M, TAU, LAM, INERTIA, T_REF, D_REF = 2e-4, 0.35, 14.0, 1e-5, -3.6e-6, 1e-4


def synthetic(n_angles: int = 3, lattice: float = 0.0) -> DecisionTable:
    """Closed-form stop curves, with an optional lattice torque per angle (mean zero)."""
    time = np.arange(0, 4.1 + 1e-9, 0.01)
    torque = np.empty((2, n_angles, time.size))
    offsets = lattice * np.cos(2 * np.pi * np.arange(n_angles) / n_angles)
    for d, direction in enumerate((1, -1)):
        for k in range(n_angles):
            torque[d, k] = -direction * M * np.exp(-time / TAU) + T_REF + offsets[k]
    attrs = {"note": "synthetic", "config": RotorConfig.model_validate({}).model_dump_json()}
    return DecisionTable(time, torque, D_REF, LAM, 0.9, INERTIA, attrs)


def closed_bias(t: np.ndarray, direction: int, asymmetry: float) -> np.ndarray:
    memory = -direction * M * np.exp(-t / TAU) * LAM / (LAM + 1 / TAU)
    return (memory + T_REF * asymmetry / D_REF) / INERTIA


def test_bias_is_the_laplace_weighted_torque() -> None:
    """To the 1e-3 of linear interpolation and trapezoids of the 0.01 table spacing."""
    table = synthetic()
    t = np.array([0.3, 1.0, 2.2, 3.5])
    for asymmetry in (0.0, 2e-5, D_REF):
        beta = table.bias(t, asymmetry)
        for d, direction in enumerate((1, -1)):
            want = closed_bias(t, direction, asymmetry)
            np.testing.assert_allclose(
                beta[d, 0], want, rtol=1e-3, atol=1e-3 * abs(T_REF) / INERTIA
            )


def test_memory_and_asymmetry_parts() -> None:
    table = synthetic(lattice=5e-7)
    np.testing.assert_allclose(table.asymmetry_torque(), T_REF, rtol=1e-12)
    np.testing.assert_allclose(table.memory_torque(), M * np.exp(-table.time / TAU), rtol=1e-9)


def test_escape_probability_is_the_normal_cdf() -> None:
    beta = np.array([-0.1, 0.0, 0.05])
    got = escape_probability(beta, LAM, 2e-4)
    np.testing.assert_allclose(got, norm.cdf(beta / math.sqrt(LAM * 2e-4)), rtol=1e-12)
    np.testing.assert_array_equal(escape_probability(beta, LAM, 0.0), [0.0, 0.5, 1.0])
    with pytest.raises(ValueError, match="Dw"):
        escape_probability(beta, LAM, -1.0)


def test_probability_matches_the_estimators_definitions() -> None:
    table = synthetic()
    t, dw = np.array([1.0, 3.0]), 3e-4
    s = math.sqrt(LAM * dw)
    for asymmetry in (0.0, 2e-5):
        a_want = norm.cdf(-closed_bias(t, 1, asymmetry) / s)
        b_want = norm.cdf(closed_bias(t, -1, asymmetry) / s)
        a, b = table.conditionals(t, asymmetry, dw)
        np.testing.assert_allclose(a, a_want, atol=2e-3)
        np.testing.assert_allclose(b, b_want, atol=2e-3)
        p = table.probability(t, asymmetry, dw)
        want = 0.5 * (a + b) if asymmetry == 0 else 2 * a * b / (a + b)
        np.testing.assert_allclose(p, want, rtol=1e-12)


def test_limits_short_stops_invert_long_stops_follow_the_asymmetry() -> None:
    table = synthetic()
    assert table.probability(0.5, 1e-4, 1e-4) > 0.999  # the memory wins
    assert table.probability(4.0 - 0.6, 1e-4, 1e-6) < 1e-3  # the asymmetry wins
    assert table.probability(3.4, 0.0, 1.0) == pytest.approx(0.5, abs=0.01)  # noise wins
    a, b = table.conditionals(3.4, 0.0, 1e-4)
    assert float(a) == pytest.approx(float(b), abs=1e-12)  # mirror symmetry at Delta = 0


def test_calibrate_inverts_probability() -> None:
    table = synthetic()
    dw = table.calibrate(0.2, 3.0, 2e-5, (1e-9, 1e2))
    assert float(table.probability(3.0, 2e-5, dw)) == pytest.approx(0.2, abs=1e-9)
    with pytest.raises(ValueError, match="not reached"):
        table.calibrate(0.9, 3.0, 2e-5, (1e-9, 1e2))


def test_critical_stop_closed_form() -> None:
    table = synthetic()
    factor = LAM / (LAM + 1 / TAU)
    for asymmetry, dw in ((2e-5, 1e-8), (0.0, 2e-4), (1e-4, 1e-3)):
        scale = max(abs(T_REF * asymmetry / D_REF) / INERTIA, math.sqrt(LAM * dw))
        want = TAU * math.log(M * factor / INERTIA / scale)
        assert table.critical_stop(asymmetry, dw) == pytest.approx(want, abs=0.01)
    assert math.isnan(table.critical_stop(0.0, 1e-30))  # the memory outlasts the table


def test_table_roundtrip_and_range(tmp_path) -> None:
    table = synthetic()
    table.save(tmp_path / "t.nc")
    back = load_table(tmp_path / "t.nc")
    np.testing.assert_array_equal(back.torque, table.torque)
    assert (back.growth_rate, back.asymmetry, back.inertia) == (LAM, D_REF, INERTIA)
    assert back.attrs["note"] == "synthetic"
    with pytest.raises(ValueError, match="range"):
        table.bias(table.t_max + 0.1, 0.0)
    at_zero = DecisionTable(table.time, table.torque, 0.0, LAM, 1.0, INERTIA)
    with pytest.raises(ValueError, match="asymmetry 0"):
        at_zero.bias(1.0, 2e-5)


def test_sigma_and_diffusion_are_inverse() -> None:
    assert diffusion_of(2e-8, 1e-5) == pytest.approx(4e-6)
    assert sigma_of(diffusion_of(1.5e-7, 1e-5), 1e-5) == pytest.approx(1.5e-7)


def test_release_amplitude_scales_the_bias_the_release_acts_on() -> None:
    """r is the least-squares ratio of the measured to the predicted check amplitudes,
    and the escape probabilities use r beta: a table whose checks came out 0.9 of C beta/lambda
    predicts exactly what a table with 0.9 times the torque would."""
    plain = synthetic()
    assert plain.amplitude_scale == 1.0  # no checks: nothing measured
    predicted = np.array([0.05, -0.02, np.nan])
    checked = DecisionTable(
        plain.time,
        plain.torque,
        plain.asymmetry,
        plain.growth_rate,
        plain.response,
        plain.inertia,
        {
            **plain.attrs,
            "check_predicted_ccw": predicted,
            "check_amplitude_ccw": 0.9 * predicted,
            "check_predicted_cw": np.array([0.01]),
            "check_amplitude_cw": np.array([0.009]),
        },
    )
    assert checked.amplitude_scale == pytest.approx(0.9, rel=1e-12)
    weaker = DecisionTable(
        plain.time, 0.9 * plain.torque, plain.asymmetry, LAM, 0.9, INERTIA, plain.attrs
    )
    dw = 3e-4
    for t, asymmetry in ((0.5, 0.0), (2.0, 2e-5), (3.0, D_REF)):
        np.testing.assert_allclose(
            checked.conditionals(t, asymmetry, dw),
            weaker.conditionals(t, asymmetry, dw),
            rtol=1e-12,
        )
        np.testing.assert_allclose(checked.bias(t, asymmetry), plain.bias(t, asymmetry), rtol=0)
    assert checked.critical_stop(2e-5, dw) == pytest.approx(
        weaker.critical_stop(2e-5, dw), rel=1e-9
    )
