"""The no-flux dish wall on cut cells: exact geometry, conservation, the Neumann spectrum of
the disk, and radial symmetry, each against its analytic value."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import j0, jn_zeros, jnp_zeros, jv

from pde_rotor.model.wall import CutCells, make_cut_cells, redistributed_rate, wall_fluxes

RADIUS = 3.0


def dish_coords(dx: float, radius: float = RADIUS) -> np.ndarray:
    """Cell centres of the square grid of :func:`pde_rotor.model.domain.make_domain`."""
    n = 2 * math.ceil(radius / dx - 1e-9) + 2
    return (np.arange(n) + 0.5) * dx - n * dx / 2


def rate(c: np.ndarray, cells: CutCells, v: np.ndarray | None = None) -> np.ndarray:
    """dc/dt = D lap c - div(c v) with D = 1 behind the no-flux wall."""
    return redistributed_rate(wall_fluxes(c, v, cells, 1.0), cells)


def steps_to(t_end: float, cells: CutCells, fraction: float = 0.9) -> tuple[int, float]:
    """Forward Euler steps to `t_end` at `fraction` of the 5-point Laplacian's dt limit."""
    steps = math.ceil(t_end / (fraction * cells.dx**2 / 4))
    return steps, t_end / steps


def evolve(c: np.ndarray, cells: CutCells, t_end: float) -> np.ndarray:
    """c at `t_end` by forward Euler (:func:`steps_to`)."""
    steps, dt = steps_to(t_end, cells)
    for _ in range(steps):
        c = c + dt * rate(c, cells)
    return c


@pytest.mark.parametrize("dx", [0.1, 0.07, 0.025])
def test_volumes_and_apertures_are_those_of_the_circle(dx: float) -> None:
    """The volume fractions add up to the disk's area and the cut faces' apertures to its
    projections; both are symmetric under the square's reflections."""
    cells = make_cut_cells(dish_coords(dx), RADIUS)
    assert np.sum(cells.volume) * dx**2 == pytest.approx(math.pi * RADIUS**2, rel=1e-12)
    # every column of x-faces crosses the disk over its chord: sum_j alpha dx = 2 sqrt(L^2 - x^2)
    faces = dish_coords(dx)[:-1] + dx / 2
    chords = 2 * np.sqrt(np.clip(RADIUS**2 - faces**2, 0, None))
    np.testing.assert_allclose(cells.aperture_x[:-1].sum(axis=1) * dx, chords, atol=1e-12)
    np.testing.assert_allclose(cells.aperture_y[:, :-1].sum(axis=0) * dx, chords, atol=1e-12)
    for flip in (cells.volume[::-1], cells.volume[:, ::-1], cells.volume.T):
        np.testing.assert_allclose(flip, cells.volume, atol=1e-12)
    assert ((cells.volume > 0) & (cells.volume < 1)).sum() == cells.cut.size


def test_the_circle_must_leave_the_outer_ring_free() -> None:
    coords = dish_coords(0.1)
    with pytest.raises(ValueError, match="outermost cells"):
        make_cut_cells(coords, -coords[0])


def test_camphor_is_conserved_with_flow_to_round_off() -> None:
    """Without sublimation and sources nothing crosses the wall: the total of kappa c
    stays put, with diffusion and advection by a flow that is 0 outside the circle."""
    dx = 0.1
    coords = dish_coords(dx)
    cells = make_cut_cells(coords, RADIUS)
    x, y = np.meshgrid(coords, coords, indexing="ij")
    c = np.where(cells.mask, 1.0 + 0.5 * np.sin(1.3 * x + 0.2) * np.cos(0.8 * y), 0.0)
    inside = x**2 + y**2 < RADIUS**2
    v = np.stack([inside * np.cos(0.7 * y), inside * 0.6 * np.sin(0.9 * x + 0.3)])
    start = cells.total(c)
    for _ in range(200):
        c = c + 0.2 * dx**2 * rate(c, cells, v)
    assert abs(cells.total(c) / start - 1) < 1e-13
    assert np.abs(c[~cells.mask]).max() == 0.0


def spectrum(dx: float) -> np.ndarray:
    """The eigenvalues of the operator of :func:`rate`, assembled column by column."""
    cells = make_cut_cells(dish_coords(dx), RADIUS)
    held = np.flatnonzero(cells.mask)
    matrix = np.zeros((held.size, held.size))
    unit = np.zeros(cells.volume.size)
    for m, p in enumerate(held):
        unit[p] = 1.0
        matrix[:, m] = rate(unit.reshape(cells.volume.shape), cells).reshape(-1)[held]
        unit[p] = 0.0
    return np.linalg.eigvals(matrix)


