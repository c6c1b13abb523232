"""The consistent scheme of bodies: the contour forms against the area integrals they
rewrite, and the circles' radial rule."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.model.bodies import make_bodies, plate_indicator
from pde_rotor.model.body_schemes import (
    BodyScheme,
    contour_integrals,
    filtered_body_fields,
    ring_rule,
)
from pde_rotor.model.filtering import PROFILE_REFINEMENT, disk_profile

DX = 0.025
BODIES = [
    {
        "name": "pair",
        "plate": {"shape": "none"},
        "pills": [{"x": 0.3, "y": 0.1}, {"x": -0.2, "y": 0.0, "radius": 0.15}],
        "motion": {"kind": "free", "mass": 1e-3},
        "start": {"x": 0.31, "y": -1.2, "angle": 0.3},
    },
    {
        "name": "disk",
        "plate": {"shape": "disk", "radius": 0.3},
        "pills": [{"x": 0.1, "y": 0.0}],
        "motion": {"kind": "free", "mass": 1e-3},
        "start": {"x": -1.3, "y": 1.3, "angle": 0.3},
    },
    {
        "name": "hexagon",
        "plate": {"shape": "polygon", "n_corners": 6, "radius": 0.5},
        "pills": [{"x": 0.3, "y": 0.0}],
        "motion": {"kind": "free", "mass": 1e-3},
        "start": {"x": 1.3, "y": 1.6, "angle": 0.3},
    },
]


def test_contour_forms_equal_the_area_integrals() -> None:
    """For a smooth c (its gradient exact), int F grad c dA and int F (r - X) x grad c dA
    summed over a fine grid equal the contour forms: with the filtered F of a circle's
    weight for the pills and the disk, with the model's F for the polygon (the rotor's
    band), to 1e-4 of the force."""
    config = RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 3.5, "dx": DX, "dt": 1e-5},
            "numerics": {"scheme": "consistent"},
            "bodies": BODIES,
        }
    )
    bodies = make_bodies(config)
    scheme = BodyScheme.from_config(config, bodies)
    axis = DX * (np.arange(2 * math.ceil(3.5 / DX) + 2) - (2 * math.ceil(3.5 / DX) + 1) / 2)
    x, y = np.meshgrid(axis, axis, indexing="ij")
    bump = np.exp(-((x - 0.2) ** 2 + (y - 0.1) ** 2))
    wave = 1 + 0.3 * np.sin(2 * x + y)
    c = bump * wave
    grad_x = bump * (-2 * (x - 0.2) * wave + 0.6 * np.cos(2 * x + y))
    grad_y = bump * (-2 * (y - 0.1) * wave + 0.3 * np.cos(2 * x + y))
    for k, body in enumerate(bodies):
        pose = body.start
        contour = contour_integrals(c, (x[0, 0], y[0, 0]), DX, body.shape, pose, scheme, k)
        if body.shape.plate == "polygon":
            F = plate_indicator(x, y, body.shape, pose)
        else:
            F, _ = filtered_body_fields(
                x, y, body.shape, pose, scheme.filters[k], scheme.profile_step
            )
        rx, ry = x - pose.x, y - pose.y
        area = (
            DX
            * DX
            * np.array(
                [np.sum(F * grad_x), np.sum(F * grad_y), np.sum(F * (rx * grad_y - ry * grad_x))]
            )
        )
        assert np.abs(contour - area).max() <= 1e-4 * np.abs(area[:2]).max(), body.name
    assert contour_integrals(c, (x[0, 0], y[0, 0]), DX, bodies[1].shape, pose, scheme, 1)[
        2
    ] == pytest.approx(0.0, abs=1e-15)  # a disk plate feels no torque about its centre


@pytest.mark.parametrize("radius", [0.1, 0.3])
def test_ring_rule_integrates_the_filtered_profiles_slope(radius: float) -> None:
    """The circle's radial rule: the weights add up to f_eps(0) (the integral of
    -f_eps' from the centre out), the first moment to int f_eps dh, and the radii are
    the midpoints of half cells (the midpoint rule: to 1e-4)."""
    step = DX / PROFILE_REFINEMENT
    profile = disk_profile(radius, 0.025, DX, ("gaussian", 0.7))
    radii, weights = ring_rule(profile, step, DX)
    assert weights.sum() == pytest.approx(profile[0], rel=1e-4)
    d = np.arange(profile.size) * step
    integral = np.sum(0.5 * (profile[1:] + profile[:-1])) * step
    assert np.sum(weights * radii) == pytest.approx(integral, rel=1e-4)
    np.testing.assert_allclose(np.diff(radii), DX / 2, rtol=1e-12)
    assert radii[0] == pytest.approx(DX / 4) and radii[-1] < d[-1]
