"""The indicators' building blocks (pde_rotor.physics.indicators): the polynomial expm1,
the logistic profile, the cubic spline of a table and a strip's filtered F.

The row loops of F and G against the cell functions: tests/kernels/test_indicators.py.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
import pytest
from scipy.ndimage import map_coordinates, spline_filter
from scipy.special import expit

from pde_rotor.config import X_SATURATION
from pde_rotor.model.filtering import filtered_strip, strip_table
from pde_rotor.physics.build import CPU

_expm1 = CPU.indicators.vector_expm1
_logistic = CPU.indicators.logistic
_filtered_corner = CPU.indicators.filtered_corner


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


@nb.njit
def corner_values(h, q, coef, t_n, t_x0, t_inv):
    out = np.empty_like(h)
    for k in range(h.size):
        out[k] = _filtered_corner(h[k], q[k], coef, t_n, t_x0, t_inv)
    return out


def test_the_corner_table_is_its_cubic_spline_and_0_where_its_taps_leave_it() -> None:
    """corner_taps and corner_sum (split so that the CPU computes the taps of many cells
    at once) against scipy's spline of the same table (a bump that vanishes towards the
    table's border, like the plate's), on random points, and 0 where the 4 x 4
    taps leave the table."""
    rng = np.random.default_rng(3)
    t_n, t_x0, step = 60, -0.3, 0.02
    node = np.arange(t_n) - 31.5
    x, y = node[:, None], node[None, :]
    values = np.exp(-(x**2 + y**2) / 32.0) * (1.0 + 0.01 * y)
    coef = spline_filter(values, order=3, mode="grid-constant").reshape(-1)
    fx, fy = rng.uniform(1.0, t_n - 2.0, (2, 2000))
    h, q = t_x0 + fx * step, t_x0 + fy * step
    exact = map_coordinates(values, [fx, fy], order=3, mode="grid-constant")
    got = corner_values(h, q, coef, t_n, t_x0, 1.0 / step)
    np.testing.assert_allclose(got, exact, rtol=0, atol=1e-10)  # scipy pads the border
    outside = np.array([0.999, t_n - 1.999, 5.0, 5.0]), np.array([5.0, 5.0, 0.5, t_n - 1.5])
    h, q = t_x0 + outside[0] * step, t_x0 + outside[1] * step
    got = corner_values(h, q, coef, t_n, t_x0, 1.0 / step)
    assert np.all(got == 0.0)


@pytest.mark.parametrize("phi", [0.0, 0.7, -2.2])
def test_filtered_strip_equals_the_numpy_reference(phi: float) -> None:
    """The compiled F_eps of a strip (the B-spline of its mirrored quadrant
    coefficients) equals scipy's spline of the table's values (its own prefilter,
    mirrored) at points inside, on its axes, across its edges and beyond its table,
    to 1e-12; both are 0 beyond the table."""
    dx = 0.025
    table = strip_table(0.6, 0.3, dx, dx, 8, ("gaussian", 0.7))
    rng = np.random.default_rng(3)
    u = np.concatenate([rng.uniform(-1.0, 1.0, 300), np.zeros(20), rng.uniform(-0.4, 0.4, 20)])
    v = np.concatenate([rng.uniform(-0.9, 0.9, 300), rng.uniform(-0.3, 0.3, 20), np.zeros(20)])
    c, s = math.cos(phi), math.sin(phi)
    x, y = u * c - v * s, u * s + v * c
    want = filtered_strip(table, x, y, phi)
    got = np.array(
        [
            CPU.indicators.filtered_strip(
                a, b, c, s, table.coef, table.rows, table.columns, table.x0, 1.0 / table.step
            )
            for a, b in zip(x, y, strict=True)
        ]
    )
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    assert (want == 0.0).sum() > 50 and (want > 0.99).sum() > 10  # beyond and inside
