"""One inversion rule: the same omega(t) gives the same events in every estimator.

A prescribed omega(t) with five stop-and-release cycles runs through the run tracker
(:class:`~pde_rotor.trackers.InversionTracker`), the sweep's restart/bank commit rule
(``pde_rotor.sweep.estimators.restart.release_outcome``), the ensemble backends' classification
(:meth:`~pde_rotor.backends.ensemble.EnsembleResult.release_events`) and the paper's
protocol estimator (:func:`~pde_rotor.statistics.proportions.protocol_counts`). The cycles cover a
commitment in the old direction, an inversion, a release that never commits, a
commitment exactly at the threshold after a check just below it, and a brief weak
reversal followed by a commitment in the old direction.
"""

from __future__ import annotations

import itertools
import math
from types import SimpleNamespace

import numpy as np
import pytest

from pde_rotor.backends.ensemble import EnsembleResult, EnsembleState
from pde_rotor.config import RotorConfig
from pde_rotor.model.pde import RotorState
from pde_rotor.model.protocol import StopSchedule
from pde_rotor.model.setup import Setup
from pde_rotor.statistics.inversion import Release, classify_release, commits, direction
from pde_rotor.statistics.proportions import protocol_counts, restart_counts
from pde_rotor.sweep import RestartEstimator
from pde_rotor.sweep.estimators.restart import Timing, release_outcome
from pde_rotor.trackers import InversionTracker

FRACTION = 0.5
CHECK = 0.01
CONFIG = RotorConfig.model_validate(
    {
        "grid": {"dx": 0.05, "dt": 4e-4},
        "geometry": {"smoothing": 0.05},
        "protocol": {"t_ini": 1.0, "t_stop": 0.5, "t_release": 1.0, "cycles": 5},
        "output": {"event_interval": CHECK, "commit_fraction": FRACTION},
    }
)
SCHEDULE = StopSchedule.from_config(CONFIG.protocol, CONFIG.grid.dt)
CHECK_STEPS = round(CHECK / CONFIG.grid.dt)


def release_profile(cycle: int, k: int) -> float:
    """omega k steps after release `cycle` (0-based); see the module docstring."""
    if cycle == 0:
        return min(0.08 * k, 10.0)  # from +10: |omega| = 5 between checks, commits at k = 75
    if cycle == 1:
        return -min(0.08 * k, 10.0)  # from +10: inverts, commits at k = 75
    if cycle == 2:
        return 1.0  # from -10: reversed but weak (1 < 5) until the next stop
    if cycle == 3:
        return -0.4999999 if k < 200 else -0.5  # from +1: -0.5 is the threshold itself
    return 0.2 if k < 100 else -3.0  # from -0.5: weak reversal (0.2 < 0.25), then keeps CW


