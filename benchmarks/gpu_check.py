"""One-command check of the GPU ensemble backend on a GPU machine (run by gpu_check.sh).

Records, in one results file (``gpu_check_results.json`` and a text copy,
``gpu_check_results.txt``, in ``--out``, default ``$OUT`` or ``./gpu_check``):

1. the device: ``nvidia-smi`` and ``numba.cuda.detect()``;
2. the CUDA tests (tests/backends/test_gpu.py, tests/sweep/test_sweep_gpu.py) run with
   ``NUMBA_ENABLE_CUDASIM=0`` on the device: the test modules enable the simulator only
   when the variable is unset;
3. member-steps/s of ``run_ensemble(backend="gpu")`` with E members at the resolution of
   configs/paper_fig4a.yaml (fp64, its scheme), against ``backend="cpu"`` with one member,
   each timed as the difference of two runs of different length (setup cancels), with
   the first call's wall time (compilation and warm-up) reported separately;
4. a small restart sweep (configs/sweeps/fig5_quick.yaml, 2 samples at 2 stop durations)
   once on the GPU (``set.solver.backend=gpu``) and once on the CPU (dask), each run's
   stored outcome compared (discrete values equal, floats to ``--rtol``);
5. bodies: a free disk and a fixed_axis hexagon (:data:`BODIES`) advanced on the GPU
   and on the CPU from the same smooth fields, poses, velocities, forces, c and v
   compared (to :data:`BODIES_TOLERANCE`), and the wall time per step of each;
6. a crowd: the ring channel of configs/sweeps/crowd_ring.yaml with 16 boats on their
   track, contact on, flow on (:data:`CROWD_SETS`), E members (one
   placement each) advanced from rest by ``run_bodies_ensemble`` on the GPU; member 0
   against the CPU's run of the same config (poses and fields, to
   :data:`BODIES_TOLERANCE`), and member-steps/s of the GPU ensemble against one member
   on the CPU.

Exits 1 if a check fails (no device, a failed test, a rate hidden by timing noise, a
sweep outcome or a bodies run that differs), 0 otherwise; the goal of 5e5
member-steps/s is reported, not enforced. ``--tiny`` runs the same steps in numba's
CUDA simulator on a tiny grid, a few members and steps, one test, a protocol sweep of
two runs, 3 bodies steps and 2 steps of a 3-boat ring on a coarse grid (compared, not
timed): the check of this script itself on a machine without a
GPU.

Run:  python benchmarks/gpu_check.py [--tiny] [--out DIR] [--sizes 64,128,256]
      [--steps 2000] [--cpu-steps 2000] [--rtol 1e-6] [--body-steps 200]
      [--crowd-members 64] [--crowd-steps 200]
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import io
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable, Sequence
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
"""The checkout (the tests and configs are read from it)."""

GOAL = 5e5
"""Member-steps per second to report against (fp64, H100-class GPU, paper grid)."""

TINY_GRID: dict[str, Any] = {
    "grid": {"dx": 0.1, "dt": 1e-3, "domain_radius": 1.6},
    "geometry": {"radius": 0.3, "pill_radius": 0.06, "pill_inset": 0.03, "smoothing": 0.05},
    "numerics": {"scheme": "paper"},
    "noise": {"sigma": 1e-5},
}
"""The grid of tests/backends/test_gpu.py (32 x 32 cells), on which the simulator
interprets a member-step in a fraction of a second."""

TINY_SWEEP: dict[str, Any] = {
    "name": "gpu_check_tiny",
    "base": {
        **TINY_GRID,
        "rotor": {"omega0": 20.0},
        "noise": {"sigma": 0.0},
        "protocol": {"t_ini": 0.005, "t_stop": 0.003, "t_release": 0.002, "cycles": 1},
    },
    "axes": {"geometry.asymmetry": [0.0, 0.05]},
    "estimator": {"kind": "protocol"},
    "samples": 1,
    "seed": 3,
}
"""Two protocol runs of 10 steps, one stop, on the tiny grid of tests/sweep/test_sweep_gpu.py."""

BODIES: list[dict[str, Any]] = [
    {
        "name": "disk",
        "plate": {"shape": "disk", "radius": 0.2},
        "pills": [{"x": 0.1, "y": 0.0, "radius": 0.06}],
        "motion": {"kind": "free", "mass": 1e-3, "inertia": 1e-4},
        "start": {"x": -1.3, "y": 0.05, "angle": 0.3, "omega": 2.0, "velocity": [0.3, -0.2]},
    },
    {
        "name": "hexagon",
        "plate": {"shape": "polygon", "n_corners": 6, "radius": 0.3},
        "pills": [{"x": 0.2, "y": 0.05, "radius": 0.06}, {"x": -0.15, "y": -0.1, "radius": 0.06}],
        "motion": {"kind": "fixed_axis"},
        "start": {"x": 1.45, "y": -0.05, "angle": 0.4, "omega": 3.0},
    },
]
"""The bodies case: one free disk, one fixed_axis hexagon with two pills (flow on)."""

BODIES_GRID = {
    True: {"dx": 0.1, "dt": 1e-3, "domain_radius": 3.1},
    False: {"dx": 0.025, "dt": 1e-4, "domain_radius": 3.1},
}
"""The bodies case's grid: tiny (62 x 62 cells, paper scheme) or the paper's dx and dt
(consistent scheme)."""

BODIES_TOLERANCE = 1e-10
"""Largest difference of the GPU's bodies run from the CPU's: poses, velocities and forces
absolute, c and v relative to their largest value."""

CROWD_SWEEP = "configs/sweeps/crowd_ring.yaml"
"""The crowd case's sweep: its first point at the settings of :data:`CROWD_SETS`."""

