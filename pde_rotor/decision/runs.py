"""Noise-free runs that measure a :class:`~pde_rotor.decision.table.DecisionTable`.

For each direction before the stop (CCW, CW) the steady rotating state of the restart
estimators (:func:`pde_rotor.sweep.tasks.warm_state`) is stopped at `n_angles` stop
angles spread evenly over one period 2π/N and held at rest for t_max + TAIL; the torque
on the stopped plate, Eq. (torque), is recorded along the way (the stop curves: memory,
asymmetry and lattice torque of Figs. 5 and 7 in one run each). At the end of the first
angle's stop, two releases (ω = 0 and ω = kick) give the growth rate λ and the kick
response C from their difference, which is linear in the kick. Optional check releases
at shorter stops compare the amplitude of ω e^{-λt} with the model's C β/λ.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np

from ..config import RotorConfig
from ..solver.simulation import Simulation
from ..sweep.estimators import Timing, period_steps
from ..sweep.spec import RestartEstimator
from ..sweep.tasks import warm_state
from .table import DIRECTIONS, TAIL, DecisionTable

SETTLE = 0.25
"""Time after the release before the fits start: the stable modes have decayed."""

LINEAR_OMEGA = 3.0
"""|ω| below which the release is linear (about 2 % of the steady ω ≈ 175)."""

RELEASE_SPAN = 10.0
"""Length of the release after a table's stop: longer than any recorded release (cap 2)."""


def _one_stop(config: RotorConfig, n_start: int, n_stop: int) -> RotorConfig:
    """`config` noise-free, with one stop from global step `n_start` lasting `n_stop` steps
    (the restart estimators' one-stop protocol, :meth:`Timing.protocol`)."""
    quiet = config.model_copy(deep=True)
    quiet.noise.sigma = 0.0
    n_release = round(RELEASE_SPAN / config.grid.dt)
    return Timing(n_start, n_stop, n_release, 1).protocol(quiet)


def release_record(
    stopped: Simulation, n_start: int, kick: float, interval: float, cap: float = 2.0
) -> tuple[np.ndarray, np.ndarray]:
    """ω(t) after releasing `stopped` now, from ω = `kick`, noise-free.

    Recorded every `interval` until |ω| exceeds 2 LINEAR_OMEGA or `cap` has passed.

    Returns:
        times since the release, ω.
    """
    dt = stopped.config.grid.dt
    n_now = round(stopped.t / dt)
    sim = stopped.branch(_one_stop(stopped.config, n_start, n_now - n_start))
    sim.rotor.omega = kick
    times, omegas = [], []
    t0 = sim.t
    for k in range(1, math.ceil(cap / interval) + 1):
        sim.run(t0 + k * interval)
        times.append(k * interval)
        omegas.append(sim.rotor.omega)
        if abs(sim.rotor.omega) > 2 * LINEAR_OMEGA:
            break
    return np.array(times), np.array(omegas)


def fit_window(times: np.ndarray, *records: np.ndarray) -> np.ndarray:
    """Mask of the linear, settled part of releases: t >= SETTLE and every |ω| < LINEAR_OMEGA
    (up to the first sample that leaves it)."""
    linear = np.all([np.abs(r) < LINEAR_OMEGA for r in records], axis=0)
    first_out = np.argmin(linear) if not linear.all() else len(times)
    mask = times >= SETTLE
    mask[first_out:] = False
    return mask


def fit_response(
    times: np.ndarray, omega_free: np.ndarray, omega_kicked: np.ndarray, kick: float
) -> tuple[float, float, int]:
    """λ and C from two releases of one state: ω_kicked - ω_free = kick h(t) ≈ kick C e^{λt}.

    Returns:
        λ, C and the number of samples fitted.

    Raises:
        RuntimeError: fewer than 5 samples in the fit window, or the difference changes sign.
    """
    mask = fit_window(times, omega_free, omega_kicked)
    diff = (omega_kicked - omega_free)[mask] / kick
    if mask.sum() < 5 or np.any(diff <= 0):
        msg = (
            f"kick response: {int(mask.sum())} samples in the fit window "
            f"(t >= {SETTLE}, |omega| < {LINEAR_OMEGA}); lower the kick or the interval"
        )
        raise RuntimeError(msg)
    slope, intercept = np.polyfit(times[mask], np.log(diff), 1)
    return float(slope), float(np.exp(intercept)), int(mask.sum())


def release_amplitude(times: np.ndarray, omega: np.ndarray, growth_rate: float) -> float:
    """lim ω e^{-λt} of a free release: the mean over its linear, settled samples
    (nan if there are none: a large bias leaves the linear range before SETTLE)."""
    mask = fit_window(times, omega)
    if not mask.any():
        return math.nan
    return float(np.mean(omega[mask] * np.exp(-growth_rate * times[mask])))


