"""benchmarks/gpu_check.sh: its tiny mode end to end in numba's CUDA simulator, its
failure without a device, and the comparison of the GPU and CPU sweeps."""

from __future__ import annotations

import importlib.util
import json
import math
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "gpu_check.sh"


def load_gpu_check() -> Any:
    """benchmarks/gpu_check.py as a module (benchmarks/ is not a package)."""
    spec = importlib.util.spec_from_file_location("gpu_check", ROOT / "benchmarks" / "gpu_check.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


gpu_check = load_gpu_check()


def run_script(out: Path, *args: str, **env: str) -> subprocess.CompletedProcess[str]:
    """The shell script with this interpreter (no pip install), results in `out`."""
    environ = {k: v for k, v in os.environ.items() if k not in ("NUMBA_ENABLE_CUDASIM", "OUT")}
    environ.update(PYTHON=sys.executable, **env)
    command = ["bash", str(SCRIPT), *args, "--out", str(out)]
    return subprocess.run(command, env=environ, capture_output=True, text=True, check=False)


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[subprocess.CompletedProcess, Path]:
    """One tiny run (about 40 s on two loaded cores)."""
    out = tmp_path_factory.mktemp("gpu_check")
    return run_script(out, "--tiny"), out


def test_the_tiny_run_records_every_figure(tiny_run):
    done, out = tiny_run
    assert done.returncode == 0, done.stdout + done.stderr
    results = json.loads((out / "gpu_check_results.json").read_text())
    assert results["mode"].startswith("tiny")
    assert "simulator" in results["device"]["name"]
    assert results["device"]["nvidia_smi"] and results["device"]["numba_detect"]
    tests = results["tests"]
    assert tests["on"] == "simulator"
    assert (tests["returncode"], tests["failures"], tests["errors"]) == (0, 0, 0)
    assert tests["passed"] >= 1
    rate = results["throughput"]
    assert rate["grid"] == gpu_check.TINY_GRID["grid"]
    cpu = rate["cpu"]["member_steps_per_s"]
    assert cpu > 0 and rate["cpu"]["members"] == 1
    assert [r["members"] for r in rate["gpu"]] == [2]
    for r in rate["gpu"]:
        assert r["member_steps_per_s"] > 0 and r["first_call_s"] > 0
        assert r["speedup"] == pytest.approx(r["member_steps_per_s"] / cpu)
    assert rate["goal_member_steps_per_s"] == gpu_check.GOAL
    sweep = results["sweep"]
    assert (sweep["gpu"]["backend"], sweep["cpu"]["backend"]) == ("gpu", "cpu")
    assert (sweep["gpu"]["stored_by"], sweep["cpu"]["stored_by"]) == (["gpu"], ["cpu"])
    assert sweep["gpu"]["runs"] == sweep["cpu"]["runs"] == sweep["gpu"]["computed"] == 2
    assert sweep["agree"] and sweep["mismatches"] == []
    assert 0 <= sweep["max_rel_deviation"] <= sweep["rtol"]
    bodies = results["bodies"]
    assert bodies["grid"] == gpu_check.BODIES_GRID[True] and bodies["steps"] == 3
    assert bodies["agree"] and bodies["gpu_s"] > 0 and bodies["cpu_s"] > 0
    assert bodies["max_pose_deviation"] <= gpu_check.BODIES_TOLERANCE
    assert bodies["max_field_deviation"] <= gpu_check.BODIES_TOLERANCE
    crowd = results["crowd"]
    assert (crowd["boats"], crowd["members"], crowd["steps"]) == (3, 2, 1)
    assert crowd["integrator"] == "heun" and crowd["agree"]
    assert crowd["max_pose_deviation"] <= gpu_check.BODIES_TOLERANCE
    assert crowd["max_field_deviation"] <= gpu_check.BODIES_TOLERANCE
    checks = ("device", "tests", "throughput", "sweep", "bodies", "crowd")
    assert results["checks"] == dict.fromkeys(checks, True)
    assert results["ok"]
    assert results["install_s"] is None and results["check_s"] > 0  # PYTHON given: no install
    text = (out / "gpu_check_results.txt").read_text()
    for figure in (
        "device: numba CUDA simulator",
        "tests on the simulator",
        "cpu  E = 1",
        "gpu  E = 2",
        "x cpu",
        "goal 5e+05",
        "agree",
        "bodies (free disk, fixed_axis hexagon)",
        "crowd (3 boats on a ring track",
        "checks: device ok",
    ):
        assert figure in text, figure
    assert text.splitlines()[0] in done.stdout


def test_every_failed_check_fails_the_run(tiny_run):
    """Each check turns False on its own failure, and the run is ok only if all hold."""
    results = json.loads((tiny_run[1] / "gpu_check_results.json").read_text())
    assert all(gpu_check.checks_of(results).values())
    failures = {
        "device": ("device", "available", False),
        "tests": ("tests", "returncode", 1),
        "throughput": ("throughput", "measured", False),
        "sweep": ("sweep", "agree", False),
        "bodies": ("bodies", "agree", False),
        "crowd": ("crowd", "agree", False),
    }
    for check, (section, key, value) in failures.items():
        broken = {**results, section: {**results[section], key: value}}
        checks = gpu_check.checks_of(broken)
        assert [name for name, ok in checks.items() if not ok] == [check]


def test_without_a_device_the_check_fails(tmp_path):
    """With the GPUs hidden, the (non-tiny) run says so and exits with status 1."""
    done = run_script(tmp_path, CUDA_VISIBLE_DEVICES="")
    assert done.returncode == 1, done.stdout + done.stderr
    results = json.loads((tmp_path / "gpu_check_results.json").read_text())
    assert results["mode"] == "device" and not results["ok"]
    assert results["checks"]["device"] is False and results["device"]["reason"]
    assert "checks: device FAILED" in (tmp_path / "gpu_check_results.txt").read_text()


def test_the_sweep_comparison_finds_every_difference():
    cpu = {
        "a": {"inverted": True, "committed": True, "t_commit": 1.5, "extra_steps": 3},
        "b": {"inverted": False, "committed": False, "t_commit": math.nan, "omegas": [1.0, -2.0]},
    }
    close = {
        "a": {**cpu["a"], "t_commit": 1.5 * (1 + 1e-9)},
        "b": {**cpu["b"], "omegas": [1.0, -2.0 * (1 - 1e-9)]},
    }
    assert gpu_check.compare_runs(close, cpu, rtol=1e-6) == []
    assert gpu_check.max_float_deviation(close, cpu) == pytest.approx(1e-9, rel=1e-3)
    broken = {
        "inverted": {"a": {**cpu["a"], "inverted": False}, "b": cpu["b"]},
        "t_commit": {"a": {**cpu["a"], "t_commit": 1.6}, "b": cpu["b"]},
        "extra_steps": {"a": {**cpu["a"], "extra_steps": 4}, "b": cpu["b"]},
        "t_commit GPU 1.0": {"a": cpu["a"], "b": {**cpu["b"], "t_commit": 1.0}},
        "omegas": {"a": cpu["a"], "b": {**cpu["b"], "omegas": [1.0]}},
        "only on the CPU": {"a": cpu["a"]},
        "only on the GPU": {**cpu, "c": cpu["a"]},
        "committed only on the CPU": {"a": cpu["a"], "b": {"inverted": False, "t_commit": 0.0}},
    }
    for what, gpu in broken.items():
        problems = gpu_check.compare_runs(gpu, cpu, rtol=1e-6)
        assert problems and what in problems[0], (what, problems)
    assert not gpu_check.compare_value(1.0, True, 1e-6)
    assert not gpu_check.compare_value(1, 1.0 + 1e-3, 1e-6)


def test_the_full_check_sweeps_one_design_on_both_backends():
    """The non-tiny sweep: the same runs (same keys) with solver.backend gpu and cpu."""
    gpu, cpu = (gpu_check.sweep_of(False, backend) for backend in ("gpu", "cpu"))
    assert (gpu.base["solver"]["backend"], cpu.base["solver"]["backend"]) == ("gpu", "cpu")
    assert [r.key for r in gpu.runs()] == [r.key for r in cpu.runs()]
    assert len(gpu.runs()) == 8 and gpu.spec.estimator.kind == "restart"


def test_the_full_check_crowd_is_the_ring_sweep_point():
    """16 boats at the crowd_ring sweep's grid, scheme and integrator, one placement per
    member."""
    configs = gpu_check.crowd_configs(False, 3)
    assert [len(c.bodies) for c in configs] == [16] * 3
    assert {(c.grid.dx, c.numerics.scheme, c.numerics.integrator) for c in configs} == {
        (0.05, "consistent", "euler")
    }
    assert all(c.flow.enabled and c.contact.damping > 0 for c in configs)
    assert len({c.bodies[0].start.x for c in configs}) == 3


def test_the_full_check_times_the_paper_grid():
    """configs/paper_fig4a.yaml's grid and scheme, one seed and Delta per member."""
    configs = gpu_check.bench_configs(3, tiny=False)
    grid = configs[0].grid
    assert (grid.dx, grid.dt, grid.domain_radius) == (0.025, 1e-4, 3.0)
    assert {c.numerics.scheme for c in configs} == {"consistent"}
    assert all(c.grid == grid for c in configs)
    assert len({c.noise.seed for c in configs}) == len({c.geometry.asymmetry for c in configs}) == 3
    assert all(c.noise.sigma > 0 for c in configs)