CROWD_SETS: dict[bool, list[str]] = {
    False: [
        "axes.crowd.count=[16]",
        "axes.crowd.body.motion.friction=[0.05]",
        "axes.flow.enabled=[true]",
    ],
    True: [
        "axes.crowd.count=[3]",
        "axes.crowd.body.motion.friction=[0.05]",
        "axes.flow.enabled=[true]",
        "set.grid.dx=0.1",
        "set.grid.dt=1e-3",
        "set.geometry.smoothing=0.05",
        "set.grid.domain_radius=3.8",
        "set.grid.vessel.inner_radius=0.4",
        "set.grid.vessel.outer_radius=3.8",
        "crowd.placement.radius=2.1",
        "set.numerics.scheme=paper",
        "set.numerics.integrator=heun",
    ],
}
"""The crowd case: 16 boats at the sweep's grid, scheme and integrator (dx = 0.05 in the
annulus 3.6 < r < 5.6, 224 x 224 cells, consistent, forward Euler with the contact's
dashpot), or, tiny, 3 boats in a wider annulus on a grid of 76 x 76 cells (the coarser
grid's smoothing needs a channel 3.4 wide to hold a boat's footprint) on the paper scheme
with Heun's method, the other pair of the two."""

SWEEP_FILE = "configs/sweeps/fig5_quick.yaml"
SWEEP_SETS = ["samples=2", "axes.protocol.t_stop=[0.5,1.0]"]
"""The sweep of the full check: 2 stop durations x 2 samples x 2 directions = 8 restarts
on the coarse grid."""


def device_info(tiny: bool) -> dict[str, Any]:
    """``nvidia-smi`` and ``numba.cuda.detect()`` output, and the device the backend uses."""
    from pde_rotor.backends import device_name, gpu_unavailable_reason

    smi = shutil.which("nvidia-smi")
    if smi is None:
        smi_text = "nvidia-smi: not found"
    else:
        done = subprocess.run([smi], capture_output=True, text=True, check=False)
        smi_text = (done.stdout + done.stderr).strip()
    from pde_rotor.kernels.cuda_target import cuda

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        try:
            found = bool(cuda.detect())
        except Exception as err:  # no driver: recorded, the check then fails on "available"
            print(f"{type(err).__name__}: {err}".strip())
            found = False
    reason = gpu_unavailable_reason(allow_simulator=tiny)
    return {
        "name": device_name("gpu") if reason is None else "none",
        "available": reason is None,
        "reason": reason,
        "detect_found": found,
        "nvidia_smi": smi_text,
        "numba_detect": buffer.getvalue().strip(),
    }


