"""The one inversion rule: did a stop-and-release operation invert the rotor?

The paper (section "Numerical results") counts an inversion when the direction of
rotation after a release differs from the one before the stop. Every estimator of
pde_rotor (the :class:`~pde_rotor.trackers.InversionTracker` of a run, the protocol,
restart and bank estimators of a sweep, the events of a GPU ensemble) classifies a
release with the functions here, applied to omega sampled at its own check times:

* **direction before** the stop: the sign of omega just before the stop (the state
  after the last step before the stop phase);
* **commitment**: the release commits at the first check with
  ``omega != 0 and |omega| >= commit_fraction * |omega_before|``
  (omega during the stop is 0, Eq. (eq_motion) with dphi/dt = 0, so the check at the
  release time itself never commits);
* **direction after**: the sign of omega at that check;
* a release that **never commits** (before the next stop, the end of the run or an
  estimator's time cap) has direction after 0, ``committed = False`` and is **not** an
  inversion; neither is a stop from omega_before = 0 (no direction to invert).

The paper's own protocol estimator
(:func:`pde_rotor.statistics.proportions.protocol_counts`) is this rule
with a single check, omega at the end of the release (just before the next stop),
and ``commit_fraction = 0`` (any rotation commits): it differs from a run's events only
for a release that does not commit before its end, or that commits and then reverses
again before the next stop.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

__all__ = [
    "Release",
    "ReleaseEvent",
    "ReleaseWatch",
    "classify_release",
    "commits",
    "direction",
    "release_events",
]


def direction(omega: float) -> int:
    """Direction of rotation: +1 CCW (omega > 0), -1 CW, 0 for omega = 0 or not finite."""
    return int(np.sign(omega)) if math.isfinite(omega) else 0


def commits(omega: float, omega_before: float, commit_fraction: float) -> bool:
    """Whether a check with angular velocity `omega` commits the release.

    Args:
        omega: omega at the check.
        omega_before: omega just before the stop.
        commit_fraction: in [0, 1]; 0: any rotation (omega != 0) commits.
    """
    if not 0 <= commit_fraction <= 1:
        msg = f"commit_fraction = {commit_fraction!r} must lie in [0, 1]"
        raise ValueError(msg)
    return direction(omega) != 0 and abs(omega) >= commit_fraction * abs(omega_before)


@dataclass(frozen=True)
class Release:
    """Outcome of one stop-and-release operation under the rule of this module.

    Attributes:
        omega_before: omega just before the stop.
        direction_before: its sign (+1, -1; 0: no rotation).
        direction_after: sign of omega at the committing check; 0 if not committed.
        committed: whether a check committed the release.
        inverted: committed and direction_after == -direction_before != 0.
        check: index of the committing check among the checks (-1: not committed).
        omega_after: omega at the committing check, else at the last check (NaN: none).
    """

    omega_before: float
    direction_before: int
    direction_after: int
    committed: bool
    inverted: bool
    check: int
    omega_after: float


class ReleaseWatch:
    """Applies the rule to the checks of one release as they come (run-time trackers).

    Feed each check's omega to :meth:`check` until it returns True (committed) or the
    release ends; :attr:`outcome` is the classification so far.
    """

    def __init__(self, omega_before: float, commit_fraction: float):
        """
        Args:
            omega_before: omega just before the stop.
            commit_fraction: commitment threshold relative to |omega_before|, in [0, 1].
        """
        commits(0.0, omega_before, commit_fraction)  # validates commit_fraction
        self.omega_before = float(omega_before)
        self.commit_fraction = commit_fraction
        self.checks = 0
        self._last = math.nan
        self._committed = -1

    @property
    def committed(self) -> bool:
        """Whether a check has committed the release."""
        return self._committed >= 0

    def check(self, omega: float) -> bool:
        """Record one check; True once the release has committed (later checks ignored)."""
        if self.committed:
            return True
        self._last = float(omega)
        if commits(omega, self.omega_before, self.commit_fraction):
            self._committed = self.checks
        self.checks += 1
        return self.committed

    @property
    def outcome(self) -> Release:
        """The release classified from the checks seen so far."""
        before = direction(self.omega_before)
        after = direction(self._last) if self.committed else 0
        return Release(
            omega_before=self.omega_before,
            direction_before=before,
            direction_after=after,
            committed=self.committed,
            inverted=self.committed and before != 0 and after == -before,
            check=self._committed,
            omega_after=self._last,
        )


def classify_release(
    omega_before: float, checks: Iterable[float], commit_fraction: float
) -> Release:
    """Classify one release from omega just before its stop and omega at its checks.

    `checks` is consumed only up to the committing check, so it may be a generator that
    advances a simulation (the restart estimator's release until commitment).

    Args:
        omega_before: omega just before the stop.
        checks: omega at the release's checks, in time order.
        commit_fraction: commitment threshold relative to |omega_before|, in [0, 1].
    """
    watch = ReleaseWatch(omega_before, commit_fraction)
    for omega in checks:
        if watch.check(omega):
            break
    return watch.outcome


@dataclass(frozen=True)
class ReleaseEvent:
    """A classified cycle of a recorded run (:func:`release_events`).

    Attributes:
        cycle: m = 1..M.
        t_stop: start time of the stop.
        release: the classification.
        time_to_commit: commit time minus release time (NaN: not committed).
    """

    cycle: int
    t_stop: float
    release: Release
    time_to_commit: float


def release_events(
    steps: np.ndarray,
    omega: np.ndarray,
    stop_steps: np.ndarray,
    n_stop: int,
    dt: float,
    commit_fraction: float,
) -> list[ReleaseEvent]:
    """Classify every stop of one recorded run (time series of omega at sample steps).

    Cycle m uses omega sampled at its stop step as omega_before and, as checks, the
    samples from its release step (stop step + n_stop) to the next stop step, both
    included (the last one is the state at the end of the release); for the last cycle,
    the samples up to the end of the record. A cycle is returned once its stop step is
    sampled and the record reaches its release step (as the run tracker closes a cycle
    whose release has begun); samples that are not finite (a diverged run) end the record.

    Args:
        steps: sample steps (t = step dt), increasing.
        omega: omega after each sample step.
        stop_steps: start step of every stop, increasing.
        n_stop: steps of one stop.
        dt: time step.
        commit_fraction: commitment threshold relative to |omega_before|, in [0, 1].
    """
    steps = np.asarray(steps, dtype=np.int64)
    omega = np.asarray(omega, dtype=float)
    finite = np.isfinite(omega)
    end = int(np.argmin(finite)) if not finite.all() else omega.size
    steps, omega = steps[:end], omega[:end]
    events = []
    for m, start in enumerate(np.asarray(stop_steps, dtype=np.int64)):
        at = np.flatnonzero(steps == start)
        release_step = start + n_stop
        if at.size == 0 or steps.size == 0 or steps[-1] < release_step:
            break
        last = stop_steps[m + 1] if m + 1 < len(stop_steps) else steps[-1]
        window = (steps >= release_step) & (steps <= last)
        release = classify_release(omega[at[0]], omega[window], commit_fraction)
        t_commit = math.nan
        if release.committed:
            t_commit = round((steps[window][release.check] - release_step) * dt, 12)
        events.append(ReleaseEvent(m + 1, round(float(start * dt), 12), release, t_commit))
    return events
