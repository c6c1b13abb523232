"""The sweep estimators' rules, written once for every place a run is computed.

A run is computed either by a per-run task on a dask worker (:mod:`.tasks`) or as a
member of an ensemble batch (:mod:`.batch`); both take from here what makes a stored run
mean the same whichever computed it:

* the protocol estimator itself (:func:`protocol_runs`), over any ensemble backend
  (:class:`pde_rotor.backends.base.EnsembleRunner`): the tasks call it with the CPU
  backend, the batches with theirs;
* for the restart and bank estimators: the spin-up configuration (:func:`spin_up`), the
  draw of the stop angle and of the noise Generator from the seeds (:func:`draw_stop`),
  the step counts of the stop and the release (:class:`Timing`), the commit check of
  the release (:func:`release_outcome`) and the result of a restart
  (:func:`restart_result`);
* the divergence check (:func:`check_finite`) and the record of a run with its share
  of the wall time (:func:`timed_contents`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import time
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..backends.base import EnsembleRunner
from ..backends.ensemble import ROTOR_FIELDS, EnsembleResult, EnsembleState
from ..config import RotorConfig
from ..model.protocol import steps_of
from ..statistics.inversion import classify_release
from ..statistics.proportions import protocol_counts
from .plan import SCHEMA_VERSION, Run
from .spec import BankEstimator, RestartEstimator


def steps(duration: float, dt: float) -> int:
    """Steps of `duration` (rounded)."""
    return round(duration / dt)


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
            steps(config.protocol.t_stop, dt),
            steps(cap, dt),
            max(1, steps(estimator.check_interval, dt)),
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


def stop_period(config: RotorConfig) -> float:
    """The period 2 pi / N of the stop angle."""
    return 2 * math.pi / config.geometry.n_corners


def period_steps(config: RotorConfig, omega: float) -> int:
    """Steps per period 2 pi / N of the stop angle at the angular velocity `omega`."""
    return max(1, round(stop_period(config) / (abs(omega) * config.grid.dt)))


@dataclass
class Stop:
    """Where a restart stops, and the Generator of its release's noise.

    Attributes:
        extra: steps of steady rotation after the warm state before the stop.
        timing: the restart's step counts.
        rng: the noise of the release (of the whole branch for a restart).
    """

    extra: int
    timing: Timing
    rng: np.random.Generator


def draw_stop(
    config: RotorConfig,
    estimator: RestartEstimator,
    omega: float,
    warm_step: int,
    stop_seed: int | None = None,
) -> Stop:
    """Draw the stop of a restart from the warm state at global step `warm_step`.

    The extra steps are uniform over one period 2 pi / N of the stop angle at the warm
    angular velocity `omega`. A restart (`stop_seed` None) draws them first from the
    Generator seeded with ``config.noise.seed``, which then drives the noise; a bank run
    draws them from the Generator seeded with `stop_seed` (shared by the runs of one
    stop), and its noise is the Generator seeded with ``config.noise.seed``.
    """
    rng = np.random.default_rng(config.noise.seed if stop_seed is None else stop_seed)
    extra = int(rng.integers(0, period_steps(config, omega)))
    if stop_seed is not None:
        rng = np.random.default_rng(config.noise.seed)
    return Stop(extra, Timing.of(config, estimator, warm_step + extra), rng)


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


def restart_result(
    release: dict,
    config: RotorConfig,
    phi_stop: float,
    extra: int,
    torque_end: float | None = None,
) -> dict:
    """The stored result of a restart (a bank run: with `torque_end`).

    Args:
        release: :func:`release_outcome`.
        config: the run's configuration (the period of the stop angle).
        phi_stop: the rotor angle at the stop, stored modulo 2 pi / N.
        extra: the drawn extra steps before the stop.
        torque_end: the torque on the stopped plate at the end of the stop.
    """
    result = {**release, "phi_stop": float(phi_stop % stop_period(config)), "extra_steps": extra}
    if torque_end is not None:
        result["torque_end"] = float(torque_end)
    return result


def check_finite(result: EnsembleResult, keys: Sequence[str]) -> None:
    """Raise if a member's state stopped being finite, naming its run.

    Raises:
        ValueError: the first diverged member, with its run key and time.
    """
    for m, key in enumerate(keys):
        if np.isfinite(result.diverged_at[m]):
            msg = f"run {key} diverged at t = {result.diverged_at[m]:g}"
            raise ValueError(msg)


def protocol_steps(config: RotorConfig) -> list[int]:
    """Global steps after which the protocol estimator reads omega: before every stop,
    and at the end."""
    p, dt = config.protocol, config.grid.dt
    n_ini, n_period = steps_of(p.t_ini, dt), steps_of(p.t_stop + p.t_release, dt)
    return [n_ini + m * n_period for m in range(p.cycles + 1)]


def protocol_result(omegas: Sequence[float]) -> dict:
    """The stored result of a protocol run: the omegas and the counts of
    :func:`~pde_rotor.statistics.proportions.protocol_counts`."""
    counts = protocol_counts(omegas)
    return {
        "omegas": [float(w) for w in omegas],
        "inversions_ccw": counts.ccw.k,
        "n_ccw": counts.ccw.n,
        "inversions_cw": counts.cw.k,
        "n_cw": counts.cw.n,
    }


def protocol_runs(
    configs: Sequence[RotorConfig], keys: Sequence[str], ensemble: EnsembleRunner
) -> tuple[list[dict], str]:
    """The protocol estimator: runs of one grid as one ensemble from t = 0.

    omega is recorded at the gcd of the steps it is read at (:func:`protocol_steps`).

    Args:
        configs: the runs' configurations.
        keys: their run keys (named if a run diverges).
        ensemble: the backend's ``run_ensemble``.

    Returns:
        One :func:`protocol_result` per run, and the backend that computed them.

    Raises:
        ValueError: a member whose state diverged.
    """
    reads = [protocol_steps(config) for config in configs]
    every = math.gcd(*(s for member in reads for s in member))
    dt = configs[0].grid.dt
    result = ensemble(configs, max(m[-1] for m in reads) * dt, record_interval=every * dt)
    check_finite(result, keys)
    outcomes = [
        protocol_result([result.omega[m, s // every] for s in member])
        for m, member in enumerate(reads)
    ]
    return outcomes, result.backend


RECORD_BUDGET = 2**24
"""Most (member, recorded step) pairs of one ensemble call of restarts (0.7 GB)."""

WARM_MAX = 8
"""Steady states kept per process beyond those of the current ensemble."""

_WARM: OrderedDict[str, tuple[np.ndarray, np.ndarray, int]] = OrderedDict()
"""Steady rotating states of this process (fields, rotor row, step), by spin-up hash."""

_PHI, _OMEGA, _TORQUE = (ROTOR_FIELDS.index(name) for name in ("phi", "omega", "torque"))


def warm_states(
    runs: Sequence[Run],
    configs: Sequence[RotorConfig],
    estimator: RestartEstimator,
    ensemble: EnsembleRunner,
) -> list[tuple[np.ndarray, np.ndarray, int]]:
    """The steady rotating state of each run, spun up as one ensemble where missing.

    The spin-up (:func:`spin_up`) is noise-free and starts from omega0 = direction *
    spinup_omega, so the state is the same in every process whatever ran there before.

    Raises:
        ValueError: a spin-up diverged.
        RuntimeError: a spin-up ended rotating in the other direction.
    """
    keys = []
    missing: dict[str, tuple[dict[str, Any], int]] = {}
    for run, config in zip(runs, configs, strict=True):
        key, data = spin_up(config, estimator, run.direction)
        keys.append(key)
        if key in _WARM:
            _WARM.move_to_end(key)
        else:
            missing[key] = (data, run.direction)
    if missing:
        spins = [RotorConfig.model_validate(data) for data, _ in missing.values()]
        result = ensemble(spins, estimator.warmup, record_interval=estimator.warmup)
        for m, (key, (_, direction)) in enumerate(missing.items()):
            if np.isfinite(result.diverged_at[m]):
                msg = f"spin-up diverged at t = {result.diverged_at[m]:g}"
                raise ValueError(msg)
            check_spin_up(float(result.state.rotor[m, _OMEGA]), direction, estimator)
            _WARM[key] = (result.state.data[m], result.state.rotor[m], result.state.step)
    states = [_WARM[key] for key in keys]
    while len(_WARM) > max(WARM_MAX, len(missing)):
        _WARM.popitem(last=False)
    return states


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
        stop = draw_stop(config, estimator, float(rotor[_OMEGA]), step, seed)
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
    """A stretch of an ensemble's steps with fixed member configs and noise."""

    end: int
    configs: list[RotorConfig]
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
            quiet = []
            for m in members:
                q = m.config.model_copy(deep=True)
                q.noise.sigma = 0.0
                quiet.append(q)
            self.phases.append(_Phase(approach, quiet, None))
            start = approach
        rngs = [_Delayed(m.rng, m.timing.release - start) if bank else m.rng for m in members]
        end = max(m.timing.release + m.timing.n_cap for m in members)
        self.phases.append(_Phase(end, [m.config for m in members], rngs))
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
        with equal configurations and states once."""
        configs, state = phase.configs, self.state
        if phase.rngs is not None:
            return self.ensemble(
                configs,
                target * self.dt,
                record_interval=every * self.dt,
                initial=state,
                rngs=phase.rngs,
            )
        firsts: dict[tuple[str, bytes, bytes], int] = {}
        inverse = []
        for m, config in enumerate(configs):
            key = (
                config.model_dump_json(exclude={"noise"}),
                state.data[m].tobytes(),
                state.rotor[m].tobytes(),
            )
            inverse.append(firsts.setdefault(key, len(firsts)))
        unique = [next(m for m, i in enumerate(inverse) if i == j) for j in range(len(firsts))]
        initial = EnsembleState(state.data[unique], state.rotor[unique], state.step)
        result = self.ensemble(
            [configs[m] for m in unique],
            target * self.dt,
            record_interval=every * self.dt,
            initial=initial,
        )
        return _expand(result, configs, np.array(inverse))

    def outcome(self, k: int, estimator: RestartEstimator) -> dict:
        """The result of member `k` (:func:`restart_result`)."""
        member = self.members[k]
        timing = member.timing
        omega_before = self.value(k, _OMEGA, timing.n0)
        phi_stop = self.value(k, _PHI, timing.n0)
        release = release_outcome(
            lambda step: self.value(k, _OMEGA, step), timing, estimator, omega_before, self.dt
        )
        torque_end = self.value(k, _TORQUE, timing.release) if self.bank else None
        return restart_result(release, member.config, phi_stop, member.extra, torque_end)


def _column(result: EnsembleResult, column: int) -> np.ndarray:
    """The records of one rotor column (phi, omega or torque)."""
    return getattr(result, ROTOR_FIELDS[column])


def _expand(
    result: EnsembleResult, configs: Sequence[RotorConfig], inverse: np.ndarray
) -> EnsembleResult:
    """`result` of the distinct members, as the result of every member (`inverse`:
    member -> distinct member)."""
    state = result.state
    return dataclasses.replace(
        result,
        configs=tuple(configs),
        phi=result.phi[inverse],
        omega=result.omega[inverse],
        torque=result.torque[inverse],
        friction=result.friction[inverse],
        stopped=result.stopped[inverse],
        camphor_total=result.camphor_total[inverse],
        diverged_at=result.diverged_at[inverse],
        state=EnsembleState(state.data[inverse], state.rotor[inverse], state.step),
    )


class _Delayed:
    """Noise draws for a bank release that continues a stop: zeros for the `delay` steps
    still in the stop (where a kick has no effect), then the draws of `rng`, so that its
    first draw acts at the end of the stop."""

    def __init__(self, rng: np.random.Generator, delay: int) -> None:
        self.rng = rng
        self.delay = delay

    def standard_normal(self, n: int) -> np.ndarray:
        """The next `n` draws (what the backends ask a Generator for)."""
        head = min(n, self.delay)
        self.delay -= head
        return np.concatenate([np.zeros(head), self.rng.standard_normal(n - head)])


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


def timed_contents(
    runs: Sequence[Run], compute: Callable[[], tuple[list[dict], str]]
) -> list[dict[str, Any]]:
    """Compute the results of `runs` and return their records; the wall time is split
    evenly among the runs.

    Args:
        runs: the runs computed together.
        compute: returns one result per run and the backend that computed them.
    """
    start = time.perf_counter()
    results, backend = compute()
    share = (time.perf_counter() - start) / len(runs)
    pairs = zip(runs, results, strict=True)
    return [run_content(run, result, share, backend) for run, result in pairs]
