"""Benchmark and hardware cross-check of the GPU ensemble backend (pde_rotor.backends.gpu).

Needs a CUDA GPU and the gpu extra (``pip install -e '.[gpu]'``); without one it prints
why and exits with status 2. Prints, at the paper's resolution (dx = 0.025, dt = 1e-4:
242 x 242 cells, 45 244 inside the disk of radius 3):

1. validation (skip with --skip-validate): phi(t), omega(t) of GPU and CPU solver for
   members that differ in Delta and t_stop, without noise, over 10 time units on the
   coarse grid (dx = 0.05, dt = 4e-4; goal: 1e-8 relative) and over 2 time units at the
   paper resolution (goal: 1e-6), and one noisy member with a fixed seed (same noise
   sequence on both backends, goal: 1e-8);
2. the card's device-to-device copy bandwidth (cudaMemcpy, bytes read + written);
3. member-steps per second against the batch size E = 1, 8, 32, 128, 512 for each
   threads-per-block / launch-bound variant, timed as the difference of two runs of
   different length (setup and compilation cancel), with the effective memory
   throughput: 48 bytes (c, v_x, v_y read and written once) per interior cell and
   member-step, as a fraction of the copy bandwidth;
4. the CPU solver's steps per second on one core of the same machine, and the speedup;
5. projected wall time of the paper's Fig. 5 protocol (31 t_stop values, M = 100 stops
   each, t_ini = 10, t_release = 10): as 31 members running all 100 cycles, and as
   3100 independent one-stop members (restart estimator).

Run:  python benchmarks/bench_gpu.py [--sizes 1,8,32,128,512] [--tpb 128,256,512]
      [--min-blocks 0,-1] [--seconds 3] [--skip-validate] [--skip-cpu]
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any

import numpy as np

from pde_rotor import RotorConfig, Simulation
from pde_rotor.backends import cpu, gpu_unavailable_reason

COARSE: dict[str, Any] = {"grid": {"dx": 0.05, "dt": 4e-4}, "geometry": {"smoothing": 0.05}}
"""The coarse test resolution of the suite (tests/conftest.py)."""


def member_configs(
    n_members: int, base: dict[str, Any] | None = None, sigma: float = 0.0
) -> list[RotorConfig]:
    """Members differing in Delta (and seed), otherwise the paper's defaults plus `base`."""
    base = base or {}
    configs = []
    for m in range(n_members):
        data: dict[str, Any] = {key: dict(value) for key, value in base.items()}
        data.setdefault("geometry", {})["asymmetry"] = 1e-3 * (m % 41 - 20)
        data["noise"] = {"sigma": sigma, "seed": 1000 + m}
        configs.append(RotorConfig.model_validate(data))
    return configs