def test_stiffest_rate_is_that_of_a_full_cell() -> None:
    """Flux redistribution removes the small cut cells' stiffness: the spectrum is real,
    in [-8 / dx^2, 0], so the 5-point Laplacian's dt limit holds behind the wall."""
    dx = 0.25
    values = spectrum(dx)
    assert np.abs(values.imag).max() < 1e-9 / dx**2
    assert values.real.max() < 1e-9
    assert values.real.min() > -8 / dx**2
    # and the least nonzero rate is the l = 1 Neumann mode J1'(k L) = 0
    k = jnp_zeros(1, 1)[0] / RADIUS
    slow = np.sort(-values.real)[1:3]
    np.testing.assert_allclose(slow, k**2, rtol=5e-3)


def mode_decay(dx: float, order: int, t_end: float = 1.0) -> tuple[float, float]:
    """The decay rate of J_order(k r) cos(order theta) + 0.3 (k its first nonzero Neumann
    wavenumber) as the eigenvalue of the operator: the Euler factor per step is 1 - dt
    lambda, whatever the time step's own error. Returns it and D k^2."""
    coords = dish_coords(dx)
    cells = make_cut_cells(coords, RADIUS)
    x, y = np.meshgrid(coords, coords, indexing="ij")
    r, theta = np.hypot(x, y), np.arctan2(y, x)
    k = (jnp_zeros(order, 1)[0] if order else jnp_zeros(0, 2)[0]) / RADIUS
    shape = jv(order, k * r) * np.cos(order * theta)
    c = np.where(cells.mask, shape + 0.3, 0.0)
    project = lambda f: np.sum(cells.volume * f * shape)  # noqa: E731
    before = project(c)
    steps, dt = steps_to(t_end, cells)
    factor = (project(evolve(c, cells, t_end)) / before) ** (1 / steps)
    return (1 - factor) / dt, k**2


@pytest.mark.parametrize(("order", "tolerance"), [(0, 1.5e-3), (1, 4e-4)])
def test_neumann_modes_decay_at_the_bessel_rates_and_converge(order: int, tolerance: float) -> None:
    """J1(k r) cos(theta) with J1'(k L) = 0 (and the lowest radial mode J0(k r), J0'(k L) =
    0) decays at D k^2, within `tolerance` on dx = 0.1 and at least three times closer on
    dx = 0.05 (second order; measured: -2.7e-4 then -6.8e-5 for l = 1, -1.0e-3 then
    -2.6e-4 for l = 0)."""
    coarse, exact = mode_decay(0.1, order)
    fine, _ = mode_decay(0.05, order)
    assert abs(coarse / exact - 1) < tolerance
    assert abs(fine / exact - 1) < abs(coarse / exact - 1) / 3


def radial_solution(r: np.ndarray, t: float, width: float, modes: int = 60) -> np.ndarray:
    """c(r, t) of D = 1 diffusion in the disk with dc/dr = 0 at L from the Gaussian
    exp(-r^2 / (2 width^2)): the series in J0(k_n r), J0'(k_n L) = 0 (k_0 = 0)."""
    k = np.concatenate([[0.0], jn_zeros(1, modes) / RADIUS])  # J0' = -J1
    nodes = np.linspace(0, RADIUS, 4001)
    weight = np.full(nodes.size, 2.0)
    weight[[0, -1]] = 1.0
    weight[1:-1:2] = 4.0
    weight *= (nodes[1] - nodes[0]) / 3  # Simpson
    start = np.exp(-(nodes**2) / (2 * width**2))
    out = np.zeros_like(r)
    for kn in k:
        basis = j0(kn * nodes)
        coefficient = np.sum(weight * start * basis * nodes) / np.sum(weight * basis**2 * nodes)
        out += coefficient * math.exp(-(kn**2) * t) * j0(kn * r)
    return out


def blob_error(dx: float, t_end: float = 1.0, width: float = 1.2) -> tuple[float, float]:
    """Largest error against :func:`radial_solution`, and largest difference between the
    cells at one radius (the blob's anisotropy), after diffusing to `t_end`."""
    coords = dish_coords(dx)
    cells = make_cut_cells(coords, RADIUS)
    x, y = np.meshgrid(coords, coords, indexing="ij")
    r = np.hypot(x, y)
    c = evolve(np.where(cells.mask, np.exp(-(r**2) / (2 * width**2)), 0.0), cells, t_end)
    inside = r < RADIUS - dx
    error = np.abs(c - radial_solution(r, t_end, width))[inside].max()
    return error, np.abs(c - c.T)[inside].max() + np.abs(c - c[::-1, :]).max()


def test_radial_blob_stays_radial_and_converges() -> None:
    """A Gaussian blob that reaches the wall diffuses as the radial series does (no
    staircase anisotropy: the error is the largest at any angle), keeps the square's
    mirror symmetries, and its error falls at second order with dx (measured: 4.9e-4 on
    dx = 0.1, 4.5e-5 on dx = 0.05)."""
    coarse, asymmetry = blob_error(0.1)
    fine, _ = blob_error(0.05)
    assert asymmetry < 1e-12
    assert coarse < 2e-3
    assert fine < coarse / 3
