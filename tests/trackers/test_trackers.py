"""Trackers: exact sampling of the stops, inversion detection, time series, snapshots, progress."""

from __future__ import annotations

import csv
import math
from types import SimpleNamespace

import numpy as np
import pytest
from pde.storage import FileStorage
from tqdm.auto import tqdm

from pde_rotor.config import RotorConfig
from pde_rotor.model.pde import RotorState
from pde_rotor.model.protocol import StopSchedule
from pde_rotor.solver.simulation import Simulation
from pde_rotor.trackers import (
    EVENT_COLUMNS,
    InversionTracker,
    ProgressBarTracker,
    SnapshotTracker,
    TimeSeriesTracker,
)
from pde_rotor.trackers.base import sampling_times

TINY = {
    "grid": {"dx": 0.05, "dt": 4e-4, "domain_radius": 1.75},
    "geometry": {"smoothing": 0.05},
    "protocol": {"t_ini": 0.4, "t_stop": 0.2, "t_release": 0.4, "cycles": 2},
    "noise": {"seed": 0},
}
"""A few thousand steps on a 72 x 72 grid: well under a second."""


def fake_state(config: RotorConfig) -> SimpleNamespace:
    """Just what the rotor trackers read from a state: the rotor (driven by hand), the
    fields of a 4 x 4 grid of c = 1 and its cell size."""
    dx = config.grid.dx
    return SimpleNamespace(
        rotor=RotorState(phi=0.0, omega=0.0),
        data=np.ones((3, 4, 4)),
        grid=SimpleNamespace(discretization=np.array([dx, dx])),
    )


def drive(tracker, omega_of_t, t_end: float) -> list[float]:
    """Call the tracker at the times its interrupts ask for, with omega = omega_of_t(t)."""
    state = fake_state(tracker.config)
    t = tracker.initialize(state, {"controller": {"t_start": 0.0, "t_end": t_end}})
    times = []
    while t <= t_end + 1e-12:
        state.rotor.omega = omega_of_t(t)
        tracker.handle(state, t)
        times.append(t)
        t = tracker.interrupt.next(t)
    return times


def test_sampling_times_hit_every_stop_exactly():
    config = RotorConfig.model_validate(TINY)
    schedule = StopSchedule.from_config(config.protocol, config.grid.dt)
    times = sampling_times(schedule, 0.03, config.protocol.t_end)
    for m in range(schedule.cycles):
        start = schedule.n_ini + m * schedule.n_period
        assert start * schedule.dt == schedule.stop_times()[m]
        assert start * schedule.dt in times
        assert (start + schedule.n_stop) * schedule.dt in times
    steps = times / schedule.dt
    np.testing.assert_allclose(steps, np.round(steps), rtol=0, atol=1e-9)  # whole steps
    assert times[0] == 0.0
    assert times[-1] == pytest.approx(config.protocol.t_end, abs=1e-12)


def test_inversion_events_from_a_prescribed_omega(tmp_path):
    """Cycle 1 inverts and commits, cycle 2 never commits, cycle 3 inverts quickly.

    Cycle 2 turns weakly the other way (omega = +1 after -10; 1 < 0.5 * 10) until the
    next stop: it never commits, so it has no direction after and is not an inversion
    (the rule of pde_rotor.statistics.inversion), although its sign at the end is reversed.
    """
    config = RotorConfig.model_validate(
        {
            "grid": {"dx": 0.05, "dt": 4e-4},
            "geometry": {"smoothing": 0.05},
            "protocol": {"t_ini": 1.0, "t_stop": 0.5, "t_release": 1.0, "cycles": 3},
        }
    )
    p = config.protocol
    stops = [p.t_ini + k * p.period for k in range(3)]
    releases = [s + p.t_stop for s in stops]

    def omega(t: float) -> float:
        if t < stops[0] + 1e-9:
            return 10.0
        if t < releases[0] + 1e-9:
            return 0.0
        if t < stops[1] + 1e-9:
            return -min(10.0 * (t - releases[0]), 10.0)  # |omega| = 5 at 0.5 after release
        if t < releases[1] + 1e-9:
            return 0.0
        if t < stops[2] + 1e-9:
            return 1.0  # below 0.5 * 10: never commits
        if t < releases[2] + 1e-9:
            return 0.0
        return -2.0 if t - releases[2] > 0.045 else -0.1  # commits 0.05 after release

    csv_path = tmp_path / "events.csv"
    tracker = InversionTracker(config, 0.01, 0.5, csv_path, tmp_path / "events.nc")
    drive(tracker, omega, p.t_end)

    # every row is on disk as soon as it is known, before the run ends (row 2 when
    # stop 3 begins, rows 1 and 3 at their commits)
    with csv_path.open() as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == list(EVENT_COLUMNS)
    assert [r["cycle"] for r in rows] == ["1", "2", "3"]
    tracker.finalize({"controller": {"successful": True, "t_final": p.t_end}})
    tracker.finalize({})  # idempotent

    ev = {e.cycle: e for e in tracker.events}
    assert [ev[m].omega_before for m in (1, 2, 3)] == [10.0, -10.0, 1.0]
    assert ev[1].committed and ev[1].inverted and ev[1].direction_after == -1
    assert ev[1].time_to_commit == pytest.approx(0.5, abs=1e-12)
    assert not ev[2].committed and math.isnan(ev[2].time_to_commit)
    assert ev[2].direction_after == 0 and not ev[2].inverted
    assert ev[2].omega_after == 1.0  # the last sample of the release, for the record
    assert ev[3].committed and ev[3].inverted
    assert ev[3].time_to_commit == pytest.approx(0.05, abs=1e-12)
    assert tracker.inversion_probability == pytest.approx(2 / 3)

    ds = tracker.to_dataset()
    assert list(ds["cycle"].values) == [1, 2, 3]
    assert ds.attrs["inversions"] == 2
    with csv_path.open() as fh:
        assert len(list(csv.DictReader(fh))) == 3
    assert (tmp_path / "events.nc").exists()


