"""The restart estimator's rules: independent single stops from a steady rotating state.

What makes a restart (and a bank run, :mod:`.bank`) mean the same whichever backend
computed it: the noise-free spin-up and its cache key (:func:`spin_up`,
:func:`check_spin_up`), the steady states of this process (:func:`warm_states`), the
draw of the stop angle and of the noise Generator from the seeds (:func:`draw_stop`),
the step counts of the stop and the release (:class:`Timing`), the commit check of the
release by the one inversion rule (:func:`release_outcome`) and the stored result
(:func:`restart_result`). :mod:`.releases` runs them as ensembles.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...backends.base import EnsembleRunner
from ...backends.ensemble import ROTOR_FIELDS
from ...config import RotorConfig
from ...statistics.inversion import classify_release
from ..plan import Run
from ..spec import RestartEstimator


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


WARM_MAX = 8
"""Steady states kept per process beyond those of the current ensemble."""

_WARM: OrderedDict[str, tuple[np.ndarray, np.ndarray, int]] = OrderedDict()
"""Steady rotating states of this process (fields, rotor row, step), by spin-up hash."""

PHI, OMEGA, TORQUE = (ROTOR_FIELDS.index(name) for name in ("phi", "omega", "torque"))
"""The columns of phi, omega and the torque in an ensemble state's rotor row."""


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
            check_spin_up(float(result.state.rotor[m, OMEGA]), direction, estimator)
            _WARM[key] = (result.state.data[m], result.state.rotor[m], result.state.step)
    states = [_WARM[key] for key in keys]
    while len(_WARM) > max(WARM_MAX, len(missing)):
        _WARM.popitem(last=False)
    return states
