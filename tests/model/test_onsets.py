"""The onsets of docs/bodies.md: closed forms against independent numerical solves.

The independent solves are written here, not taken from the module: a radial finite-volume
solve of Eq. (eqc) in the lab frame (rest state and the displaced disk), and the exact
drive of a translating disk against the weakly nonlinear expansion. Parameters are the
schema's defaults (pde_rotor.config.RotorConfig()).
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import fsolve
from scipy.sparse.linalg import spsolve

from pde_rotor.config import RotorConfig
from pde_rotor.model import onsets
from pde_rotor.model.onsets import (
    CamphorDisk,
    Wall,
    dish_drift_rate,
    dish_hopf_onset,
    dish_hopf_rate,
    free_disk_critical_friction,
    free_disk_cubic_coefficient,
    free_disk_displacement_force,
    free_disk_drive,
    free_disk_force_coefficient,
    free_disk_growth_rate,
    free_disk_smoothed_coefficients,
    free_disk_steady_speed,
    rest_concentration,
    rotor_critical_friction,
    rotor_critical_half_length,
    rotor_friction_moment,
    rotor_grid,
    rotor_growth_rate,
    rotor_torque_coefficient,
)

DOCS = Path(__file__).resolve().parents[2] / "docs" / "bodies.md"


@pytest.fixture(scope="module")
def disk() -> CamphorDisk:
    return CamphorDisk.from_config(RotorConfig())


def radial_lab_frame(
    disk: CamphorDisk, smoothing: float, spacing: float, lam: complex, wall: Wall
) -> tuple[np.ndarray, np.ndarray, complex]:
    """Radial finite volumes of the rest state and the displaced disk, in the lab frame.

    Cells of width `spacing` fill [0, L]; the wall sits on the last face. F = G is the
    tanh indicator of width `smoothing` (0: a step, rho on a face). Displacing the disk by
    X along x adds -(X . grad F)(a c0 + S) to Eq. (eqc), so the cos(theta) mode h of the
    field obeys (D L_1 - a (1 - F) - lambda) h = F' (a c0 + S), and the force per unit
    displacement is k pi int F' (h + c0') r dr (docs/bodies.md, "Dish").

    Returns:
        (cell centres, c0, Phi(lambda)).
    """
    n = round(wall.radius / spacing)
    r = (np.arange(n) + 0.5) * spacing
    faces = np.arange(n + 1) * spacing
    if smoothing == 0:
        indicator, slope = (r < disk.radius).astype(float), None
    else:
        edge = np.tanh((disk.radius - r) / smoothing)
        indicator, slope = 0.5 * (1 + edge), -(1 - edge**2) / (2 * smoothing)
    inner = faces[:-1] / (r * spacing**2)
    outer = faces[1:] / (r * spacing**2)

    def operator(order: int, rate: complex) -> sp.csc_matrix:
        main = -inner - outer - order**2 / r**2
        main[-1] += outer[-1] if wall.condition == "no_flux" else -outer[-1]
        lap = sp.diags([inner[1:], main, outer[:-1]], [-1, 0, 1])
        sink = disk.evaporation * (1 - indicator) + rate
        return (disk.diffusion * lap.tocsc() - sp.diags(sink)).tocsc()

    rest = spsolve(operator(0, 0.0), -disk.source * indicator).real
    if slope is None:
        return r, rest, math.nan
    drive = slope * (disk.evaporation * rest + disk.source)
    mode = spsolve(operator(1, complex(lam)), drive.astype(complex))
    force = disk.tension_slope * math.pi * np.sum(slope * (mode + np.gradient(rest, r)) * r)
    return r, rest, complex(force * spacing)


# --- free disk: rest state and linear response ---------------------------------------------


def test_config_defaults_make_the_disk(disk):
    cfg = RotorConfig()
    assert disk.radius == cfg.geometry.pill_radius
    assert disk.supply == cfg.camphor.supply
    assert disk.source * disk.area == pytest.approx(cfg.camphor.supply)


def test_rest_state_is_the_radial_solve_with_a_sharp_disk(disk):
    """c0 in closed form against finite volumes with F a step (rho on a face), on a dish
    of radius 12 (far enough that its wall changes c0 near the disk by < 1e-10)."""
    wall = Wall(12.0, "absorbing")
    r, rest, _ = radial_lab_frame(disk, 0.0, disk.radius / 100, 0.0, wall)
    near = r < 3.0
    exact = rest_concentration(disk, r[near])
    assert np.max(np.abs(rest[near] - exact)) < 1e-5 * exact.max()
    assert np.allclose(rest_concentration(disk, r[near], wall), exact, atol=1e-9)


@pytest.mark.parametrize("condition", ["absorbing", "no_flux"])
def test_rest_state_in_a_dish_meets_its_wall(disk, condition):
    wall = Wall(1.5, condition)
    r, rest, _ = radial_lab_frame(disk, 0.0, disk.radius / 100, 0.0, wall)
    exact = rest_concentration(disk, r, wall)
    assert np.max(np.abs(rest - exact)) < 1e-5 * exact.max()
    edge = rest_concentration(disk, np.array([wall.radius - 1e-6, wall.radius]), wall)
    if condition == "absorbing":
        assert edge[1] == pytest.approx(0.0, abs=1e-14)
    else:
        assert abs(edge[1] - edge[0]) < 1e-12


def test_rest_state_carries_the_whole_supply_through_the_rim(disk):
    """-2 pi rho D dc0/dr(rho) = s0 from either side of the rim: everything the disk
    supplies leaves through its rim (one-sided second-order differences)."""
    h = 1e-4 * disk.radius
    for side in (-1, 1):
        c = rest_concentration(disk, disk.radius + side * h * np.arange(3))
        slope = side * (-3 * c[0] + 4 * c[1] - c[2]) / (2 * h)
        flux = -2 * math.pi * disk.radius * disk.diffusion * slope
        assert flux == pytest.approx(disk.supply, rel=1e-6)


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
    grid = onsets._modes_for(disk, 0.0, 1, 24)
    rest = np.linalg.solve(grid.mode_operator(0).toarray(), grid.source())
    assert np.max(np.abs(rest - rest_concentration(disk, grid.r))) < 1e-10
    first = np.linalg.solve(grid.mode_operator(1).toarray(), -grid.x_derivative({0: rest})[1])
    assert grid.force(first) == pytest.approx(free_disk_force_coefficient(disk), rel=1e-10)


def test_force_coefficient_is_continuous_through_zero(disk):
    """K(lambda) = Phi(lambda)/lambda and its Taylor polynomial near 0 join smoothly, and
    Phi(lambda)/lambda tends to the closed form K(0)."""
    below = 0.9999 * onsets.SMALL_RATE * disk.evaporation
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


# --- free disk: the pitchfork ------------------------------------------------------------


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


# --- a disk in a dish ----------------------------------------------------------------------


@pytest.mark.parametrize("condition", ["absorbing", "no_flux"])
@pytest.mark.parametrize("lam", [0.0, 0.3, 0.4j])
def test_dish_force_is_the_lab_frame_radial_solve(disk, condition, lam):
    """Phi(lambda) from Bessel functions with the wall against the lab-frame finite volumes
    (smoothed F = G, delta = rho / 40, 32 cells per delta): agreement to 1e-3 K(0)."""
    wall = Wall(1.5, condition)
    delta = disk.radius / 40
    _, _, numeric = radial_lab_frame(disk, delta, delta / 32, lam, wall)
    exact = free_disk_displacement_force(disk, lam, wall)
    assert abs(numeric - exact) < 1e-3 * free_disk_force_coefficient(disk)


def test_walls_push_and_pull(disk):
    """A no-flux wall holds the disk at the centre (F(0) < 0, camphor piles up at the
    wall); an absorbing one pulls it away (F(0) > 0), so the centre has no Hopf onset."""
    assert free_disk_displacement_force(disk, 0.0, Wall(2.0, "no_flux")) < 0
    assert free_disk_displacement_force(disk, 0.0, Wall(2.0, "absorbing")) > 0
    with pytest.raises(ValueError, match="does not hold"):
        dish_hopf_onset(disk, Wall(2.0, "absorbing"))
    mu_c = free_disk_critical_friction(disk)
    assert dish_drift_rate(disk, Wall(3.0, "absorbing"), 2 * mu_c) > 0
    assert math.isnan(dish_drift_rate(disk, Wall(3.0, "no_flux"), 2 * mu_c))


def test_hopf_onset_is_a_pair_of_imaginary_roots(disk):
    """At (mu_c, omega_c) lambda = i omega_c solves m lambda^2 + mu A lambda - Phi(lambda) = 0,
    and the root moves into Re lambda > 0 as mu falls below mu_c."""
    wall = Wall(2.0, "no_flux")
    mass = 1e-3
    mu_c, omega = dish_hopf_onset(disk, wall, mass)

    def chi(lam: complex, mu: float) -> complex:
        return mass * lam**2 + mu * disk.area * lam - free_disk_displacement_force(disk, lam, wall)

    assert abs(chi(1j * omega, mu_c)) < 1e-12
    for factor, sign in ((0.99, 1), (1.01, -1)):

        def parts(z, mu=factor * mu_c):
            value = chi(complex(z[0], z[1]), mu)
            return [value.real, value.imag]

        root = fsolve(parts, [0.0, omega], xtol=1e-13)
        assert abs(chi(complex(*root), factor * mu_c)) < 1e-12
        assert np.sign(root[0]) == sign


def test_hopf_rate_follows_the_pair_from_the_onset(disk):
    """dish_hopf_rate solves the characteristic equation, is i omega_c at mu_c, and its
    real part falls through 0 there (the same root fsolve finds from i omega_c)."""
    wall = Wall(3.0, "no_flux")
    mass = 1e-4
    mu_c, omega = dish_hopf_onset(disk, wall, mass)
    assert dish_hopf_rate(disk, wall, mu_c, mass) == pytest.approx(1j * omega, abs=1e-10)
    rates = [dish_hopf_rate(disk, wall, f * mu_c, mass) for f in (0.97, 0.99, 1.01, 1.03)]
    assert rates[0].real > rates[1].real > 0 > rates[2].real > rates[3].real
    for factor, lam in zip((0.97, 0.99, 1.01, 1.03), rates, strict=True):
        force = free_disk_displacement_force(disk, lam, wall)
        assert abs(mass * lam**2 + factor * mu_c * disk.area * lam - force) < 1e-12
        assert lam.imag > 0


def test_dish_onset_tends_to_the_free_disk(disk):
    """As the wall recedes the Hopf frequency falls to 0 and mu_c tends to the free disk's."""
    mu_c = free_disk_critical_friction(disk)
    far = [dish_hopf_onset(disk, Wall(radius, "no_flux")) for radius in (3.0, 5.0, 8.0)]
    assert far[0][1] > far[1][1] > far[2][1]
    assert far[2][1] < 1e-2
    assert far[2][0] == pytest.approx(mu_c, rel=1e-5)