def max_relative(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b| per member, worst member."""
    return float(np.max(np.max(np.abs(a - b), axis=1) / np.max(np.abs(b), axis=1)))


def validate() -> bool:
    """GPU against CPU at the tolerances of docs/gpu.md; prints one line per check."""
    from pde_rotor.backends import gpu

    ok = True
    protocol = {"t_ini": 2.0, "t_stop": 0.5, "t_release": 2.0, "cycles": 3}
    checks = [
        ("coarse, 10 time units", COARSE, protocol, 10.0, 0.0, 1e-8),
        ("paper resolution, 2 time units", {}, {**protocol, "t_ini": 1.0}, 2.0, 0.0, 1e-6),
        ("coarse with noise, 2 time units", COARSE, protocol, 2.0, 1e-6, 1e-8),
    ]
    for label, grid, proto, t_end, sigma, tol in checks:
        members = []
        for m, (asym, t_stop) in enumerate([(0.02, 0.5), (-0.01, 0.3)]):
            data = {
                **{k: dict(v) for k, v in grid.items()},
                "protocol": {**proto, "t_stop": t_stop},
                "noise": {"sigma": sigma, "seed": 7 + m},
            }
            data.setdefault("geometry", {})["asymmetry"] = asym
            members.append(RotorConfig.model_validate(data))
        want = cpu.run_ensemble(members, t_end, record_interval=0.01)
        got = gpu.run_ensemble(members, t_end, record_interval=0.01)
        err_phi = max_relative(got.phi, want.phi)
        err_omega = max_relative(got.omega, want.omega)
        passed = max(err_phi, err_omega) <= tol and np.array_equal(got.stopped, want.stopped)
        ok &= passed
        print(
            f"  {label:34s} max rel. deviation phi {err_phi:.2e}, omega {err_omega:.2e} "
            f"(goal {tol:g}): {'ok' if passed else 'FAILED'}"
        )
    return ok


def copy_bandwidth(n_bytes: int = 2**31, repeats: int = 20) -> float:
    """Device-to-device copy bandwidth in bytes/s (each byte counted read and written)."""
    from numba import cuda

    a = cuda.device_array(n_bytes // 8, dtype=np.float64)
    b = cuda.device_array_like(a)
    b.copy_to_device(a)
    start, end = cuda.event(), cuda.event()
    start.record()
    for _ in range(repeats):
        b.copy_to_device(a)
    end.record()
    end.synchronize()
    seconds = start.elapsed_time(end) / 1e3
    return 2 * a.nbytes * repeats / seconds


def member_steps_per_second(configs: list[RotorConfig], seconds: float, **options: Any) -> float:
    """Throughput of gpu.run_ensemble, timed as the difference of a short and a long run."""
    from pde_rotor.backends import gpu

    dt = configs[0].grid.dt

    def timed(n_steps: int) -> float:
        start = time.perf_counter()
        gpu.run_ensemble(configs, n_steps * dt, record_interval=dt * 10, **options)
        return time.perf_counter() - start

    timed(10)  # compile and warm up
    short = 20
    t_short = timed(short)
    probe = timed(short + 200) - t_short
    long = short + max(200, int(200 * seconds / max(probe, 1e-3)))
    t_long = timed(long)
    return len(configs) * (long - short) / (t_long - t_short)


def cpu_steps_per_second(n_steps: int = 2000) -> float:
    """Steps per second of the fused CPU solver at the paper resolution (one core)."""
    sim = Simulation(RotorConfig.model_validate({}))
    dt = sim.config.grid.dt
    sim.run(50 * dt)
    start = time.perf_counter()
    sim.run(sim.t + n_steps * dt)
    return n_steps / (time.perf_counter() - start)


def main() -> int:
    """Run the benchmark; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1,8,32,128,512", help="batch sizes E")
    parser.add_argument("--tpb", default="128,256,512", help="threads per block")
    parser.add_argument("--min-blocks", default="0,-1", help="launch bound (0: none, -1: auto)")
    parser.add_argument("--seconds", type=float, default=3.0, help="target time per timing")
    parser.add_argument("--skip-validate", action="store_true")
    parser.add_argument("--skip-cpu", action="store_true")
    args = parser.parse_args()

    reason = gpu_unavailable_reason()
    if reason is not None:
        print(f"bench_gpu: no GPU to benchmark: {reason}", file=sys.stderr)
        return 2
    from numba import cuda

    device = cuda.get_current_device()
    print(f"device: {device.name.decode() if isinstance(device.name, bytes) else device.name}")
    ok = True
    if not args.skip_validate:
        print("validation against the CPU solver:")
        ok = validate()

    bandwidth = copy_bandwidth()
    print(f"device-to-device copy bandwidth: {bandwidth / 1e9:.0f} GB/s")
    paper = RotorConfig.model_validate({})
    interior = int(Simulation(paper).pde.domain.interior_mask.sum())
    bytes_per_member_step = 48 * interior
    print(
        f"paper grid: {interior} interior cells, {bytes_per_member_step / 1e6:.2f} MB/member-step"
    )

    sizes = [int(v) for v in args.sizes.split(",")]
    variants = [(int(t), int(b)) for t in args.tpb.split(",") for b in args.min_blocks.split(",")]
    best: dict[int, float] = {}
    print(f"{'E':>5} {'tpb':>5} {'minB':>5} {'member-steps/s':>15} {'GB/s':>8} {'of copy':>8}")
    for n_members in sizes:
        configs = member_configs(n_members, sigma=1e-6)
        for tpb, min_blocks in variants:
            rate = member_steps_per_second(
                configs,
                args.seconds,
                threads_per_block=tpb,
                min_blocks_per_sm=None if min_blocks < 0 else min_blocks,
            )
            throughput = rate * bytes_per_member_step
            best[n_members] = max(best.get(n_members, 0.0), rate)
            print(
                f"{n_members:5d} {tpb:5d} {min_blocks:5d} {rate:15.4g} "
                f"{throughput / 1e9:8.0f} {throughput / bandwidth:8.1%}"
            )

    if not args.skip_cpu:
        cpu_rate = cpu_steps_per_second()
        print(f"CPU solver: {cpu_rate:.0f} steps/s on one core")
        for n_members, rate in best.items():
            print(
                f"  E = {n_members:4d}: best GPU {rate:.4g} member-steps/s = {rate / cpu_rate:.0f}x"
            )

    steps_run = round((10 + 100 * (1.0 + 10)) / paper.grid.dt)
    steps_one = round((1.0 + 10) / paper.grid.dt)
    if 32 in best:
        per_member = best[32] / 32
        print(
            f"Fig. 5 as 31 members x 100 cycles ({steps_run:.3g} steps each at t_stop = 1): "
            f"{steps_run / per_member / 60:.0f} min"
        )
    if 512 in best:
        print(
            f"Fig. 5 as 3100 one-stop members ({steps_one:.3g} steps each): "
            f"{3100 * steps_one / best[512] / 60:.0f} min"
        )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