def junit_counts(path: Path) -> dict[str, int]:
    """Tests, failures, errors and skips of a pytest junit XML file."""
    counts = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    for suite in ET.parse(path).getroot().iter("testsuite"):
        for name in counts:
            counts[name] += int(suite.get(name, 0))
    return counts


def run_tests(out: Path, tiny: bool) -> dict[str, Any]:
    """The CUDA test files on the device (with `tiny`: in the simulator, the one test
    of the backend choice, which asserts which of the two it runs on)."""
    files = ["tests/backends/test_gpu.py"]
    if not tiny:
        files += ["tests/backends/test_gpu_bodies.py", "tests/sweep/test_sweep_gpu.py"]
    xml = out / "tests_junit.xml"
    xml.unlink(missing_ok=True)  # no counts of an earlier run
    command = [sys.executable, "-m", "pytest", *files, "-n", "0", "-q", "-p", "no:cacheprovider"]
    command.append(f"--junitxml={xml}")
    if tiny:
        command += ["-k", "backend_choice"]
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1" if tiny else "0"}
    start = time.perf_counter()
    done = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True, check=False)
    (out / "tests_output.txt").write_text(done.stdout + done.stderr)
    counts = junit_counts(xml) if xml.is_file() else {}
    return {
        "files": files,
        "on": "simulator" if tiny else "device",
        "returncode": done.returncode,
        "seconds": time.perf_counter() - start,
        **counts,
        "passed": counts.get("tests", 0)
        - sum(counts.get(k, 0) for k in ("failures", "errors", "skipped")),
        "summary": done.stdout.strip().splitlines()[-1] if done.stdout.strip() else "",
    }


def paper_base() -> dict[str, Any]:
    """The sections of configs/paper_fig4a.yaml (its noise is replaced per member)."""
    import yaml

    return yaml.safe_load((ROOT / "configs" / "paper_fig4a.yaml").read_text())


def timed_rate(
    run: Callable[[int], Any], n_members: int, short: int, steps: int
) -> dict[str, float]:
    """Member-steps/s of `run(n_steps)` as the difference of a short and a long run (the
    faster of two each), NaN if timing noise hides the difference.

    The first call (compilation, warm-up) is timed separately as ``first_call_s``.
    """

    def seconds(n_steps: int) -> float:
        start = time.perf_counter()
        run(n_steps)
        return time.perf_counter() - start

    first = seconds(short)
    t_short = min(seconds(short), seconds(short))
    t_long = min(seconds(short + steps), seconds(short + steps))
    rate = n_members * steps / (t_long - t_short) if t_long > t_short else math.nan
    return {
        "members": n_members,
        "steps": steps,
        "first_call_s": first,
        "short_s": t_short,
        "long_s": t_long,
        "member_steps_per_s": rate,
    }


def bench_configs(n_members: int, tiny: bool) -> list[Any]:
    """`n_members` configs of the timed grid (paper or tiny), differing in Delta and seed,
    from benchmarks/bench_gpu.py's ``member_configs``."""
    if "bench_gpu" not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            "bench_gpu", Path(__file__).with_name("bench_gpu.py")
        )
        assert spec is not None and spec.loader is not None
        sys.modules["bench_gpu"] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules["bench_gpu"])
    base = TINY_GRID if tiny else paper_base()
    return sys.modules["bench_gpu"].member_configs(n_members, base, base["noise"]["sigma"])


