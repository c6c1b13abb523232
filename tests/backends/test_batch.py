"""Batches of member runs (the sweeps' entry point) against single runs with trackers.

Each member of a :func:`~pde_rotor.backends.run_batch` call must give the events that
``pde_rotor.run`` of the same config writes (the InversionTracker, same inversion rule,
same samples), whatever batch it shares and however the batch is chunked.
"""

from __future__ import annotations

import numpy as np
import pytest

import pde_rotor
from pde_rotor.backends import cpu, run_batch
from pde_rotor.config import RotorConfig
from pde_rotor.model.protocol import StopSchedule
from pde_rotor.statistics.proportions import protocol_counts

BASE = {
    "grid": {"dx": 0.05, "dt": 4e-4, "domain_radius": 1.75},
    "geometry": {"smoothing": 0.05, "asymmetry": 0.05},
    "protocol": {"t_ini": 0.4, "t_stop": 0.2, "t_release": 0.4, "cycles": 2},
    "noise": {"sigma": 0.01, "seed": 0},
    "output": {"event_interval": 0.01, "progress": False, "movie": False},
}


def member(**sections) -> RotorConfig:
    data = {key: dict(value) for key, value in BASE.items()}
    for key, value in sections.items():
        data[key].update(value)
    return RotorConfig.model_validate(data)


MEMBERS = [
    member(),
    member(noise={"sigma": 0.02, "seed": 3}, output={"commit_fraction": 0.3}),
    member(protocol={"t_stop": 0.12, "t_release": 0.28}, geometry={"asymmetry": 0}),
]
"""Different noise, commit fraction and protocol (the third ends earlier and runs on
freely in the batch, to the others' end)."""

FIELDS = ("direction_before", "direction_after", "committed", "inverted")


@pytest.fixture(scope="module")
def single_runs():
    return [pde_rotor.run(cfg) for cfg in MEMBERS]


@pytest.mark.parametrize("max_members", [None, 2])
def test_batch_members_have_the_events_of_their_single_runs(single_runs, max_members):
    runs = run_batch(MEMBERS, backend="cpu", max_members=max_members)
    assert [run.config for run in runs] == MEMBERS
    inverted = 0
    for run, single in zip(runs, single_runs, strict=True):
        assert run.backend == "cpu" and np.isnan(run.diverged_at)
        events = single.events
        assert len(run.events) == events.sizes["cycle"] == run.config.protocol.cycles
        for name in FIELDS:
            got = [getattr(event.release, name) for event in run.events]
            assert got == list(events[name].values), name
        np.testing.assert_allclose(
            [event.time_to_commit for event in run.events], events["time_to_commit"].values
        )
        inverted += int(events["inverted"].values.sum())
        schedule = StopSchedule.from_config(run.config.protocol, run.config.grid.dt)
        t = single.timeseries["time"].values
        at_stops = [
            single.timeseries["omega"].values[np.isclose(t, s)][0] for s in schedule.stop_times()
        ]
        np.testing.assert_allclose(run.protocol_omegas[:-1], at_stops, rtol=1e-12)
        assert run.protocol_omegas[-1] == pytest.approx(single.timeseries["omega"].values[-1])
        counts = protocol_counts(run.protocol_omegas)
        assert counts.total.n == run.config.protocol.cycles
    assert inverted > 0  # the members do invert: the comparison is not all-False


def test_bad_batches_fail_before_running():
    with pytest.raises(ValueError, match="at least one member"):
        run_batch([], backend="cpu")
    with pytest.raises(ValueError, match="max_members = 0"):
        run_batch(MEMBERS, backend="cpu", max_members=0)


def test_the_cpu_backend_advances_to_an_end_between_two_records():
    """t_end off the record grid: the CPU backend still stops at t_end (as the GPU
    backend does), with the state and noise of a run recorded at every step."""
    config = member()
    dt = config.grid.dt
    coarse = cpu.run_ensemble([config], 7 * dt, record_interval=3 * dt)
    fine = cpu.run_ensemble([config], 7 * dt, record_interval=dt)
    assert coarse.state.step == fine.state.step == 7
    np.testing.assert_array_equal(coarse.state.rotor, fine.state.rotor)
    np.testing.assert_array_equal(coarse.state.data, fine.state.data)
    np.testing.assert_array_equal(coarse.omega, fine.omega[:, [0, 3, 6]])
