"""One run on several threads (``solver.threads``): the same bits as on one.

The fused step shares its rows, spline columns and contour nodes among numba's threads
and adds every sum over fixed parts in a fixed order (:mod:`pde_rotor.kernels.cpu`), so
the thread count must not change a single bit of a run: checked on a short coarse run of
either scheme and integrator, through stops and with noise. The kernel splits the work
into as many blocks as it is told; with fewer threads numba runs the blocks one after
the other, so the partition is checked on any machine and the concurrency where there
are two cores.
"""

from __future__ import annotations

from collections.abc import Callable

import numba
import numpy as np
import pytest

from pde_rotor.config import ConfigError, RotorConfig
from pde_rotor.model.pde import RotorPDE
from pde_rotor.solver import threads
from pde_rotor.solver.rotor import FusedStepper, make_fused_stepper
from pde_rotor.solver.simulation import Simulation
from pde_rotor.solver.threads import resolve_threads, running_on

SHORT_RUN = {
    "protocol": {"t_ini": 0.02, "t_stop": 0.02, "t_release": 0.02, "cycles": 2},
    "noise": {"sigma": 1e-5, "seed": 7},
    "geometry": {"asymmetry": 0.05},
}
"""Turning, stopped and released twice within t = 0.1, with noise: every path of a step."""


def run_on(config: RotorConfig, threads: int) -> tuple[np.ndarray, np.ndarray]:
    """Fields and rotor after t = 0.1 with the kernel's work split into `threads` blocks."""

    def stepper(pde: RotorPDE, dt: float, rng: np.random.Generator) -> FusedStepper:
        fused = make_fused_stepper(pde, dt, rng)
        fused.threads = threads
        return fused

    sim = Simulation(config, stepper=stepper)
    with running_on(min(threads, numba.config.NUMBA_NUM_THREADS)):
        sim.run(0.1)
    return sim.state.data.copy(), sim.rotor.as_array()


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
@pytest.mark.parametrize("integrator", ["euler", "heun"])
def test_two_threads_give_the_bits_of_one(
    small_config: Callable[..., RotorConfig], scheme: str, integrator: str
) -> None:
    config = small_config(SHORT_RUN, {"numerics": {"scheme": scheme, "integrator": integrator}})
    one_fields, one_rotor = run_on(config, 1)
    two_fields, two_rotor = run_on(config, 2)
    assert np.any(one_fields != 0.0) and one_rotor[1] != 0.0  # the run did something
    np.testing.assert_array_equal(two_fields, one_fields)
    np.testing.assert_array_equal(two_rotor, one_rotor)


def test_default_takes_the_free_cores_and_a_request_is_bounded_by_numba(
    monkeypatch, tmp_path
) -> None:
    """null: the usable cores less the tasks other processes run now, at most numba's
    count; more threads than numba may start are refused in one line naming the key."""
    load = tmp_path / "loadavg"
    monkeypatch.setattr(threads, "LOADAVG", load)
    monkeypatch.setattr(threads, "usable_cores", lambda: 4)
    load.write_text("1.31 0.92 0.80 3/412 1234\n")  # this process and two others
    assert threads.free_cores() == 2
    load.write_text("7.0 7.0 7.0 9/412 1234\n")
    assert threads.free_cores() == 1
    assert threads.other_load(samples=3, pause=0.0) == 8.0  # what a sweep estimate counts
    load.write_text("0.01 0.02 0.00 1/412 1234\n")
    assert threads.free_cores() == 4
    load.unlink()  # not Linux: every usable core
    assert threads.free_cores() == 4
    assert 1 <= resolve_threads(None) <= numba.get_num_threads()
    with running_on(1):
        assert resolve_threads(None) == 1  # a sweep worker's runs
    assert resolve_threads(1) == 1
    limit = numba.config.NUMBA_NUM_THREADS
    with pytest.raises(ConfigError, match=r"^solver\.threads = \d+: numba starts at most"):
        resolve_threads(limit + 1)
    with pytest.raises(ValueError, match="threads"):
        RotorConfig.model_validate({"solver": {"threads": 0}})