def throughput(sizes: Sequence[int], steps: int, cpu_steps: int, tiny: bool) -> dict[str, Any]:
    """GPU member-steps/s for each ensemble size and the CPU backend's, and the ratios."""
    from pde_rotor.backends import run_ensemble

    one = bench_configs(1, tiny)
    grid = one[0].grid
    short = 2 if tiny else 100
    results: dict[str, Any] = {
        "grid": {"dx": grid.dx, "dt": grid.dt, "domain_radius": grid.domain_radius},
        "scheme": one[0].numerics.scheme,
    }

    def runner(configs: list[Any], backend: str) -> Callable[[int], Any]:
        dt = configs[0].grid.dt
        return lambda n: run_ensemble(
            configs, n * dt, backend=backend, record_interval=dt * min(n, 100)
        )

    results["cpu"] = timed_rate(runner(one, "cpu"), 1, short, cpu_steps)
    cpu_rate = results["cpu"]["member_steps_per_s"]
    results["gpu"] = []
    for n_members in sizes:
        rate = timed_rate(runner(bench_configs(n_members, tiny), "gpu"), n_members, short, steps)
        rate["speedup"] = rate["member_steps_per_s"] / cpu_rate
        results["gpu"].append(rate)
    rates = [r["member_steps_per_s"] for r in results["gpu"]]
    best = max((r for r in rates if math.isfinite(r)), default=math.nan)
    results["measured"] = all(math.isfinite(r) and r > 0 for r in [cpu_rate, *rates])
    results["best_gpu_member_steps_per_s"] = best
    results["goal_member_steps_per_s"] = GOAL
    results["goal_met"] = best >= GOAL
    return results


def compare_value(got: Any, want: Any, rtol: float) -> bool:
    """Whether two stored values agree: floats to `rtol` (NaN equals NaN), lists element
    by element, everything else (bool, int, str, None) exactly."""
    if isinstance(got, list) and isinstance(want, list):
        return len(got) == len(want) and all(
            compare_value(a, b, rtol) for a, b in zip(got, want, strict=True)
        )
    if isinstance(got, float) or isinstance(want, float):
        if isinstance(got, bool) or isinstance(want, bool) or got is None or want is None:
            return False
        if math.isnan(got) or math.isnan(want):
            return math.isnan(got) and math.isnan(want)
        return math.isclose(got, want, rel_tol=rtol, abs_tol=0.0)
    return type(got) is type(want) and got == want


def compare_runs(
    gpu: dict[str, dict[str, Any]], cpu: dict[str, dict[str, Any]], rtol: float
) -> list[str]:
    """The differences between two sweeps' run results (by run key): one line each."""
    problems = [f"run {key}: only on the CPU" for key in sorted(cpu.keys() - gpu.keys())]
    problems += [f"run {key}: only on the GPU" for key in sorted(gpu.keys() - cpu.keys())]
    for key in sorted(gpu.keys() & cpu.keys()):
        got, want = gpu[key], cpu[key]
        for name in sorted(got.keys() | want.keys()):
            if name not in got or name not in want:
                problems.append(f"run {key}: {name} only on the {'GPU' if name in got else 'CPU'}")
            elif not compare_value(got[name], want[name], rtol):
                problems.append(f"run {key}: {name} GPU {got[name]!r} != CPU {want[name]!r}")
    return problems


def max_float_deviation(gpu: dict[str, dict[str, Any]], cpu: dict[str, dict[str, Any]]) -> float:
    """Largest relative difference of the finite float results of the runs of both."""
    worst = 0.0
    for key in gpu.keys() & cpu.keys():
        for name in gpu[key].keys() & cpu[key].keys():
            pairs = zip(
                *(v if isinstance(v, list) else [v] for v in (gpu[key][name], cpu[key][name])),
                strict=False,
            )
            for a, b in pairs:
                if isinstance(a, float) and isinstance(b, float) and math.isfinite(a + b) and b:
                    worst = max(worst, abs(a - b) / abs(b))
    return worst


def sweep_of(tiny: bool, backend: str) -> Any:
    """The sweep of the check (:data:`TINY_SWEEP` or :data:`SWEEP_FILE` with
    :data:`SWEEP_SETS`) with ``solver.backend`` = `backend`."""
    from pde_rotor.sweep import Sweep, SweepSpec

    if tiny:
        base = {**TINY_SWEEP["base"], "solver": {"backend": backend}}
        return Sweep.from_spec(SweepSpec.model_validate({**TINY_SWEEP, "base": base}))
    return Sweep.load(ROOT / SWEEP_FILE, [*SWEEP_SETS, f"set.solver.backend={backend}"])


