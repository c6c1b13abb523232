"""The body core's filtered strip (pde_rotor.kernels.body_core) against the numpy reference."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor.kernels.body_core import CPU_BODIES
from pde_rotor.model.filtering import filtered_strip, strip_table


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
            CPU_BODIES.filtered_strip(
                a, b, c, s, table.coef, table.rows, table.columns, table.x0, 1.0 / table.step
            )
            for a, b in zip(x, y, strict=True)
        ]
    )
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    assert (want == 0.0).sum() > 50 and (want > 0.99).sum() > 10  # beyond and inside
