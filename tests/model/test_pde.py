"""Physics of the model: analytic steady states of Eqs. (eqv) and (eqc), the torque sign of
Eq. (torque), mirror symmetry, and the spin-up of Eq. (eq_motion).

The analytic tests call the compiled field kernels of pde_rotor.solver.rotor directly, with
indicator arrays F and G of a test geometry (a disk instead of the polygon, one pill at
the origin), and iterate them to the steady state from c = v = 0.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from pde.trackers import CallbackTracker
from scipy.special import i0, i1, k0, k1

from pde_rotor import RotorConfig, Simulation
from pde_rotor.kernels.cpu import euler_fields
from pde_rotor.kernels.records import make_record
from pde_rotor.model.pde import RotorPDE

# fine enough for < 1 % against the Bessel solutions, small enough to take ~1 s each
ANALYTIC_GRID = {"domain_radius": 1.5, "dx": 0.025, "dt": 1e-5}
# tanh edges of the test disks half a cell wide (sharp, yet sampled smoothly)
ANALYTIC_SMOOTHING = 0.5 * ANALYTIC_GRID["dx"]


def smooth_disk(r: np.ndarray, radius: float, width: float) -> np.ndarray:
    """The paper's tanh indicator of a disk: 1/2 (1 + tanh((radius - r) / width))."""
    return 0.5 * (1.0 + np.tanh((radius - r) / width))


def relax(
    step: Callable[[np.ndarray, np.ndarray], None], state: np.ndarray, n_steps: int
) -> np.ndarray:
    """Apply ``step(cur, nxt)`` n_steps times, swapping buffers; returns the final state."""
    cur, nxt = state, np.zeros_like(state)
    for _ in range(n_steps):
        step(cur, nxt)
        cur, nxt = nxt, cur
    return cur


def rotating_disk_flow(
    r: np.ndarray, radius: float, big_l: float, eta: float, eta_b: float, d_eta: float, omega: float
) -> np.ndarray:
    """Steady azimuthal flow v_theta(r) of Eq. (eqv) around a disk rotating at omega.

    With F = 1 for r < R and 0 outside, v = v_theta(r) e_theta and the vector Laplacian
    of such a field is (v'' + v'/r - v/r^2) e_theta, so Eq. (eqv) at steady state reads

        D_eta (v'' + v'/r - v/r^2) - eta_b v + eta F (omega r - v) = 0.

    Inside, r is annihilated by the operator, so v_p = eta omega r / (eta + eta_b) is a
    particular solution and the regular homogeneous one is I1(k_in r),
    k_in = sqrt((eta + eta_b) / D_eta): v = A I1(k_in r) + v_p. Outside,
    v = B I1(k_out r) + C K1(k_out r), k_out = sqrt(eta_b / D_eta), with v(L) = 0.
    A, B, C follow from v(L) = 0 and continuity of v and v' at r = R
    (I1' = I0 - I1/x, K1' = -K0 - K1/x).
    """
    k_in = math.sqrt((eta + eta_b) / d_eta)
    k_out = math.sqrt(eta_b / d_eta)
    slope = eta * omega / (eta + eta_b)

    def di1(x: float) -> float:
        return i0(x) - i1(x) / x

    def dk1(x: float) -> float:
        return -k0(x) - k1(x) / x

    xi, xo, xl = k_in * radius, k_out * radius, k_out * big_l
    matrix = np.array(
        [
            [i1(xi), -i1(xo), -k1(xo)],
            [k_in * di1(xi), -k_out * di1(xo), -k_out * dk1(xo)],
            [0.0, i1(xl), k1(xl)],
        ]
    )
    a, b, c = np.linalg.solve(matrix, [-slope * radius, -slope, 0.0])
    inside = a * i1(k_in * r) + slope * r
    outside = b * i1(k_out * r) + c * k1(k_out * r)
    return np.where(r < radius, inside, outside)