def sweep_check(out: Path, tiny: bool, rtol: float) -> dict[str, Any]:
    """The same sweep on the GPU and on the CPU, stored in two directories, compared."""
    from pde_rotor.sweep import read_runs, run_sweep, sweep_backend

    result: dict[str, Any] = {"sweep": "tiny protocol sweep" if tiny else SWEEP_FILE}
    result["sets"] = [] if tiny else SWEEP_SETS
    stored = {}
    for backend in ("gpu", "cpu"):
        sweep = sweep_of(tiny, backend)
        sweep_dir = out / f"sweep_{backend}"
        shutil.rmtree(sweep_dir, ignore_errors=True)
        start = time.perf_counter()
        outcome = run_sweep(sweep, sweep_dir, workers=1 if tiny else None, progress=False)
        result[backend] = {
            "backend": sweep_backend(sweep),
            "runs": outcome.total,
            "computed": outcome.computed,
            "failed": len(outcome.failed),
            "seconds": time.perf_counter() - start,
            "dir": str(sweep_dir),
        }
        records = read_runs(sweep_dir)
        result[backend]["stored_by"] = sorted({rec["backend"] for rec in records.values()})
        stored[backend] = {key: rec["result"] for key, rec in records.items()}
        flags = [r["inverted"] for r in stored[backend].values() if "inverted" in r]
        if flags:
            result[backend]["inverted"] = f"{sum(flags)} of {len(flags)}"
    problems = compare_runs(stored["gpu"], stored["cpu"], rtol)
    result["rtol"] = rtol
    result["max_rel_deviation"] = max_float_deviation(stored["gpu"], stored["cpu"])
    result["mismatches"] = problems
    result["agree"] = (
        not problems
        and bool(stored["cpu"])
        and result["gpu"]["stored_by"] == ["gpu"]
        and result["cpu"]["stored_by"] == ["cpu"]
        and result["gpu"]["failed"] == result["cpu"]["failed"] == 0
    )
    return result


def bodies_check(tiny: bool, steps: int) -> dict[str, Any]:
    """:data:`BODIES` on the GPU and on the CPU, `steps` steps from the same smooth fields:
    the largest differences and each backend's wall time (compilation included)."""
    import numpy as np

    from pde_rotor import RotorConfig
    from pde_rotor.backends.gpu_bodies import gpu_bodies_stepper
    from pde_rotor.solver.simulation import Simulation

    config = RotorConfig.model_validate(
        {
            "grid": BODIES_GRID[tiny],
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": "paper" if tiny else "consistent"},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "bodies": BODIES,
        }
    )
    result: dict[str, Any] = {"grid": BODIES_GRID[tiny], "scheme": config.numerics.scheme}
    result["steps"] = steps
    sims = {}
    for backend in ("gpu", "cpu"):
        sim = Simulation(config, stepper=gpu_bodies_stepper if backend == "gpu" else None)
        x, y = sim.pde.cell_coordinates()
        mask = sim.pde.domain.interior_mask
        sim.state.data[0] = mask * (1 + 0.5 * np.sin(1.3 * x + 0.2) * np.cos(0.7 * y + 0.1))
        sim.state.data[1] = mask * 0.3 * np.sin(0.9 * y) * np.cos(0.4 * x)
        sim.state.data[2] = mask * 0.2 * np.cos(1.1 * x) * np.sin(0.5 * y)
        start = time.perf_counter()
        sim.run(steps * config.grid.dt)
        result[f"{backend}_s"] = time.perf_counter() - start
        sims[backend] = sim
    gpu, cpu = sims["gpu"], sims["cpu"]
    result["max_pose_deviation"] = float(np.abs(gpu.bodies.poses - cpu.bodies.poses).max())
    scale = float(np.abs(cpu.state.data).max())
    result["max_field_deviation"] = float(np.abs(gpu.state.data - cpu.state.data).max()) / scale
    result["tolerance"] = BODIES_TOLERANCE
    result["agree"] = (
        result["max_pose_deviation"] <= BODIES_TOLERANCE
        and result["max_field_deviation"] <= BODIES_TOLERANCE
    )
    return result