def test_rotor_at_rest_before_a_stop_is_never_inverted():
    config = RotorConfig.model_validate(TINY)
    tracker = InversionTracker(config, 0.02, 0.5)
    drive(tracker, lambda t: 0.0, config.protocol.t_end)
    tracker.finalize({"controller": {"successful": True}})
    assert len(tracker.events) == config.protocol.cycles
    assert not any(e.inverted or e.committed for e in tracker.events)


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """A real coarse run with time series (every 0.02 and every step), events, snapshots."""
    out = tmp_path_factory.mktemp("tiny")
    config = RotorConfig.model_validate(TINY)
    sim = Simulation(config)
    ts = TimeSeriesTracker(sim.config, 0.02, out / "ts.nc", attrs={"config_hash": "h"})
    ev = InversionTracker(sim.config, 0.02, 0.5)
    snap = SnapshotTracker(sim.config, out / "snap.h5", 0.4)
    fine = TimeSeriesTracker(sim.config, config.grid.dt)
    sim.run(trackers=[ts, ev, snap, fine])
    return SimpleNamespace(config=config, sim=sim, ts=ts, ev=ev, snap=snap, out=out, fine=fine)


def test_timeseries_samples_stops_exactly_and_freezes_the_rotor(tiny_run):
    config = tiny_run.config
    ts = tiny_run.ts
    ev = tiny_run.ev
    ds = ts.to_dataset()
    t = ds["time"].values
    schedule = StopSchedule.from_config(config.protocol, config.grid.dt)
    for event, start in zip(ev.events, schedule.stop_times(), strict=True):
        k = int(np.flatnonzero(t == start)[0])
        assert ds["omega"].values[k] == event.omega_before
        end = start + config.protocol.t_stop
        inside = (t > start + 1e-9) & (t <= end + 1e-9)
        assert inside.sum() >= 2
        assert np.all(ds["omega"].values[inside] == 0.0)
        assert np.all(ds["stopped"].values[inside] == 1)
        assert np.all(ds["phi"].values[inside] == ds["phi"].values[k])  # phi frozen
    assert ds["stopped"].values[t < schedule.stop_times()[0]].sum() == 0


def test_timeseries_every_step_follows_the_euler_update_of_phi(tiny_run):
    """Sampled every step: phi_(n+1) = phi_n + dt omega_n (Eq. (eq_motion), Euler), except
    in the stop phases, where phi is frozen; so the samples are the solver's own states."""
    config = tiny_run.config
    fine = tiny_run.fine
    ds = fine.to_dataset()
    dt = config.grid.dt
    phi, omega, stopped = ds["phi"].values, ds["omega"].values, ds["stopped"].values
    assert ds.sizes["time"] == round(config.protocol.t_end / dt) + 1
    moving = stopped[1:] == 0
    np.testing.assert_array_equal(phi[1:][moving], phi[:-1][moving] + dt * omega[:-1][moving])
    np.testing.assert_array_equal(phi[1:][~moving], phi[:-1][~moving])
    assert moving.sum() > 0 and (~moving).sum() == config.protocol.cycles * round(
        config.protocol.t_stop / dt
    )


