"""Sweeps on an ensemble backend: the seam of pde_rotor.sweep.execution, the batches and
one tiny sweep through the GPU kernels in numba's CUDA simulator.

As in test_gpu.py, ``NUMBA_ENABLE_CUDASIM=1`` is set before numba-cuda is imported, so
CI without a GPU runs the GPU code path (``NUMBA_ENABLE_CUDASIM=0`` on a GPU machine runs
it on the hardware).
"""

from __future__ import annotations

import os
import sys
from typing import Any

if "numba.cuda" not in sys.modules:
    os.environ.setdefault("NUMBA_ENABLE_CUDASIM", "1")
    from numba.core import config as numba_config

    numba_config.reload_config()

import inspect
import json
from collections import OrderedDict

import numpy as np
import pytest
import xarray as xr

from pde_rotor.backends import cpu
from pde_rotor.backends import gpu as gpu_backend
from pde_rotor.backends.base import EnsembleBackend, EnsembleRunner
from pde_rotor.sweep import (
    Sweep,
    SweepError,
    SweepSpec,
    batch,
    execution,
    gather,
    read_runs,
    run_sweep,
    tasks,
)
from pde_rotor.sweep.estimators import restart

TINY_GPU: dict[str, Any] = {
    "grid": {"dx": 0.1, "dt": 1e-3, "domain_radius": 1.6},
    "geometry": {"radius": 0.3, "pill_radius": 0.06, "pill_inset": 0.03, "smoothing": 0.05},
    "rotor": {"omega0": 20.0},
    "noise": {"sigma": 0.0},
    "protocol": {"t_ini": 0.05, "t_stop": 0.02, "t_release": 0.03, "cycles": 2},
    "numerics": {"scheme": "paper"},
}
"""The smallest grid of test_gpu.py and a two-stop protocol of 150 steps, in the
``paper`` scheme like test_gpu.py's machinery checks (the simulator's speed)."""


def protocol_sweep(backend: str = "cpu", **changes: Any) -> Sweep:
    """Two Delta values x 2 protocol runs on the tiny GPU grid."""
    data = {
        "name": "gpu_tiny",
        "base": {**TINY_GPU, "solver": {"backend": backend}},
        "axes": {"geometry.asymmetry": [0.0, 0.05]},
        "estimator": {"kind": "protocol"},
        "samples": 2,
        "seed": 3,
        **changes,
    }
    return Sweep.from_spec(SweepSpec.model_validate(data))


class Recorder:
    """An ensemble runner that counts its batches and runs them on the CPU backend."""

    def __init__(self) -> None:
        self.batches: list[int] = []

    def __call__(self, configs: Any, t_end: float, **options: Any) -> Any:
        self.batches.append(len(configs))
        return cpu.run_ensemble(configs, t_end, **options)


def omegas(sweep: Sweep, sweep_dir: Any) -> np.ndarray:
    """omega before every stop and at the end, of every run, from the store."""
    stored = read_runs(sweep_dir)
    return np.array([stored[r.key]["result"]["omegas"] for r in sweep.runs()])


def test_batches_give_the_runs_of_the_dask_path(tmp_path):
    """An ensemble runner computes the runs in batches of at most batch_size members and
    stores what the per-run CPU tasks store: the same omegas, the same report."""
    sweep = protocol_sweep()
    run_sweep(sweep, tmp_path / "dask", workers=1, progress=False)
    recorder = Recorder()
    outcome = run_sweep(sweep, tmp_path / "batch", ensemble=recorder, batch_size=3)
    assert (outcome.computed, outcome.failed) == (4, [])
    assert recorder.batches == [3, 1]
    np.testing.assert_allclose(omegas(sweep, tmp_path / "batch"), omegas(sweep, tmp_path / "dask"))
    assert read_runs(tmp_path / "dask")[sweep.runs()[0].key]["backend"] == "cpu"
    assert np.ptp(omegas(sweep, tmp_path / "dask")) > 1.0  # the runs really move
    xr.testing.assert_identical(gather(sweep, tmp_path / "batch"), gather(sweep, tmp_path / "dask"))


def test_a_gpu_sweep_goes_to_the_ensemble_and_a_cpu_sweep_to_dask(tmp_path, monkeypatch):
    """solver.backend resolved to gpu sends every run to run_ensemble(backend="gpu");
    cpu (and auto without a GPU) never calls it."""
    calls: list[str] = []

    def fake_ensemble(configs: Any, t_end: float, *, backend: str, **options: Any) -> Any:
        calls.append(backend)
        return cpu.run_ensemble(configs, t_end, **options)

    monkeypatch.setattr(execution, "run_ensemble", fake_ensemble)
    monkeypatch.setattr(execution, "resolve_backend", lambda requested: "gpu")
    outcome = run_sweep(protocol_sweep("gpu"), tmp_path / "gpu", progress=False)
    assert (outcome.computed, calls) == (4, ["gpu"])
    monkeypatch.setattr(execution, "resolve_backend", lambda requested: "cpu")
    outcome = run_sweep(protocol_sweep("auto"), tmp_path / "cpu", workers=1, progress=False)
    assert (outcome.computed, calls) == (4, ["gpu"])