def crowd_configs(tiny: bool, members: int) -> list[Any]:
    """The crowd case's `members` configs: :data:`CROWD_SWEEP`'s point at
    :data:`CROWD_SETS`, one ring placement (and noise seed) per sample."""
    from pde_rotor import RotorConfig
    from pde_rotor.sweep import Sweep

    sweep = Sweep.load(ROOT / CROWD_SWEEP, [*CROWD_SETS[tiny], f"samples={members}"])
    return [RotorConfig.model_validate(run.config) for run in sweep.runs()]


def crowd_check(tiny: bool, steps: int, members: int) -> dict[str, Any]:
    """The crowd ensemble on the GPU against member 0 on the CPU after `steps` steps from
    rest; unless `tiny`, member-steps/s of both (:func:`timed_rate`)."""
    import numpy as np

    from pde_rotor.backends.gpu_bodies import run_bodies_ensemble
    from pde_rotor.solver.simulation import Simulation

    configs = crowd_configs(tiny, members)
    dt = configs[0].grid.dt
    result: dict[str, Any] = {
        "boats": len(configs[0].bodies),
        "members": members,
        "grid": {
            "dx": configs[0].grid.dx,
            "dt": dt,
            "cells": int(2 * round(configs[0].grid.domain_radius / configs[0].grid.dx)),
        },
        "integrator": configs[0].numerics.integrator,
        "steps": steps,
    }
    start = time.perf_counter()
    gpu = run_bodies_ensemble(configs, steps * dt, record_interval=steps * dt)
    result["gpu_s"] = time.perf_counter() - start
    start = time.perf_counter()
    cpu = Simulation(configs[0])
    cpu.run(steps * dt)
    result["cpu_s"] = time.perf_counter() - start
    result["max_pose_deviation"] = float(np.abs(gpu.poses[0, -1] - cpu.bodies.poses).max())
    scale = float(np.abs(cpu.state.data).max())
    result["max_field_deviation"] = float(np.abs(gpu.data[0] - cpu.state.data).max()) / scale
    result["tolerance"] = BODIES_TOLERANCE
    result["agree"] = (
        bool(np.isfinite(gpu.ended_at).sum() == 0)
        and result["max_pose_deviation"] <= BODIES_TOLERANCE
        and result["max_field_deviation"] <= BODIES_TOLERANCE
    )
    if not tiny:
        short = 20

        def on_gpu(n: int) -> Any:
            return run_bodies_ensemble(configs, n * dt, record_interval=n * dt)

        def on_cpu(n: int) -> Any:
            return Simulation(configs[0]).run(n * dt)

        result["gpu"] = timed_rate(on_gpu, members, short, steps)
        result["cpu"] = timed_rate(on_cpu, 1, short, steps)
        result["speedup"] = (
            result["gpu"]["member_steps_per_s"] / result["cpu"]["member_steps_per_s"]
        )
    return result


def checks_of(results: dict[str, Any]) -> dict[str, bool]:
    """The pass/fail checks of a results dictionary (the goal is not one of them)."""
    tests = results["tests"]
    return {
        "device": results["device"]["available"],
        "tests": tests["returncode"] == 0 and tests.get("passed", 0) > 0,
        "throughput": results["throughput"]["measured"],
        "sweep": results["sweep"]["agree"],
        "bodies": results["bodies"]["agree"],
        "crowd": results["crowd"]["agree"],
    }


