"""Measure the constants of the cost estimate (pde_rotor.sweep.cost) on this machine.

Times the fused solver on the paper's grid (dx = delta = 0.025), the coarse grid
(dx = delta = 0.05) and a third (dx = delta = 1/30) of a turning rotor; takes the cost
per interior cell of one step from the Euler update of the fields on the paper's grid,
and the cost per support cell as the mean over the three grids of the rest of a step;
prints how well the two give each grid's step; does the same for a stopped plate (F and
G are not recomputed: only the rotor integrals cost on the support cells); and times the
movie frames of configs/quickstart.yaml. The steps run on one thread (solver.threads: 1)
and are timed in CPU seconds of that thread, which other work on the machine does not
inflate (it only delays them): the constants are for one idle core, and the sweep
estimate adds the load it finds. pde_rotor/sweep/cost.py holds the constants it measured
on the project's machine (docs/results.md); a machine that is faster or slower scales
them all.

Run:  python benchmarks/bench_cost.py [--steps 3000] [--scheme consistent|paper]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pde_rotor import Simulation, run
from pde_rotor.config import load_config, validate_config
from pde_rotor.kernels.cpu import euler_fields
from pde_rotor.kernels.records import make_record
from pde_rotor.sweep.cost import (
    SECONDS_PER_CELL_STEP,
    SECONDS_PER_STOPPED_SUPPORT_CELL_STEP,
    SECONDS_PER_SUPPORT_CELL_STEP,
    cell_counts,
)

GRIDS = {"paper": (0.025, 1e-4), "coarse": (0.05, 4e-4), "third": (1 / 30, 2e-4)}
QUICKSTART = Path(__file__).resolve().parents[1] / "configs" / "quickstart.yaml"


def ms_per_step(
    dx: float, dt: float, n_steps: int, scheme: str, stopped: bool = False
) -> tuple[float, tuple[int, int]]:
    """Milliseconds per step of a rotating (or, with `stopped`, a stopped) plate on the
    grid, and its cell counts."""
    long = 1e3 * dt * n_steps  # a stop from t = 0 that outlasts the timing
    protocol = {"t_ini": 0.0, "t_stop": long, "cycles": 1} if stopped else {"cycles": 0}
    config = validate_config(
        {
            "grid": {"dx": dx, "dt": dt},
            "geometry": {"smoothing": dx},
            "protocol": protocol,
            "numerics": {"scheme": scheme},
            "solver": {"threads": 1},
        }
    )
    sim = Simulation(config)
    sim.run(50 * dt)  # compile, or load the cached kernel
    start = time.thread_time()
    sim.run(sim.t + n_steps * dt)
    return 1e3 * (time.thread_time() - start) / n_steps, cell_counts(config)


def euler_seconds(scheme: str, calls: int = 300) -> float:
    """CPU seconds of one Euler update of the fields on the paper's grid."""
    config = validate_config({"numerics": {"scheme": scheme}, "protocol": {"cycles": 0}})
    sim = Simulation(config)
    sim.run(50 * config.grid.dt)
    pde = sim.pde
    cur = sim.state.data.reshape(-1).copy()
    nxt = cur.copy()
    record = make_record(pde.setup)
    args = (cur, nxt, pde.F.reshape(-1), pde.G.reshape(-1), pde.domain.arrays(), record, 1.0)
    euler_fields(*args)
    start = time.thread_time()
    for _ in range(calls):
        euler_fields(*args)
    return (time.thread_time() - start) / calls


def fit_support(
    measured: dict[str, tuple[float, tuple[int, int]]], per_cell: float, what: str
) -> float:
    """The mean support cost per cell-step over the grids, given the interior cost, and
    each grid's step predicted by the two."""
    each = {
        name: (1e-3 * ms - interior * per_cell) / support
        for name, (ms, (interior, support)) in measured.items()
    }
    per_support = sum(each.values()) / len(each)
    print(f"fit, {what}: {per_support:.3g} s per support cell-step (mean of the grids)")
    for name, (ms, (interior, support)) in measured.items():
        predicted = 1e3 * (interior * per_cell + support * per_support)
        print(f"  {name:<7} predicted {predicted:.3f} ms/step, measured {ms:.3f}")
    return per_support


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=3000)
    parser.add_argument("--scheme", choices=["consistent", "paper"], default="consistent")
    args = parser.parse_args()
    measured = {
        name: ms_per_step(dx, dt, args.steps, args.scheme) for name, (dx, dt) in GRIDS.items()
    }
    for name, (ms, (interior, support)) in measured.items():
        print(f"{name:<7} {interior:6d} interior, {support:5d} support cells: {ms:.3f} ms/step")
    per_cell = euler_seconds(args.scheme) / measured["paper"][1][0]
    print(f"interior: {per_cell:.3g} s per cell-step (the Euler update on the paper's grid)")
    fit_support(measured, per_cell, "turning plate")
    now = SECONDS_PER_SUPPORT_CELL_STEP[args.scheme]
    print(f"pde_rotor.sweep.cost ({args.scheme}): {SECONDS_PER_CELL_STEP:.3g} and {now:.3g}")
    stopped = {
        name: ms_per_step(dx, dt, args.steps, args.scheme, stopped=True)
        for name, (dx, dt) in GRIDS.items()
    }
    for name, (ms, _) in stopped.items():
        ratio = ms / measured[name][0]
        print(f"{name:<7} stopped plate: {ms:.3f} ms/step, {ratio:.2f} of a turning one")
    fit_support(stopped, per_cell, "stopped plate")
    now = SECONDS_PER_STOPPED_SUPPORT_CELL_STEP[args.scheme]
    print(f"pde_rotor.sweep.cost ({args.scheme}), stopped plate: {now:.3g}")
    config = load_config(QUICKSTART, ["output.progress=false"])
    with_movie = run(config, "runs/bench_cost", movie=True, overwrite=True).wall_time
    without = run(config, "runs/bench_cost", movie=False, overwrite=True).wall_time
    frames = round(config.protocol.t_end / config.output.movie_interval) + 1
    print(f"movie: {(with_movie - without) / frames * 1e3:.0f} ms per frame ({frames} frames)")


if __name__ == "__main__":
    main()
