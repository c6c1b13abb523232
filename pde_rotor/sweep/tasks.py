"""The work of one run on a worker: warm states, restarts, bank groups, protocol runs.

Everything here is picklable and runs in a dask worker process; :func:`execute_group`
is the task a sweep submits.
"""

from __future__ import annotations

import json
from collections import OrderedDict
from collections.abc import Sequence
from typing import Any

from ..backends import cpu
from ..config import RotorConfig
from ..solver.simulation import Simulation
from .estimators import (
    Timing,
    check_spin_up,
    draw_stop,
    protocol_runs,
    release_outcome,
    restart_result,
    spin_up,
    steps,
    timed_contents,
)
from .plan import Run
from .spec import BankEstimator, RestartEstimator

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


def _release(
    sim: Simulation, timing: Timing, estimator: RestartEstimator, omega_before: float
) -> dict:
    """Release `sim` (at the end of its stop) until its direction is committed."""
    dt = sim.config.grid.dt

    def omega_at(step: int) -> float:
        sim.run(step * dt)
        return sim.rotor.omega

    return release_outcome(omega_at, timing, estimator, omega_before, dt)


def run_restart(config: RotorConfig, estimator: RestartEstimator, direction: int) -> dict:
    """One independent stop from the steady state rotating in `direction`.

    The stop and the noise are drawn by :func:`.estimators.draw_stop`: the Generator
    seeded with ``config.noise.seed`` first draws the number of extra steps before the
    stop (uniform over one period 2 pi / N of the stop angle), then drives the noise of
    the branch.

    Returns:
        direction_before/after (+1, -1; after 0 if not committed), inverted, committed,
        omega_before (omega just before the stop), phi_stop (stop angle modulo 2 pi / N),
        extra_steps, t_commit (release time until commitment).
    """
    warm = warm_state(config, estimator, direction)
    dt = config.grid.dt
    stop = draw_stop(config, estimator, warm.rotor.omega, steps(warm.t, dt))
    timing = stop.timing
    sim = warm.branch(timing.protocol(config), rng=stop.rng)
    sim.run(timing.n0 * dt)
    omega_before, phi_stop = sim.rotor.omega, sim.rotor.phi
    sim.run((timing.n0 + timing.n_stop) * dt)
    release = _release(sim, timing, estimator, omega_before)
    return restart_result(release, config, phi_stop, stop.extra)


def run_bank(
    configs: Sequence[RotorConfig], estimator: BankEstimator, direction: int, stop_seed: int
) -> list[dict]:
    """One stop shared by `configs` (equal but for ``noise``), released once per config.

    The stop angle is uniform over one period 2 pi / N, drawn by the Generator seeded
    with `stop_seed` (independent for every sample, direction and point;
    :func:`.estimators.draw_stop`); the steps before and during the stop are noise-free
    (during the stop the noise has no effect, Eq. (eq_motion)). Each release branches
    from the end-of-stop state with its config's noise, seeded from its ``noise.seed``.

    Returns:
        One result per config, as :func:`run_restart`, with ``torque_end``: the torque on
        the stopped plate at the end of the stop.
    """
    base = configs[0]
    warm = warm_state(base, estimator, direction)
    dt = base.grid.dt
    drawn = draw_stop(base, estimator, warm.rotor.omega, steps(warm.t, dt), stop_seed)
    timing = drawn.timing
    quiet = timing.protocol(base)
    quiet.noise.sigma = 0.0
    stop = warm.branch(quiet)
    stop.run(timing.n0 * dt)
    omega_before, phi_stop = stop.rotor.omega, stop.rotor.phi
    stop.run((timing.n0 + timing.n_stop) * dt)
    torque_end = float(stop.rotor.torque)
    results = []
    for config in configs:
        sim = stop.branch(timing.protocol(config))
        release = _release(sim, timing, estimator, omega_before)
        results.append(restart_result(release, config, phi_stop, drawn.extra, torque_end))
    return results


def run_protocol(config: RotorConfig) -> dict:
    """One run of the paper's protocol with the CPU backend (:func:`.estimators.protocol_runs`).

    Returns:
        omegas (omega just before each of the M stops and at the end), and the inversion
        counts of :func:`~pde_rotor.statistics.proportions.protocol_counts`.
    """
    return protocol_runs([config], [config.config_hash()], cpu.run_ensemble)[0][0]


def execute(run: Run) -> dict[str, Any]:
    """Run one sweep run and return its file content (config, settings, result, timing)."""
    return execute_group([run])[0]


def execute_group(runs: Sequence[Run]) -> list[dict[str, Any]]:
    """Run a group of runs (one stop shared for the bank estimator); their file contents.

    Protocol runs go to the protocol estimator with the CPU backend (the code the
    ensemble batches run). The wall time of a group is split evenly among its runs.
    """
    kind = runs[0].estimator["kind"]
    configs = [RotorConfig.model_validate(run.config) for run in runs]

    def compute() -> tuple[list[dict], str]:
        if kind == "protocol":
            return protocol_runs(configs, [run.key for run in runs], cpu.run_ensemble)
        if kind == "bank":
            estimator = BankEstimator.model_validate(runs[0].estimator)
            assert runs[0].stop_seed is not None
            return run_bank(configs, estimator, runs[0].direction, runs[0].stop_seed), "cpu"
        estimator = RestartEstimator.model_validate(runs[0].estimator)
        pairs = zip(configs, runs, strict=True)
        return [run_restart(c, estimator, r.direction) for c, r in pairs], "cpu"

    return timed_contents(runs, compute)


def stop_group(run: Run) -> str:
    """Runs with equal value share one stop under the bank estimator (each run its own
    group under the other estimators)."""
    if run.estimator["kind"] != "bank":
        return run.key
    data = {k: v for k, v in run.config.items() if k != "noise"}
    return json.dumps([data, run.direction, run.stop_seed], sort_keys=True)