def summary(results: dict[str, Any]) -> str:
    """The figures of `results` as text lines."""
    dev, tests, rate, sweep = (results[k] for k in ("device", "tests", "throughput", "sweep"))
    checks = "checks: " + ", ".join(
        f"{k} {'ok' if v else 'FAILED'}" for k, v in results["checks"].items()
    )
    lines = [
        f"gpu_check {results['mode']} run, {results['date']} on {results['host']}",
        f"device: {dev['name']}" + (f" (unavailable: {dev['reason']})" if dev["reason"] else ""),
    ]
    if not dev["available"]:
        return "\n".join(
            [*lines, "tests, throughput, sweep, bodies, crowd: not run (no device)", checks]
        )
    lines += [
        f"tests on the {tests['on']}: {tests.get('passed', 0)} passed, "
        f"{tests.get('failures', 0)} failed, {tests.get('errors', 0)} errors, "
        f"{tests.get('skipped', 0)} skipped ({tests['seconds']:.1f} s)",
        f"throughput at dx = {rate['grid']['dx']}, dt = {rate['grid']['dt']}, "
        f"L = {rate['grid']['domain_radius']}, scheme {rate['scheme']}, fp64:",
        f"  cpu  E = 1: {rate['cpu']['member_steps_per_s']:.4g} member-steps/s "
        f"({rate['cpu']['steps']} steps; first call {rate['cpu']['first_call_s']:.2f} s)",
    ]
    lines += [
        f"  gpu  E = {r['members']}: {r['member_steps_per_s']:.4g} member-steps/s "
        f"= {r['speedup']:.3g} x cpu ({r['steps']} steps; first call, compile included, "
        f"{r['first_call_s']:.2f} s)"
        for r in rate["gpu"]
    ]
    lines.append(
        f"  goal {rate['goal_member_steps_per_s']:.0e} member-steps/s: "
        f"{'met' if rate['goal_met'] else 'not met'} "
        f"(best {rate['best_gpu_member_steps_per_s']:.4g})"
    )
    label = " ".join([sweep["sweep"], *(f"--set {v}" for v in sweep["sets"])])
    inverted = {b: sweep[b].get("inverted", "-") for b in ("gpu", "cpu")}
    lines += [
        f"sweep {label}: {sweep['cpu']['runs']} runs, gpu {sweep['gpu']['seconds']:.1f} s, "
        f"cpu {sweep['cpu']['seconds']:.1f} s",
        f"  inverted: gpu {inverted['gpu']}, cpu {inverted['cpu']}; max rel. deviation "
        f"{sweep['max_rel_deviation']:.2e} (tolerance {sweep['rtol']:g}): "
        + ("agree" if sweep["agree"] else f"DIFFER ({len(sweep['mismatches'])} mismatches)"),
    ]
    lines += [f"  {line}" for line in sweep["mismatches"][:10]]
    bodies = results["bodies"]
    lines.append(
        f"bodies (free disk, fixed_axis hexagon) at dx = {bodies['grid']['dx']}, "
        f"dt = {bodies['grid']['dt']}, scheme {bodies['scheme']}, {bodies['steps']} steps: "
        f"gpu {bodies['gpu_s']:.3g} s, cpu {bodies['cpu_s']:.3g} s (compilation included); "
        f"max deviation poses {bodies['max_pose_deviation']:.2e}, fields "
        f"{bodies['max_field_deviation']:.2e} (tolerance {bodies['tolerance']:g}): "
        + ("agree" if bodies["agree"] else "DIFFER")
    )
    crowd = results["crowd"]
    lines.append(
        f"crowd ({crowd['boats']} boats on a ring track, contact and flow on, "
        f"{crowd['integrator']}) at dx = {crowd['grid']['dx']}, {crowd['grid']['cells']}^2 "
        f"cells, E = {crowd['members']}, {crowd['steps']} steps: gpu {crowd['gpu_s']:.3g} s, "
        f"cpu {crowd['cpu_s']:.3g} s (compilation included); max deviation of member 0 "
        f"poses {crowd['max_pose_deviation']:.2e}, fields {crowd['max_field_deviation']:.2e} "
        f"(tolerance {crowd['tolerance']:g}): " + ("agree" if crowd["agree"] else "DIFFER")
    )
    if "speedup" in crowd:
        lines.append(
            f"  gpu E = {crowd['members']}: {crowd['gpu']['member_steps_per_s']:.4g} "
            f"member-steps/s, cpu {crowd['cpu']['member_steps_per_s']:.4g}: "
            f"{crowd['speedup']:.3g} x cpu"
        )
    install = "-" if results["install_s"] is None else f"{results['install_s']:.0f} s"
    lines.append(f"wall time: install {install}, checks {results['check_s']:.0f} s")
    return "\n".join([*lines, checks])