def test_a_gpu_request_without_a_gpu_is_one_line_before_anything_runs(tmp_path, monkeypatch):
    def no_gpu(requested: str) -> str:
        raise RuntimeError("backend 'gpu' requested but no CUDA device was found")

    monkeypatch.setattr(execution, "resolve_backend", no_gpu)
    with pytest.raises(SweepError, match=r"^base: solver.backend: backend 'gpu' requested"):
        run_sweep(protocol_sweep("gpu"), tmp_path / "never")
    assert not (tmp_path / "never").exists()


RESTART = {
    "kind": "restart",
    "warmup": 0.1,
    "check_interval": 0.005,
    "release_cap": 0.1,
    "commit_fraction": 0.02,  # the tiny plate turns slowly once released
}


@pytest.mark.parametrize(
    ("estimator", "axes", "spin_ups"),
    [
        (RESTART, {"geometry.asymmetry": [0.0, 0.05]}, 4),
        ({**RESTART, "kind": "bank"}, {"noise.sigma": [0.0, 1e-5]}, 2),
    ],
)
def test_restart_and_bank_batches_read_the_runs_the_tasks_compute(
    tmp_path, monkeypatch, estimator, axes, spin_ups
):
    """Restarts and bank releases computed as ensembles from the warm states (every step
    recorded, the noise-free bank approach, the delayed release noise) give the results
    of the per-run tasks: the same stop, outcome, commit time and end-of-stop torque."""
    sweep = protocol_sweep(
        estimator=estimator, axes=axes, samples=3, base={**TINY_GPU, "noise": {"sigma": 1e-5}}
    )
    run_sweep(sweep, tmp_path / "tasks", workers=1, progress=False)
    recorder = Recorder()
    monkeypatch.setattr(restart, "_WARM", OrderedDict())  # no state of another test
    outcome = run_sweep(sweep, tmp_path / "batch", ensemble=recorder, progress=False)
    assert (outcome.computed, outcome.failed) == (12, [])
    # one ensemble of the spin-ups (per configuration without noise, and direction)
    assert recorder.batches[0] == spin_ups
    batched, by_task = read_runs(tmp_path / "batch"), read_runs(tmp_path / "tasks")
    for run in sweep.runs():
        got, want = batched[run.key]["result"], by_task[run.key]["result"]
        assert got.keys() == want.keys()
        for name, value in want.items():
            assert got[name] == pytest.approx(value, rel=1e-9, nan_ok=True), name
    results = [by_task[r.key]["result"] for r in sweep.runs()]
    assert len({r["extra_steps"] for r in results}) > 1  # the stops differ
    assert any(r["committed"] for r in results)


def test_a_tiny_sweep_runs_through_the_gpu_kernels(tmp_path, fast_simulator):
    """The GPU backend (CUDA simulator) stores the runs the CPU backend stores.

    The protocol is shortened to 45 steps with stops of 5: the simulator interprets
    every step of every member in Python.
    """
    short = {"t_ini": 0.015, "t_stop": 0.005, "t_release": 0.01, "cycles": 2}
    sweep = protocol_sweep(samples=1, base={**TINY_GPU, "protocol": short})
    run_sweep(sweep, tmp_path / "cpu", ensemble=Recorder(), progress=False)
    ensemble = lambda configs, t_end, **options: gpu_backend.run_ensemble(  # noqa: E731
        configs, t_end, threads_per_block=2, chunk_steps=64, **options
    )
    outcome = run_sweep(sweep, tmp_path / "gpu", ensemble=ensemble, progress=False)
    assert (outcome.computed, outcome.failed) == (2, [])
    np.testing.assert_allclose(
        omegas(sweep, tmp_path / "gpu"), omegas(sweep, tmp_path / "cpu"), rtol=1e-9
    )
    on_gpu, on_cpu = gather(sweep, tmp_path / "gpu"), gather(sweep, tmp_path / "cpu")
    xr.testing.assert_allclose(on_gpu, on_cpu, rtol=1e-9)
    assert read_runs(tmp_path / "gpu")[sweep.runs()[0].key]["backend"] == "gpu"


