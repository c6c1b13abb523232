"""A single run with its trackers on an ensemble backend: an ensemble of one member.

``solver.backend: gpu`` (or ``auto`` on a GPU machine) runs a configuration through
:func:`pde_rotor.backends.run_ensemble` instead of the CPU solver's py-pde Controller.
The backend advances the member in segments and returns its records; this module hands
every tracker of :mod:`pde_rotor.trackers` the samples it asks for, so a run writes the
same files on every backend:

* the rotor trackers (time series, inversion events) read the records, taken every
  ``gcd`` of their sampling steps (phi, omega, torque, friction, stop flag and the
  total camphor of Eqs. (eqc), (eq_motion), (torque));
* every other tracker (snapshots, movie, any py-pde tracker) may read c and v: the run
  returns to the host at each of its times (the segment ends) and it reads the member's
  fields there;
* trackers on wall-clock interrupts (the progress bar) are called at every segment end
  (at most :data:`SEGMENT_STEPS` steps apart); the time series is checkpointed as on the
  CPU.

The noise stream is the CPU solver's (``default_rng(noise.seed)``, drawn in step
order), so the same seed gives the same run on both paths.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from pde.trackers.interrupts import RealtimeInterrupts

from ..backends import EnsembleState, run_ensemble
from ..backends.ensemble import RECORD_FIELDS
from ..model.protocol import steps_of
from ..trackers import InversionTracker, TimeSeriesTracker
from .rotor import SimulationDivergedError
from .simulation import Simulation

SEGMENT_STEPS = 100_000
"""Most steps between two returns to the host (progress bar, checkpoints)."""

_SAMPLE_TRACKERS = (TimeSeriesTracker, InversionTracker)
"""Trackers that read only the rotor state (and the total camphor): fed from records."""


def _wall_clock(tracker: Any) -> bool:
    """Whether the tracker's interrupts follow the wall clock (the progress bar)."""
    return isinstance(tracker.interrupt, RealtimeInterrupts)


def _steps(tracker: Any, dt: float, n_end: int) -> np.ndarray:
    """The steps at which `tracker` asks to be called, in [0, n_end]."""
    interrupt = tracker.interrupt.copy()
    times = [interrupt.initialize(0.0)]
    while times[-1] <= (n_end + 0.5) * dt:
        times.append(interrupt.next(times[-1]))
    steps = np.round(np.asarray(times[:-1]) / dt).astype(np.int64)
    return np.unique(steps[(steps >= 0) & (steps <= n_end)])


def _plan(trackers: Sequence[Any], dt: float, n_end: int) -> tuple[int, np.ndarray]:
    """Record interval in steps (gcd of the rotor trackers' steps) and the segment ends."""
    sample_steps = [np.array([n_end], dtype=np.int64)]
    field_steps = [np.array([n_end], dtype=np.int64), np.arange(0, n_end, SEGMENT_STEPS)]
    for tracker in trackers:
        if _wall_clock(tracker):
            continue
        steps = _steps(tracker, dt, n_end)
        (sample_steps if isinstance(tracker, _SAMPLE_TRACKERS) else field_steps).append(steps)
    every = int(np.gcd.reduce(np.concatenate(sample_steps)))
    ends = np.unique(np.concatenate(field_steps))
    return max(every, 1), ends[ends > 0]


def run_single(sim: Simulation, trackers: Sequence[Any], backend: str) -> None:
    """Run ``sim.config`` to ``protocol.t_end`` on `backend`, feeding `trackers`.

    On return (or when SimulationDivergedError is raised) ``sim`` holds the state
    reached: fields, rotor and time. The trackers are finalized after a completed run;
    after a divergence, as after a CPU run, the caller finalizes them.

    Args:
        sim: the simulation (its config, state and rotor; its solver is not used).
        trackers: trackers of :mod:`pde_rotor.trackers` built for `sim`.
        backend: resolved backend, "gpu" or "cpu" (the CPU ensemble backend).

    Raises:
        SimulationDivergedError: the member's state stopped being finite.
    """
    cfg = sim.config
    dt = cfg.grid.dt
    t_end = cfg.protocol.t_end
    n_end = steps_of(t_end, dt)
    area = sim.pde.domain.cell_area
    info = {"controller": {"t_start": 0.0, "t_end": t_end}}
    next_t = [tracker.initialize(sim.state, info) for tracker in trackers]
    every, ends = _plan(trackers, dt, n_end)
    rng = np.random.default_rng(cfg.noise.seed)
    start = np.append(sim.rotor.as_array(), sim.state.data[0].sum() * area)
    _deliver(sim, trackers, next_t, {0: start}, field_step=0)
    state: EnsembleState | None = None
    for end in ends:
        result = run_ensemble(
            [cfg], end * dt, backend=backend, record_interval=every * dt, initial=state, rngs=[rng]
        )
        state = result.state
        sim.state.data[...] = state.data[0]
        steps = np.round(result.t / dt).astype(np.int64)
        columns = np.column_stack([getattr(result, name)[0] for name in RECORD_FIELDS])
        rows = {int(step): row for step, row in zip(steps, columns, strict=True)}
        failed = result.diverged_at[0]
        reached = int(end) if math.isnan(failed) else round(failed / dt)
        if math.isnan(failed):
            rows[reached] = np.append(state.rotor[0], state.data[0, 0].sum() * area)
        rows = {k: v for k, v in rows.items() if k <= reached and np.isfinite(v).all()}
        _deliver(sim, trackers, next_t, rows, field_step=reached if math.isnan(failed) else -1)
        sim.state.rotor.update_from(state.rotor[0])
        sim.t = reached * dt
        if not math.isnan(failed):
            msg = (
                f"simulation diverged at t = {failed:.6g} on the {result.backend} backend: "
                f"non-finite state (dt = {dt:g}, stability limit {sim.pde.config.dt_limit():.4g})"
            )
            raise SimulationDivergedError(msg)
    done = {"successful": True, "stop_reason": "Reached final time", "t_final": t_end}
    for tracker in trackers:
        tracker.finalize({"controller": done})


def _deliver(
    sim: Simulation,
    trackers: Sequence[Any],
    next_t: list[float],
    rows: dict[int, np.ndarray],
    field_step: int,
) -> None:
    """Hand each tracker its samples among `rows` (fields only at `field_step`)."""
    dt = sim.config.grid.dt
    last = max(rows) if rows else -1
    for k, tracker in enumerate(trackers):
        if _wall_clock(tracker):
            if field_step >= 0:
                sim.state.rotor.update_from(rows[field_step][:5])
                tracker.handle(sim.state, field_step * dt)
            continue
        while next_t[k] <= last * dt + 0.5 * dt:
            step = round(next_t[k] / dt)
            row = rows.get(step)
            if row is None or (not isinstance(tracker, _SAMPLE_TRACKERS) and step != field_step):
                break
            sim.state.rotor.update_from(row[:5])
            if isinstance(tracker, TimeSeriesTracker):
                tracker.sample(next_t[k], sim.state.rotor, float(row[5]))
            else:
                tracker.handle(sim.state, next_t[k])
            next_t[k] = tracker.interrupt.next(next_t[k])