def omega_at(step: int) -> float:
    """omega after `step` steps: +10 up to the first stop, 0 in stops, the profiles after."""
    starts = SCHEDULE.stop_steps()
    if step <= starts[0]:
        return 10.0
    m = min(int((step - starts[0] - 1) // SCHEDULE.n_period), SCHEDULE.cycles - 1)
    k = step - starts[m] - SCHEDULE.n_stop
    return 0.0 if k <= 0 else release_profile(m, k)


END = SCHEDULE.n_ini + SCHEDULE.cycles * SCHEDULE.n_period
EXPECTED = {
    "committed": [True, True, False, True, True],
    "direction_after": [1, -1, 0, -1, -1],
    "inverted": [False, True, False, True, False],
    "check_steps": [75, 75, None, 200, 100],
}
"""The rule applied by hand to the profiles (first check at or above the threshold)."""


def by_tracker() -> list[tuple[int, int, bool, bool]]:
    """(direction_before, direction_after, committed, inverted) per cycle, from the tracker."""
    state = SimpleNamespace(rotor=RotorState(phi=0.0, omega=0.0))
    tracker = InversionTracker(CONFIG, CHECK, FRACTION)
    for step in SCHEDULE.sample_steps(CHECK_STEPS, END):
        state.rotor.omega = omega_at(int(step))
        tracker.handle(state, step * CONFIG.grid.dt)
    tracker.finalize({"controller": {"successful": True}})
    for event, check in zip(tracker.events, EXPECTED["check_steps"], strict=True):
        want = math.nan if check is None else check * CONFIG.grid.dt
        assert event.time_to_commit == pytest.approx(want, nan_ok=True, abs=1e-12)
    return [
        (e.direction_before, e.direction_after, e.committed, e.inverted) for e in tracker.events
    ]


def by_sweep_release() -> list[tuple[int, int, bool, bool]]:
    """The same per cycle from the restart/bank estimators' commit rule
    (sweep.estimators.restart)."""
    estimator = RestartEstimator(commit_fraction=FRACTION, check_interval=CHECK)
    out = []
    for start in SCHEDULE.stop_steps():
        timing = Timing(
            n0=int(start),
            n_stop=SCHEDULE.n_stop,
            n_cap=SCHEDULE.n_period - SCHEDULE.n_stop,
            n_check=CHECK_STEPS,
        )
        res = release_outcome(omega_at, timing, estimator, omega_at(int(start)), CONFIG.grid.dt)
        out.append(
            (res["direction_before"], res["direction_after"], res["committed"], res["inverted"])
        )
    return out


def by_ensemble(record_steps: int) -> list[tuple[int, int, bool, bool]]:
    """The same per cycle from an ensemble result recorded every `record_steps` steps."""
    steps = np.arange(0, END + 1, record_steps)
    omega = np.array([[omega_at(int(s)) for s in steps]])
    nan = np.full_like(omega, np.nan)
    result = EnsembleResult(
        setups=(Setup(CONFIG),),
        t=steps * CONFIG.grid.dt,
        phi=nan,
        omega=omega,
        torque=nan,
        friction=nan,
        stopped=omega == 0.0,
        camphor_total=nan,
        diverged_at=np.array([np.nan]),
        state=EnsembleState(data=np.zeros((1, 3, 1, 1)), rotor=np.zeros((1, 5)), step=END),
        backend="cpu",
        wall_seconds=0.0,
    )
    events = result.release_events(0, FRACTION, check_interval=CHECK)
    return [
        (
            e.release.direction_before,
            e.release.direction_after,
            e.release.committed,
            e.release.inverted,
        )
        for e in events
    ]


def test_every_estimator_classifies_the_same_trajectory_alike():
    """Tracker, sweep release and ensemble give the rule's answer for every cycle."""
    tracker = by_tracker()
    assert [row[2] for row in tracker] == EXPECTED["committed"]
    assert [row[1] for row in tracker] == EXPECTED["direction_after"]
    assert [row[3] for row in tracker] == EXPECTED["inverted"]
    assert by_sweep_release() == tracker
    assert by_ensemble(CHECK_STEPS) == tracker
    assert by_ensemble(5) == tracker  # finer records, checks still every event_interval
    before = [row[0] for row in tracker]
    after = [row[1] for row in tracker]
    assert restart_counts(before, after).total.k == sum(EXPECTED["inverted"])


def test_protocol_estimator_differs_only_where_a_release_never_commits():
    """The paper's estimator: the sign at the end of each release, committed or not.

    It counts a cycle when the signs just before consecutive stops differ. It agrees
    with the run's events on every cycle that commits without reversing again; on the
    never-committing cycle 3 (weak reversed rotation until the next stop) it counts an
    inversion where the rule counts none.
    """
    ends = [omega_at(int(s)) for s in SCHEDULE.stop_steps()] + [omega_at(END)]
    counts = protocol_counts(ends)
    paper = [np.sign(b) != np.sign(a) for b, a in itertools.pairwise(ends)]
    assert counts.total.k == sum(paper)
    tracker = by_tracker()
    for cycle, (row, inverted) in enumerate(zip(tracker, paper, strict=True)):
        if row[2]:
            assert inverted == row[3], cycle
        else:
            assert inverted and not row[3]
    assert counts.total.k == sum(EXPECTED["inverted"]) + EXPECTED["committed"].count(False)


@pytest.mark.parametrize(
    ("checks", "expected"),
    [
        ([0.0, 4.0, -6.0], Release(8.0, 1, 1, True, False, 1, 4.0)),
        ([0.0, -3.9999, -4.0, 5.0], Release(8.0, 1, -1, True, True, 2, -4.0)),
        ([0.0, -1.0, -2.0], Release(8.0, 1, 0, False, False, -1, -2.0)),
    ],
)
def test_rule_commits_at_the_first_check_at_or_above_the_threshold(checks, expected):
    """Threshold 0.5 * 8 = 4: the release check (omega = 0) never commits, exactly 4 does,
    3.9999 does not; later checks do not change a committed release."""
    assert classify_release(8.0, checks, FRACTION) == expected


def test_zero_and_non_finite_omega_have_no_direction():
    assert direction(0.0) == 0 and direction(math.nan) == 0 and direction(-math.inf) == 0
    assert not commits(0.0, 0.0, 0.0)  # a rotor at rest never commits, even at fraction 0
    release = classify_release(0.0, [0.0, 3.0], FRACTION)
    assert release.committed and release.direction_before == 0 and not release.inverted
    with pytest.raises(ValueError, match="commit_fraction"):
        classify_release(1.0, [1.0], 1.5)


def test_sweep_release_from_rest_is_not_an_inversion() -> None:
    """A stop from omega = 0 has no direction to invert, in the sweep's estimators too.

    With omega_before = 0 the threshold commit_fraction |omega_before| is 0; a rule that
    compared |omega| >= 0 alone would commit at the first check to direction 0 and count
    0 == -0 as an inversion.
    """
    estimator = RestartEstimator(commit_fraction=FRACTION, check_interval=CHECK)
    timing = Timing(n0=0, n_stop=SCHEDULE.n_stop, n_cap=10 * CHECK_STEPS, n_check=CHECK_STEPS)
    still = release_outcome(lambda step: 0.0, timing, estimator, 0.0, CONFIG.grid.dt)
    assert (still["direction_before"], still["inverted"], still["committed"]) == (0, False, False)
    moving = release_outcome(lambda step: -3.0, timing, estimator, 0.0, CONFIG.grid.dt)
    assert (moving["direction_after"], moving["inverted"]) == (-1, False)