def main(argv: Sequence[str] | None = None) -> int:
    """Run the check; returns the exit status (1 if a check failed)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--tiny",
        action="store_true",
        default=os.environ.get("GPU_CHECK_TINY") == "1",
        help="CUDA simulator, tiny grid (also GPU_CHECK_TINY=1)",
    )
    parser.add_argument("--out", type=Path, default=Path(os.environ.get("OUT") or "gpu_check"))
    parser.add_argument("--sizes", default=None, help="ensemble sizes E [64,128,256; tiny: 2]")
    parser.add_argument("--steps", type=int, default=None, help="timed GPU steps [2000; tiny: 4]")
    parser.add_argument(
        "--cpu-steps", type=int, default=None, help="timed CPU steps [2000; tiny: 1000]"
    )
    parser.add_argument("--rtol", type=float, default=1e-6, help="sweep float tolerance")
    parser.add_argument(
        "--body-steps", type=int, default=None, help="steps of the bodies case [200; tiny: 3]"
    )
    parser.add_argument(
        "--crowd-members", type=int, default=None, help="members of the crowd case [64; tiny: 2]"
    )
    parser.add_argument(
        "--crowd-steps", type=int, default=None, help="steps of the crowd case [200; tiny: 1]"
    )
    args = parser.parse_args(argv)
    tiny = args.tiny
    sizes = [int(v) for v in (args.sizes or ("2" if tiny else "64,128,256")).split(",")]
    steps = args.steps or (4 if tiny else 2000)
    cpu_steps = args.cpu_steps or (1000 if tiny else 2000)
    os.environ["NUMBA_ENABLE_CUDASIM"] = "1" if tiny else "0"
    if "numba.cuda" in sys.modules:
        raise RuntimeError("gpu_check: numba.cuda was imported before the simulator was chosen")
    from numba.core import config as numba_config

    numba_config.reload_config()

    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    results: dict[str, Any] = {
        "mode": "tiny (CUDA simulator)" if tiny else "device",
        "date": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "host": platform.node(),
    }
    results["device"] = device_info(tiny)
    print(f"device: {results['device']['name']}", flush=True)
    if results["device"]["available"]:
        results["tests"] = run_tests(out, tiny)
        print(f"tests: {results['tests']['summary']}", flush=True)
        print(f"timing: E = {sizes} on the GPU, 1 member on the CPU", flush=True)
        results["throughput"] = throughput(sizes, steps, cpu_steps, tiny)
        print("sweep: on the GPU, then on the CPU", flush=True)
        results["sweep"] = sweep_check(out, tiny, args.rtol)
        print("bodies: on the GPU, then on the CPU", flush=True)
        results["bodies"] = bodies_check(tiny, args.body_steps or (3 if tiny else 200))
        print("crowd: an ensemble on the GPU, member 0 on the CPU", flush=True)
        crowd_members = args.crowd_members or (2 if tiny else 64)
        results["crowd"] = crowd_check(
            tiny, args.crowd_steps or (1 if tiny else 200), crowd_members
        )
    else:  # nothing to test, time or compare
        results["tests"] = {"returncode": None}
        results["throughput"] = {"measured": False}
        results["sweep"] = {"agree": False}
        results["bodies"] = {"agree": False}
        results["crowd"] = {"agree": False}
    install = os.environ.get("GPU_CHECK_INSTALL_S")
    results["install_s"] = float(install) if install else None
    results["check_s"] = time.perf_counter() - start
    results["checks"] = checks_of(results)
    results["ok"] = all(results["checks"].values())
    (out / "gpu_check_results.json").write_text(json.dumps(results, indent=2) + "\n")
    text = summary(results) + f"\nresults: {out / 'gpu_check_results.json'}"
    (out / "gpu_check_results.txt").write_text(
        text
        + "\n\n"
        + results["device"]["nvidia_smi"]
        + "\n\n"
        + results["device"]["numba_detect"]
        + "\n"
    )
    print(text)
    return 0 if results["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
