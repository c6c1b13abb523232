"""CPU ensemble backend: the members one after the other with the fused CPU solver.

Each member is a :class:`~pde_rotor.solver.simulation.Simulation`; its py-pde stepper
(:meth:`pde_rotor.solver.rotor.RotorSolver.make_stepper`) is called from record to record,
exactly as py-pde's Controller calls it between tracker times. This is the reference
that :mod:`pde_rotor.backends.gpu` is cross-validated against, and the fallback of
``backend = "auto"`` on machines without a GPU.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np

from ..config import RotorConfig
from ..model.setup import Setup
from ..solver.rotor import SimulationDivergedError
from ..solver.simulation import Simulation
from .ensemble import RECORD_FIELDS, EnsembleResult, EnsembleState, default_rngs, make_plan


def _record(sim: Simulation, cell_area: float) -> np.ndarray:
    """One row of the records: the rotor state and the total camphor int c dA."""
    return np.append(sim.rotor.as_array(), sim.state.data[0].sum() * cell_area)


def run_ensemble(
    configs: Sequence[Setup | RotorConfig],
    t_end: float | None = None,
    *,
    record_interval: float | None = None,
    initial: EnsembleState | None = None,
    rngs: Sequence[np.random.Generator] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> EnsembleResult:
    """Advance every member with the CPU solver, one after the other.

    Arguments as for :func:`pde_rotor.backends.run_ensemble`. A member whose state stops
    being finite is recorded as diverged (the solver's
    :class:`~pde_rotor.solver.rotor.SimulationDivergedError`, resolved to the start of the record
    interval in which it was raised) and the others go on.
    """
    start = time.perf_counter()
    plan = make_plan(configs, t_end, record_interval, initial)
    rngs = default_rngs(plan.configs) if rngs is None else list(rngs)
    state = initial if initial is not None else EnsembleState.initial(plan.configs, plan.domain)
    n_members, n_records = plan.n_members, plan.record_steps.size
    records = np.full((n_members, n_records, len(RECORD_FIELDS)), np.nan)
    area = plan.domain.cell_area
    final = EnsembleState(data=state.data.copy(), rotor=state.rotor.copy(), step=plan.step_end)
    diverged = np.full(n_members, -1, dtype=np.int64)
    dt = plan.dt
    targets = plan.record_steps[1:].tolist()
    if plan.record_steps[-1] < plan.step_end:  # t_end between two records: advance to it
        targets.append(plan.step_end)
    for m, setup in enumerate(plan.setups):
        sim = Simulation(setup, rng=rngs[m])
        sim.state.data[:] = state.data[m]
        sim.state.rotor.update_from(state.rotor[m])
        stepper = sim.solver.make_stepper(sim.state, dt)
        records[m, 0] = _record(sim, area)
        t = plan.step_start * dt
        for r, step in enumerate(targets, start=1):
            try:
                t = stepper(sim.state, t, step * dt)
            except SimulationDivergedError:
                diverged[m] = round(t / dt)
                break
            if r < n_records:
                records[m, r] = _record(sim, area)
        final.data[m] = sim.state.data
        final.rotor[m] = sim.rotor.as_array()
        if progress is not None:
            progress((m + 1) * plan.n_steps, n_members * plan.n_steps)
    return EnsembleResult.from_records(
        plan, records, diverged, final, "cpu", time.perf_counter() - start
    )