def test_timeseries_total_camphor_matches_final_state(tiny_run):
    config = tiny_run.config
    sim = tiny_run.sim
    ts = tiny_run.ts
    out = tiny_run.out
    ds = ts.to_dataset()
    assert ds["time"].values[-1] == pytest.approx(config.protocol.t_end)
    expected = sim.state.data[0].sum() * config.grid.dx**2
    assert ds["camphor_total"].values[-1] == pytest.approx(expected, rel=1e-12)
    assert np.all(np.diff(ds["camphor_total"].values) > 0)  # pills keep supplying camphor
    import xarray as xr

    with xr.open_dataset(out / "ts.nc", engine="h5netcdf") as disk:
        assert disk.attrs["status"] == "completed"
        assert disk.attrs["config_hash"] == "h"
        assert disk["omega"].attrs["equation"].startswith("Eq. (eq_motion)")
        np.testing.assert_array_equal(disk["omega"].values, ds["omega"].values)


def test_events_one_row_per_cycle(tiny_run):
    config = tiny_run.config
    ev = tiny_run.ev
    assert [e.cycle for e in ev.events] == list(range(1, config.protocol.cycles + 1))


def test_snapshots_hold_the_fields_and_the_angle(tiny_run):
    config = tiny_run.config
    sim = tiny_run.sim
    out = tiny_run.out
    storage = FileStorage(out / "snap.h5", write_mode="readonly")
    try:
        times = np.asarray(storage.times)
        np.testing.assert_allclose(times, np.arange(0.0, config.protocol.t_end + 1e-9, 0.4))
        np.testing.assert_array_equal(storage[-1].data, sim.state.data)
        assert storage.info["rotor_phi"][-1] == sim.rotor.phi
        assert storage.info["status"] == "completed"
        assert len(storage.info["rotor_phi"]) == len(storage)
    finally:
        storage.close()
    assert not (out / "snap.h5.part").exists()


def test_progress_bar_shows_time_and_omega(capsys):
    config = RotorConfig.model_validate(TINY)
    state = fake_state(config)
    bar = ProgressBarTracker(config, leave=True)
    t_end = config.protocol.t_end
    bar.initialize(state, {"controller": {"t_start": 0.0, "t_end": t_end}})
    state.rotor.omega = -123.4
    bar.handle(state, 0.5 * t_end)
    assert bar.bar.n == pytest.approx(0.5 * t_end)
    bar.finalize({"controller": {"successful": True, "t_final": t_end}})
    err = capsys.readouterr().err
    assert "omega=-123.4" in err
    assert f"t={t_end:.2f}/{t_end:.2f}" in err  # completed runs end at 100 %
    assert bar.bar.disable  # closed


def test_progress_bar_says_compiling_then_measures_the_eta(capsys):
    """Before the first steps: "compiling"; the ETA is the rate of the steps measured after
    the first interrupt, so 10 s of compiling do not enter it."""
    config = RotorConfig.model_validate(TINY)
    state = fake_state(config)
    wall = iter([0.0, 10.0, 10.4, 10.8])  # compiling takes 10 s, then 0.04 per 0.4 s
    bar = ProgressBarTracker(config, clock=lambda: next(wall))
    t_end = config.protocol.t_end
    bar.initialize(None, {"controller": {"t_start": 0.0, "t_end": t_end}})
    assert ProgressBarTracker.COMPILING in bar.bar.postfix
    postfixes = []
    for t in (0.0, 0.04, 0.08, 0.12):
        bar.handle(state, t)
        postfixes.append(bar.bar.postfix)
    assert postfixes[0].startswith(ProgressBarTracker.COMPILING)
    assert postfixes[1].startswith("ETA measuring")
    for t, wall_time, postfix in ((0.08, 0.4, postfixes[2]), (0.12, 0.8, postfixes[3])):
        remaining = (t_end - t) * wall_time / (t - 0.04)
        assert postfix.startswith(f"ETA {tqdm.format_interval(remaining)},")
    bar.finalize({"controller": {"successful": True, "t_final": t_end}})
    assert "compiling" in capsys.readouterr().err


def test_timeseries_checkpoints_during_the_run(tmp_path):
    """With a zero checkpoint period the file is rewritten (complete, status running) at
    every sample, so a killed run still leaves a readable time series."""
    import xarray as xr

    config = RotorConfig.model_validate(TINY)
    field = fake_state(config)
    path = tmp_path / "ts.nc"
    tracker = TimeSeriesTracker(config, 0.2, path, checkpoint_seconds=0.0)
    tracker.initialize(field, {"controller": {"t_start": 0.0}})
    for k, t in enumerate([0.0, 0.2, 0.4]):
        field.rotor.omega = float(k)
        tracker.handle(field, t)
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            assert ds.attrs["status"] == "running"
            assert ds.sizes["time"] == k + 1
            assert ds["omega"].values[-1] == k
            assert ds["camphor_total"].values[-1] == pytest.approx(16 * config.grid.dx**2)
    tracker.finalize({"controller": {"successful": True}})
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.attrs["status"] == "completed"