def single_pill_concentration(
    r: np.ndarray, rho: float, big_l: float, diff: float, evap: float, source: float
) -> np.ndarray:
    """Steady c(r) of Eq. (eqc) with v = 0, F = 0 and one pill of radius rho at the origin.

    D (c'' + c'/r) - a c + s G = 0 with G = 1 for r < rho. With k = sqrt(a / D):
    inside c = s / a + A I0(k r) (regular at 0); outside c = B I0(k r) + C K0(k r) with
    c(L) = 0. Continuity of c and c' at rho (I0' = I1, K0' = -K1) fixes A, B, C.
    For L -> infinity, B -> 0 and the outside solution is the pure K0 decay.
    """
    k = math.sqrt(evap / diff)
    x, xl = k * rho, k * big_l
    matrix = np.array(
        [
            [i0(x), -i0(x), -k0(x)],
            [i1(x), -i1(x), k1(x)],
            [0.0, i0(xl), k0(xl)],
        ]
    )
    a, b, c = np.linalg.solve(matrix, [-source / evap, 0.0, 0.0])
    inside = source / evap + a * i0(k * r)
    outside = b * i0(k * r) + c * k0(k * r)
    return np.where(r < rho, inside, outside)


def test_steady_flow_around_rotating_disk_matches_bessel_solution() -> None:
    """Eq. (eqv) with a rigidly rotating disk: steady v_theta(r) = Bessel I1/K1 solution.

    The fused kernel is iterated with F = disk indicator of radius R (tanh edge of half a
    cell), G = 0, c = 0 and fixed omega until stationary; then v_theta matches
    :func:`rotating_disk_flow` to 1 % of its maximum and v_r vanishes. eta, eta_b and
    D_eta are distinct so that a swapped coefficient is detected.
    """
    cfg = RotorConfig.model_validate(
        {
            "grid": ANALYTIC_GRID,
            "geometry": {"smoothing": ANALYTIC_SMOOTHING},
            "flow": {"drag": 2.0, "bulk_drag": 0.5, "viscosity": 0.8},
        }
    )
    pde = RotorPDE(cfg)
    dom = pde.domain
    dt = 0.9 * cfg.dt_limit()
    params = make_record(pde.setup)
    params["dt"] = dt  # euler_fields reads no stop schedule, which needs the config's step
    x, y = pde.cell_coordinates()
    r = np.hypot(x, y)
    radius, omega = cfg.geometry.radius, -3.0
    F = smooth_disk(r, radius, cfg.geometry.smoothing) * dom.interior_mask
    G = np.zeros_like(F)
    assert np.abs(F[~dom.support_mask]).max() < 1e-15  # the kernel skips F off the support

    def step(cur: np.ndarray, nxt: np.ndarray) -> None:
        euler_fields(
            cur.reshape(-1),
            nxt.reshape(-1),
            F.reshape(-1),
            G.reshape(-1),
            dom.arrays(),
            params,
            omega,
        )

    n_relax = round(2.0 / dt)
    before = relax(step, np.zeros((3, *F.shape)), n_relax)
    after = relax(step, before.copy(), round(0.25 / dt))

    flow = cfg.flow
    expected = rotating_disk_flow(
        r, radius, cfg.grid.domain_radius, flow.drag, flow.bulk_drag, flow.viscosity, omega
    )
    inside = dom.interior_mask & (r > 0)
    scale = np.abs(expected[inside]).max()
    assert np.abs(after - before).max() < 1e-4 * scale  # stationary
    safe_r = np.where(r > 0, r, 1.0)
    v_theta = (x * after[2] - y * after[1]) / safe_r
    v_r = (x * after[1] + y * after[2]) / safe_r
    assert np.abs(v_theta - expected)[inside].max() < 0.01 * scale
    assert np.abs(v_r)[inside].max() < 0.001 * scale
    assert np.all(after[0] == 0.0)  # no camphor without source


