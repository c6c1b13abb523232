"""The work of one run on a worker: warm states, restarts, bank groups, protocol runs.

Everything here is picklable and runs in a dask worker process; :func:`execute_group`
is the task a sweep submits.
"""

from __future__ import annotations

import hashlib
import json
import math
import time
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..config import RotorConfig
from ..solver.simulation import Simulation
from ..statistics.inversion import classify_release
from ..statistics.proportions import protocol_counts
from .plan import SCHEMA_VERSION, Run
from .spec import BankEstimator, RestartEstimator

_WARM: OrderedDict[str, Simulation] = OrderedDict()
"""Steady rotating states of this process, by hash of the spin-up configuration."""
_WARM_MAX = 8


def spin_up(
    config: RotorConfig, estimator: RestartEstimator, direction: int
) -> tuple[str, dict[str, Any]]:
    """The spin-up configuration of `config` in `direction` and its hash (the cache key)."""
    data = config.model_dump(mode="json")
    data["protocol"].update(t_ini=estimator.warmup, cycles=0)
    data["noise"].update(sigma=0.0, seed=0)
    data["rotor"]["omega0"] = direction * estimator.spinup_omega
    data.pop("output", None)
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest(), data


def check_spin_up(omega: float, direction: int, estimator: RestartEstimator) -> None:
    """Raise unless the spin-up ended rotating in `direction`.

    Raises:
        RuntimeError: omega after the warmup has the other sign (or none).
    """
    if np.sign(omega) != direction:
        msg = (
            f"spin-up from omega0 = {direction * estimator.spinup_omega:g} ended with omega = "
            f"{omega:.4g} at t = {estimator.warmup:g}, not in the requested direction; "
            "raise estimator.spinup_omega"
        )
        raise RuntimeError(msg)


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


def _steps(duration: float, dt: float) -> int:
    return round(duration / dt)


@dataclass(frozen=True)
class Timing:
    """Step counts of one restart: global step of the stop, stop, release cap, check."""

    n0: int
    n_stop: int
    n_cap: int
    n_check: int

    @classmethod
    def of(cls, config: RotorConfig, estimator: RestartEstimator, n0: int) -> Timing:
        """The timing of a restart of `config` that stops after global step `n0`."""
        dt = config.grid.dt
        cap = estimator.release_cap
        cap = cap if cap is not None else config.protocol.t_release
        return cls(
            n0,
            _steps(config.protocol.t_stop, dt),
            _steps(cap, dt),
            max(1, _steps(estimator.check_interval, dt)),
        )

    @property
    def release(self) -> int:
        """Global step at which the stop ends and the release begins."""
        return self.n0 + self.n_stop

    def protocol(self, config: RotorConfig) -> RotorConfig:
        """`config` with the one-stop protocol of this restart."""
        dt = config.grid.dt
        data = config.model_dump(mode="json")
        data["protocol"].update(
            t_ini=self.n0 * dt, t_stop=self.n_stop * dt, t_release=self.n_cap * dt, cycles=1
        )
        return RotorConfig.model_validate(data)


def period_steps(config: RotorConfig, omega: float) -> int:
    """Steps per period 2 pi / N of the stop angle at the angular velocity `omega`."""
    period = 2 * math.pi / config.geometry.n_corners
    return max(1, round(period / (abs(omega) * config.grid.dt)))