@pytest.mark.parametrize("backend", [cpu, gpu_backend], ids=["cpu", "gpu"])
def test_both_backends_implement_the_ensemble_interface(backend):
    """Each backend module is an EnsembleBackend, its run_ensemble an EnsembleRunner
    that takes every argument of the interface, by the same kind and default."""
    assert isinstance(backend, EnsembleBackend)
    assert isinstance(backend.run_ensemble, EnsembleRunner)
    declared = inspect.signature(EnsembleBackend.run_ensemble).parameters
    offered = inspect.signature(backend.run_ensemble).parameters
    for name, parameter in declared.items():
        if name == "self":
            continue
        assert name in offered, name
        assert offered[name].kind == parameter.kind, name
        assert offered[name].default == parameter.default, name
    extra = [p for name, p in offered.items() if name not in declared]
    assert all(p.default is not inspect.Parameter.empty for p in extra)


@pytest.mark.parametrize(
    ("estimator", "axes"),
    [
        ({"kind": "protocol"}, {"geometry.asymmetry": [0.0, 0.05]}),
        (RESTART, {"geometry.asymmetry": [0.0, 0.05]}),
        ({**RESTART, "kind": "bank"}, {"noise.sigma": [0.0, 1e-5]}),
    ],
    ids=["protocol", "restart", "bank"],
)
def test_the_dask_tasks_and_the_cpu_batches_store_the_same_runs(monkeypatch, estimator, axes):
    """The task a dask worker runs (tasks.execute_group, per stop group) and a batch on
    the CPU ensemble backend (batch.execute_batch) give every run the same record but for
    its wall time: the same result, bit for bit, key, point, sample, direction and
    backend."""
    sweep = protocol_sweep(
        estimator=estimator, axes=axes, samples=2, base={**TINY_GPU, "noise": {"sigma": 1e-5}}
    )
    runs = execution.in_order(sweep.runs())
    groups: dict[str, list] = {}
    for run in runs:
        groups.setdefault(tasks.stop_group(run), []).append(run)
    monkeypatch.setattr(restart, "_WARM", OrderedDict())  # each path spins up its own
    by_task = {c["key"]: c for group in groups.values() for c in tasks.execute_group(group)}
    monkeypatch.setattr(restart, "_WARM", OrderedDict())
    by_batch = {
        c["key"]: c
        for part in batch.batches(runs, 3)
        for c in batch.execute_batch(part, cpu.run_ensemble)
    }
    assert by_task.keys() == by_batch.keys() == {r.key for r in runs}
    for key, want in by_task.items():
        got = by_batch[key]
        assert got.keys() == want.keys()
        for name in want.keys() - {"result", "wall_time", "cpu_time"}:
            assert got[name] == want[name], name
        for name, value in want["result"].items():
            assert got["result"][name] == pytest.approx(value, rel=0, abs=0, nan_ok=True), name
    assert len({json.dumps(c["result"]) for c in by_task.values()}) == len(runs)


def test_a_crowd_sweep_on_the_gpu_path_stores_what_the_cpu_tasks_store(tmp_path) -> None:
    """Two free disks in a no-flux dish, 10 steps: the GPU batches (one member per run,
    simulator) store the measures the CPU's dask tasks compute, to 1e-10."""
    disk = {
        "plate": {"shape": "none"},
        "pills": [{"radius": 0.1}],
        "motion": {"kind": "free", "mass": 1e-3, "inertia": 5e-6, "friction": 0.3},
    }
    spec = {
        "name": "gpu_crowd",
        "base": {
            "grid": {"dx": 0.1, "dt": 1e-3, "domain_radius": 2.5, "wall": "no_flux"},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": "paper"},
            "protocol": {"t_ini": 0.01, "cycles": 0},
        },
        "crowd": {
            "count": 2,
            "body": disk,
            "placement": {"kind": "ring", "radius": 1.2, "speed": 0.2},
        },
        "estimator": {"kind": "collective", "record_interval": 0.005, "bins": 3},
        "samples": 1,
        "seed": 0,
    }
    sweep = Sweep.from_spec(SweepSpec.model_validate(spec))
    outcome = run_sweep(sweep, tmp_path / "gpu", ensemble=gpu_backend.run_ensemble, progress=False)
    assert outcome.computed == 1 and not outcome.failed
    want = tasks.execute_group(sweep.runs())[0]
    got = read_runs(tmp_path / "gpu")[want["key"]]
    assert got["backend"] == "gpu" and want["backend"] == "cpu"
    for name in ("t", "mean_speed", "polar_order", "rotational_order", "pair_counts"):
        np.testing.assert_allclose(got["result"][name], want["result"][name], atol=1e-10)