def test_steady_camphor_of_fixed_pill_matches_bessel_solution() -> None:
    """Eq. (eqc) with v = 0, F = 0 and one pill at the origin: steady c = I0/K0 solution.

    The no-flow kernel is iterated with G = the paper's tanh indicator of one pill of
    radius rho (edge half a cell wide) from c = 0 to the steady state, which matches
    :func:`single_pill_concentration` with s = s0 / (pi rho^2) (the model's own source
    normalisation, Eq. (eqc)) to 1 % of its maximum everywhere. D and a are distinct.
    """
    cfg = RotorConfig.model_validate(
        {
            "grid": ANALYTIC_GRID,
            "geometry": {"radius": 1.0, "pill_radius": 0.3, "smoothing": ANALYTIC_SMOOTHING},
            "camphor": {"diffusion": 0.8, "evaporation": 1.5, "supply": 2.0},
            "flow": {"enabled": False},
        }
    )
    pde = RotorPDE(cfg)
    dom = pde.domain
    dt = 0.9 * cfg.dt_limit()
    params = make_record(pde.setup)
    params["dt"] = dt  # euler_fields reads no stop schedule, which needs the config's step
    x, y = pde.cell_coordinates()
    r = np.hypot(x, y)
    rho = cfg.geometry.pill_radius
    G = smooth_disk(r, rho, cfg.geometry.smoothing) * dom.interior_mask
    F = np.zeros_like(G)
    assert np.abs(G[~dom.support_mask]).max() < 1e-15  # the kernel skips G off the support

    def step(cur: np.ndarray, nxt: np.ndarray) -> None:
        euler_fields(
            cur.reshape(-1),
            nxt.reshape(-1),
            F.reshape(-1),
            G.reshape(-1),
            dom.arrays(),
            params,
            0.0,
        )

    before = relax(step, np.zeros((3, *G.shape)), round(3.0 / dt))
    after = relax(step, before.copy(), round(0.25 / dt))

    cam = cfg.camphor
    source = cam.supply / (math.pi * rho**2)
    expected = single_pill_concentration(
        r, rho, cfg.grid.domain_radius, cam.diffusion, cam.evaporation, source
    )
    inside = dom.interior_mask
    scale = expected[inside].max()
    assert np.abs(after[0] - before[0]).max() < 1e-4 * scale  # stationary
    assert np.abs(after[0] - expected)[inside].max() < 0.01 * scale
    # total amount: a int c dA = s int G dA - boundary flux; compare with the exact profile
    total = after[0].sum() * dom.cell_area
    radial = np.linspace(0.0, cfg.grid.domain_radius, 20001)
    exact_total = np.trapezoid(
        2
        * np.pi
        * radial
        * single_pill_concentration(
            radial, rho, cfg.grid.domain_radius, cam.diffusion, cam.evaporation, source
        ),
        radial,
    )
    assert total == pytest.approx(exact_total, rel=0.01)


def rotor_history(sim: Simulation, t_end: float, interval: float) -> np.ndarray:
    """Run `sim` to t_end and return rows (t, phi, omega) sampled every `interval`."""
    rows: list[tuple[float, float, float]] = []

    def record(state: Any, t: float) -> None:
        rows.append((t, state.rotor.phi, state.rotor.omega))

    sim.run(t_end, trackers=[CallbackTracker(record, interrupts=interval)])
    return np.array(rows)


def test_torque_sign_physical_spins_up_printed_decays(
    small_config: Callable[..., RotorConfig],
) -> None:
    """Eq. (torque): the derived sign drives rotation, the printed sign stops the rotor.

    T = oint r x (gamma n) dl = -k int F r x grad c dA ("physical"): camphor is
    left behind a moving pill, the surface tension is higher ahead of it, and a small
    omega0 grows by orders of magnitude (self-propulsion). The printed
    T = int r x (-grad gamma) dA ("printed") has the opposite sign: it opposes the
    rotation, so |omega| falls at every sample, by an order of magnitude within 1.5.
    (Below omega0 / 10 the consistent scheme's decay is slow, about 0.25 per unit
    time; the paper scheme's, whose lattice torque acts on a slow plate, reaches
    1e-4 omega0 by t = 3.)
    """
    physical = Simulation(small_config({"rotor": {"torque": "physical"}}))
    printed = Simulation(small_config({"rotor": {"torque": "printed"}}))
    omega0 = physical.config.rotor.omega0
    assert omega0 > 0
    grown = rotor_history(physical, 1.0, 0.1)
    decayed = rotor_history(printed, 1.5, 0.1)
    assert grown[-1, 2] > 1000 * omega0
    assert np.all(np.diff(grown[:, 2]) > 0)
    assert np.all(np.diff(np.abs(decayed[:, 2])) < 0)
    assert abs(decayed[-1, 2]) < 0.1 * omega0


