"""Sweep runs in batches on an ensemble backend (:func:`pde_rotor.backends.run_ensemble`).

A batch is a list of runs of one estimator on one grid; they advance together as the
members of one ensemble, and each run's result is read from the ensemble's records by
the rules the per-run tasks use (:mod:`.tasks`), so a stored run means the same whichever
backend computed it:

* protocol runs start at t = 0; omega just before every stop and at the end is read
  from records at the stop steps;
* restarts and bank runs start from the steady rotating state (spun up once per
  process and configuration, as an ensemble of its own), with the stop angle drawn as
  in :func:`.tasks.run_restart` and :func:`.tasks.run_bank`. Every step is recorded,
  so the stop, the end of the stop and every commit check are read at the same steps as
  on the CPU. A bank run approaches its stop noise-free: the members advance without
  noise to the last stop begun (the members are split so that no stop has ended by
  then) and continue with their noise, whose first draw acts at the end of each stop, as
  in the CPU task.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..backends import EnsembleResult, EnsembleState
from ..backends.base import EnsembleRunner
from ..config import RotorConfig
from .estimators import (
    Timing,
    check_finite,
    check_spin_up,
    draw_stop,
    protocol_runs,
    release_outcome,
    restart_result,
    spin_up,
    timed_contents,
)
from .plan import Run
from .spec import BankEstimator, RestartEstimator

RECORD_BUDGET = 2**24
"""Most (member, recorded step) pairs of one ensemble call of restarts (0.7 GB)."""

_WARM: dict[str, tuple[np.ndarray, np.ndarray, int]] = {}
"""Steady rotating states of this process (fields, rotor row, step), by spin-up hash."""


def batches(runs: Sequence[Run], size: int) -> list[list[Run]]:
    """Split runs into batches of at most `size` members sharing grid and numerics."""
    by_grid: dict[str, list[Run]] = {}
    for run in runs:
        shared = json.dumps([run.config["grid"], run.config["numerics"]], sort_keys=True)
        by_grid.setdefault(shared, []).append(run)
    return [group[i : i + size] for group in by_grid.values() for i in range(0, len(group), size)]


def execute_batch(runs: Sequence[Run], ensemble: EnsembleRunner) -> list[dict[str, Any]]:
    """Compute runs of one estimator as ensembles; their run-file contents.

    Protocol runs go to the protocol estimator (:func:`.estimators.protocol_runs`), the
    code the per-run tasks call with the CPU backend.

    Args:
        runs: runs sharing grid and numerics (:func:`batches`).
        ensemble: the backend's ``run_ensemble``; the backend its result names is
            recorded in each run's record.

    Raises:
        ValueError: a member whose state diverged.
        RuntimeError: a spin-up that ends in the other direction.
    """
    if runs[0].estimator["kind"] == "protocol":
        configs = [RotorConfig.model_validate(run.config) for run in runs]
        keys = [run.key for run in runs]
        return timed_contents(runs, lambda: protocol_runs(configs, keys, ensemble))
    return timed_contents(runs, lambda: _restarts(runs, ensemble))


def _warm_states(
    runs: Sequence[Run],
    configs: Sequence[RotorConfig],
    estimator: RestartEstimator,
    ensemble: EnsembleRunner,
) -> list[tuple[np.ndarray, np.ndarray, int]]:
    """The steady rotating state of each run, spun up as one ensemble where missing."""
    keys = []
    missing: dict[str, tuple[dict[str, Any], int]] = {}
    for run, config in zip(runs, configs, strict=True):
        key, data = spin_up(config, estimator, run.direction)
        keys.append(key)
        if key not in _WARM:
            missing[key] = (data, run.direction)
    if missing:
        spins = [RotorConfig.model_validate(data) for data, _ in missing.values()]
        result = ensemble(spins, estimator.warmup, record_interval=estimator.warmup)
        for m, (key, (_, direction)) in enumerate(missing.items()):
            if np.isfinite(result.diverged_at[m]):
                msg = f"spin-up diverged at t = {result.diverged_at[m]:g}"
                raise ValueError(msg)
            check_spin_up(float(result.state.rotor[m, 1]), direction, estimator)
            _WARM[key] = (result.state.data[m], result.state.rotor[m], result.state.step)
    return [_WARM[key] for key in keys]


@dataclass
class _Member:
    """One restart in an ensemble: its run key, timing, config and noise Generator."""

    key: str
    timing: Timing
    extra: int
    config: RotorConfig
    rng: np.random.Generator


def _restarts(runs: Sequence[Run], ensemble: EnsembleRunner) -> tuple[list[dict], str]:
    """Restart or bank runs, in ensembles that fit :data:`RECORD_BUDGET`."""
    bank = runs[0].estimator["kind"] == "bank"
    model = BankEstimator if bank else RestartEstimator
    estimator = model.model_validate(runs[0].estimator)
    configs = [RotorConfig.model_validate(run.config) for run in runs]
    warm = _warm_states(runs, configs, estimator, ensemble)
    members = []
    for run, config, (_, rotor, step) in zip(runs, configs, warm, strict=True):
        stop = draw_stop(config, estimator, float(rotor[1]), step, run.stop_seed if bank else None)
        timing = stop.timing
        members.append(_Member(run.key, timing, stop.extra, timing.protocol(config), stop.rng))
    order = sorted(range(len(runs)), key=lambda m: members[m].timing.n0)
    results: list[dict | None] = [None] * len(runs)
    backend = "cpu"
    for part in _parts(order, members, bank):
        outcomes, backend = _ensemble_restarts(
            [members[m] for m in part], [warm[m] for m in part], estimator, ensemble, bank
        )
        for m, outcome in zip(part, outcomes, strict=True):
            results[m] = outcome
    return [r for r in results if r is not None], backend


def _parts(order: list[int], members: Sequence[_Member], bank: bool) -> list[list[int]]:
    """Members in stop order, split to fit the record budget; for the bank also so
    that every stop of a part has begun before the first one ends."""
    parts: list[list[int]] = []
    for m in order:
        timing = members[m].timing
        if parts:
            part = [*parts[-1], m]
            first = members[part[0]].timing
            span = max(members[k].timing.release + members[k].timing.n_cap for k in part)
            records = span - (first.n0 - members[part[0]].extra) + 1
            fits = len(part) * records <= RECORD_BUDGET
            if fits and (not bank or timing.n0 <= first.release):
                parts[-1] = part
                continue
        parts.append([m])
    return parts


def _ensemble_restarts(
    members: Sequence[_Member],
    warm: Sequence[tuple[np.ndarray, np.ndarray, int]],
    estimator: RestartEstimator,
    ensemble: EnsembleRunner,
    bank: bool,
) -> tuple[list[dict], str]:
    """One ensemble of restarts recorded at every step; the result of each member."""
    dt = members[0].config.grid.dt
    step0 = warm[0][2]
    initial = EnsembleState(
        data=np.stack([w[0] for w in warm]), rotor=np.stack([w[1] for w in warm]), step=step0
    )
    end = max(m.timing.release + m.timing.n_cap for m in members)
    phases: list[tuple[int, EnsembleResult]] = []
    if bank:
        quiet = []
        for m in members:
            q = m.config.model_copy(deep=True)
            q.noise.sigma = 0.0
            quiet.append(q)
        approach = max(m.timing.n0 for m in members)
        first = ensemble(quiet, approach * dt, record_interval=dt, initial=initial)
        check_finite(first, [m.key for m in members])
        phases.append((step0, first))
        initial, step0 = first.state, approach
    rngs: list[Any] = [
        _Delayed(m.rng, m.timing.release - step0) if bank else m.rng for m in members
    ]
    configs = [m.config for m in members]
    result = ensemble(configs, end * dt, record_interval=dt, initial=initial, rngs=rngs)
    check_finite(result, [m.key for m in members])
    phases.append((step0, result))

    def record(k: int, name: str, step: int) -> float:
        begin, phase = next((b, r) for b, r in reversed(phases) if step >= b)
        return float(getattr(phase, name)[k, step - begin])

    outcomes = []
    for k, member in enumerate(members):
        timing = member.timing
        omega_before = record(k, "omega", timing.n0)
        release = release_outcome(
            lambda step, k=k: record(k, "omega", step), timing, estimator, omega_before, dt
        )
        torque_end = record(k, "torque", timing.release) if bank else None
        phi_stop = record(k, "phi", timing.n0)
        outcomes.append(restart_result(release, member.config, phi_stop, member.extra, torque_end))
    return outcomes, result.backend


class _Delayed:
    """Noise draws for a bank release that continues a stop: zeros for the `delay` steps
    still in the stop (where a kick has no effect), then the draws of `rng`, so that its
    first draw acts at the end of the stop, as in :func:`.tasks.run_bank`."""

    def __init__(self, rng: np.random.Generator, delay: int) -> None:
        self.rng = rng
        self.delay = delay

    def standard_normal(self, n: int) -> np.ndarray:
        """The next `n` draws (what the backends ask a Generator for)."""
        head = min(n, self.delay)
        self.delay -= head
        return np.concatenate([np.zeros(head), self.rng.standard_normal(n - head)])
