"""The work of a group of runs on a dask worker: the estimators of :mod:`.estimators`
with the CPU ensemble backend, and the groups a sweep submits.

Everything here is picklable and runs in a dask worker process; :func:`execute_group`
is the task a sweep submits. :func:`warm_state` is the steady rotating state of the
restart estimators as a :class:`~pde_rotor.solver.simulation.Simulation`, for studies
that continue it by hand (:mod:`pde_rotor.decision.runs`).
"""

from __future__ import annotations

import json
from collections import OrderedDict
from collections.abc import Sequence
from typing import Any

import numba

from ..backends import cpu
from ..config import RotorConfig
from ..solver.simulation import Simulation
from ..solver.threads import running_on
from .estimators.base import timed_contents
from .estimators.collective import collective_runs
from .estimators.protocol import protocol_runs
from .estimators.releases import restart_runs
from .estimators.restart import check_spin_up, spin_up
from .plan import Run
from .spec import RestartEstimator

_WARM: OrderedDict[str, Simulation] = OrderedDict()
"""Steady rotating states of this process, by hash of the spin-up configuration."""
_WARM_MAX = 8


def warm_key(config: RotorConfig, estimator: RestartEstimator, direction: int) -> str:
    """Runs with equal keys share the spin-up of :func:`warm_state` (in one process)."""
    return spin_up(config, estimator, direction)[0]


def warm_state(config: RotorConfig, estimator: RestartEstimator, direction: int) -> Simulation:
    """The steady rotating state for `config` and `direction`, computed once per process.

    The spin-up is noise-free and starts from omega0 = direction * spinup_omega, so the
    state is the same in every process whatever ran there before.

    Raises:
        RuntimeError: the rotor does not rotate in the requested direction after warmup.
    """
    key, data = spin_up(config, estimator, direction)
    if key in _WARM:
        _WARM.move_to_end(key)
        return _WARM[key]
    sim = Simulation(RotorConfig.model_validate(data))
    sim.run(estimator.warmup)
    check_spin_up(sim.rotor.omega, direction, estimator)
    _WARM[key] = sim
    while len(_WARM) > _WARM_MAX:
        _WARM.popitem(last=False)
    return sim


def warm_group(run: Run) -> str:
    """Runs with equal value share their spin-ups (all but protocol, noise and direction
    agree): one steady state per direction."""
    data = {k: v for k, v in run.config.items() if k not in ("protocol", "noise")}
    return json.dumps(data, sort_keys=True)


def execute(run: Run) -> dict[str, Any]:
    """Run one sweep run and return its file content (config, settings, result, timing)."""
    return execute_group([run])[0]


def execute_group(runs: Sequence[Run], threads: int = 1) -> list[dict[str, Any]]:
    """Run a group of runs (one stop shared for the bank estimator); their file contents.

    The estimators of :mod:`.estimators`, the code the ensemble batches run, with the
    CPU backend (a collective run: its own bodies run on the CPU): a restart or bank
    group advances from one step it reads to the next and ends its release once
    committed. The wall time of a group is split evenly among
    its runs. The runs step on `threads` threads (their ``solver.threads`` is null:
    numba's count, set here; at most the threads numba may start in this process).
    """
    with running_on(min(threads, numba.config.NUMBA_NUM_THREADS)):
        if runs[0].estimator["kind"] == "collective":
            return timed_contents(runs, lambda: collective_runs(runs))
        if runs[0].estimator["kind"] == "protocol":
            configs = [RotorConfig.model_validate(run.config) for run in runs]
            keys = [run.key for run in runs]
            return timed_contents(runs, lambda: protocol_runs(configs, keys, cpu.run_ensemble))
        return timed_contents(runs, lambda: restart_runs(runs, cpu.run_ensemble, every_step=False))


def stop_group(run: Run) -> str:
    """Runs with equal value share one stop under the bank estimator (each run its own
    group under the other estimators)."""
    if run.estimator["kind"] != "bank":
        return run.key
    data = {k: v for k, v in run.config.items() if k != "noise"}
    return json.dumps([data, run.direction, run.stop_seed], sort_keys=True)
