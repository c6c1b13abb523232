"""Bodies in numpy: the indicators of every plate shape, the shorthand rotor, the footprint.

Every plate's F is 1/2 (1 + tanh(-h / delta)) of a gauge h whose level sets {h < t} are
the plate grown by t (a polygon of apothem a + t, a disk of radius R + t, a rectangle of
sides L + 2t, W + 2t). Its area A(t) is then quadratic in t, and since F - H(-h) is odd
in h, int F dA = A(0) + A''(0) int_0^inf t (1 - tanh(t / delta)) dt
= A(0) + A''(0) pi^2 delta^2 / 24: the smoothed plates' exact areas, up to the
exponentially small tail where the level sets shrink to nothing.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
import pytest

from pde_rotor.config import FREE_FRICTION, RotorConfig, validate_config
from pde_rotor.model.bodies import (
    MOTIONLESS,
    Body,
    BodyShape,
    Pose,
    body_support,
    pill_centres,
    pill_indicator,
    pill_source,
    plate_indicator,
    plate_velocity,
)
from pde_rotor.model.domain import make_domain
from pde_rotor.model.geometry import RotorShape
from pde_rotor.model.geometry import pill_centres as rotor_pill_centres
from pde_rotor.model.geometry import pill_indicator as rotor_pill_indicator
from pde_rotor.model.geometry import plate_indicator as rotor_plate_indicator
from pde_rotor.model.setup import Setup

PHIS = (0.0, 0.3, 1.0, 2.5, -4.2)
DYADIC_DX = 2.0**-6
"""A grid spacing whose cell centres, and whole-cell shifts of them, are exact floats."""


def one_body(body: dict[str, Any], **sections: Any) -> Body:
    """The one body of a config (a large dish, the paper's smoothing)."""
    data = {"grid": {"domain_radius": 5.0}, **sections, "bodies": [body]}
    return Setup(validate_config(data)).bodies[0]


def with_smoothing(shape: BodyShape, smoothing: float) -> BodyShape:
    return dataclasses.replace(shape, smoothing=smoothing)


def square(half: float, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """Cell centres (i + 1/2) dx of the square [-half, half]^2, as (x, y) arrays."""
    n = round(2 * half / dx)
    coords = (np.arange(n) - n / 2 + 0.5) * dx
    return np.meshgrid(coords, coords, indexing="ij")


SHAPES: dict[str, tuple[dict[str, Any], float, float]] = {
    # plate, area A(0), A''(0) of the grown plate
    "polygon": (
        {"shape": "polygon", "n_corners": 5, "radius": 0.6},
        5 / 2 * 0.6**2 * math.sin(2 * math.pi / 5),
        2 * 5 * math.tan(math.pi / 5),
    ),
    "disk": ({"shape": "disk", "radius": 0.5}, math.pi * 0.5**2, 2 * math.pi),
    "strip": ({"shape": "strip", "length": 1.2, "width": 0.8}, 1.2 * 0.8, 8.0),
}


@pytest.mark.parametrize("phi", PHIS)
def test_shorthand_body_is_the_paper_rotor_bit_for_bit(phi: float) -> None:
    """The shorthand's body: pills at pill_centres(shape, 0), footprint the rotor's support
    radius, F equal to the rotor's at every angle and G at phi = 0, to the last bit.

    At other angles the body rotates its pills as X + R(phi) p_j, the rotor as
    R_c e((phi + 2 pi j / N) + Delta): the same points up to rounding (1e-15).
    """
    config = RotorConfig.model_validate({"geometry": {"asymmetry": 0.05, "smoothing": 0.03}})
    (body,) = Setup(config).bodies
    rotor = RotorShape.from_config(config.geometry)
    assert np.array_equal(body.shape.pills[:, :2], rotor_pill_centres(rotor, 0.0))
    assert body.shape.reach == rotor.support_radius
    assert body.shape.apothem == rotor.apothem
    x, y = square(1.2, 0.025)
    pose = Pose(0.0, 0.0, phi)
    assert np.array_equal(
        plate_indicator(x, y, body.shape, pose), rotor_plate_indicator(x, y, rotor, phi)
    )
    g_body, g_rotor = pill_indicator(x, y, body.shape, pose), rotor_pill_indicator(x, y, rotor, phi)
    if phi == 0.0:
        assert np.array_equal(g_body, g_rotor)
    np.testing.assert_allclose(g_body, g_rotor, rtol=0, atol=1e-14)
    source = config.camphor.supply / (math.pi * config.geometry.pill_radius**2) * g_rotor
    atol = 1e-14 * source.max()
    np.testing.assert_allclose(pill_source(x, y, body.shape, pose), source, rtol=0, atol=atol)


def test_shorthand_body_moves_as_the_rotor() -> None:
    """Motion, start, protocol and noise of the shorthand's body are the rotor's."""
    config = RotorConfig.model_validate({"noise": {"sigma": 1e-7}})
    (body,) = Setup(config).bodies
    rotor = config.rotor
    assert (body.motion, body.inertia, body.friction) == (
        "fixed_axis",
        rotor.inertia,
        rotor.friction,
    )
    assert body.mass == MOTIONLESS
    assert body.start == Pose(0.0, 0.0, rotor.phi0)
    assert (body.omega0, body.velocity0) == (rotor.omega0, (0.0, 0.0))
    assert body.protocol == config.protocol
    assert body.noise_sigma == config.noise.sigma


def smoothed_disk_area(radius: float, delta: float) -> float:
    """pi R^2 + pi^3 delta^2 / 12: A'' = 2 pi (exact to ~ delta^2 exp(-2 R / delta))."""
    return math.pi * radius**2 + math.pi**3 * delta**2 / 12


@pytest.mark.parametrize("name", list(SHAPES))
def test_smoothed_area_is_exact(name: str) -> None:
    """sum F dx^2 = A + A'' pi^2 delta^2 / 24 (module docstring) for a plate at two
    poses, to 1e-3 of the delta^2 term, the term that separates the smoothed plate from
    the sharp one. The poses are turned: at phi = 0 a rectangle's corner bisectors run
    along the lattice's diagonals, where the midpoint rule's error at the kink of
    max(...) does not average out (dx^2 / 3 here)."""
    plate, area, curvature = SHAPES[name]
    delta = 0.05
    shape = with_smoothing(one_body({"plate": plate}).shape, delta)
    x, y = square(1.6, delta / 8)
    correction = curvature * math.pi**2 * delta**2 / 24
    for pose in (Pose(0.0, 0.0, 0.1), Pose(0.013, -0.021, 0.37)):
        total = plate_indicator(x, y, shape, pose).sum() * (delta / 8) ** 2
        assert abs(total - (area + correction)) < 1e-3 * correction, (pose, total - area)


def test_floating_pills_are_their_own_plate() -> None:
    """Without a plate F_k is G_k; each pill's area is that of a smoothed disk (delta
    an eighth of the radius, so that the exponential tail stays below 1e-10)."""
    pills = [{"x": 0.3, "y": 0.0, "radius": 0.15}, {"x": -0.3, "y": 0.1, "radius": 0.1}]
    delta = 0.0125
    shape = with_smoothing(one_body({"plate": {"shape": "none"}, "pills": pills}).shape, delta)
    x, y = square(1.0, delta / 4)
    pose = Pose(0.1, 0.0, 0.7)
    f = plate_indicator(x, y, shape, pose)
    assert np.array_equal(f, pill_indicator(x, y, shape, pose))
    exact = sum(smoothed_disk_area(p["radius"], delta) for p in pills)
    assert f.sum() * (delta / 4) ** 2 == pytest.approx(exact, rel=1e-9)


def test_disk_is_rotation_invariant_and_has_the_square_grids_symmetries() -> None:
    """A disk about a cell-symmetric origin is the same at every angle and equal to its
    mirror images and its transpose, exactly."""
    shape = one_body({"plate": {"shape": "disk", "radius": 0.45}}).shape
    x, y = square(0.8, DYADIC_DX)
    f = plate_indicator(x, y, shape, Pose(0.0, 0.0, 0.0))
    for phi in PHIS:
        assert np.array_equal(plate_indicator(x, y, shape, Pose(0.0, 0.0, phi)), f)
    assert np.array_equal(f, f[::-1, :])
    assert np.array_equal(f, f[:, ::-1])
    assert np.array_equal(f, f.T)


def test_strip_has_the_rectangles_symmetries() -> None:
    """A strip is symmetric under x -> -x and y -> -y (exactly), turned by pi it is itself
    and turned by pi/2 it is its transpose (to the rounding of cos(pi/2) = 6e-17)."""
    shape = one_body({"plate": {"shape": "strip", "length": 1.0, "width": 0.4}}).shape
    x, y = square(0.8, DYADIC_DX)
    f = plate_indicator(x, y, shape, Pose(0.0, 0.0, 0.0))
    assert np.array_equal(f, f[::-1, :])
    assert np.array_equal(f, f[:, ::-1])
    assert not np.allclose(f, f.T)  # a rectangle, not a square
    np.testing.assert_allclose(plate_indicator(x, y, shape, Pose(0, 0, math.pi)), f, atol=1e-14)
    turned = plate_indicator(x, y, shape, Pose(0.0, 0.0, math.pi / 2))
    np.testing.assert_allclose(turned, f.T, atol=1e-14)
    # the long axis is the body's x axis: F is 1/2 at x = L/2 and y = W/2
    edge = plate_indicator(np.array([0.5, 0.0]), np.array([0.0, 0.2]), shape, Pose(0, 0, 0))
    np.testing.assert_allclose(edge, 0.5, atol=1e-15)


PLATES = [
    {"plate": {"shape": "polygon", "n_corners": 6, "radius": 0.5}, "pills": [{"x": 0.2}]},
    {"plate": {"shape": "disk", "radius": 0.4}, "pills": [{"x": 0.1, "y": -0.2}]},
    {"plate": {"shape": "strip", "length": 0.9, "width": 0.5}, "pills": [{"x": -0.3}]},
    {"plate": {"shape": "none"}, "pills": [{"x": 0.2}, {"x": -0.2, "radius": 0.05}]},
]


@pytest.mark.parametrize("body", PLATES, ids=[b["plate"]["shape"] for b in PLATES])
def test_whole_cell_translation_shifts_the_fields_exactly(body: dict[str, Any]) -> None:
    """F and G of a body at X = (k dx, m dx) are those at the origin shifted by (k, m)
    cells, to the last bit (positions are measured from X first)."""
    shape = one_body(body).shape
    x, y = square(1.5, DYADIC_DX)
    k, m, phi = 7, -5, 0.83
    moved = Pose(k * DYADIC_DX, m * DYADIC_DX, phi)
    for indicator in (plate_indicator, pill_indicator):
        here = indicator(x, y, shape, Pose(0.0, 0.0, phi))
        there = indicator(x, y, shape, moved)
        assert np.array_equal(there[k:, : m or None], here[:-k, -m:])
        assert here.max() > 0.99


def test_pills_turn_with_the_body() -> None:
    """The pill centres are X + R(phi) p_j; G peaks there and s0 / (pi rho^2) G is the
    source, its integral the supply s0 of each pill."""
    pills = [{"x": 0.2, "y": 0.0, "supply": 2.0}, {"x": -0.1, "y": 0.25, "radius": 0.08}]
    delta = 0.01
    body = one_body({"plate": {"shape": "disk", "radius": 0.5}, "pills": pills})
    shape = with_smoothing(body.shape, delta)
    pose = Pose(0.3, -0.2, math.pi / 2)
    np.testing.assert_allclose(pill_centres(shape, pose), [[0.3, 0.0], [0.05, -0.3]], atol=1e-15)
    x, y = square(1.2, delta / 4)
    total = pill_source(x, y, shape, pose).sum() * (delta / 4) ** 2
    # each pill's smoothed area times s0 / (pi rho^2); the second's s0 is camphor.supply
    expected = sum(
        s / (math.pi * r**2) * smoothed_disk_area(r, delta) for s, r in ((2.0, 0.1), (1.0, 0.08))
    )
    assert total == pytest.approx(expected, rel=1e-9)


def test_plate_velocity_is_a_rigid_motion_weighted_by_f() -> None:
    """F u with u = U + omega z x (r - X): the paper rotor's omega (-y, x) F at the
    origin, bit for bit; at the body's position it is U; its divergence F-weighted 0."""
    config = RotorConfig()
    (body,) = Setup(config).bodies
    x, y = square(1.0, 0.025)
    pose, omega = Pose(0.0, 0.0, 0.4), 3.0
    f = plate_indicator(x, y, body.shape, pose)
    assert np.array_equal(
        plate_velocity(x, y, body.shape, pose, (0.0, 0.0), omega), omega * np.stack([-y, x]) * f
    )
    disk = one_body({"plate": {"shape": "disk", "radius": 0.5}}).shape
    pose = Pose(0.25, -0.5, 0.0)
    u = plate_velocity(np.array(0.25), np.array(-0.5), disk, pose, (1.5, -2.0), omega)
    np.testing.assert_allclose(u, [1.5, -2.0], rtol=1e-15)
    u = plate_velocity(np.array(0.25), np.array(-0.45), disk, pose, (0.0, 0.0), omega)
    np.testing.assert_allclose(u, [-omega * 0.05, 0.0], rtol=1e-14)


@pytest.mark.parametrize("body", PLATES, ids=[b["plate"]["shape"] for b in PLATES])
def test_footprint_holds_every_nonzero_value(body: dict[str, Any]) -> None:
    """Beyond the footprint F_k and G_k are below 4.3e-18 (1/2 (1 + tanh(-20))), and the
    support rows of the domain hold every cell where either exceeds it."""
    config = validate_config(
        {"grid": {"domain_radius": 3.0, "domain_centre": [0.4, -0.3]}, "bodies": [body]}
    )
    (shape_body,) = Setup(config).bodies
    shape = shape_body.shape
    pose = Pose(0.6, -0.1, 1.1)
    ring = np.linspace(0, 2 * math.pi, 721)
    x = pose.x + shape.reach * np.cos(ring)
    y = pose.y + shape.reach * np.sin(ring)
    for indicator in (plate_indicator, pill_indicator):
        assert indicator(x, y, shape, pose).max() < 4.3e-18
    domain = make_domain(config.grid, RotorShape.from_config(config.geometry))
    xs, ys = np.meshgrid(domain.x_coords, domain.y_coords, indexing="ij")
    lo, hi = body_support(domain, shape, pose)
    columns = np.arange(domain.coords.size)
    inside = (columns >= lo[:, None]) & (columns < hi[:, None])
    for indicator in (plate_indicator, pill_indicator):
        values = indicator(xs, ys, shape, pose)
        assert (values[~inside] < 4.3e-18).all()
        assert (values[inside] > 0.5).any()


@pytest.mark.parametrize("body", PLATES, ids=[b["plate"]["shape"] for b in PLATES])
@pytest.mark.parametrize("widths", [3.0, 6.0, 10.0])
def test_a_cut_footprint_drops_only_its_tail(body: dict[str, Any], widths: float) -> None:
    """At ``numerics.footprint_widths`` = w the footprint is w delta beyond plate and pills:
    beyond it every pill's term and F are below the tail 1 / (1 + e^(2 w)) (so G_k below
    the pills' count times it), within a quarter delta inside it some value exceeds
    the tail / e (the footprint is no larger than the bound needs), and the contact
    radius stays the saturated footprint, 20 delta beyond plate and pills, whatever w."""
    full = one_body(body).shape
    shape = one_body(body, numerics={"footprint_widths": widths}).shape
    assert shape.widths == widths and full.widths == 20.0
    assert shape.contact == full.contact == full.reach
    assert shape.reach < full.reach
    tail = 1.0 / (1.0 + math.exp(2.0 * widths))
    count = len(shape.pills)
    pose = Pose(0.3, -0.2, 0.7)
    ring = np.linspace(0, 2 * math.pi, 3601)
    outside = shape.reach * np.linspace(1.0, 1.5, 26)[:, None]
    inside = (shape.reach - shape.smoothing / 4) * np.ones((1, 1))
    for radii, check in ((outside, "outside"), (inside, "inside")):
        x = pose.x + radii * np.cos(ring)
        y = pose.y + radii * np.sin(ring)
        f = plate_indicator(x, y, shape, pose)
        g = pill_indicator(x, y, shape, pose)
        if check == "outside":
            bound = count * tail + 1e-15  # numpy's 1 + tanh(-w) loses 1e-16
            assert f.max() < bound and g.max() < bound
        else:
            assert max(f.max(), g.max()) > tail / math.e


def test_motion_coefficients_follow_the_kind() -> None:
    """A fixed body neither turns nor translates, a fixed_axis body does not translate
    (infinite mass and inertia make force / m and torque / I vanish); a free body has its
    mass, its inertia from the rotor section and a camphor disk's friction where it leaves
    them out."""
    pill = {"pills": [{}]}
    config = validate_config(
        {
            "grid": {"domain_radius": 6.0},
            "rotor": {"inertia": 2e-5, "friction": 3e-4},
            "noise": {"sigma": 1e-7},
            "bodies": [
                {**pill, "motion": {"kind": "fixed"}},
                {**pill, "motion": {"kind": "fixed_axis"}, "start": {"x": 2.0}},
                {
                    **pill,
                    "motion": {"kind": "free", "mass": 1e-4, "inertia": 4e-5},
                    "start": {"x": -2.0, "velocity": [0.5, 0.0]},
                },
            ],
        }
    )
    fixed, axis, free = Setup(config).bodies
    assert (fixed.mass, fixed.inertia, fixed.friction) == (MOTIONLESS, MOTIONLESS, 0.0)
    assert (axis.mass, axis.inertia, axis.friction) == (MOTIONLESS, 2e-5, 3e-4)
    assert (free.mass, free.inertia, free.friction) == (1e-4, 4e-5, FREE_FRICTION)
    assert [b.noise_sigma for b in (fixed, axis, free)] == [0.0, 1e-7, 0.0]
    assert [b.name for b in (fixed, axis, free)] == ["body0", "body1", "body2"]
    assert free.velocity0 == (0.5, 0.0)
    assert all(b.protocol is None for b in (fixed, axis, free))
    assert not fixed.shape.pills.flags.writeable
