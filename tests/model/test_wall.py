"""The no-flux dish wall on cut cells: exact geometry, conservation, stability at the
5-point limit, the Neumann spectrum of the disk, and radial symmetry, each against its
analytic value."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.special import j0, jn_zeros, jnp_zeros, jv

from pde_rotor.model.clusters import implicit_factors
from pde_rotor.model.wall import CutCells, make_cut_cells, make_wall_step, wall_fluxes

RADIUS = 3.0


def dish_coords(dx: float, radius: float = RADIUS) -> np.ndarray:
    """Cell centres of the square grid of :func:`pde_rotor.model.domain.make_domain`."""
    n = 2 * math.ceil(radius / dx - 1e-9) + 2
    return (np.arange(n) + 0.5) * dx - n * dx / 2


def steps_to(t_end: float, dx: float, fraction: float = 0.9) -> tuple[int, float]:
    """Steps to `t_end` at `fraction` of the 5-point Laplacian's dt limit dx^2 / 4 (D = 1)."""
    steps = math.ceil(t_end / (fraction * dx**2 / 4))
    return steps, t_end / steps


def evolve(c: np.ndarray, cells: CutCells, t_end: float) -> np.ndarray:
    """c at `t_end` by the wall's step (:func:`make_wall_step`), D = 1, no sources."""
    steps, dt = steps_to(t_end, cells.dx)
    step = make_wall_step(cells, 1.0, dt)
    zero = np.zeros_like(c)
    for _ in range(steps):
        c = step(c, None, zero)
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
    assert not (cells.stiff & (cells.volume == 1.0)).any()
    assert cells.stiff.any()


def test_the_circle_must_leave_the_outer_ring_free() -> None:
    coords = dish_coords(0.1)
    with pytest.raises(ValueError, match="outermost cells"):
        make_cut_cells(coords, -coords[0])


def test_camphor_is_conserved_with_flow_to_round_off() -> None:
    """Without sublimation and sources nothing crosses the wall: the total of kappa c
    stays put, with diffusion (explicit and implicit faces) and advection by a flow that
    is 0 outside the circle."""
    dx = 0.1
    coords = dish_coords(dx)
    cells = make_cut_cells(coords, RADIUS)
    assert cells.stiff.any()
    x, y = np.meshgrid(coords, coords, indexing="ij")
    c = np.where(cells.mask, 1.0 + 0.5 * np.sin(1.3 * x + 0.2) * np.cos(0.8 * y), 0.0)
    inside = x**2 + y**2 < RADIUS**2
    v = np.stack([inside * np.cos(0.7 * y), inside * 0.6 * np.sin(0.9 * x + 0.3)])
    start = cells.total(c)
    step = make_wall_step(cells, 1.0, 0.2 * dx**2)
    for _ in range(200):
        c = step(c, v, np.zeros_like(c))
    assert abs(cells.total(c) / start - 1) < 1e-13
    assert np.abs(c[~cells.mask]).max() == 0.0


def step_matrix(cells: CutCells, dt: float) -> np.ndarray:
    """The wall's step (D = 1, no sources) as a matrix on the cells that hold c."""
    step = make_wall_step(cells, 1.0, dt)
    held = np.flatnonzero(cells.mask)
    matrix = np.zeros((held.size, held.size))
    unit = np.zeros(cells.volume.size)
    zero = np.zeros(cells.volume.shape)
    for m, p in enumerate(held):
        unit[p] = 1.0
        matrix[:, m] = step(unit.reshape(cells.volume.shape), None, zero).reshape(-1)[held]
        unit[p] = 0.0
    return matrix


@pytest.mark.parametrize("dx", [0.25, 0.2])
def test_step_is_stable_at_the_five_point_limit(dx: float) -> None:
    """At the 5-point Laplacian's limit dt = dx^2 / (4 D) the step's eigenvalues are real
    and lie in [-1, 1], although the smallest cut cells alone would need a dt two to five
    times smaller (open apertures of 8.6 and 21 kappa): their implicit faces take it. A
    constant is the null mode (nothing flows through the wall)."""
    cells = make_cut_cells(dish_coords(dx), RADIUS)
    ax, ay = cells.aperture_x, cells.aperture_y
    open_sum = ax + np.roll(ax, 1, 0) + ay + np.roll(ay, 1, 1)
    assert (open_sum[cells.mask] / cells.volume[cells.mask]).max() > 8
    values = np.linalg.eigvals(step_matrix(cells, dx**2 / 4))
    assert np.abs(values.imag).max() < 1e-9
    assert np.abs(values).max() <= 1 + 1e-9
    assert np.abs(wall_fluxes(cells.mask * 1.0, None, cells, 1.0)).max() < 1e-12


def mode_decay(dx: float, order: int, t_end: float = 1.0) -> tuple[float, float]:
    """The decay rate of J_order(k r) cos(order theta) + 0.3 (k its first nonzero Neumann
    wavenumber) as the eigenvalue of the operator: the Euler factor per step is 1 - dt
    lambda, whatever the time step's own error (the implicit faces change it at order
    dt^2 on a few cells). Returns it and D k^2."""
    coords = dish_coords(dx)
    cells = make_cut_cells(coords, RADIUS)
    x, y = np.meshgrid(coords, coords, indexing="ij")
    r, theta = np.hypot(x, y), np.arctan2(y, x)
    k = (jnp_zeros(order, 1)[0] if order else jnp_zeros(0, 2)[0]) / RADIUS
    shape = jv(order, k * r) * np.cos(order * theta)
    c = np.where(cells.mask, shape + 0.3, 0.0)
    project = lambda f: np.sum(cells.volume * f * shape)  # noqa: E731
    before = project(c)
    steps, dt = steps_to(t_end, dx)
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


def test_the_clusters_are_factored_once_per_time_step_and_not_copied() -> None:
    """Every ``run`` builds its stepper and asks for the wall's arrays again: the same
    geometry and dt D / dx^2 hand back the same factors, another coefficient its own,
    equal to a fresh factorisation; a copy made by ``replace`` starts without them."""
    cells = make_cut_cells(dish_coords(0.1), RADIUS)
    first, again, other = cells.arrays(0.2), cells.arrays(0.2), cells.arrays(0.1)
    assert first[9].shape[0] > 0  # this dish has implicit clusters
    assert all(a is b for a, b in zip(first[9:], again[9:], strict=True))
    assert other[11] is not first[11]
    for got, want in zip(other[9:], implicit_factors(cells, 0.1), strict=True):
        np.testing.assert_array_equal(got, want)
    assert replace(cells, dx=cells.dx)._factors == {}
