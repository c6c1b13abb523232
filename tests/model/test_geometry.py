"""Geometry of the rotor: corner pills (Eqs. (rc), (rj)), the indicators F and G.

The plate is the regular N-gon whose edges have the outward normals
e_j = e(phi + 2 pi (j - 1/2) / N), Eq. (ejt0) rotated by phi, at the distance
a = R cos(pi/N) (the apothem) from the origin; its corners are therefore at the angles
phi + 2 pi j / N, at the distance R. The pills sit at the corners, shifted by Delta, at
R_c = R - rho / cos(pi/N) - p, Eq. (rc); the printed Eq. (rj) (edge-midpoint angles)
is the erratum documented in pde_rotor.model.geometry.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.model.geometry import (
    RotorShape,
    edge_normal_angles,
    pill_angles,
    pill_centres,
    pill_indicator,
    plate_indicator,
)
from pde_rotor.model.pde import RotorPDE

PHIS = (0.0, 1.0, 2.5, -4.2)


def paper_config(**geometry: float) -> RotorConfig:
    """Paper resolution (all defaults) with geometry overrides."""
    return RotorConfig.model_validate({"geometry": geometry})


def polygon_corners(shape: RotorShape, phi: float) -> np.ndarray:
    """Corners of the plate, as intersections of adjacent edge lines r . e_j = a.

    Independent of :func:`pill_angles`: corner j solves r . e_j = a and r . e_{j+1} = a.
    """
    ang = edge_normal_angles(shape.n_corners, phi)
    corners = []
    for j in range(shape.n_corners):
        a1, a2 = ang[j], ang[(j + 1) % shape.n_corners]
        normals = np.array([[math.cos(a1), math.sin(a1)], [math.cos(a2), math.sin(a2)]])
        corners.append(np.linalg.solve(normals, [shape.apothem, shape.apothem]))
    return np.array(corners)


def edge_clearance(shape: RotorShape, phi: float, points: np.ndarray) -> np.ndarray:
    """Distance of each point (rows of `points`) from the nearest edge line (> 0 inside)."""
    ang = edge_normal_angles(shape.n_corners, phi)
    normals = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    return shape.apothem - np.max(points @ normals.T, axis=1)


@pytest.mark.parametrize("asymmetry", [0.0, 0.05, -0.2])
@pytest.mark.parametrize("phi", PHIS)
def test_pills_sit_at_the_corners(phi: float, asymmetry: float) -> None:
    """Pill j sits at R_c e(phi + 2 pi j / N + Delta), Eqs. (rc) and corrected (rj).

    The corners (intersections of adjacent edges) lie at distance R; each pill centre
    lies at distance R_c = R - rho / cos(pi/N) - p in the direction of a corner rotated
    by Delta, one pill per corner.
    """
    g = paper_config(asymmetry=asymmetry).geometry
    shape = RotorShape.from_config(g)
    corners = polygon_corners(shape, phi)
    np.testing.assert_allclose(np.hypot(*corners.T), g.radius, rtol=1e-13)
    centres = pill_centres(shape, phi)
    r_c = g.radius - g.pill_radius / math.cos(math.pi / g.n_corners) - g.pill_inset
    np.testing.assert_allclose(np.hypot(*centres.T), r_c, rtol=1e-13)
    corner_angles = np.arctan2(corners[:, 1], corners[:, 0])
    pill_dirs = np.arctan2(centres[:, 1], centres[:, 0])
    shift = np.angle(np.exp(1j * (pill_dirs - corner_angles)))
    np.testing.assert_allclose(shift, asymmetry, atol=1e-12)


def test_pills_touch_both_corner_edges_without_inset() -> None:
    """With p = 0, Eq. (rc) makes every pill tangent to both edges of its corner.

    A circle of radius rho tangent to two edges meeting at a corner of interior angle
    pi - 2 pi / N has its centre on the bisector at rho / sin(pi/2 - pi/N) =
    rho / cos(pi/N) from the corner: the distance to both edge lines equals rho exactly.
    With p > 0 the pills move inward by p along the bisector and gain p cos(pi/N).
    """
    for inset_cfg in (paper_config(pill_inset=0.0), paper_config()):
        g = inset_cfg.geometry
        shape = RotorShape.from_config(g)
        centres = pill_centres(shape, 0.7)
        ang = edge_normal_angles(shape.n_corners, 0.7)
        normals = np.stack([np.cos(ang), np.sin(ang)], axis=1)
        dist = shape.apothem - centres @ normals.T  # (pill, edge)
        two_nearest = np.sort(dist, axis=1)[:, :2]
        expected = g.pill_radius + g.pill_inset * math.cos(math.pi / g.n_corners)
        np.testing.assert_allclose(two_nearest, expected, rtol=1e-12)


def test_printed_rj_angles_are_edge_midpoints_and_would_stick_out() -> None:
    """The printed Eq. (rj) puts pills at e_j angles; at R_c they would leave the plate.

    The model's pill angles differ from the edge-normal angles by pi/N (mod 2 pi/N).
    A pill at R_c in an edge-midpoint direction has clearance a - R_c to that edge,
    which for the paper's geometry is smaller than rho: the printed equation
    contradicts Eq. (rc) and Fig. 1, while the corner pills have clearance >= rho.
    """
    g = paper_config().geometry
    shape = RotorShape.from_config(g)
    phi = 0.4
    used = pill_angles(shape.n_corners, phi, 0.0)
    printed = edge_normal_angles(shape.n_corners, phi)
    step = 2 * math.pi / shape.n_corners
    offsets = np.mod(used[:, None] - printed[None, :], step)
    np.testing.assert_allclose(offsets, math.pi / shape.n_corners, atol=1e-12)

    printed_centres = shape.pill_distance * np.stack([np.cos(printed), np.sin(printed)], axis=1)
    assert np.all(edge_clearance(shape, phi, printed_centres) < g.pill_radius)
    assert np.all(edge_clearance(shape, phi, pill_centres(shape, phi)) >= g.pill_radius)


@pytest.mark.parametrize("asymmetry", [0.0, 0.1, -0.3])
def test_pill_disks_lie_inside_the_plate(asymmetry: float) -> None:
    """Every point of every pill disk lies inside the plate; F ~ 1 under the pills.

    Points on each pill rim have positive edge clearance, so F > 1/2 there, and under
    the pill centre F = 1/2 (1 + tanh(clearance / delta)) is 1 to within exp(-2 x)
    with x = clearance / delta >= (rho + p cos(pi/N) - |Delta| R_c) / delta; G is
    1/2 (1 + tanh(rho / delta)) there.
    """
    g = paper_config(asymmetry=asymmetry).geometry
    shape = RotorShape.from_config(g)
    phi = 1.3
    centres = pill_centres(shape, phi)
    theta = np.linspace(0, 2 * np.pi, 721)
    rim = np.concatenate(
        [c + g.pill_radius * np.stack([np.cos(theta), np.sin(theta)], axis=1) for c in centres]
    )
    assert np.all(edge_clearance(shape, phi, rim) > 0)
    assert np.all(plate_indicator(rim[:, 0], rim[:, 1], shape, phi) > 0.5)
    f_centre = plate_indicator(centres[:, 0], centres[:, 1], shape, phi)
    clearance = edge_clearance(shape, phi, centres)
    np.testing.assert_allclose(f_centre, 0.5 * (1 + np.tanh(clearance / g.smoothing)), rtol=1e-14)
    assert np.all(f_centre > 0.999)
    g_centre = pill_indicator(centres[:, 0], centres[:, 1], shape, phi)
    expected = 0.5 * (1 + math.tanh(g.pill_radius / g.smoothing))
    # the other pills add only their exponentially small tails
    np.testing.assert_allclose(g_centre, expected, atol=1e-6)


def test_config_rejects_pills_sticking_out() -> None:
    """The config accepts |Delta| up to the geometric limit and rejects beyond it.

    Rotating a pill by Delta about the origin brings it closer to one edge of its corner:
    clearance a - R_c cos(pi/N - |Delta|). The limit solves clearance = rho.
    """
    base = paper_config().geometry
    shape = RotorShape.from_config(base)
    half = math.pi / base.n_corners
    limit = half - math.acos((shape.apothem - base.pill_radius) / shape.pill_distance)
    ok_shape = RotorShape.from_config(paper_config(asymmetry=0.99 * limit).geometry)
    clearance = edge_clearance(ok_shape, 0.0, pill_centres(ok_shape, 0.0))
    assert np.all(clearance >= base.pill_radius)
    assert np.min(clearance) < base.pill_radius * 1.01  # close to the limit
    with pytest.raises(ValueError, match="stick out"):
        paper_config(asymmetry=1.01 * limit)


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
@pytest.mark.parametrize("resolution", ["paper", "coarse"])
def test_support_restricted_update_equals_full_evaluation(
    resolution: str, scheme: str, coarse_config: Callable[..., RotorConfig], indicators_of
) -> None:
    """The compiled core's F and G on the support equal numpy F and G on the whole grid.

    tanh(x) is -1 to 4e-18 for x <= -20, so F and G vanish outside the support disk
    (the filtered fields to 1e-15: their tails keep the tanh's decay rate); inside
    it the compiled and numpy versions agree to round-off. Checked for several phi and
    Delta, with point values (paper) and the filter tables (consistent: the core's
    spline and linear interpolation against scipy's and numpy's).
    """
    for asymmetry in (0.0, 0.07, -0.25):
        overrides = {"geometry": {"asymmetry": asymmetry}, "numerics": {"scheme": scheme}}
        cfg = (
            coarse_config(overrides)
            if resolution == "coarse"
            else RotorConfig.model_validate(
                {**paper_config(asymmetry=asymmetry).model_dump(), **overrides}
            )
        )
        pde = RotorPDE(cfg)
        x, y = pde.cell_coordinates()
        outside_support = np.hypot(x, y) >= pde.shape.support_radius
        for phi in PHIS:
            F_full, G_full = pde.indicators(phi)
            assert np.all(np.abs(F_full[outside_support]) < 1e-15)
            assert np.all(np.abs(G_full[outside_support]) < 1e-15)
            F, G, _ = indicators_of(pde, phi)
            # the compiled loops fuse multiply-adds where LLVM chooses (fastmath
            # "contract"): an ulp of r . e_j or |r - R_j| moves F and G by up to 1e-15 on
            # the tanh's steepest slope (1 / (2 delta)); the filtered fields also sum 16
            # spline taps in another order than scipy
            np.testing.assert_allclose(F, F_full, rtol=0, atol=1e-14)
            np.testing.assert_allclose(G, G_full, rtol=0, atol=1e-14)
            # the plate and the pills are really there (the comparison is not vacuous)
            assert F.max() > 0.99
            assert G.max() > 0.5


@pytest.mark.parametrize("phi", [0.0, 0.3, 1.0])
def test_indicator_areas(phi: float) -> None:
    """int F dA and int G dA equal their exact values for tanh edges.

    With f(s) = 1/2 (1 + tanh(s / delta)), f' is the logistic density of mean 0 and
    variance pi^2 delta^2 / 12. The set {F >= f(sigma)} is the N-gon of apothem
    a - sigma, of area N tan(pi/N) (a - sigma)^2, so by the layer-cake formula
    int F dA = N tan(pi/N) (a^2 + pi^2 delta^2 / 12). Likewise each pill contributes
    pi (rho^2 + pi^2 delta^2 / 12) (Sommerfeld; corrections ~ exp(-2 rho / delta)).
    Consequence: the supply s0 / (pi rho^2) int G dA exceeds N s0 by
    pi^2 delta^2 / (12 rho^2) (5 % at the paper's delta).
    """
    cfg = paper_config()
    g = cfg.geometry
    pde = RotorPDE(cfg)
    F, G = pde.indicators(phi)
    area = pde.domain.cell_area
    var = math.pi**2 * g.smoothing**2 / 12
    apothem = g.radius * math.cos(math.pi / g.n_corners)
    plate = g.n_corners * math.tan(math.pi / g.n_corners) * (apothem**2 + var)
    pills = g.n_corners * math.pi * (g.pill_radius**2 + var)
    assert F.sum() * area == pytest.approx(plate, rel=5e-4)
    assert G.sum() * area == pytest.approx(pills, rel=5e-4)
