"""The GPU ensemble backend against the CPU solver, run in numba's CUDA simulator.

The kernels of :mod:`pde_rotor.backends.gpu` execute here on the CPU
(``NUMBA_ENABLE_CUDASIM=1``, set below before numba-cuda is imported), so CI without a
GPU runs the GPU code path. The simulator interprets every thread in Python, hence the
tiny grid (dx = 0.1, a plate of radius 0.3: about 1000 cells) and runs of a few hundred
steps. On a machine with a GPU, ``NUMBA_ENABLE_CUDASIM=0 pytest tests/test_gpu.py`` runs
the same checks on the hardware.

Checked properties: one physics, two backends. Without noise phi(t), omega(t), the
torques and the fields agree to 1e-10 relative with the CPU solver (both compile
the one physics core, pde_rotor.physics) for members that
differ in Delta, t_stop, t_ini and flow; with noise the same seed gives the same
trajectory (the host draws the CPU solver's noise sequence); the result does not
depend on the launch configuration or on splitting a run; a member whose state stops
being finite is flagged without disturbing the others.
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

if "numba.cuda" not in sys.modules:
    os.environ.setdefault("NUMBA_ENABLE_CUDASIM", "1")
    from numba.core import config as numba_config

    numba_config.reload_config()  # numba read its environment when conftest imported it

import numpy as np
import pytest
import yaml
from pde.storage import FileStorage
from typer.testing import CliRunner

from pde_rotor.api import RunResult
from pde_rotor.backends import (
    backend_for,
    cpu,
    gpu_available,
    member_stepper,
    resolve_backend,
    run_ensemble,
)
from pde_rotor.backends import gpu as gpu_backend
from pde_rotor.cli.main import app
from pde_rotor.config import RotorConfig
from pde_rotor.solver.simulation import Simulation

TINY: dict[str, Any] = {
    "grid": {"dx": 0.1, "dt": 1e-3, "domain_radius": 1.6},
    "geometry": {"radius": 0.3, "pill_radius": 0.06, "pill_inset": 0.03, "smoothing": 0.05},
    "numerics": {"scheme": "paper"},
}
"""Smallest grid the config accepts around a small plate (32 x 32 cells in the loop box):
the support of F and G, radius R + 20 delta / cos(pi/N), fits inside L - dx. The
checks of the ensemble machinery (noise, launches, restarts, flags) run the ``paper``
scheme, whose per-cell work the simulator interprets several times faster; the default
``consistent`` scheme has its own agreement test below."""

PROTOCOL: dict[str, Any] = {"t_ini": 0.015, "t_stop": 0.005, "t_release": 0.01, "cycles": 2}
"""Short stop-and-release protocol: two stops (5 steps each) within the first 0.045 time
units; every simulated step costs the simulator about a tenth of a second per member."""

RECORD = 0.005
"""Time between records (5 steps)."""


@pytest.fixture(autouse=True)
def _every_test_on_the_simulator(fast_simulator: None) -> None:
    """Every test here runs the kernels (:func:`conftest.fast_simulator`)."""


def rel_error(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b|."""
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def assert_same_run(gpu_result: Any, cpu_result: Any, rtol: float) -> None:
    """Rotor time series, torques, total camphor, stop flags and final fields agree to `rtol`."""
    np.testing.assert_array_equal(gpu_result.t, cpu_result.t)
    np.testing.assert_array_equal(gpu_result.stopped, cpu_result.stopped)
    for m in range(cpu_result.n_members):
        for name in ("phi", "omega", "torque", "friction", "camphor_total"):
            got, want = getattr(gpu_result, name)[m], getattr(cpu_result, name)[m]
            assert rel_error(got, want) < rtol, (m, name, rel_error(got, want))
        assert rel_error(gpu_result.state.data[m], cpu_result.state.data[m]) < rtol
    np.testing.assert_allclose(gpu_result.state.rotor, cpu_result.state.rotor, rtol=rtol, atol=0)


