"""pde_rotor.theory.free_disk: K(lambda), the critical friction, the growth rate and the
pitchfork of a free disk against independent solves (the lab-frame finite volumes of
:mod:`tests.theory.lab_frame`, the exact drive of a translating disk against its weakly
nonlinear expansion), and docs/bodies.md's table of them."""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

from pde_rotor.theory import free_disk
from pde_rotor.theory.disk import Wall, free_disk_displacement_force, rest_concentration
from pde_rotor.theory.free_disk import (
    free_disk_critical_friction,
    free_disk_cubic_coefficient,
    free_disk_drive,
    free_disk_force_coefficient,
    free_disk_growth_rate,
    free_disk_smoothed_coefficients,
    free_disk_steady_speed,
)

from .lab_frame import radial_lab_frame

DOCS = Path(__file__).resolve().parents[2] / "docs" / "bodies.md"


def test_force_coefficient_is_the_smoothed_solve_as_delta_shrinks(disk):
    """K(0) in closed form against radial finite volumes with the tanh indicator: the
    critical friction K/A agrees to 1e-4 at delta = rho / 40 and the error falls with
    delta; at a growth rate lambda = 0.5 a, K agrees to 1e-3 (the larger smoothed
    area, 1 + pi^2 delta^2 / (12 rho^2), stays in K alone)."""
    mu_c = free_disk_critical_friction(disk)
    errors = []
    for delta in (disk.radius / 20, disk.radius / 40):
        force, area = free_disk_smoothed_coefficients(disk, delta)
        errors.append(abs(force / area / mu_c - 1))
    assert errors[1] < errors[0]
    assert errors[1] < 1e-4
    lam = 0.5 * disk.evaporation
    force, _ = free_disk_smoothed_coefficients(disk, disk.radius / 40, lam)
    assert force == pytest.approx(free_disk_force_coefficient(disk, lam), rel=1e-3)


def test_force_coefficient_is_the_lab_frame_solve_on_a_wide_surface(disk):
    """K(0) = dPhi/dlambda at 0 and K(0.5 a) = Phi(0.5 a)/0.5 a from this file's lab-frame
    finite volumes (delta = rho / 40, a dish of radius 10 whose wall acts at e^-20):
    the closed forms to 1e-3 (the smoothed disk's extra area is 5e-4)."""
    wall, delta, eps = Wall(10.0, "absorbing"), disk.radius / 40, 1e-3

    def phi(lam: float) -> float:
        return radial_lab_frame(disk, delta, delta / 32, lam, wall)[2].real

    slope = (phi(eps) - phi(-eps)) / (2 * eps)
    assert slope == pytest.approx(free_disk_force_coefficient(disk), rel=1e-3)
    lam = 0.5 * disk.evaporation
    assert phi(lam) / lam == pytest.approx(free_disk_force_coefficient(disk, lam), rel=1e-3)


def test_chebyshev_modes_reproduce_the_closed_forms(disk):
    """The radial Chebyshev panels (the machinery of the nonlinear drive) give c0 and
    K(0) to 1e-10: sharp matching at rho, no smoothing to extrapolate."""
    grid = free_disk._modes_for(disk, 0.0, 1, 24)
    rest = np.linalg.solve(grid.mode_operator(0).toarray(), grid.source())
    assert np.max(np.abs(rest - rest_concentration(disk, grid.r))) < 1e-10
    first = np.linalg.solve(grid.mode_operator(1).toarray(), -grid.x_derivative({0: rest})[1])
    assert grid.force(first) == pytest.approx(free_disk_force_coefficient(disk), rel=1e-10)


def test_force_coefficient_is_continuous_through_zero(disk):
    """K(lambda) = Phi(lambda)/lambda and its Taylor polynomial near 0 join smoothly, and
    Phi(lambda)/lambda tends to the closed form K(0)."""
    below = 0.9999 * free_disk.SMALL_RATE * disk.evaporation
    quotient = free_disk_displacement_force(disk, below) / below
    assert free_disk_force_coefficient(disk, below) == pytest.approx(quotient, rel=1e-8)
    quotient = free_disk_displacement_force(disk, 1e-2) / 1e-2
    slope = (free_disk_force_coefficient(disk, 1e-2) - free_disk_force_coefficient(disk)) / 1e-2
    assert quotient == pytest.approx(free_disk_force_coefficient(disk) + 1e-2 * slope, rel=1e-12)
    assert free_disk_displacement_force(disk, 0.0) == pytest.approx(0.0, abs=1e-14)


