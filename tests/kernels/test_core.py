"""The physics core's building blocks: the polynomial expm1 and the logistic profile.

The row loops of F and G against the core's cell functions: tests/test_indicators.py.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from scipy.special import expit

from pde_rotor.kernels.core import CPU, X_SATURATION

_expm1 = CPU.vector_expm1
_logistic = CPU.logistic


@nb.njit
def expm1_values(x: np.ndarray) -> np.ndarray:
    out = np.empty_like(x)
    for i in range(x.size):
        out[i] = _expm1(x[i])
    return out


@nb.njit
def logistic_values(x: np.ndarray) -> np.ndarray:
    out = np.empty_like(x)
    for i in range(x.size):
        out[i] = _logistic(x[i])
    return out


def test_vector_expm1_is_expm1_to_2e_14_over_the_whole_range() -> None:
    x = np.linspace(0.0, 2 * X_SATURATION, 200_001)
    np.testing.assert_allclose(expm1_values(x), np.expm1(x), rtol=2e-14, atol=0)
    tiny = np.array([1e-300, 1e-20, 1e-8])
    np.testing.assert_allclose(expm1_values(tiny), np.expm1(tiny), rtol=1e-15, atol=0)


def test_logistic_is_the_tanh_profile_and_saturates() -> None:
    x = np.linspace(-30.0, 30.0, 60_001)
    got = logistic_values(x)
    exact = expit(2 * x)  # = (1 + tanh x) / 2
    inside = np.abs(x) <= X_SATURATION
    np.testing.assert_allclose(got[inside], exact[inside], rtol=2e-14, atol=0)
    assert np.max(np.abs(got - exact)) <= 4.5e-16
    assert np.all(got[x >= X_SATURATION] == 1.0)
    assert np.all(got[x <= -X_SATURATION] < 4.3e-18)
    assert np.all(np.diff(got) >= 0)
