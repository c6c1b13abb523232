"""Computational domain: the square grid around the disk of radius L (section "Numerical results").

The paper integrates on a circle of radius L = 3 with c = 0 and v = 0 on the boundary.
The kernels update only interior cells (centre radius < L); every other cell holds 0.
That is a faithful Dirichlet problem only if every interior cell's 5-point stencil lies
inside the array and every cell of the square's border lies outside the disk.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
from matplotlib.path import Path as MplPath
from pde import CartesianGrid

from pde_rotor.config import ConfigError, RotorConfig, validate_config
from pde_rotor.model.domain import make_domain
from pde_rotor.model.geometry import RotorShape
from pde_rotor.model.pde import RotorPDE
from tests.conftest import COARSE


def configs(coarse_config: Callable[..., RotorConfig]) -> list[RotorConfig]:
    """Paper resolution, coarse resolution, and two other radii/spacings."""
    return [
        RotorConfig.model_validate({}),
        coarse_config(),
        coarse_config({"grid": {"domain_radius": 2.2}}),
        coarse_config({"grid": {"dx": 0.04, "dt": 2e-4, "domain_radius": 1.9}}),
    ]


def test_grid_is_square_symmetric_and_has_spacing_dx(
    coarse_config: Callable[..., RotorConfig],
) -> None:
    """n x n cells of side dx, cell centres symmetric about the origin, area dx^2."""
    for cfg in configs(coarse_config):
        dom = RotorPDE(cfg).domain
        dx = cfg.grid.dx
        n = dom.coords.size
        assert dom.grid.shape == (n, n)
        np.testing.assert_allclose(dom.grid.discretization, [dx, dx], rtol=1e-12)
        np.testing.assert_allclose(np.diff(dom.coords), dx, rtol=1e-9)
        np.testing.assert_allclose(dom.coords + dom.coords[::-1], 0.0, atol=1e-12)
        assert dom.cell_area == pytest.approx(dx**2, rel=1e-14)


def test_border_cells_lie_outside_the_disk_and_only_one_ring_is_added(
    coarse_config: Callable[..., RotorConfig],
) -> None:
    """Every border cell of the square has centre radius >= L (it holds the Dirichlet 0).

    Hence every interior cell has its four neighbours inside the array, and the
    kernels never need py-pde's boundary conditions on the square. The square is
    not wasteful: with n = 2 ceil(L / dx) + 2 cells the border cells' centres lie at
    (ceil(L / dx) + 1/2) dx, in [L + dx/2, L + 3 dx/2).
    """
    for cfg in configs(coarse_config):
        dom = RotorPDE(cfg).domain
        mask = dom.interior_mask
        assert not mask[0, :].any()
        assert not mask[-1, :].any()
        assert not mask[:, 0].any()
        assert not mask[:, -1].any()
        border = abs(dom.coords[0])
        radius = cfg.grid.domain_radius
        dx = cfg.grid.dx
        assert radius + 0.5 * dx - 1e-12 <= border < radius + 1.5 * dx


def test_interior_cells_are_the_cells_whose_centre_lies_in_the_disk(
    coarse_config: Callable[..., RotorConfig],
) -> None:
    """interior_lo/hi and interior_mask select the cells with centre inside the circle.

    Checked against geometry computed another way: ray casting (matplotlib's
    point-in-polygon) against a 4096-gon inscribed in the circle (every centre inside it
    is interior) and one circumscribed about it (every interior centre lies inside it);
    the mask has the 8 symmetries of the square grid; and its area obeys the rigorous
    bounds pi (L - dx/sqrt 2)^2 <= N dx^2 <= pi (L + dx/sqrt 2)^2 (a cell whose centre
    is within L of the origin lies within L + dx/sqrt 2, and every point within
    L - dx/sqrt 2 belongs to such a cell).
    """
    sides = 4096
    angles = 2 * np.pi * np.arange(sides) / sides
    unit = np.column_stack([np.cos(angles), np.sin(angles)])
    for cfg in configs(coarse_config):
        dom = RotorPDE(cfg).domain
        radius, dx = cfg.grid.domain_radius, cfg.grid.dx
        from_ranges = np.zeros((dom.coords.size,) * 2, dtype=bool)
        for i, (lo, hi) in enumerate(zip(dom.interior_lo, dom.interior_hi, strict=True)):
            from_ranges[i, lo:hi] = True
        mask = dom.interior_mask
        np.testing.assert_array_equal(from_ranges, mask)
        x, y = np.meshgrid(dom.coords, dom.coords, indexing="ij")
        centres = np.column_stack([x.ravel(), y.ravel()])
        inscribed = MplPath(radius * unit).contains_points(centres).reshape(mask.shape)
        outer = MplPath(radius / math.cos(math.pi / sides) * unit)
        circumscribed = outer.contains_points(centres).reshape(mask.shape)
        assert inscribed.sum() > 0.99 * mask.sum()
        assert np.all(mask[inscribed])
        assert np.all(circumscribed[mask])
        for image in (mask[::-1], mask[:, ::-1], mask.T):
            np.testing.assert_array_equal(image, mask)
        area = mask.sum() * dx**2
        assert math.pi * (radius - dx / math.sqrt(2)) ** 2 <= area
        assert area <= math.pi * (radius + dx / math.sqrt(2)) ** 2


def test_support_ranges_cover_the_support_inside_the_interior(
    coarse_config: Callable[..., RotorConfig],
) -> None:
    """support_lo/hi enumerate the cells within the support radius of F and G.

    For these configurations (support radius < L - dx) the support cells and their
    4 neighbours (read by the central differences of the torque integral) are interior.
    """
    for cfg in configs(coarse_config):
        pde = RotorPDE(cfg)
        dom = pde.domain
        x, y = pde.cell_coordinates()
        r2 = x**2 + y**2
        support = r2 < pde.shape.support_radius**2
        from_ranges = np.zeros_like(support)
        for i, (lo, hi) in enumerate(zip(dom.support_lo, dom.support_hi, strict=True)):
            from_ranges[i, lo:hi] = True
        np.testing.assert_array_equal(from_ranges, support)
        assert pde.shape.support_radius < cfg.grid.domain_radius - cfg.grid.dx
        stencil = support.copy()
        stencil[1:, :] |= support[:-1, :]
        stencil[:-1, :] |= support[1:, :]
        stencil[:, 1:] |= support[:, :-1]
        stencil[:, :-1] |= support[:, 1:]
        assert np.all(dom.interior_mask[stencil])


def test_dish_centre_moves_the_grid_not_the_kernels_frame(
    coarse_config: Callable[..., RotorConfig],
) -> None:
    """grid.domain_centre moves the dish: the py-pde grid covers the square about it and
    x_coords, y_coords are the centre plus coords, while coords, the interior and the
    kernels' frame stay those of the dish at the origin, bit for bit; the rotor's support
    rows lie about the origin, at minus the centre in that frame. At the default centre
    the grid is the square about the origin."""
    base = coarse_config()
    shape = RotorShape.from_config(base.geometry)
    plain = make_domain(base.grid, shape)
    n = plain.coords.size
    half = n * base.grid.dx / 2
    assert plain.grid == CartesianGrid([[-half, half], [-half, half]], [n, n])
    assert np.array_equal(plain.coords, plain.grid.axes_coords[0])
    centre = (0.35, -0.2)
    moved = make_domain(base.grid.model_copy(update={"domain_centre": centre}), shape)
    assert np.array_equal(moved.coords, plain.coords)
    assert np.array_equal(moved.interior_lo, plain.interior_lo)
    assert np.array_equal(moved.interior_hi, plain.interior_hi)
    np.testing.assert_allclose(moved.grid.axes_coords[0], moved.x_coords, atol=1e-12)
    np.testing.assert_allclose(moved.grid.axes_coords[1], moved.y_coords, atol=1e-12)
    assert np.array_equal(moved.x_coords, centre[0] + plain.coords)
    assert moved.dish_frame(0.0, 0.0) == (-0.35, 0.2)
    x, y = np.meshgrid(moved.x_coords, moved.y_coords, indexing="ij")
    expected = x**2 + y**2 < shape.support_radius**2
    np.testing.assert_array_equal(moved.support_mask, expected)
    assert not np.array_equal(moved.support_mask, plain.support_mask)


def test_dish_centre_that_cuts_the_rotor_is_refused(
    coarse_config: Callable[..., RotorConfig],
) -> None:
    """The rotor's support plus one cell must lie inside the moved dish (a ValueError
    from the domain, a ConfigError naming grid.domain_centre from the config)."""
    base = coarse_config()
    shape = RotorShape.from_config(base.geometry)
    far = base.grid.domain_radius - shape.support_radius
    with pytest.raises(ValueError, match="dish centre"):
        make_domain(base.grid.model_copy(update={"domain_centre": (far, 0.0)}), shape)
    with pytest.raises(ConfigError, match=r"^grid\.domain_centre = \["):
        validate_config({**COARSE, "grid": {**COARSE["grid"], "domain_centre": [far, 0.0]}})
    validate_config({**COARSE, "grid": {**COARSE["grid"], "domain_centre": [far / 2, 0.0]}})