@pytest.mark.parametrize("x", np.geomspace(1e-3, 1e2, 11))
def test_a_free_disk_self_propels_at_every_size(disk, x):
    """K(0) > 0 for every q rho: the front of a moving disk holds less camphor than its
    back, so the surface tension (gamma0 - k c) pulls it forward, and the disk moves by
    itself below the critical friction. K decreases with lambda."""
    sized = dataclasses.replace(disk, radius=x / disk.decay)
    assert free_disk_force_coefficient(sized) > 0
    assert free_disk_force_coefficient(sized, 0.1) < free_disk_force_coefficient(sized)


def test_growth_rate_changes_sign_at_the_critical_friction(disk):
    mu_c = free_disk_critical_friction(disk)
    assert abs(free_disk_growth_rate(disk, mu_c)) < 1e-9
    assert free_disk_growth_rate(disk, 0.95 * mu_c) > 0
    assert free_disk_growth_rate(disk, 1.05 * mu_c) < 0
    mass = 1e-3
    lam = free_disk_growth_rate(disk, 0.9 * mu_c, mass)
    balance = free_disk_force_coefficient(disk, lam) - 0.9 * mu_c * disk.area
    assert balance == pytest.approx(mass * lam, rel=1e-9)
    assert lam < free_disk_growth_rate(disk, 0.9 * mu_c)


def test_growth_rate_refuses_a_friction_beyond_the_continuous_spectrum(disk):
    with pytest.raises(ValueError, match="sublimation rate"):
        free_disk_growth_rate(disk, 100 * free_disk_critical_friction(disk))


def test_cubic_coefficient_is_the_exact_drive_expanded(disk):
    """(f(U) - K U) / U^3 -> K3 as U -> 0, the exact drive solving all Fourier modes at
    once; K3 < 0: the pitchfork is supercritical."""
    k0 = free_disk_force_coefficient(disk)
    k3 = free_disk_cubic_coefficient(disk)
    ratios = [(free_disk_drive(disk, u) - k0 * u) / u**3 for u in (0.02, 0.04)]
    extrapolated = (4 * ratios[0] - ratios[1]) / 3  # the next term is O(U^2)
    assert extrapolated == pytest.approx(k3, rel=1e-4)
    assert k3 < 0


def test_drive_converges_in_modes_and_nodes(disk):
    coarse = free_disk_drive(disk, 1.0, modes=12, nodes=12)
    fine = free_disk_drive(disk, 1.0, modes=20, nodes=20)
    assert coarse == pytest.approx(fine, rel=1e-6)
    assert fine < free_disk_force_coefficient(disk) * 1.0  # f(U) < K(0) U: it saturates


def test_steady_speed_follows_the_pitchfork_near_onset(disk):
    """U^2 = pi rho^2 (mu_c - mu) / |K3| close to mu_c, and U solves f(U) = mu A U."""
    mu_c = free_disk_critical_friction(disk)
    mu = mu_c * (1 - 2e-3)
    speed = free_disk_steady_speed(disk, mu)
    expected = math.sqrt(disk.area * (mu_c - mu) / abs(free_disk_cubic_coefficient(disk)))
    assert speed == pytest.approx(expected, rel=5e-3)  # the next order is O(mu_c - mu)
    assert free_disk_drive(disk, speed) == pytest.approx(mu * disk.area * speed, rel=1e-8)
    assert free_disk_steady_speed(disk, 1.01 * mu_c) == 0.0


def test_docs_table_of_free_disk_onsets_is_the_closed_form(disk):
    """docs/bodies.md's table: mu_c and K3 for each rho, from the code."""
    text = DOCS.read_text(encoding="utf-8")
    tag = "<!-- docs-test: free-disk -->"
    assert tag in text
    rows = []
    for line in text.split(tag, 1)[1].lstrip("\n").splitlines():
        if not line.startswith("|"):
            break
        rows.append(line)
    body = rows[2:]
    assert len(body) >= 3
    for row in body:
        cells = [cell.strip() for cell in row.strip("|").split("|")]
        rho, mu_c, k3 = (
            float(re.sub(r"[^0-9.e+-]", "", c.replace("\u2212", "-"))) for c in cells[:3]
        )
        sized = dataclasses.replace(disk, radius=rho)
        assert mu_c == pytest.approx(free_disk_critical_friction(sized), rel=1e-4), row
        assert k3 == pytest.approx(free_disk_cubic_coefficient(sized), rel=1e-3), row
