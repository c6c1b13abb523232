"""F and G of the CPU row loops against the physics core's cell functions.

The CPU computes F and G row by row, the loops over corners outside the loops over
cells so that they vectorise (:mod:`pde_rotor.kernels.indicators`); the GPU calls the cell
functions (``plate_cell``, ``pill_cell``, ``filtered_plate``, ``filtered_pills``) once
per cell. Both must give the same fields: the row loops sum the same terms in the same
order.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
import pytest

from pde_rotor.kernels.indicators import StripRows, filtered_strip_row
from pde_rotor.kernels.records import make_record
from pde_rotor.model.filtering import strip_table
from pde_rotor.model.pde import RotorPDE
from pde_rotor.physics.build import CPU
from pde_rotor.physics.indicators import PolygonFilter
from tests.conftest import compiled_indicators

_plate_cell = CPU.indicators.plate_cell
_pill_cell = CPU.indicators.pill_cell
_filtered_plate = CPU.indicators.filtered_plate
_filtered_pills = CPU.indicators.filtered_pills


@nb.njit
def cell_indicators(coords, slo, shi, params, tab, plate, edge, pill):
    """F and G of the cell functions, one cell at a time (the GPU's way)."""
    p = params[0]
    n = coords.size
    F = np.zeros(n * n)
    G = np.zeros(n * n)
    n_corners = p.n_corners
    apothem, rho, inv_delta = p.apothem, p.pill_radius, 1.0 / p.smoothing
    for i in range(n):
        for j in range(slo[i], shi[i]):
            x, y = coords[i], coords[j]
            if not p.filtered:
                F[i * n + j] = _plate_cell(x, y, tab, n_corners, apothem, inv_delta)
                G[i * n + j] = _pill_cell(x, y, tab, n_corners, rho, inv_delta)
            else:
                polygon = PolygonFilter(
                    n_corners, apothem, p.tan_half, p.crease, p.corner_end, edge, p.edge_u0,
                    p.edge_inv_step, plate, p.table_n, p.table_x0, p.table_inv_step,
                )  # fmt: skip
                F[i * n + j] = _filtered_plate(x, y, tab, polygon)
                G[i * n + j] = _filtered_pills(x, y, tab, n_corners, pill, p.profile_inv_step)
    return F.reshape(n, n), G.reshape(n, n)


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
@pytest.mark.parametrize("phi", [0.0, 0.1234, math.pi / 12, 2.0])
def test_row_loops_equal_the_cell_functions(small_config, scheme: str, phi: float) -> None:
    """To rounding (the vector loops may fuse a multiply-add the scalar code does not),
    and exactly 0 outside the support in both."""
    pde = RotorPDE(small_config({"numerics": {"scheme": scheme}}))
    F, G, tab = compiled_indicators(pde, phi)
    dom = pde.domain
    F_cell, G_cell = cell_indicators(
        dom.coords, dom.support_lo, dom.support_hi,
        make_record(pde.setup), tab,
        *pde.scheme.kernel_tables()[2:],
    )  # fmt: skip
    assert F.max() > 0.99 and G.max() > 0.9  # the fields are there
    np.testing.assert_allclose(F, F_cell, rtol=0, atol=1e-14)
    np.testing.assert_allclose(G, G_cell, rtol=0, atol=1e-14)


def test_the_corner_table_ends_where_f_is_below_1e_13(small_config, request) -> None:
    """Beyond ``corner_end`` (about a + 15 delta past the corners) the cells near a
    bisector take the edge profile instead of the 2-D table: F moves by less than 2e-13
    on every cell, at 13 angles, against the table on all of them; G not at all; and
    cells do switch (a sixth of the corner cells on the paper grid)."""
    config = small_config({"numerics": {"scheme": "consistent"}})
    pde = RotorPDE(config)
    end = pde.scheme.tables.corner_end
    request.getfixturevalue("full_corner_table")
    full = RotorPDE(config)
    assert full.scheme.tables.corner_end > end + 0.1
    switched = 0
    for phi in np.linspace(0.0, math.pi / 3, 13) + 0.01:
        F, G, _ = compiled_indicators(pde, phi)
        F_full, G_full, _ = compiled_indicators(full, phi)
        np.testing.assert_array_equal(G, G_full)
        assert np.abs(F - F_full).max() < 2e-13
        switched += np.count_nonzero(F_full != F)
    assert switched > 0


_filtered_strip = CPU.indicators.filtered_strip


@nb.njit
def strip_rows(coords, axis, table, strip_row):
    """F_eps of a strip on every row of the grid, by the row function (`strip_row`
    True) or by the cell function ``filtered_strip``, one cell at a time."""
    n = coords.size
    F = np.zeros((n, n))
    weights = np.empty((8, n))
    taps = np.empty(n, np.uint64)
    plate, rows, columns, x0, inv = table
    for i in range(n):
        if strip_row:
            filtered_strip_row(F[i], coords[i], coords, axis, table, StripRows(weights, taps))
        else:
            for j in range(n):
                F[i, j] = _filtered_strip(
                    coords[i], coords[j], axis[0], axis[1], plate, rows, columns, x0, inv
                )
    return F


@pytest.mark.parametrize("phi", [0.0, 0.3, math.pi / 2, 2.2])
def test_strip_row_equals_the_cell_function_bit_for_bit(phi: float) -> None:
    """A strip plate's filtered F on a row (``filtered_strip_row``, two passes) is the
    physics' ``filtered_strip`` on each cell, bit for bit: the same taps and weights,
    the same sums; 0 where the taps leave the table, which the grid reaches."""
    dx = 0.05
    table = strip_table(0.3, 0.15, 0.025, dx, 8, ("sharpened", 0.95))
    coords = dx * (np.arange(48) - 23.7)  # the strip off the cells' centres
    packed = (table.coef, table.rows, table.columns, table.x0, 1.0 / table.step)
    axis = (math.cos(phi), math.sin(phi))
    rows = strip_rows(coords, axis, packed, True)
    cells = strip_rows(coords, axis, packed, False)
    assert rows.max() > 0.9  # the plate is there
    assert (cells == 0.0).sum() > 100  # and the table ends inside the grid
    np.testing.assert_array_equal(rows, cells)