def release_outcome(
    omega_at: Callable[[int], float],
    timing: Timing,
    estimator: RestartEstimator,
    omega_before: float,
    dt: float,
) -> dict:
    """The restart and bank estimators' release, classified by the one inversion rule.

    omega is checked every check_interval after the release, at most until the release
    cap, and the checks go to :func:`pde_rotor.statistics.inversion.classify_release` (commit once
    omega != 0 and |omega| >= commit_fraction |omega_before|; never committed: direction
    after 0, not an inversion), which stops reading them at the committing check.

    Args:
        omega_at: omega after a global step (advances a simulation, or reads records).
        timing: the restart's step counts.
        estimator: commit fraction, check interval.
        omega_before: omega just before the stop.
        dt: time step.
    """
    n_checks = -(-timing.n_cap // timing.n_check)  # the last check is at the cap
    offsets = [min(k * timing.n_check, timing.n_cap) for k in range(1, n_checks + 1)]
    checks = (omega_at(timing.release + n) for n in offsets)
    release = classify_release(omega_before, checks, estimator.commit_fraction)
    return {
        "direction_before": release.direction_before,
        "direction_after": release.direction_after,
        "inverted": release.inverted,
        "committed": release.committed,
        "omega_before": float(omega_before),
        "omega_end": float(release.omega_after),
        "t_commit": float(offsets[release.check] * dt) if release.committed else math.nan,
    }


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

    The Generator seeded with ``config.noise.seed`` first draws the number of extra
    steps before the stop (uniform over one period 2 pi / N of the stop angle), then
    drives the noise of the branch.

    Returns:
        direction_before/after (+1, -1; after 0 if not committed), inverted, committed,
        omega_before (omega just before the stop), phi_stop (stop angle modulo 2 pi / N),
        extra_steps, t_commit (release time until commitment).
    """
    warm = warm_state(config, estimator, direction)
    dt = config.grid.dt
    rng = np.random.default_rng(config.noise.seed)
    extra = int(rng.integers(0, period_steps(config, warm.rotor.omega)))
    timing = Timing.of(config, estimator, _steps(warm.t, dt) + extra)
    sim = warm.branch(timing.protocol(config), rng=rng)
    sim.run(timing.n0 * dt)
    omega_before, phi_stop = sim.rotor.omega, sim.rotor.phi
    sim.run((timing.n0 + timing.n_stop) * dt)
    result = _release(sim, timing, estimator, omega_before)
    period = 2 * math.pi / config.geometry.n_corners
    return {**result, "phi_stop": float(phi_stop % period), "extra_steps": extra}


def run_bank(
    configs: Sequence[RotorConfig], estimator: BankEstimator, direction: int, stop_seed: int
) -> list[dict]:
    """One stop shared by `configs` (equal but for ``noise``), released once per config.

    The stop angle is uniform over one period 2 pi / N, drawn by the Generator seeded
    with `stop_seed` (independent for every sample, direction and point); the steps
    before and during the stop are noise-free (during the stop the noise has no effect,
    Eq. (eq_motion)). Each release branches from the end-of-stop state with its config's
    noise, seeded from its ``noise.seed``.

    Returns:
        One result per config, as :func:`run_restart`, with ``torque_end``: the torque on
        the stopped plate at the end of the stop.
    """
    base = configs[0]
    warm = warm_state(base, estimator, direction)
    dt = base.grid.dt
    n_period = period_steps(base, warm.rotor.omega)
    extra = int(np.random.default_rng(stop_seed).integers(0, n_period))
    timing = Timing.of(base, estimator, _steps(warm.t, dt) + extra)
    quiet = timing.protocol(base)
    quiet.noise.sigma = 0.0
    stop = warm.branch(quiet)
    stop.run(timing.n0 * dt)
    omega_before, phi_stop = stop.rotor.omega, stop.rotor.phi
    stop.run((timing.n0 + timing.n_stop) * dt)
    torque_end = float(stop.rotor.torque)
    period = 2 * math.pi / base.geometry.n_corners
    results = []
    for config in configs:
        sim = stop.branch(timing.protocol(config))
        result = _release(sim, timing, estimator, omega_before)
        results.append(
            {
                **result,
                "phi_stop": float(phi_stop % period),
                "extra_steps": extra,
                "torque_end": torque_end,
            }
        )
    return results


def run_protocol(config: RotorConfig) -> dict:
    """One run of the paper's protocol; omega just before each stop and at the end.

    Returns:
        omegas (M + 1 values), and the inversion counts of :func:`protocol_counts`.
    """
    sim = Simulation(config)
    dt = config.grid.dt
    p = config.protocol
    n_ini, n_period = _steps(p.t_ini, dt), _steps(p.t_stop + p.t_release, dt)
    omegas = []
    for m in range(p.cycles + 1):
        sim.run((n_ini + m * n_period) * dt)
        omegas.append(float(sim.rotor.omega))
    counts = protocol_counts(omegas)
    return {
        "omegas": omegas,
        "inversions_ccw": counts.ccw.k,
        "n_ccw": counts.ccw.n,
        "inversions_cw": counts.cw.k,
        "n_cw": counts.cw.n,
    }


def run_content(run: Run, result: dict, wall_time: float, backend: str) -> dict[str, Any]:
    """What the record of `run` in the store holds: its key, point, sample, result and cost.

    The resolved config is not repeated: the run key is its hash, and the sweep file in
    the sweep directory resolves it again.
    """
    return {
        "key": run.key,
        "schema": SCHEMA_VERSION,
        "coords": run.coords,
        "sample": run.sample,
        "direction": run.direction,
        "result": result,
        "wall_time": wall_time,
        "backend": backend,
    }


def execute(run: Run) -> dict[str, Any]:
    """Run one sweep run and return its file content (config, settings, result, timing)."""
    return execute_group([run])[0]


def execute_group(runs: Sequence[Run]) -> list[dict[str, Any]]:
    """Run a group of runs (one stop shared for the bank estimator); their file contents.

    The wall time of a bank group is split evenly among its runs.
    """
    start = time.perf_counter()
    kind = runs[0].estimator["kind"]
    configs = [RotorConfig.model_validate(run.config) for run in runs]
    if kind == "bank":
        estimator = BankEstimator.model_validate(runs[0].estimator)
        assert runs[0].stop_seed is not None
        results = run_bank(configs, estimator, runs[0].direction, runs[0].stop_seed)
    elif kind == "restart":
        estimator = RestartEstimator.model_validate(runs[0].estimator)
        pairs = zip(configs, runs, strict=True)
        results = [run_restart(c, estimator, r.direction) for c, r in pairs]
    else:
        results = [run_protocol(c) for c in configs]
    share = (time.perf_counter() - start) / len(runs)
    pairs = zip(runs, results, strict=True)
    return [run_content(run, result, share, "cpu") for run, result in pairs]


def stop_group(run: Run) -> str:
    """Runs with equal value share one stop under the bank estimator (each run its own
    group under the other estimators)."""
    if run.estimator["kind"] != "bank":
        return run.key
    data = {k: v for k, v in run.config.items() if k != "noise"}
    return json.dumps([data, run.direction, run.stop_seed], sort_keys=True)
