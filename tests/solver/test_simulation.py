"""Inversion after a short stop (memory in the flow) and Simulation plumbing.

The paper (section "Numerical results", Figs. 4 and 8): after a stop of t_stop = 0.5 the
rotor always turns the other way; with the flow switched off (v = 0 in Eqs. (eqc) and
(eq_motion)) there is no systematic inversion. Without noise the outcome is
deterministic but depends on the angle at which the plate stops, because the Cartesian
grid adds a lattice torque (period pi/6, docs/model.md). These tests stop the plate at
several angles and compare the torque left at the end of the stop with the largest lattice
torque of the same grid, computed independently from the stopped plate's steady state.
"""

from __future__ import annotations

import numpy as np
import pytest

from pde_rotor import RotorConfig, Simulation
from pde_rotor.model.analysis import stopped_torque
from pde_rotor.solver.rotor import SimulationDivergedError
from tests.conftest import DIVERGING

COARSE = {"grid": {"dx": 0.05, "dt": 4e-4}, "geometry": {"smoothing": 0.05}}
PAPER: dict = {}


def stop_and_release(
    base: dict, flow: bool, t_warm: float, n_angles: int, angle_step: int
) -> list[tuple[float, float, float, float]]:
    """Spin up once, then stop at `n_angles` different angles, each from the same state.

    The stop angle is varied by delaying the stop by multiples of `angle_step` steps.

    Returns:
        One (stop angle, omega before the stop, torque at the end of the stop, omega one
        time unit after the release) per angle.
    """
    spin = {**base, "flow": {"enabled": flow}, "protocol": {"cycles": 0}}
    warm = Simulation(RotorConfig.model_validate(spin))
    warm.run(t_warm)
    dt = warm.config.grid.dt
    results = []
    for k in range(n_angles):
        t_ini = t_warm + k * angle_step * dt
        protocol = {"t_ini": t_ini, "t_stop": 0.5, "t_release": 5.0, "cycles": 1}
        sim = warm.branch(RotorConfig.model_validate({**spin, "protocol": protocol}))
        sim.run(t_ini)
        phi_stop, omega_before = sim.rotor.phi, sim.rotor.omega
        sim.run(t_ini + 0.5)
        torque_end = sim.rotor.torque
        sim.run(t_ini + 1.5)
        results.append((phi_stop, omega_before, torque_end, sim.rotor.omega))
    return results


def max_lattice_torque(base: dict) -> float:
    """Largest torque on a stopped symmetric plate over one lattice period (steady c)."""
    phis = np.linspace(0, np.pi / 6, 12, endpoint=False)
    return float(np.abs(stopped_torque(RotorConfig.model_validate(base), phis)).max())


def check_inversion(base: dict, t_warm: float, n_angles: int, angle_step: int) -> None:
    """With flow every stop inverts; without flow the lattice, not memory, decides."""
    lattice = max_lattice_torque(base)
    with_flow = stop_and_release(base, True, t_warm, n_angles, angle_step)
    for phi, before, torque, after in with_flow:
        assert np.sign(after) == -np.sign(before), f"no inversion at stop angle {phi:.3f}"
        # the memory torque opposes the old rotation and beats the lattice torque
        assert -np.sign(before) * torque > lattice, (phi, torque, lattice)
    without_flow = stop_and_release(base, False, t_warm, n_angles, angle_step)
    for _, _, torque, after in without_flow:
        assert abs(torque) < 1.5 * lattice
        assert abs(after) > 10  # the rotor restarts in some direction
    inverted = [np.sign(after) == -np.sign(before) for _, before, _, after in without_flow]
    assert not all(inverted), "no-flow rotor inverted systematically"


def test_inversion_needs_flow_coarse_grid():
    """Coarse grid: eight stop angles spread over more than one lattice period."""
    check_inversion(COARSE, t_warm=6.0, n_angles=8, angle_step=1)


@pytest.mark.slow
def test_inversion_needs_flow_paper_resolution():
    """Paper resolution (about 6 minutes): six stop angles spread over one lattice period."""
    check_inversion(PAPER, t_warm=8.0, n_angles=6, angle_step=5)


def test_branch_continues_the_same_trajectory():
    """A branch with the same config continues exactly where the original would go."""
    config = RotorConfig.model_validate({**COARSE, "protocol": {"cycles": 0}})
    original = Simulation(config)
    original.run(0.4)
    branch = original.branch()
    original.run(0.8)
    branch.run(0.8)
    assert branch.rotor.phi == original.rotor.phi
    np.testing.assert_array_equal(branch.state.data, original.state.data)


def test_branch_rejects_another_grid():
    """Branching onto a different grid is an error naming the grid."""
    sim = Simulation(RotorConfig.model_validate({**COARSE, "protocol": {"cycles": 0}}))
    other = RotorConfig.model_validate({**COARSE, "grid": {"dx": 0.04, "dt": 2e-4}})
    with pytest.raises(ValueError, match="grid"):
        sim.branch(other)


def test_diverged_run_keeps_the_failing_state():
    """After SimulationDivergedError the simulation holds the non-finite state, not the start."""
    config = RotorConfig.model_validate({**COARSE, **DIVERGING})
    sim = Simulation(config)
    with pytest.raises(SimulationDivergedError, match="diverged at t ="):
        sim.run(1.0)
    assert not np.isfinite(sim.state.data).all()