def test_members_match_their_own_cpu_runs(small_config: Callable[..., RotorConfig]) -> None:
    """Three members with different Delta, t_stop, t_ini and flow, no noise: phi, omega agree.

    Each member of one GPU batch follows its own CPU run (Eqs. (eqc), (eqv), (eq_motion)
    with the stop schedule) to 1e-10 relative over 45 steps that include two stops. The
    members really differ (so swapped parameters would fail), omega is 0 during every
    stop, and the run is not trivial: omega changes by as much as its own size.
    """
    members = [
        small_config(TINY, {"geometry": {"asymmetry": 0.05}, "protocol": PROTOCOL}),
        small_config(
            TINY,
            {
                "geometry": {"asymmetry": -0.03},
                "protocol": {**PROTOCOL, "t_ini": 0.01, "t_stop": 0.01},
                "rotor": {"omega0": 20.0, "phi0": 0.3},
            },
        ),
        small_config(
            TINY,
            {"flow": {"enabled": False}, "geometry": {"asymmetry": 0.02}, "protocol": PROTOCOL},
        ),
    ]
    t_end = 0.045
    want = cpu.run_ensemble(members, t_end, record_interval=RECORD)
    got = gpu_backend.run_ensemble(
        members, t_end, record_interval=RECORD, threads_per_block=2, chunk_steps=32
    )
    assert got.backend == "gpu"
    assert_same_run(got, want, rtol=1e-10)
    assert np.all(np.isnan(got.diverged_at))
    for m in range(3):
        assert np.all(got.omega[m][got.stopped[m]] == 0.0)
        assert got.stopped[m].any() and not got.stopped[m].all()
        assert np.ptp(got.omega[m]) > 0.5 * np.abs(got.omega[m]).max()
        assert np.all(np.diff(got.camphor_total[m]) > 0)  # pills release camphor from c = 0
    for a, b in [(0, 1), (0, 2), (1, 2)]:
        assert rel_error(got.omega[a], got.omega[b]) > 1e-2
    # member 1 stops 0.005 earlier and 0.005 longer than member 0
    first_stop = [np.argmax(got.stopped[m]) for m in range(2)]
    assert got.t[first_stop[1]] < got.t[first_stop[0]]


def test_consistent_scheme_matches_cpu_to_1e10(small_config: Callable[..., RotorConfig]) -> None:
    """Filtered F, G and the contour torque: GPU and CPU builds of one core agree.

    Both backends compile the same physics core (:mod:`pde_rotor.physics`), so the
    ``consistent`` scheme's members follow their CPU runs to 1e-10 relative through a
    stop, as the ``paper`` scheme's do.
    """
    numerics = {"scheme": "consistent", "contour_nodes": 8, "band_nodes": 2}
    members = [
        small_config(
            TINY,
            {"numerics": numerics, "protocol": PROTOCOL, "geometry": {"asymmetry": 0.04}},
        ),
        small_config(
            TINY,
            {"numerics": numerics, "protocol": PROTOCOL, "rotor": {"omega0": -15.0}},
        ),
    ]
    t_end = 0.025
    want = cpu.run_ensemble(members, t_end, record_interval=RECORD)
    got = gpu_backend.run_ensemble(
        members, t_end, record_interval=RECORD, threads_per_block=2, chunk_steps=20
    )
    assert_same_run(got, want, rtol=1e-10)
    assert rel_error(got.omega[0], got.omega[1]) > 1e-2
    assert np.abs(got.torque[0]).max() > 0