def measure_table(
    config: RotorConfig,
    n_angles: int = 4,
    t_max: float = 3.5,
    interval: float = 0.01,
    kick: float = 0.01,
    checks: Sequence[float] = (),
    estimator: RestartEstimator | None = None,
    progress: Callable[[str], None] | None = None,
) -> DecisionTable:
    """Measure the decision table of `config` (its noise is ignored).

    Args:
        config: grid, scheme, plate, flow; ``geometry.asymmetry`` is the table's Δ_ref
            (a nonzero Δ_ref lets the table predict every Δ).
        n_angles: stop angles per direction, evenly over one period 2π/N.
        t_max: longest stop the table predicts.
        interval: time between recorded torques and release samples (a multiple of dt).
        kick: ω of the kicked release (small: the response must stay linear).
        checks: stop durations of the check releases (first angle, both directions).
        estimator: spin-up (warmup, spinup_omega) of the restart estimators.
        progress: called with one line per finished stop.

    Returns:
        The table; ``attrs`` hold the config, fit sizes, λ of each direction and the
        check amplitudes measured and predicted.
    """
    estimator = estimator or RestartEstimator()
    quiet = config.model_copy(deep=True)
    quiet.noise.sigma = 0.0
    dt = quiet.grid.dt
    every = max(1, round(interval / dt))
    n_t = math.ceil((t_max + TAIL) / (every * dt)) + 1
    torque = np.empty((len(DIRECTIONS), n_angles, n_t))
    rates, responses, fitted = [], [], []
    stopped_states = {}
    check_steps = [round(c / (every * dt)) for c in checks]
    check_states: dict[tuple[int, int], Simulation] = {}
    for d, direction in enumerate(DIRECTIONS):
        warm = warm_state(quiet, estimator, direction)
        n_period = period_steps(quiet, warm.rotor.omega)
        n_warm = round(warm.t / dt)
        for k in range(n_angles):
            n_start = n_warm + (k * n_period) // n_angles
            stop = warm.branch(_one_stop(quiet, n_start, (n_t - 1) * every + 1))
            stop.run(n_start * dt)
            for j in range(n_t):
                stop.run((n_start + j * every + 1) * dt)
                torque[d, k, j] = stop.rotor.torque
                if k == 0 and j in check_steps:
                    check_states[d, j] = stop.branch()
            if k == 0:
                stopped_states[d] = (stop, n_start)
            if progress:
                progress(f"direction {direction:+d}, angle {k + 1}/{n_angles}: stopped")
    record_interval = every * dt
    for d in range(len(DIRECTIONS)):
        stop, n_start = stopped_states[d]
        t_rel, free = release_record(stop, n_start, 0.0, record_interval)
        t_kick, kicked = release_record(stop, n_start, kick, record_interval)
        n = min(len(t_rel), len(t_kick))
        rate, response, samples = fit_response(t_rel[:n], free[:n], kicked[:n], kick)
        rates.append(rate)
        responses.append(response)
        fitted.append(samples)
    time = np.arange(n_t) * record_interval
    table = DecisionTable(
        time=time,
        torque=torque,
        asymmetry=float(quiet.geometry.asymmetry),
        growth_rate=float(np.mean(rates)),
        response=float(np.mean(responses)),
        inertia=float(quiet.rotor.inertia),
        attrs={
            "config": quiet.model_dump_json(),
            "growth_rate_by_direction": np.array(rates),
            "response_by_direction": np.array(responses),
            "fit_samples": np.array(fitted),
            "kick": kick,
            "warmup": estimator.warmup,
        },
    )
    if checks:
        starts = {d: n for d, (_, n) in stopped_states.items()}
        table = _with_checks(table, check_states, check_steps, starts)
    return table


def _with_checks(
    table: DecisionTable,
    states: dict[tuple[int, int], Simulation],
    steps: Sequence[int],
    starts: dict[int, int],
) -> DecisionTable:
    """`table` with the check releases' amplitudes, measured and predicted, in attrs."""
    attrs = {**table.attrs, "check_t_stop": table.time[list(steps)]}
    for d, name in enumerate(("ccw", "cw")):
        measured, predicted = [], []
        for j in steps:
            beta = table.bias(table.time[j], table.asymmetry)
            times, omega = release_record(states[d, j], starts[d], 0.0, table.time[1])
            measured.append(release_amplitude(times, omega, table.growth_rate))
            predicted.append(table.response * float(beta[d, 0]) / table.growth_rate)
        attrs[f"check_amplitude_{name}"] = np.array(measured)
        attrs[f"check_predicted_{name}"] = np.array(predicted)
    return dataclasses.replace(table, attrs=attrs)


def table_steps(
    config: RotorConfig,
    n_angles: int,
    t_max: float,
    n_checks: int,
    estimator: RestartEstimator | None = None,
) -> int:
    """Time steps :func:`measure_table` takes (about 1 time unit per release)."""
    warmup = (estimator or RestartEstimator()).warmup
    per_direction = warmup + n_angles * (t_max + TAIL) + (2 + n_checks) * 1.0
    return round(len(DIRECTIONS) * per_direction / config.grid.dt)
