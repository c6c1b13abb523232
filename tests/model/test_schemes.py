"""The discretisation schemes (pde_rotor.model.schemes) and their compiled core.

Checked against analysis, not against earlier runs: the Gauss rule for the edge profile
reproduces the moments of 1/2 sech^2; the contour form of int F r x grad c dA equals the
area form with the exact gradient of an analytic field; the compiled contour torque
equals the numpy reference; and the stopped plate's
torque of both schemes has the symmetries of grid and hexagon: mirror T(-phi) = -T(phi),
the hexagon's period T(phi + pi/3) = T(phi) and the lattice's T(phi + pi/2) = T(phi).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.kernels.cpu import rotor_integrals, spline_window
from pde_rotor.kernels.records import make_record
from pde_rotor.model.analysis import stopped_concentration, stopped_torque
from pde_rotor.model.geometry import edge_normal_angles, plate_indicator
from pde_rotor.model.pde import RotorPDE
from pde_rotor.model.schemes import contour_cross_grad, interpolate_spline, sech2_gauss
from pde_rotor.physics.build import CPU
from pde_rotor.physics.spline import make_spline


@pytest.mark.parametrize("n_nodes", [2, 4, 8])
def test_sech2_gauss_rule_has_the_profile_moments(n_nodes: int) -> None:
    """Weights sum to 1, odd moments vanish, s^2 and s^4 give pi^2/12 and 7 pi^4/240."""
    nodes, weights = sech2_gauss(n_nodes)
    assert weights.sum() == pytest.approx(1.0, abs=1e-12)
    assert np.sum(weights * nodes**3) == pytest.approx(0.0, abs=1e-12)
    assert np.sum(weights * nodes**2) == pytest.approx(math.pi**2 / 12, rel=1e-10)
    if 2 * n_nodes - 1 >= 4:
        assert np.sum(weights * nodes**4) == pytest.approx(7 * math.pi**4 / 240, rel=1e-10)


def test_core_spline_equals_scipy_and_is_fourth_order() -> None:
    """The core's windowed spline (prefilter + basis) equals scipy's cubic spline.

    On a field that vanishes at the grid's border, spline_window + interpolate agree
    with map_coordinates (order 3, whole grid) to 1e-12, pass through the samples, and
    halving dx cuts the interpolation error about 16-fold (fourth order).
    """
    errors = []
    for dx in (0.05, 0.025):
        axis = -2.0 + dx * (np.arange(round(4.0 / dx)) + 0.5)
        n = axis.size
        x, y = np.meshgrid(axis, axis, indexing="ij")
        field = np.exp(-(x * x + 2 * y * y)) * np.cos(2 * x + y)
        flat = np.concatenate([field.reshape(-1), np.zeros(2 * n * n)])
        coef = np.zeros(n * n)
        lo, hi = 1, n - 1
        spline_window(flat, coef, n, lo, hi, lo, hi)
        rng = np.random.default_rng(2)
        px, py = rng.uniform(-0.6, 0.6, (2, 100))
        got = np.array(
            [
                CPU.spline.interpolate(coef, 0, n, axis[0], 1 / dx, a, b)
                for a, b in zip(px, py, strict=True)
            ]
        )
        want = interpolate_spline(field, axis[0], dx, px, py)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
        node = CPU.spline.interpolate(coef, 0, n, axis[0], 1 / dx, axis[n // 2], axis[n // 2 + 3])
        assert node == pytest.approx(field[n // 2, n // 2 + 3], abs=1e-13)
        exact = np.exp(-(px * px + 2 * py * py)) * np.cos(2 * px + py)
        errors.append(np.abs(got - exact).max())
    assert 10.0 < errors[0] / errors[1] < 24.0


def scalar_spline(field: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """The coefficients of field[lo:hi, lo:hi] from the physics' one-line ``spline_line``
    (the GPU kernels' filter) run as plain Python: rows into a buffer, then columns."""
    spline = make_spline(lambda f: f)
    n = field.shape[0]
    flat = np.ascontiguousarray(field).reshape(-1)
    rows = np.zeros(n * n)
    coef = np.zeros(n * n)
    for i in range(lo, hi):
        spline.spline_line(flat, i * n + lo, rows, i * n + lo, 1, hi - lo)
    for j in range(lo, hi):
        spline.spline_line(rows, lo * n + j, coef, lo * n + j, n, hi - lo)
    return coef.reshape(n, n)[lo:hi, lo:hi]


def test_prefilter_commutes_with_mirroring_bit_for_bit() -> None:
    """The prefilter of a field mirrored along x, along y or both is the mirror image of
    its prefilter, bit for bit, so that a mirror-symmetric c has mirror-symmetric
    coefficients (a held disk at the dish's centre then reads the same c on both
    sides); the CPU's lines side by side (spline_window, with the window's margin
    left out) have the bits of the one-line filter of the GPU kernels."""
    n, lo, hi, keep = 64, 3, 61, 27
    field = np.random.default_rng(4).standard_normal((n, n))
    whole = np.zeros((n, n))
    mirrors = {"x": (slice(None, None, -1), slice(None)), "y": (slice(None), slice(None, None, -1))}
    mirrors["both"] = (slice(None, None, -1), slice(None, None, -1))
    window = (slice(lo, hi), slice(lo, hi))
    for flip in mirrors.values():
        got = {}
        for name, values in (("field", field), ("mirrored", field[flip])):
            coef = np.zeros(n * n)
            spline_window(np.ascontiguousarray(values).reshape(-1), coef, n, lo, hi, lo, hi)
            got[name] = coef.reshape(n, n)
        np.testing.assert_array_equal(got["mirrored"][window], got["field"][flip][window])
        symmetric = field + field[flip]
        coef = np.zeros(n * n)
        spline_window(symmetric.reshape(-1), coef, n, lo, hi, lo, hi)
        whole[window] = coef.reshape(n, n)[window]
        np.testing.assert_array_equal(whole, whole[flip])
        np.testing.assert_array_equal(whole[window], scalar_spline(symmetric, lo, hi))
        taps = np.zeros(n * n)
        spline_window(symmetric.reshape(-1), taps, n, lo, hi, keep, n - keep)
        inner = (slice(keep, n - keep), slice(keep, n - keep))
        np.testing.assert_array_equal(taps.reshape(n, n)[inner], whole[inner])


def analytic_field(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A field with a six-fold angular part (so the hexagon feels a torque) and its gradient.

    c = exp(-r^2 / w) (1 + A Im(z^6)), z = x + i y: r x grad c = dc/dtheta
    = 6 A exp(-r^2 / w) Re(z^6) does not average out over the plate.
    """
    w, amp = 0.3, 20.0
    z = x + 1j * y
    bump = np.exp(-(x * x + y * y) / w)
    angular = 1 + amp * np.imag(z**6)
    c = bump * angular
    dcdx = -2 * x / w * c + bump * amp * np.imag(6 * z**5)
    dcdy = -2 * y / w * c + bump * amp * np.real(6 * z**5)
    return c, dcdx, dcdy


@pytest.mark.parametrize("phi", [0.0, 0.37, 1.2])
def test_contour_form_equals_area_form(phi: float) -> None:
    """-int c r x grad F dA over the N-gon level sets equals int F r x grad c dA.

    The area form uses the exact gradient of an analytic field and F averaged over 8 x 8
    points per cell (a fine Riemann sum of the smoothed plate); the contour form
    interpolates the grid values. They agree to 5e-3 relative (the Riemann sum of the
    reference itself errs by O(dx^2) |lap integrand|, about 2e-3 here); a wrong sign,
    factor or edge orientation would miss by O(1).
    """
    cfg = RotorConfig.model_validate(
        {"numerics": {"scheme": "consistent", "contour_nodes": 64, "band_nodes": 8}}
    )
    pde = RotorPDE(cfg)
    x, y = pde.cell_coordinates()
    c, dcdx, dcdy = analytic_field(x, y)
    offsets = (np.arange(8) + 0.5) * pde.domain.dx / 8 - 0.5 * pde.domain.dx
    F = sum(plate_indicator(x + a, y + b, pde.shape, phi) for a in offsets for b in offsets) / 64
    integrand = F * (x * dcdy - y * dcdx)
    area_form = integrand.sum() * pde.domain.cell_area
    contour = contour_cross_grad(
        c,
        pde.domain.coords[0],
        pde.domain.dx,
        pde.scheme,
        edge_normal_angles(pde.shape.n_corners, phi),
        pde.shape.apothem,
        pde.shape.smoothing,
    )
    scale = np.abs(integrand).sum() * pde.domain.cell_area
    assert contour == pytest.approx(area_form, rel=5e-3)
    assert abs(area_form) > 0.1 * scale  # the field has a torque of its own


def test_compiled_contour_torque_equals_numpy_reference(
    coarse_config: Callable[..., RotorConfig], indicators_of
) -> None:
    """rotor_integrals (physics core, CPU) gives the numpy contour and friction integrals."""
    cfg = coarse_config({"numerics": {"scheme": "consistent"}, "geometry": {"asymmetry": 0.1}})
    pde = RotorPDE(cfg)
    dom = pde.domain
    phi = 0.61
    x, y = pde.cell_coordinates()
    c, _, _ = analytic_field(x, y)
    state = np.stack(
        [c * dom.interior_mask, 0.3 * y * dom.interior_mask, -0.2 * x * dom.interior_mask]
    )
    F, _, tab = indicators_of(pde, phi)
    scheme = pde.scheme
    got = rotor_integrals(
        state.reshape(-1),
        F.reshape(-1),
        dom.arrays(),
        make_record(pde.setup),
        tab,
        scheme.kernel_tables(),
        np.zeros(x.size),
    )
    want = contour_cross_grad(
        state[0],
        dom.coords[0],
        dom.dx,
        scheme,
        edge_normal_angles(pde.shape.n_corners, phi),
        pde.shape.apothem,
        pde.shape.smoothing,
    )
    assert got[0] == pytest.approx(want, rel=1e-12)
    F_ref, _ = pde.indicators(phi)
    area = dom.cell_area
    assert got[1] == pytest.approx(np.sum(F_ref * (x * x + y * y)) * area, rel=1e-12)
    cross_v = np.sum(F_ref * (x * state[2] - y * state[1])) * area
    assert got[2] == pytest.approx(cross_v, rel=1e-12)


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_stopped_torque_has_mirror_hexagon_and_lattice_symmetry(
    scheme: str, coarse_config: Callable[..., RotorConfig]
) -> None:
    """T(-phi) = -T(phi), T(phi + pi/3) = T(phi), T(phi + pi/2) = T(phi) for Delta = 0.

    The grid is symmetric under y -> -y and quarter turns, the hexagon under turns by
    pi/3, so the lattice torque of a stopped symmetric plate has these symmetries to
    round-off; a mistake in the pill or edge angles, or in the torque's sign convention
    for one edge, breaks them.
    """
    cfg = coarse_config({"numerics": {"scheme": scheme}})
    phis = np.array([0.11, 0.29])
    base = stopped_torque(cfg, phis)
    scale = np.abs(base).max()
    assert scale > 0  # the lattice torque itself is not zero on this grid
    np.testing.assert_allclose(stopped_torque(cfg, -phis), -base, rtol=0, atol=1e-9 * scale + 1e-18)
    np.testing.assert_allclose(
        stopped_torque(cfg, phis + np.pi / 3), base, rtol=0, atol=1e-9 * scale + 1e-18
    )
    np.testing.assert_allclose(
        stopped_torque(cfg, phis + np.pi / 2), base, rtol=0, atol=1e-9 * scale + 1e-18
    )


def test_stopped_concentration_is_scheme_aware(coarse_config: Callable[..., RotorConfig]) -> None:
    """The steady state of the stopped plate uses the scheme's filtered G."""
    paper = RotorPDE(coarse_config({"numerics": {"scheme": "paper"}}))
    consistent = RotorPDE(coarse_config({"numerics": {"scheme": "consistent"}}))
    c_paper = stopped_concentration(paper, 0.2)
    c_cons = stopped_concentration(consistent, 0.2)
    assert 0 < np.abs(c_paper - c_cons).max() < 0.05 * c_paper.max()
    # and the filtered plate keeps the mass of F, N tan(pi/N) (a^2 + pi^2 delta^2 / 12)
    geo = consistent.config.geometry
    t = math.tan(math.pi / geo.n_corners)
    mass = geo.n_corners * t * (consistent.shape.apothem**2 + math.pi**2 * geo.smoothing**2 / 12)
    F_filtered, _ = consistent.indicators(0.2)
    assert F_filtered.sum() * paper.domain.cell_area == pytest.approx(mass, rel=2e-5)


def test_stopped_concentration_solves_the_five_point_equation(
    small_config: Callable[..., RotorConfig],
) -> None:
    """The sparse solve's c satisfies D lap c - a (1 - F) c + s0 / (pi rho^2) G = 0 on every
    interior cell, with lap the 5-point stencil applied by array shifts and c = 0 on the
    other cells (a check independent of how the matrix is built), to round-off."""
    pde = RotorPDE(small_config({"geometry": {"asymmetry": 2e-5}}))
    cfg, mask = pde.config, pde.domain.interior_mask
    c = stopped_concentration(pde, 0.3)
    F, G = pde.indicators(0.3)
    assert (c[~mask] == 0).all()
    padded = np.pad(c, 1)
    lap = (
        padded[2:, 1:-1] + padded[:-2, 1:-1] + padded[1:-1, 2:] + padded[1:-1, :-2] - 4 * c
    ) / pde.domain.dx**2
    source = cfg.camphor.supply / (np.pi * cfg.geometry.pill_radius**2) * G
    residual = cfg.camphor.diffusion * lap - cfg.camphor.evaporation * (1 - F) * c + source
    assert np.abs(residual[mask]).max() < 1e-10 * np.abs(source).max()
    assert c[mask].min() > 0  # camphor everywhere inside, not a trivial solution
