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
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..backends import EnsembleResult, EnsembleState
from ..config import RotorConfig
from ..model.protocol import steps_of
from ..statistics.proportions import protocol_counts
from .plan import Run
from .spec import BankEstimator, RestartEstimator
from .tasks import Timing, check_spin_up, period_steps, release_outcome, run_content, spin_up

EnsembleRunner = Callable[..., EnsembleResult]
"""``run_ensemble(configs, t_end, *, record_interval=..., initial=..., rngs=...)``."""

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

    Args:
        runs: runs sharing grid and numerics (:func:`batches`).
        ensemble: the backend's ``run_ensemble``; the backend its result names is
            recorded in each run's record.

    Raises:
        ValueError: a member whose state diverged.
        RuntimeError: a spin-up that ends in the other direction.
    """
    start = time.perf_counter()
    if runs[0].estimator["kind"] == "protocol":
        results, backend = _protocol(runs, ensemble)
    else:
        results, backend = _restarts(runs, ensemble)
    share = (time.perf_counter() - start) / len(runs)
    pairs = zip(runs, results, strict=True)
    return [run_content(run, result, share, backend) for run, result in pairs]


def _check(result: EnsembleResult, keys: Sequence[str]) -> None:
    """Raise if a member's state stopped being finite, naming its run."""
    for m, key in enumerate(keys):
        if np.isfinite(result.diverged_at[m]):
            msg = f"run {key} diverged at t = {result.diverged_at[m]:g}"
            raise ValueError(msg)


def _protocol(runs: Sequence[Run], ensemble: EnsembleRunner) -> tuple[list[dict], str]:
    """Protocol runs: omega after the steps before each stop and at the end."""
    configs = [RotorConfig.model_validate(run.config) for run in runs]
    steps = []
    for config in configs:
        p, dt = config.protocol, config.grid.dt
        n_ini, n_period = steps_of(p.t_ini, dt), steps_of(p.t_stop + p.t_release, dt)
        steps.append([n_ini + m * n_period for m in range(p.cycles + 1)])
    every = math.gcd(*(s for member in steps for s in member))
    dt = configs[0].grid.dt
    result = ensemble(configs, max(m[-1] for m in steps) * dt, record_interval=every * dt)
    _check(result, [run.key for run in runs])
    outcomes = []
    for m, member in enumerate(steps):
        omegas = [float(result.omega[m, s // every]) for s in member]
        counts = protocol_counts(omegas)
        outcomes.append(
            {
                "omegas": omegas,
                "inversions_ccw": counts.ccw.k,
                "n_ccw": counts.ccw.n,
                "inversions_cw": counts.cw.k,
                "n_cw": counts.cw.n,
            }
        )
    return outcomes, result.backend


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
        n_period = period_steps(config, float(rotor[1]))
        rng = np.random.default_rng(run.stop_seed if bank else config.noise.seed)
        extra = int(rng.integers(0, n_period))
        timing = Timing.of(config, estimator, step + extra)
        if bank:
            rng = np.random.default_rng(config.noise.seed)
        members.append(_Member(run.key, timing, extra, timing.protocol(config), rng))
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
        _check(first, [m.key for m in members])
        phases.append((step0, first))
        initial, step0 = first.state, approach
    rngs: list[Any] = [
        _Delayed(m.rng, m.timing.release - step0) if bank else m.rng for m in members
    ]
    configs = [m.config for m in members]
    result = ensemble(configs, end * dt, record_interval=dt, initial=initial, rngs=rngs)
    _check(result, [m.key for m in members])
    phases.append((step0, result))

    def record(k: int, name: str, step: int) -> float:
        begin, phase = next((b, r) for b, r in reversed(phases) if step >= b)
        return float(getattr(phase, name)[k, step - begin])

    outcomes = []
    period = 2 * math.pi / members[0].config.geometry.n_corners
    for k, member in enumerate(members):
        timing = member.timing
        omega_before = record(k, "omega", timing.n0)
        outcome = release_outcome(
            lambda step, k=k: record(k, "omega", step), timing, estimator, omega_before, dt
        )
        outcome["phi_stop"] = record(k, "phi", timing.n0) % period
        outcome["extra_steps"] = member.extra
        if bank:
            outcome["torque_end"] = record(k, "torque", timing.release)
        outcomes.append(outcome)
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