def test_mirror_image_run_is_mirrored(small_config: Callable[..., RotorConfig]) -> None:
    """Reflection y -> -y maps the model onto itself with phi -> -phi, Delta -> -Delta.

    Under the mirror the edge normals e(phi + 2 pi (j - 1/2) / N) and the pill angles
    phi + 2 pi j / N + Delta map to the same sets with phi -> -phi, Delta -> -Delta;
    Eqs. (eqc) and (eqv) are invariant (v_y flips sign), and r x grad c and r x v flip
    sign, so omega -> -omega. The grid is symmetric under j -> n - 1 - j, so the two
    runs agree to round-off: phi_b = -phi_a, omega_b = -omega_a, c_b(x, y) = c_a(x, -y),
    (v_x, v_y)_b(x, y) = (v_x, -v_y)_a(x, -y).
    """
    rotor = {"omega0": 0.3, "phi0": 0.7}
    a = Simulation(small_config({"rotor": rotor, "geometry": {"asymmetry": 0.01}}))
    b = Simulation(
        small_config(
            {
                "rotor": {"omega0": -rotor["omega0"], "phi0": -rotor["phi0"]},
                "geometry": {"asymmetry": -0.01},
            }
        )
    )
    a.run(0.5)
    b.run(0.5)
    assert abs(a.rotor.omega) > 10  # a real, asymmetric rotation happened
    assert b.rotor.omega == pytest.approx(-a.rotor.omega, rel=1e-10)
    assert b.rotor.phi == pytest.approx(-a.rotor.phi, rel=1e-10)
    da, db = a.state.data, b.state.data
    scale_c, scale_v = np.abs(da[0]).max(), np.abs(da[1:]).max()
    np.testing.assert_allclose(db[0], da[0][:, ::-1], rtol=0, atol=1e-10 * scale_c)
    np.testing.assert_allclose(db[1], da[1][:, ::-1], rtol=0, atol=1e-10 * scale_v)
    np.testing.assert_allclose(db[2], -da[2][:, ::-1], rtol=0, atol=1e-10 * scale_v)


def test_symmetric_rotor_at_rest_stays_at_rest(small_config: Callable[..., RotorConfig]) -> None:
    """A symmetric plate (Delta = 0) at rest with c = v = 0 and no noise stays at rest.

    With phi0 = 0 the hexagon (corner on the x axis) and the grid share the mirror
    y -> -y, so c stays mirror symmetric and T = -k int F r x grad c dA = 0; the
    rest state is unstable (self-propulsion), so round-off grows, but stays far below
    any physical rotation over t = 0.5. The check is sensitive: with phi0 = 0.1 (off
    the grid's mirror axes) the spurious lattice torque starts the rotor, and with
    Delta != 0 the asymmetric pills do.
    """
    rest = Simulation(small_config({"rotor": {"omega0": 0.0, "phi0": 0.0}}))
    history = rotor_history(rest, 0.5, 0.05)
    assert np.all(np.abs(history[:, 2]) < 1e-9)
    assert np.all(np.abs(history[:, 1]) < 1e-10)
    assert np.abs(rest.state.data[0]).max() > 0.1  # camphor was released

    off_axis = {"rotor": {"omega0": 0.0, "phi0": 0.1}}
    asymmetric = {"rotor": {"omega0": 0.0, "phi0": 0.0}, "geometry": {"asymmetry": 0.01}}
    for broken in (off_axis, asymmetric):
        sim = Simulation(small_config(broken))
        sim.run(0.5)
        assert abs(sim.rotor.omega) > 1e-3


def test_spin_up_is_steady_and_converges_at_first_order_in_dt(
    small_config: Callable[..., RotorConfig],
) -> None:
    """Spin-up from omega0 reaches a steady omega that converges as dt -> 0 at first order.

    Forward Euler moves a pill up to half a coarse cell per step at omega ~ 170, so the
    steady omega carries an O(dt) error (docs/model.md). Halving dt twice (4e-4, 2e-4,
    1e-4 at dx = delta = 0.05, no noise) must change the steady omega in one direction,
    each change smaller than the one before, at an observed order log2(d1 / d2) of a
    first-order method. The relaxation time of omega is of order 1: after the monotone
    spin-up, omega is steady over the last time unit (change < 0.1 %).
    """
    steady = []
    for dt in (4e-4, 2e-4, 1e-4):
        sim = Simulation(small_config({"grid": {"dt": dt}}))
        history = rotor_history(sim, 6.0, 0.5)
        t, omega = history[:, 0], history[:, 2]
        assert np.all(np.diff(omega[t <= 3.0]) > 0)  # monotone spin-up
        last_unit = omega[t >= t[-1] - 1.0 - 1e-9]
        assert np.ptp(last_unit) < 1e-3 * omega[-1]
        steady.append(omega[-1])
    d1, d2 = steady[0] - steady[1], steady[1] - steady[2]
    assert d1 * d2 > 0 and abs(d2) < abs(d1)
    assert 0.5 < math.log2(d1 / d2) < 1.5