def test_heun_ensemble_is_the_cpus(small_config: Callable[..., RotorConfig]) -> None:
    """Heun's method: the members run as their fixed_axis bodies on the bodies' kernel,
    and two members (Delta, seeds) with noise through a stop give the CPU's Heun records
    and fields to 1e-10, as the Euler members do on the rotor's kernel."""
    heun = {
        "numerics": {"integrator": "heun"},
        "noise": {"sigma": 1e-5, "seed": 3},
        "rotor": {"omega0": 50.0},
        "protocol": {"t_ini": 0.003, "t_stop": 0.002, "t_release": 0.001, "cycles": 2},
    }
    members = [
        small_config(TINY, heun),
        small_config(TINY, heun, {"geometry": {"asymmetry": 0.04}, "noise": {"seed": 4}}),
    ]
    want = cpu.run_ensemble(members, 0.008, record_interval=0.002)
    got = gpu_backend.run_ensemble(members, 0.008, record_interval=0.002)
    assert_same_run(got, want, rtol=1e-10)
    assert rel_error(got.omega[0], got.omega[1]) > 1e-4  # the members differ by far more
    assert got.stopped[0].any() and not got.stopped[0].all()


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_rotor_run_with_heun_on_the_gpu_is_the_cpus_heun(
    small_config: Callable[..., RotorConfig], scheme: str
) -> None:
    """``solver.backend: gpu`` with Heun is accepted for the rotor and runs it as its
    fixed_axis body on the bodies' kernel (``member_stepper``), which follows the CPU
    rotor's Heun through two stops with noise to 1e-10: phi, omega, the torques, the
    stop flag and c, v, on both schemes."""
    cfg = small_config(
        TINY,
        {
            "numerics": {"scheme": scheme, "integrator": "heun"},
            "rotor": {"omega0": 50.0},
            "noise": {"sigma": 1e-5, "seed": 3},
            "protocol": {"t_ini": 0.003, "t_stop": 0.002, "t_release": 0.001, "cycles": 2},
            "solver": {"backend": "gpu"},
        },
    )
    assert backend_for(cfg) == "gpu"
    cpu_run, gpu_run = Simulation(cfg), Simulation(cfg, stepper=member_stepper("gpu"))
    for t in (0.004, 0.009):  # in the first stop, then after the second release
        cpu_run.run(t)
        gpu_run.run(t)
        want, got = cpu_run.rotor, gpu_run.rotor
        assert got.phi == pytest.approx(want.phi, rel=1e-10, abs=1e-12)
        assert got.omega == pytest.approx(want.omega, rel=1e-10, abs=1e-10)
        assert got.torque == pytest.approx(want.torque, rel=1e-9, abs=1e-15)
        assert got.friction == pytest.approx(want.friction, rel=1e-9, abs=1e-15)
        assert got.stopped == want.stopped
        scale = np.abs(cpu_run.state.data).max()
        assert np.abs(gpu_run.state.data - cpu_run.state.data).max() <= 1e-10 * scale
    assert cpu_run.rotor.omega != 0.0 and not cpu_run.rotor.stopped


def test_noise_same_seed_same_trajectory(small_config: Callable[..., RotorConfig]) -> None:
    """With noise, Eq. (noiseav), a seed gives the CPU solver's trajectory on the GPU.

    The noise moves omega far more than the tolerance (a run with another seed differs by
    more than 1e-3 relative), yet GPU and CPU with the same seed agree to 1e-8, also when
    the GPU draws the noise in chunks of 7 steps and the CPU per record interval.
    """
    inertia = RotorConfig.model_validate({}).rotor.inertia
    noisy = {"noise": {"sigma": 2.0 * inertia, "seed": 11}, "protocol": PROTOCOL}
    cfg = small_config(TINY, noisy, {"geometry": {"asymmetry": 0.04}})
    other = small_config(TINY, noisy, {"geometry": {"asymmetry": 0.04}, "noise": {"seed": 12}})
    t_end = 0.03
    want = cpu.run_ensemble([cfg, other], t_end, record_interval=RECORD)
    got = gpu_backend.run_ensemble(
        [cfg], t_end, record_interval=RECORD, threads_per_block=2, chunk_steps=7
    )
    assert rel_error(want.omega[1], want.omega[0]) > 1e-3
    assert rel_error(got.omega[0], want.omega[0]) < 1e-8
    assert rel_error(got.phi[0], want.phi[0]) < 1e-8


