"""The consistent scheme of bodies: the contour forms against the area integrals they
rewrite, and the circles' radial rule."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.config import load_config
from pde_rotor.model.bodies import Pose, plate_indicator
from pde_rotor.model.body_schemes import (
    BodyScheme,
    contour_integrals,
    filtered_body_fields,
    ring_rule,
)
from pde_rotor.model.filtering import PROFILE_REFINEMENT, disk_profile
from pde_rotor.model.setup import Setup

DX = 0.025
BODIES = [
    {
        "name": "pair",
        "plate": {"shape": "none"},
        "pills": [{"x": 0.3, "y": 0.1}, {"x": -0.2, "y": 0.0, "radius": 0.15}],
        "motion": {"kind": "free", "mass": 1e-3, "friction": 1e-4},
        "start": {"x": 0.31, "y": -1.2, "angle": 0.3},
    },
    {
        "name": "disk",
        "plate": {"shape": "disk", "radius": 0.3},
        "pills": [{"x": 0.1, "y": 0.0}],
        "motion": {"kind": "free", "mass": 1e-3, "friction": 1e-4},
        "start": {"x": -1.3, "y": 1.3, "angle": 0.3},
    },
    {
        "name": "hexagon",
        "plate": {"shape": "polygon", "n_corners": 6, "radius": 0.5},
        "pills": [{"x": 0.3, "y": 0.0}],
        "motion": {"kind": "free", "mass": 1e-3, "friction": 1e-4},
        "start": {"x": 1.3, "y": 1.6, "angle": 0.3},
    },
    {
        "name": "strip",
        "plate": {"shape": "strip", "length": 0.7, "width": 0.2},
        "pills": [{"x": 0.1, "y": 0.0}],
        "motion": {"kind": "free", "mass": 1e-3, "friction": 1e-4},
        "start": {"x": -1.8, "y": -1.2, "angle": -0.7},
    },
]
"""Bodies of every plate; the strip's half width is 4 delta, so that the outermost band
node of the contour form (s = 5.3) has no parallel and is dropped."""


def smooth_c(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A smooth concentration and its exact gradient: (c, dc/dx, dc/dy)."""
    bump = np.exp(-((x - 0.2) ** 2 + (y - 0.1) ** 2))
    wave = 1 + 0.3 * np.sin(2 * x + y)
    grad_x = bump * (-2 * (x - 0.2) * wave + 0.6 * np.cos(2 * x + y))
    grad_y = bump * (-2 * (y - 0.1) * wave + 0.3 * np.cos(2 * x + y))
    return bump * wave, grad_x, grad_y


def consistent_surface(specs: list[dict], radius: float) -> tuple[list, BodyScheme, np.ndarray]:
    """The bodies of `specs` on the consistent scheme in a dish of `radius` (dx = DX),
    their scheme and the grid's cell centres along an axis."""
    config = RotorConfig.model_validate(
        {
            "grid": {"domain_radius": radius, "dx": DX, "dt": 1e-5},
            "numerics": {"scheme": "consistent"},
            "bodies": specs,
        }
    )
    setup = Setup(config)
    cells = 2 * math.ceil(radius / DX) + 2
    axis = DX * (np.arange(cells) - (cells - 1) / 2)
    return setup.bodies, setup.body_scheme, axis


def test_contour_forms_equal_the_area_integrals() -> None:
    """For a smooth c (its gradient exact), int F grad c dA and int F (r - X) x grad c dA
    summed over a fine grid (spacing dx / 4 about each body: at dx the tanh corners of
    the strip alias to 1e-3) equal the contour forms: with the filtered F of a circle's
    weight for the pills and the disk, with the model's F for the polygon and the strip
    (the rotor's band), to 1e-4 of the force."""
    bodies, scheme, axis = consistent_surface(BODIES, 3.5)
    c, _, _ = smooth_c(*np.meshgrid(axis, axis, indexing="ij"))
    fine = DX / 4
    for k, body in enumerate(bodies):
        pose = body.start
        contour = contour_integrals(c, (axis[0], axis[0]), DX, body.shape, pose, scheme, k)
        local = fine * np.arange(
            -math.ceil(body.shape.reach / fine), math.ceil(body.shape.reach / fine) + 1
        )
        x, y = np.meshgrid(pose.x + local, pose.y + local, indexing="ij")
        _, grad_x, grad_y = smooth_c(x, y)
        if body.shape.plate in ("polygon", "strip"):
            F = plate_indicator(x, y, body.shape, pose)
        else:
            F, _ = filtered_body_fields(
                x, y, body.shape, pose, scheme.filters[k], scheme.profile_step
            )
        rx, ry = x - pose.x, y - pose.y
        moments = [np.sum(F * grad_x), np.sum(F * grad_y), np.sum(F * (rx * grad_y - ry * grad_x))]
        area = fine * fine * np.array(moments)
        assert np.abs(contour - area).max() <= 1e-4 * np.abs(area[:2]).max(), body.name
    disk = bodies[1]
    torque = contour_integrals(c, (axis[0], axis[0]), DX, disk.shape, disk.start, scheme, 1)[2]
    assert torque == pytest.approx(0.0, abs=1e-15)  # a disk plate feels no torque about X