# --- the two-disk rotor ---------------------------------------------------------------------


def test_rotor_rest_field_balances_supply_and_sublimation(disk):
    """Integrating Eq. (eqc) at rest: int a (1 - F) c0 dA = S int G dA."""
    grid = rotor_grid(disk, 0.5, 0.01, 0.005)
    rest = onsets._rest_field(disk, grid)
    weights = 4 * np.outer(onsets._trapezoid(grid.x), onsets._trapezoid(grid.y))
    lost = np.sum(weights * disk.evaporation * (1 - grid.indicator) * rest)
    supplied = np.sum(weights * disk.source * grid.indicator)
    assert lost == pytest.approx(supplied, rel=1e-3)


def test_far_apart_rotor_is_two_free_disks(disk):
    """For l >> sqrt(D/a) each disk moves like a free disk at speed omega l:
    K_rot -> 2 l^2 K(0) (here with the smoothed disks' extra area pi^2 delta^2 / 12)."""
    half_length, delta = 4.0, disk.radius / 10
    torque = rotor_torque_coefficient(disk, half_length, smoothing=delta)
    area_factor = 1 + math.pi**2 * delta**2 / (12 * disk.radius**2)
    free = 2 * half_length**2 * free_disk_force_coefficient(disk) * area_factor
    assert torque == pytest.approx(free, rel=1.5e-3)