def test_launch_configuration_and_restart_do_not_change_the_result(
    small_config: Callable[..., RotorConfig],
) -> None:
    """Threads per block, steps per launch and a stop-and-continue give the same run.

    The block reduction order depends on the thread count, so the runs agree to round-off
    (1e-12), not bitwise. Continuing from a returned state with the same Generators
    equals one uninterrupted run, noise included.
    """
    inertia = RotorConfig.model_validate({}).rotor.inertia
    members = [
        small_config(TINY, {"geometry": {"asymmetry": 0.05}, "protocol": PROTOCOL}),
        small_config(
            TINY,
            {"noise": {"sigma": inertia, "seed": 3}, "protocol": {**PROTOCOL, "t_ini": 0.0}},
        ),
    ]
    t_mid, t_end = 0.01, 0.015  # the second member's release at 0.005 lies before t_mid
    one = gpu_backend.run_ensemble(members, t_end, record_interval=RECORD, threads_per_block=2)
    other = gpu_backend.run_ensemble(
        members, t_end, record_interval=RECORD, threads_per_block=4, chunk_steps=5
    )
    assert_same_run(other, one, rtol=1e-12)
    rngs = [np.random.default_rng(cfg.noise.seed) for cfg in members]
    options: dict[str, Any] = {"record_interval": RECORD, "rngs": rngs, "threads_per_block": 2}
    first = gpu_backend.run_ensemble(members, t_mid, **options)
    second = gpu_backend.run_ensemble(members, t_end, initial=first.state, **options)
    np.testing.assert_allclose(second.t, one.t[one.t >= t_mid - 1e-12])
    tail = one.t >= t_mid - 1e-12
    for name in ("phi", "omega"):
        np.testing.assert_allclose(getattr(second, name), getattr(one, name)[:, tail], rtol=1e-12)
    np.testing.assert_allclose(second.state.data, one.state.data, rtol=0, atol=1e-12)


