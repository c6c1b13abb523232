"""The fused solver: agreement with the numpy reference, the discrete camphor balance, the
Euler-Maruyama noise of Eqs. (eq_motion)/(noiseav), and its safety checks.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from pde import FieldCollection
from pde.trackers import CallbackTracker
from scipy.stats import chi2

from pde_rotor import RotorConfig, Simulation
from pde_rotor.model.motion import Inertia, accelerations, euler_poses, held_bodies
from pde_rotor.model.pde import RotorPDE
from pde_rotor.model.setup import Setup
from pde_rotor.solver.rotor import RotorSolver, SimulationDivergedError

STOP_AT_ONCE = {"t_ini": 0.0, "t_stop": 0.5, "t_release": 1.0, "cycles": 1}
"""Protocol whose first stop starts at t = 0 (step 0 lies in a stop phase)."""


def one_solver_step(pde: RotorPDE, state: FieldCollection) -> FieldCollection:
    """Advance a copy of `state` by one step dt of the real solver (py-pde stepper API)."""
    new = state.copy()
    dt = pde.config.grid.dt
    stepper = RotorSolver(pde).make_stepper(new)
    assert stepper(new, 0.0, dt) == pytest.approx(dt, rel=1e-12)
    return new


@pytest.mark.parametrize("stopped", [False, True], ids=["running", "stopped"])
@pytest.mark.parametrize("flow", [True, False], ids=["flow", "no_flow"])
def test_fused_step_equals_numpy_reference(
    flow: bool,
    stopped: bool,
    small_config: Callable[..., RotorConfig],
    random_state: Callable[..., FieldCollection],
) -> None:
    """One fused step equals an explicit Euler step of RotorPDE's numpy reference.

    Reference: c' = c + dt rate_c, v' = v + dt rate_v from ``evolution_rate`` (Eqs. (eqc),
    (eqv)); phi' = phi + dt omega, omega' = omega + dt (T + friction) / I from
    ``rotor_torques`` and the equation of motion of :mod:`pde_rotor.model.motion`
    (Eq. (eq_motion)). In a stop phase omega = 0 enters the flow term
    and the friction, phi and omega stay frozen (omega' = 0). Checked on a random smooth
    state with an asymmetric rotor, with the flow on and off; increments agree to 1e-12
    relative.
    """
    overrides: dict[str, Any] = {"flow": {"enabled": flow}, "geometry": {"asymmetry": 0.05}}
    if stopped:
        overrides["protocol"] = STOP_AT_ONCE
    cfg = small_config(overrides)
    pde = RotorPDE(cfg)
    state = random_state(pde, np.random.default_rng(1), flow=flow)
    phi, omega = 0.37, 12.5
    state.rotor.phi, state.rotor.omega = phi, 0.0 if stopped else omega
    rate = pde.evolution_rate(state)
    torque, friction = pde.rotor_torques(state)
    assert abs(torque) > 0
    if flow:
        assert abs(friction) > 0

    state.rotor.omega = omega
    new = one_solver_step(pde, state)
    dt = cfg.grid.dt
    increment = (new.data - state.data) / dt
    for channel in range(3):
        scale = np.abs(rate.data[channel]).max()
        if not flow and channel > 0:
            assert scale == 0.0
        np.testing.assert_allclose(
            increment[channel], rate.data[channel], rtol=0, atol=1e-12 * max(scale, 1.0)
        )
    assert new.rotor.torque == pytest.approx(torque, rel=1e-11)  # a sum with cancellations
    assert new.rotor.friction == pytest.approx(friction, rel=1e-12, abs=1e-300)
    assert new.rotor.stopped is stopped
    # the equation of motion of the numpy reference: the rotor is the fixed_axis body at 0
    setup = Setup(cfg)
    bodies = setup.bodies
    inertia = Inertia.of(bodies)
    held = held_bodies(bodies, setup.body_schedules, 0)
    assert bool(held[0]) is stopped
    pose = np.array([[0.0, 0.0, phi, 0.0, 0.0, 0.0 if stopped else omega]])
    accel = accelerations(np.array([[0.0, 0.0, torque, 0.0, 0.0, friction]]), inertia, pose)
    want = euler_poses(pose, accel, held, inertia, dt)[0]
    assert new.rotor.phi == pytest.approx(want[2], rel=1e-15)
    if stopped:
        assert new.rotor.phi == phi
        assert new.rotor.omega == 0.0 == want[5]
    else:
        assert (new.rotor.omega - omega) / dt == pytest.approx((want[5] - omega) / dt, rel=1e-10)


def discrete_boundary_flux(pde: RotorPDE, c: np.ndarray, v: np.ndarray | None) -> float:
    """Outflow of camphor through the circle |r| = L, as the discrete scheme defines it.

    Sum over interior cells of the 5-point Laplacian: interior pairs cancel, each
    interior-exterior pair leaves -c_p / dx^2 (c = 0 outside), i.e. the diffusive outflow
    D n_ext(p) c_p per unit dx^2. Sum of the central divergence of q = c v: each term
    q_p appears with +1/(2 dx) from a neighbour on one side and -1/(2 dx) from the other;
    only cells with an exterior neighbour keep a net (outward) coefficient. Times dx^2.
    """
    mask = pde.domain.interior_mask
    dx = pde.domain.dx
    ext = ~mask

    def shifted(a: np.ndarray, axis: int, step: int) -> np.ndarray:
        """a at the neighbour (+step along axis); the grid's border cells are exterior."""
        return np.roll(a, -step, axis=axis)

    n_ext = sum(shifted(ext, ax, s).astype(float) for ax in (0, 1) for s in (1, -1))
    diffusive = pde.config.camphor.diffusion * np.sum(mask * n_ext * c)
    advective = 0.0
    if v is not None:
        for ax in (0, 1):
            outward = shifted(ext, ax, 1).astype(float) - shifted(ext, ax, -1).astype(float)
            advective += 0.5 * dx * np.sum(mask * outward * c * v[ax])
    return diffusive + advective


@pytest.mark.parametrize("flow", [True, False], ids=["flow", "no_flow"])
def test_camphor_balance_is_exact(
    flow: bool,
    small_config: Callable[..., RotorConfig],
    random_state: Callable[..., FieldCollection],
) -> None:
    """d/dt int c dA = source - evaporation - boundary flux, to round-off, for each step.

    Eq. (eqc) integrated over the disk: int s G dA - int a (1 - F) c dA minus the
    outflow through |r| = L; advection only redistributes camphor inside. The scheme
    keeps this exactly: the 5-point Laplacian and the central divergence telescope to
    fluxes into the exterior cells, which hold c = 0. The state is random with c ~ 1 up
    to the boundary, so every term is large; 3 steps of the real solver are checked,
    with F and G from the numpy reference at the phi of each step.
    """
    cfg = small_config({"flow": {"enabled": flow}, "geometry": {"asymmetry": 0.05}})
    pde = RotorPDE(cfg)
    state = random_state(pde, np.random.default_rng(2), flow=flow)
    state.rotor.phi, state.rotor.omega = 0.2, 40.0
    dt, area = cfg.grid.dt, pde.domain.cell_area
    source_rate = cfg.camphor.supply / (math.pi * cfg.geometry.pill_radius**2)
    mask = pde.domain.interior_mask
    for _ in range(3):
        F, G = pde.indicators(state.rotor.phi)
        c = state.data[0]
        source = source_rate * np.sum(mask * G) * area
        evaporation = cfg.camphor.evaporation * np.sum((1 - F) * c) * area
        outflow = discrete_boundary_flux(pde, c, state.data[1:] if flow else None)
        new = one_solver_step(pde, state)
        change = np.sum(new.data[0] - c) * area
        expected = dt * (source - evaporation - outflow)
        scale = dt * (abs(source) + abs(evaporation) + abs(outflow))
        assert outflow > 0.1 * scale / dt  # the boundary term is really tested
        assert change == pytest.approx(expected, abs=1e-12 * scale)
        state = new


def omega_increments(sim: Simulation, t_end: float, window: float) -> tuple[np.ndarray, np.ndarray]:
    """Run `sim` to t_end and return the omega increments and durations of the windows."""
    samples: list[tuple[float, float]] = []

    def record(state: Any, t: float) -> None:
        samples.append((t, state.rotor.omega))

    sim.run(t_end, trackers=[CallbackTracker(record, interrupts=window)])
    t, omega = np.array(samples).T
    return np.diff(omega), np.diff(t)


@pytest.mark.parametrize("dt", [2e-3, 1e-2])
def test_noise_is_euler_maruyama_and_independent_of_dt(
    dt: float, small_config: Callable[..., RotorConfig]
) -> None:
    """Without torque and friction, omega is a Brownian motion: Var = 2 sigma^2 t / I^2.

    Eq. (eq_motion) with T = 0 (no camphor: s0 = 0, c stays 0), mu = 0, no flow and no
    stops (M = 0) is I d omega = xi dt with <xi(t) xi(s)> = 2 sigma^2 delta(t - s),
    Eq. (noiseav), so
    increments over disjoint windows of length tau are independent N(0, 2 sigma^2 tau
    / I^2) whatever dt. The normalised squared increments sum to a chi^2 variable with
    M degrees of freedom; the test accepts within the two-sided 1e-6 quantiles. A kick
    scaling like dt instead of sqrt(dt), or missing the factor 2, fails for both dt.
    (D is reduced only to allow large dt, as there is no camphor to diffuse; a thin edge
    delta and a small domain make the steps cheap.)
    """
    inertia = RotorConfig.model_validate({}).rotor.inertia
    sigma = 3.0 * inertia
    cfg = small_config(
        {
            "camphor": {"supply": 0.0, "diffusion": 0.01},
            "flow": {"enabled": False},
            "rotor": {"friction": 0.0},
            "noise": {"sigma": sigma, "seed": 7},
            "protocol": {"cycles": 0},
            "grid": {"dt": dt, "domain_radius": 1.2},
            "geometry": {"smoothing": 0.025},
        }
    )
    sim = Simulation(cfg)
    window, n_windows = 0.02, 1000
    d_omega, d_t = omega_increments(sim, window * n_windows, window)
    assert np.all(sim.state.data[0] == 0.0)
    assert d_omega.size == n_windows
    np.testing.assert_allclose(d_t, window, rtol=1e-9)
    z = d_omega * cfg.rotor.inertia / (sigma * np.sqrt(2 * d_t))  # iid N(0, 1)
    lo, hi = chi2.ppf([1e-6, 1 - 1e-6], n_windows)
    assert lo < np.sum(z**2) < hi
    assert abs(np.mean(z)) < 5 / math.sqrt(n_windows)


def test_same_seed_same_trajectory_whatever_the_chunking(
    small_config: Callable[..., RotorConfig],
) -> None:
    """The noise is drawn one number per step, in step order, from the seeded Generator.

    A run in one call and a run in several calls with a tracker interrupting at odd
    intervals therefore give bit-identical fields and rotor state; another seed does not.
    """
    noise = {"sigma": RotorConfig.model_validate({}).rotor.inertia, "seed": 11}
    one = Simulation(small_config({"noise": noise}))
    one.run(0.3)
    pieces = Simulation(small_config({"noise": noise}))
    pieces.run(0.1)
    pieces.run(0.2, trackers=[CallbackTracker(lambda _s, _t: None, interrupts=0.0132)])
    pieces.run(0.3)
    np.testing.assert_array_equal(one.state.data, pieces.state.data)
    assert (one.rotor.phi, one.rotor.omega) == (pieces.rotor.phi, pieces.rotor.omega)
    other = Simulation(small_config({"noise": {**noise, "seed": 12}}))
    other.run(0.3)
    assert other.rotor.omega != one.rotor.omega


def checkerboard_amplification(
    config: RotorConfig, channel: int, centre: float, eps: float = 1e-3
) -> float:
    """Growth factor per step of the grid's fastest mode, measured on the stepper.

    A checkerboard of amplitude eps in field `channel` (0: c, 1: v_x) on a patch
    around (centre, 0) is advanced by one step; the run without it is subtracted
    (the step is linear in each field), leaving the factor of the mode at the centre.
    """
    values = []
    for amplitude in (eps, 0.0):
        sim = Simulation(config)
        x, y = sim.pde.cell_coordinates()
        i, j = np.indices(x.shape)
        sign = (-1.0) ** (i + j)
        patch = (x - centre) ** 2 + y**2 < 0.3**2
        sim.state.data[channel][patch] = amplitude * sign[patch]
        sim.run(config.grid.dt)
        k = np.unravel_index(np.argmin((x - centre) ** 2 + y**2), x.shape)
        values.append(sim.state.data[channel][k] * sign[k])
    return (values[0] - values[1]) / eps


def test_stability_limit_is_where_the_fastest_mode_stops_decaying(
    coarse_config: Callable[..., RotorConfig],
) -> None:
    """dt_limit is the explicit Euler bound 2 / lambda_max of the stepper's own rates.

    One forward Euler step multiplies a linear mode by g = 1 - dt lambda; the step is
    stable while |g| <= 1, i.e. dt <= 2 / lambda. lambda of the checkerboard (the
    5-point stencil's fastest mode) is measured for c and v away from the plate and
    under it (where the plate adds its drag and removes evaporation); the largest one
    sets the limit the config and the stepper enforce.
    """
    cfg = coarse_config()
    rates = [
        (1 - checkerboard_amplification(cfg, channel, centre)) / cfg.grid.dt
        for channel in (0, 1)
        for centre in (0.0, 2.0)  # under the plate; 1.5 beyond its edge, F < 1e-25
    ]
    assert min(rates) > 0
    assert cfg.dt_limit() == pytest.approx(2 / max(rates), rel=1e-8)


def test_stepper_refuses_unstable_dt(small_config: Callable[..., RotorConfig]) -> None:
    """dt above the explicit stability limit is refused before any step, naming the limit.

    The config refuses it too.
    """
    cfg = small_config()
    limit = cfg.dt_limit()
    pde = RotorPDE(cfg)
    state = pde.initial_state()
    solver = RotorSolver(pde)
    with pytest.raises(ValueError, match=f"{limit:.4g}"):
        solver.make_stepper(state, dt=1.01 * limit)
    assert np.all(state.data == 0.0)
    with pytest.raises(ValueError, match=f"{limit:.4g}"):
        small_config({"grid": {"dt": 1.01 * limit}})


def test_nan_under_the_plate_stops_at_once_naming_the_time(
    small_config: Callable[..., RotorConfig],
) -> None:
    """A NaN in c under the plate makes the torque NaN in the next step: the run stops with
    SimulationDivergedError naming the time of that step (t = 0.1) and the field c."""
    sim = Simulation(small_config())
    sim.run(0.1)
    x, y = sim.pde.cell_coordinates()
    i, j = np.unravel_index(np.argmin((x - 0.2) ** 2 + y**2), x.shape)
    sim.state.data[0, i, j] = np.nan
    with pytest.raises(SimulationDivergedError, match=r"t = 0\.1\b.*non-finite c"):
        sim.run(0.2)


def test_nan_far_from_the_plate_is_caught(small_config: Callable[..., RotorConfig]) -> None:
    """A NaN in v outside the support of F spreads and is caught within the same call,
    naming v_x and a time between the injection and the end of the call."""
    sim = Simulation(small_config())
    sim.run(0.1)
    x, y = sim.pde.cell_coordinates()
    r = np.hypot(x, y)
    outside = sim.pde.domain.interior_mask & (r > sim.pde.shape.support_radius)
    i, j = np.argwhere(outside)[0]
    sim.state.data[1, i, j] = np.inf
    with pytest.raises(SimulationDivergedError, match="v_x") as err:
        sim.run(0.12)
    t_failed = float(str(err.value).split("t = ")[1].split(":")[0])
    assert 0.1 <= t_failed <= 0.12 + 1e-12


def test_pde_solve_advances_the_rotor_and_refuses_generic_solvers(
    small_config: Callable[..., RotorConfig],
) -> None:
    """RotorPDE.solve runs RotorSolver (phi and omega move); py-pde's own solvers are refused."""
    cfg = small_config({"rotor": {"omega0": 5.0}, "output": {"progress": False}})
    pde = RotorPDE(cfg)
    state = pde.initial_state()
    phi0 = state.rotor.phi
    final = pde.solve(state, t_range=0.02, tracker=None)
    assert final[0].data.max() > 0  # camphor was released
    assert final.rotor.phi != phi0
    assert state.rotor.phi == phi0  # the Controller evolved a copy
    assert final.rotor.phi == pytest.approx(phi0 + 0.02 * 5.0, rel=0.2)
    with pytest.raises(ValueError, match="frozen"):
        pde.solve(state, t_range=0.01, solver="euler")
    with pytest.raises(ValueError, match="backend"):
        RotorSolver(pde, backend="numba")


class HookedPDE(RotorPDE):
    """RotorPDE with a post-step hook that counts steps and clamps c from below."""

    def make_post_step_hook(
        self, state: FieldCollection, backend: Any = "numpy"
    ) -> tuple[Callable[..., Any], np.ndarray]:
        """Hook counting the steps and recording the time it was called with."""

        def hook(state_data: np.ndarray, t: float, post_step_data: np.ndarray) -> Any:
            post_step_data[0] += 1
            post_step_data[1] = t
            return state_data, post_step_data

        return hook, np.zeros(2)


def test_post_step_hook_of_the_pde_runs_after_every_step(
    small_config: Callable[..., RotorConfig],
) -> None:
    """A PDE's make_post_step_hook is honoured: called once per step with the step's time."""
    cfg = small_config({"output": {"progress": False}})
    pde = HookedPDE(cfg)
    solver = RotorSolver(pde)
    state = pde.initial_state()
    stepper = solver.make_stepper(state, cfg.grid.dt)
    stepper(state, 0.0, 10 * cfg.grid.dt)
    count, last_t = solver.info["post_step_data"]
    assert count == 10
    assert last_t == pytest.approx(9 * cfg.grid.dt)
    reference = RotorPDE(cfg)
    ref_state = reference.initial_state()
    RotorSolver(reference).make_stepper(ref_state, cfg.grid.dt)(ref_state, 0.0, 10 * cfg.grid.dt)
    np.testing.assert_array_equal(state.data, ref_state.data)  # stepping one by one is exact


@pytest.mark.parametrize(("integrator", "order"), [("euler", 1), ("heun", 2)])
def test_time_integrators_converge_at_their_order(
    integrator: str, order: int, coarse_config: Callable[..., RotorConfig]
) -> None:
    """omega(t = 0.4) of a spinning-down rotor with dt, dt/2, dt/4 converges at the order.

    With an error C dt^p, successive differences of omega shrink by 2^p per halving:
    about 2 for forward Euler, 4 for Heun's method (both fields and rotor, and F, G and
    the torque at the predicted angle). The start omega0 = 100 is far from the steady
    rotation, so omega changes by ~30 % over the run and the time error is large.
    """
    omegas = []
    for dt in (4e-4, 2e-4, 1e-4):
        cfg = coarse_config(
            {
                "grid": {"dt": dt},
                "rotor": {"omega0": 100.0},
                "protocol": {"cycles": 0},
                "numerics": {"integrator": integrator},
            }
        )
        sim = Simulation(cfg)
        sim.run(0.4)
        omegas.append(sim.rotor.omega)
    first, second = np.diff(omegas)
    assert abs(first) > 1e-3 * abs(omegas[-1])  # the time error is measurable
    assert first / second == pytest.approx(2.0**order, rel=0.15)


def test_the_corner_tables_end_moves_a_run_by_less_than_1e_12(
    small_config: Callable[..., RotorConfig], request: pytest.FixtureRequest
) -> None:
    """The 2-D corner table ends where F_eps falls below 1e-13 (``corner_end``): after
    250 steps of the default scheme, the rotor's angle, angular velocity, torque and
    friction, the fields c, v and F, G are those of the table on all cells near the
    bisectors, to 1e-12 (measured: 1e-14)."""
    config = small_config({"numerics": {"scheme": "consistent"}})
    sim = Simulation(config)
    sim.run(0.1)
    request.getfixturevalue("full_corner_table")
    full = Simulation(config)
    full.run(0.1)
    assert abs(full.rotor.omega) > 0.1  # the rotor turns, the corner cells change
    np.testing.assert_allclose(sim.rotor.as_array()[:4], full.rotor.as_array()[:4], rtol=1e-12)
    scale = np.abs(full.state.data).max()
    np.testing.assert_allclose(sim.state.data, full.state.data, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(sim.pde.F, full.pde.F, rtol=0, atol=2e-13)
    np.testing.assert_array_equal(sim.pde.G, full.pde.G)


def test_external_torque_without_camphor_turns_the_rotor_at_torque_over_friction(
    small_config: Callable[..., RotorConfig],
) -> None:
    """Without camphor (supply 0) and flow, Eq. (eq_motion) is I domega/dt = T_ext - mu J
    omega, J = int F |r|^2 dA: the rotor under a constant external torque reaches
    omega = T_ext / (mu J) (15 relaxation times I / (mu J) here), turning either way."""
    for torque in (1e-3, -5e-4):
        cfg = small_config(
            {
                "camphor": {"supply": 0.0},
                "flow": {"enabled": False},
                "rotor": {"external_torque": torque, "omega0": 0.0},
            }
        )
        sim = Simulation(cfg)
        pde: RotorPDE = sim.pde
        x, y = pde.cell_coordinates()
        F, _ = pde.indicators(0.0)
        polar = float(np.sum(F * (x**2 + y**2)) * pde.domain.cell_area)
        mu = cfg.rotor.friction
        t_end = 15 * cfg.rotor.inertia / (mu * polar)
        sim.run(round(t_end / cfg.grid.dt) * cfg.grid.dt)
        assert np.abs(sim.state.data).max() == 0.0  # no camphor, no flow
        assert sim.rotor.omega == pytest.approx(torque / (mu * polar), rel=1e-3)


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_saturating_tension_torque_equals_numpy_reference(
    scheme: str,
    small_config: Callable[..., RotorConfig],
    random_state: Callable[..., FieldCollection],
) -> None:
    """With gamma(c) = gamma0 - k c / (1 + c / c_sat) the fused step's torque is
    RotorPDE's (area form, and contour form with the spline of c read through the
    surface pressure) to 1e-11; on the paper scheme it is the linear law's torque of the
    field c / (1 + c / c_sat) itself (the area form reads c only through Pi); and it
    tends to the linear law's torque as c_sat grows."""
    torques = {}
    for saturation in (0.5, 1e3, None):
        cfg = small_config({"numerics": {"scheme": scheme}, "camphor": {"saturation": saturation}})
        pde = RotorPDE(cfg)
        state = random_state(pde, np.random.default_rng(2))
        state.rotor.phi, state.rotor.omega = 0.4, 3.0
        torque, _ = pde.rotor_torques(state)
        new = one_solver_step(pde, state)
        assert new.rotor.torque == pytest.approx(torque, rel=1e-11)
        torques[saturation] = torque
        if saturation == 0.5 and scheme == "paper":
            linear = RotorPDE(small_config({"numerics": {"scheme": scheme}}))
            pressed = state.copy()
            pressed.data[0] = state.data[0] / (1.0 + state.data[0] / saturation)
            assert one_solver_step(linear, pressed).rotor.torque == pytest.approx(
                new.rotor.torque, rel=1e-13
            )
    assert abs(torques[0.5] - torques[None]) > 0.1 * abs(torques[None])
    assert abs(torques[1e3] - torques[None]) < 1e-2 * abs(torques[None])