def test_rotor_critical_friction_rises_to_the_free_disks(disk):
    """mu_c(l) grows with l toward the free disk's (the rotor has a critical size at
    frictions between its contact value and the free disk's)."""
    delta = disk.radius / 10
    values = [rotor_critical_friction(disk, length, delta) for length in (0.2, 0.5, 2.0)]
    assert values[0] < values[1] < values[2] < free_disk_critical_friction(disk)
    assert values[2] == pytest.approx(free_disk_critical_friction(disk), rel=1e-2)


def test_rotor_friction_moment_is_the_smoothed_one_in_the_limit(disk):
    moment = onsets._grid_friction_moment(disk, 0.5, disk.radius / 40)
    assert moment == pytest.approx(rotor_friction_moment(disk, 0.5), rel=2e-3)


def test_paper_friction_has_no_critical_rotor_size(disk):
    """At the paper's mu = 1e-4 every two-disk rotor turns: mu_c at contact is far above."""
    with pytest.raises(ValueError, match="no critical size"):
        rotor_critical_half_length(disk, RotorConfig().rotor.friction, smoothing=0.02)


def test_rotor_growth_rate_vanishes_at_the_critical_friction(disk):
    """I lambda = K_rot(lambda) - mu J has its root at 0 exactly at mu_c(l), and grows
    below it (at the simulation's delta, where the grid is cheap)."""
    delta, length = RotorConfig().geometry.smoothing, 0.5
    mu_c = rotor_critical_friction(disk, length, delta)
    inertia = RotorConfig().rotor.inertia
    assert abs(rotor_growth_rate(disk, length, mu_c, inertia, delta)) < 1e-6
    assert rotor_growth_rate(disk, length, 0.9 * mu_c, inertia, delta) > 0


# --- the docs ------------------------------------------------------------------------------


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


def test_bad_inputs_are_refused_in_one_line():
    cfg = RotorConfig()
    with pytest.raises(ValueError, match="evaporation must be > 0"):
        dataclasses.replace(CamphorDisk.from_config(cfg), evaporation=0.0)
    with pytest.raises(ValueError, match="no_flux"):
        Wall(3.0, "reflecting")
