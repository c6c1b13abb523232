"""The restart and bank estimators as ensembles: members advanced to the steps they read.

:func:`restart_runs` takes the runs of one grid from their steady rotating states
(:func:`.restart.warm_states`), draws their stops (:func:`.restart.draw_stop`), splits
them into ensembles that fit the record budget (:data:`RECORD_BUDGET`) and reads
omega, the stop angle and a bank run's torque at the same global steps on every
backend, through the phases of each ensemble (a bank's noise-free approach,
:mod:`.bank`, then the release).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...backends.base import EnsembleRunner
from ...backends.ensemble import ROTOR_FIELDS, EnsembleResult, EnsembleState
from ...config import RotorConfig
from ...model.setup import Setup
from ..plan import Run
from ..spec import BankEstimator, RestartEstimator
from .bank import DelayedNoise, noise_free, run_distinct
from .base import check_finite
from .restart import (
    OMEGA,
    PHI,
    TORQUE,
    Timing,
    draw_stop,
    release_outcome,
    restart_result,
    warm_states,
)

RECORD_BUDGET = 2**24
"""Most (member, recorded step) pairs of one ensemble call of restarts (0.7 GB)."""


@dataclass
class _Member:
    """One restart in an ensemble: its run key, stop, config and noise Generator."""

    key: str
    timing: Timing
    extra: int
    config: RotorConfig
    rng: np.random.Generator


def restart_runs(
    runs: Sequence[Run], ensemble: EnsembleRunner, every_step: bool
) -> tuple[list[dict], str]:
    """The restart and bank estimators: `runs` (one grid) as ensembles from their
    steady rotating states (:func:`warm_states`).

    Each run stops as drawn by :func:`draw_stop`; omega just before the stop, the stop
    angle, the torque at the end of a bank run's stop and the commit checks of
    :func:`release_outcome` are read at the same global steps on every backend. A bank
    run approaches its stop and stops noise-free: the members advance without noise
    until the first stop ends (the members are split so that every stop has begun by
    then, :func:`_parts`), which members with equal configurations and states compute
    once, and continue with their noise, whose first draw acts at the end of each stop.

    Args:
        runs: restart or bank runs of one estimator sharing grid and numerics.
        ensemble: the backend's ``run_ensemble``.
        every_step: record every step in one call per phase (a GPU, where a call is
            costly); else advance from one read step to the next and read the state
            (the CPU backend, where a record costs about as much as a step), so that the
            release ends once every member has committed.

    Returns:
        One :func:`restart_result` per run, and the backend that computed them.

    Raises:
        ValueError: a member whose state diverged.
        RuntimeError: a spin-up that ends in the other direction.
    """
    bank = runs[0].estimator["kind"] == "bank"
    model = BankEstimator if bank else RestartEstimator
    estimator = model.model_validate(runs[0].estimator)
    configs = [RotorConfig.model_validate(run.config) for run in runs]
    warm = warm_states(runs, configs, estimator, ensemble)
    members = []
    for run, config, (_, rotor, step) in zip(runs, configs, warm, strict=True):
        seed = run.stop_seed if bank else None
        stop = draw_stop(config, estimator, float(rotor[OMEGA]), step, seed)
        timing = stop.timing
        members.append(_Member(run.key, timing, stop.extra, timing.protocol(config), stop.rng))
    order = sorted(range(len(runs)), key=lambda m: members[m].timing.n0)
    results: list[dict | None] = [None] * len(runs)
    backend = "cpu"
    for part in _parts(order, members, bank):
        reader = _Reader(
            [members[m] for m in part], [warm[m] for m in part], ensemble, bank, every_step
        )
        for k, m in enumerate(part):
            results[m] = reader.outcome(k, estimator)
        backend = reader.backend
    return [r for r in results if r is not None], backend


def _parts(order: list[int], members: Sequence[_Member], bank: bool) -> list[list[int]]:
    """Members in stop order, split to fit the record budget; for the bank also so
    that every stop of a part has begun before the first one ends (the end of the
    noise-free approach)."""
    parts: list[list[int]] = []
    for m in order:
        timing = members[m].timing
        if parts:
            part = [*parts[-1], m]
            first = members[part[0]].timing
            span = max(members[k].timing.release + members[k].timing.n_cap for k in part)
            records = span - (first.n0 - members[part[0]].extra) + 1
            fits = len(part) * records <= RECORD_BUDGET
            begun = timing.n0 <= min(members[k].timing.release for k in part)
            if fits and (not bank or begun):
                parts[-1] = part
                continue
        parts.append([m])
    return parts


@dataclass
class _Phase:
    """A stretch of an ensemble's steps with fixed member setups (made once for all of
    its ensemble calls) and noise."""

    end: int
    setups: list[Setup]
    rngs: list[Any] | None


class _Reader:
    """The rotor of the members of one ensemble at the global steps the estimators
    read, advanced on demand (phases: a bank's noise-free approach, then the release)."""

    def __init__(
        self,
        members: Sequence[_Member],
        warm: Sequence[tuple[np.ndarray, np.ndarray, int]],
        ensemble: EnsembleRunner,
        bank: bool,
        every_step: bool,
    ) -> None:
        self.members = members
        self.ensemble = ensemble
        self.every_step = every_step
        self.bank = bank
        self.keys = [m.key for m in members]
        self.dt = members[0].config.grid.dt
        self.state = EnsembleState(
            data=np.stack([w[0] for w in warm]),
            rotor=np.stack([w[1] for w in warm]),
            step=warm[0][2],
        )
        self.backend = "cpu"
        self.recorded: list[tuple[int, EnsembleResult]] = []
        self.rows = {self.state.step: self.state.rotor}
        self.phases: list[_Phase] = []
        start = self.state.step
        if bank:
            approach = min(m.timing.release for m in members)
            quiet = noise_free([m.config for m in members])
            self.phases.append(_Phase(approach, [Setup(c) for c in quiet], None))
            start = approach
        rngs = [DelayedNoise(m.rng, m.timing.release - start) if bank else m.rng for m in members]
        end = max(m.timing.release + m.timing.n_cap for m in members)
        self.phases.append(_Phase(end, [Setup(m.config) for m in members], rngs))
        reads: set[int] = set()
        for m in members:
            t = m.timing
            reads |= {t.n0, t.release, *range(t.release, t.release + t.n_cap, t.n_check)}
            reads.add(t.release + t.n_cap)
        self.reads = sorted(reads | {p.end for p in self.phases})

    def value(self, k: int, column: int, step: int) -> float:
        """Column `column` of the rotor of member `k` after global step `step`."""
        while step > self.state.step:
            self._advance()
        if step in self.rows:  # the initial state, or a read step on the CPU
            return float(self.rows[step][k, column])
        begin, result = next((b, r) for b, r in reversed(self.recorded) if step >= b)
        return float(_column(result, column)[k, step - begin])

    def _advance(self) -> None:
        """Advance to the end of the phase (every step recorded) or the next read step."""
        reached = self.state.step
        phase = next(p for p in self.phases if p.end > reached)
        target = phase.end
        if not self.every_step:
            target = min(target, next(s for s in self.reads if s > reached))
        every = 1 if self.every_step else target  # records at multiples: one at target
        result = self._run(phase, target, every)
        check_finite(result, self.keys)
        if self.every_step:
            self.recorded.append((reached, result))
        else:
            self.rows[target] = result.state.rotor
        self.state, self.backend = result.state, result.backend

    def _run(self, phase: _Phase, target: int, every: int) -> EnsembleResult:
        """The ensemble call of `phase` to `target`; a noise-free phase computes members
        with equal configurations and states once (:func:`.bank.run_distinct`)."""
        setups, state = phase.setups, self.state
        if phase.rngs is not None:
            return self.ensemble(
                setups,
                target * self.dt,
                record_interval=every * self.dt,
                initial=state,
                rngs=phase.rngs,
            )
        return run_distinct(self.ensemble, setups, state, target * self.dt, every * self.dt)

    def outcome(self, k: int, estimator: RestartEstimator) -> dict:
        """The result of member `k` (:func:`restart_result`)."""
        member = self.members[k]
        timing = member.timing
        omega_before = self.value(k, OMEGA, timing.n0)
        phi_stop = self.value(k, PHI, timing.n0)
        release = release_outcome(
            lambda step: self.value(k, OMEGA, step), timing, estimator, omega_before, self.dt
        )
        torque_end = self.value(k, TORQUE, timing.release) if self.bank else None
        return restart_result(release, member.config, phi_stop, member.extra, torque_end)


def _column(result: EnsembleResult, column: int) -> np.ndarray:
    """The records of one rotor column (phi, omega or torque)."""
    return getattr(result, ROTOR_FIELDS[column])