@pytest.mark.parametrize("radius", [0.1, 0.3])
def test_ring_rule_integrates_the_filtered_profiles_slope(radius: float) -> None:
    """The circle's radial rule: the weights add up to f_eps(0) (the integral of
    -f_eps' from the centre out), the first moment to int f_eps dh, and the radii are
    the midpoints of half cells (the midpoint rule: to 1e-4)."""
    step = DX / PROFILE_REFINEMENT
    profile = disk_profile(radius, 0.025, DX, ("gaussian", 0.7))
    radii, weights = ring_rule(profile, step, DX, radius + 20 * 0.025)
    assert weights.sum() == pytest.approx(profile[0], rel=1e-4)
    d = np.arange(profile.size) * step
    integral = np.sum(0.5 * (profile[1:] + profile[:-1])) * step
    assert np.sum(weights * radii) == pytest.approx(integral, rel=1e-4)
    np.testing.assert_allclose(np.diff(radii), DX / 2, rtol=1e-12)
    assert radii[0] == pytest.approx(DX / 4) and radii[-1] < d[-1]


@pytest.mark.parametrize("widths", [4.0, 8.0])
def test_ring_rule_ends_at_a_cut_footprint(widths: float) -> None:
    """With ``numerics.footprint_widths`` = w a circle's rule ends at its reach,
    rho + w delta (F_eps is not drawn beyond it): its half cells lie within, the rule keeps
    the radii of the full rule below it with their weights, and the weight it drops is
    the filtered profile's value at its last half cell's edge, to the midpoint rule's
    error on a tail that falls e-fold per half delta (4 %)."""
    rho, delta = 0.1, 0.025
    step = DX / PROFILE_REFINEMENT
    profile = disk_profile(rho, delta, DX, ("sharpened", 0.95))
    full = ring_rule(profile, step, DX, rho + 20 * delta)
    reach = rho + widths * delta
    cut = ring_rule(profile, step, DX, reach)
    assert cut[0, -1] + DX / 4 <= reach < cut[0, -1] + 3 * DX / 4  # whole half cells within
    assert cut.shape[1] < full.shape[1]
    np.testing.assert_array_equal(cut, full[:, : cut.shape[1]])
    dropped = full[1, cut.shape[1] :].sum()
    value = np.interp(cut[0, -1] + DX / 4, np.arange(profile.size) * step, profile)
    assert dropped == pytest.approx(value, rel=0.1)
    assert abs(value) > 1e-12


def test_default_footprint_keeps_every_shipped_circle_rule() -> None:
    """At the default footprint (20 delta) every shipped bodies config's circles end
    where their weight falls below its cutoff, short of the footprint: the rules, and the
    runs, of before the footprint could be cut."""
    checked = 0
    for path in sorted(Path("configs/bodies").glob("*.yaml")):
        config = load_config(path, ["numerics.scheme=consistent"])
        setup = Setup(config)
        checked += 1
        for body, filt in zip(setup.bodies, setup.body_scheme.filters, strict=True):
            for ring, end in zip(filt.rings, _circle_reaches(body.shape), strict=True):
                assert ring[0, -1] + DX < end
    assert checked >= 10


def _circle_reaches(shape) -> list[float]:
    """The reach rho + 20 delta (R + 20 delta) of each circle of a body's contour form."""
    margin = 20 * shape.smoothing
    if shape.plate == "none":
        return [float(r) + margin for r in shape.pills[:, 2]]
    return [shape.radius + margin] if shape.plate == "disk" else []


def test_square_strip_is_the_square_polygon() -> None:
    """A square strip (L = W = 2a) is the 4-gon of apothem a turned by pi/4: the same
    F_eps to the tables' accuracy (each its own table, of second order at the corners'
    creases: 5e-4 at dx / 8, as tests/model/test_filtering.py checks) and the same
    contour forms of the force and torque (the same nodes: to rounding)."""
    a = 0.3
    square = [
        {
            "name": "strip",
            "plate": {"shape": "strip", "length": 2 * a, "width": 2 * a},
            "start": {"x": -1.3, "y": 0.0},
        },
        {
            "name": "square",
            "plate": {"shape": "polygon", "n_corners": 4, "radius": a * math.sqrt(2)},
            "start": {"x": 1.3, "y": 0.0},
        },
    ]
    for body in square:
        body.update(
            pills=[{"x": 0.05, "y": 0.0}], motion={"kind": "free", "mass": 1e-3, "friction": 1e-4}
        )
    bodies, scheme, axis = consistent_surface(square, 3.0)
    x, y = np.meshgrid(axis, axis, indexing="ij")
    c, _, _ = smooth_c(x, y)
    phi = 0.37
    pose = Pose(0.31, -0.12, phi)
    F = [
        filtered_body_fields(x, y, b.shape, Pose(pose.x, pose.y, phi + turn), f, DX / 256)[0]
        for b, f, turn in zip(bodies, scheme.filters, (math.pi / 4, 0.0), strict=True)
    ]
    assert np.abs(F[0] - F[1]).max() < 5e-4
    assert F[0].sum() * DX * DX == pytest.approx(F[1].sum() * DX * DX, rel=1e-4)
    forces = [
        contour_integrals(
            c, (axis[0], axis[0]), DX, b.shape, Pose(pose.x, pose.y, phi + t), scheme, k
        )
        for k, (b, t) in enumerate(zip(bodies, (math.pi / 4, 0.0), strict=True))
    ]
    np.testing.assert_allclose(forces[0], forces[1], rtol=1e-12, atol=1e-14)
    assert np.abs(forces[0][:2]).max() > 1e-3  # c pulls on them