def test_diverged_member_is_flagged_and_others_go_on(
    small_config: Callable[..., RotorConfig],
) -> None:
    """A NaN in one member's camphor field stops that member only, on both backends.

    The NaN sits under the plate, so the torque of the first step is NaN: both backends
    report divergence at t = 0 and leave the member's state as it was; the healthy member
    equals its solo CPU run.
    """
    members = [small_config(TINY, {"geometry": {"asymmetry": 0.05}}) for _ in range(2)]
    t_end = 0.01
    start = cpu.run_ensemble(members, 0.0, record_interval=RECORD).state
    plan_n = start.data.shape[-1]
    start.data[1, 0, plan_n // 2 + 1, plan_n // 2] = np.nan
    got = gpu_backend.run_ensemble(members, t_end, record_interval=RECORD, initial=start)
    want = cpu.run_ensemble(members, t_end, record_interval=RECORD, initial=start)
    for result in (got, want):
        assert np.isnan(result.diverged_at[0])
        assert result.diverged_at[1] == 0.0
        assert np.all(np.isnan(result.omega[1, 1:]))
        assert np.all(np.isfinite(result.omega[0]))
        np.testing.assert_array_equal(result.state.rotor[1, :2], start.rotor[1, :2])
    np.testing.assert_array_equal(np.isnan(got.state.data[1]), np.isnan(start.data[1]))
    assert rel_error(got.omega[0], want.omega[0]) < 1e-8


def test_cli_run_with_backend_gpu_writes_the_cpu_run(tmp_path: Path) -> None:
    """``pde-rotor run --backend gpu`` runs one member on the GPU backend, same files.

    The run goes through ``run_ensemble`` (the CPU solver is never called), records the
    backend and device that ran, and writes the time series, events and snapshots of the
    CPU run of the same config and seed to 1e-10 relative, events (the inversion rule
    applied to the ensemble records, tested in ``test_inversion``) included.
    """
    config = {
        **TINY,
        "geometry": {**TINY["geometry"], "asymmetry": 0.05},
        "protocol": {**PROTOCOL, "t_release": 0.025},
        "noise": {"sigma": 0.5 * RotorConfig.model_validate({}).rotor.inertia, "seed": 5},
        "output": {
            "timeseries_interval": 0.01,
            "event_interval": 0.005,
            "snapshot_interval": 0.025,
            "movie": False,
            "commit_fraction": 0.2,
        },
    }
    path = tmp_path / "tiny.yaml"
    path.write_text(yaml.safe_dump(config))
    runs = {}
    for backend in ("cpu", "gpu"):
        out = tmp_path / backend
        result = CliRunner().invoke(
            app, ["run", str(path), "--backend", backend, "--out", str(out), "--quiet"]
        )
        assert result.exit_code == 0, result.output
        runs[backend] = RunResult.load(out)
    gpu, ref = runs["gpu"], runs["cpu"]
    assert gpu.backend == "gpu" and ref.backend == "cpu"
    assert gpu.timeseries.attrs["device"] == gpu_backend.device_name()
    assert "backend: gpu" in (tmp_path / "gpu" / "config.yaml").read_text()
    np.testing.assert_array_equal(gpu.timeseries["time"], ref.timeseries["time"])
    for name in ("phi", "omega", "torque", "friction", "camphor_total"):
        assert rel_error(gpu.timeseries[name].values, ref.timeseries[name].values) < 1e-10, name
    for name in ("stopped", "cycle"):
        np.testing.assert_array_equal(gpu.timeseries[name], ref.timeseries[name])
    for name in ("direction_before", "direction_after", "inverted", "committed"):
        np.testing.assert_array_equal(gpu.events[name], ref.events[name])
    np.testing.assert_allclose(gpu.events["omega_before"], ref.events["omega_before"], rtol=1e-10)
    assert gpu.events.sizes["cycle"] == PROTOCOL["cycles"]
    assert len(FileStorage(tmp_path / "gpu" / "snapshots.h5", write_mode="readonly")) == len(
        FileStorage(tmp_path / "cpu" / "snapshots.h5", write_mode="readonly")
    )


def test_backend_choice(small_config: Callable[..., RotorConfig]) -> None:
    """auto runs on a real GPU only; gpu accepts the simulator the user enabled.

    Holds on both machines: in the simulator (CI) auto resolves to the CPU, on
    hardware (``NUMBA_ENABLE_CUDASIM=0``) to the GPU; the result names the backend that
    ran. Without any GPU, a gpu request fails (test_package_imports_without_numba_cuda).
    """
    cfg = small_config(TINY)
    hardware = not gpu_backend.simulator_enabled()
    assert gpu_available() == hardware
    assert gpu_available(allow_simulator=True)
    assert resolve_backend("auto") == ("gpu" if hardware else "cpu")
    assert resolve_backend("gpu") == "gpu"
    assert resolve_backend("cpu") == "cpu"
    result = run_ensemble([cfg], 0.002, record_interval=0.001, backend="auto")
    assert result.backend == resolve_backend("auto")
    if hardware:
        ran = gpu_backend.run_ensemble([cfg], 0.002, record_interval=0.001, allow_simulator=False)
        assert ran.backend == "gpu"
    else:
        with pytest.raises(RuntimeError, match="simulator"):
            gpu_backend.run_ensemble([cfg], 0.002, record_interval=0.001, allow_simulator=False)
    other_grid = small_config(TINY, {"grid": {"dt": 5e-4}})
    with pytest.raises(ValueError, match="share the grid"):
        gpu_backend.run_ensemble([cfg, other_grid], 0.002, record_interval=0.001)


def test_package_imports_without_numba_cuda() -> None:
    """Without numba-cuda, pde_rotor imports, auto runs on the CPU, gpu fails in one line."""
    code = (
        "import sys; sys.modules['numba.cuda'] = None\n"
        "import pde_rotor, pde_rotor.backends as b\n"
        "reason = b.gpu_unavailable_reason()\n"
        "assert reason is not None and 'numba-cuda' in reason, reason\n"
        "assert b.resolve_backend('auto') == 'cpu'\n"
        "try:\n"
        "    b.resolve_backend('gpu')\n"
        "except b.BackendError as err:\n"
        "    assert \"solver.backend = 'gpu'\" in str(err) and '\\n' not in str(err)\n"
        "    print('ok')\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=False
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"
