"""Measure the constants of the cost estimate (pde_rotor.sweep.cost) on this machine.

Times the fused solver on the paper's grid (dx = delta = 0.025) and on the coarse grid
(dx = delta = 0.05) of a turning rotor, fits the cost per interior cell and per support
cell of one step to the two, checks the fit on a third grid (dx = delta = 1/30); times
a stopped plate on the same grids (F and G are not recomputed: only the rotor integrals
cost on the support cells) and fits its cost per support cell with the interior cost of
the turning fit; and times the movie frames of configs/quickstart.yaml.
pde_rotor/sweep/cost.py holds the constants fitted to the README's 0.29 ms/step on the paper's
grid and the coarse/paper ratio this script measures (0.44-0.50), and the stopped/turning
ratio it measures; a machine that is faster or slower scales them all.

Run:  python benchmarks/bench_cost.py [--steps 3000] [--scheme consistent|paper]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from pde_rotor import Simulation, run
from pde_rotor.config import load_config, validate_config
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
        }
    )
    sim = Simulation(config)
    sim.run(50 * dt)  # compile, or load the cached kernel
    start = time.perf_counter()
    sim.run(sim.t + n_steps * dt)
    return 1e3 * (time.perf_counter() - start) / n_steps, cell_counts(config)


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
    rows = [measured["paper"], measured["coarse"]]
    matrix = np.array([cells for _, cells in rows], dtype=float)
    per_cell, per_support = np.linalg.solve(matrix, [1e-3 * ms for ms, _ in rows])
    print(f"fit: {per_cell:.3g} s per interior cell-step, {per_support:.3g} s per support one")
    per_support_now = SECONDS_PER_SUPPORT_CELL_STEP[args.scheme]
    print(
        f"pde_rotor.sweep.cost ({args.scheme}): "
        f"{SECONDS_PER_CELL_STEP:.3g} and {per_support_now:.3g}"
    )
    ms, (interior, support) = measured["third"]
    predicted = 1e3 * (interior * per_cell + support * per_support)
    print(f"third grid: predicted {predicted:.3f} ms/step, measured {ms:.3f}")
    stopped = {
        name: ms_per_step(dx, dt, args.steps, args.scheme, stopped=True)[0]
        for name, (dx, dt) in GRIDS.items()
    }
    for name, ms in stopped.items():
        ratio = ms / measured[name][0]
        print(f"{name:<7} stopped plate: {ms:.3f} ms/step, {ratio:.2f} of a turning one")
    fit = [(measured[name][1], stopped[name]) for name in ("paper", "coarse")]
    per_stopped = sum((1e-3 * ms - i * per_cell) / s for (i, s), ms in fit) / len(fit)
    now = SECONDS_PER_STOPPED_SUPPORT_CELL_STEP[args.scheme]
    print(f"fit: {per_stopped:.3g} s per support cell-step of a stopped plate (now {now:.3g})")
    config = load_config(QUICKSTART, ["output.progress=false"])
    with_movie = run(config, "runs/bench_cost", movie=True, overwrite=True).wall_time
    without = run(config, "runs/bench_cost", movie=False, overwrite=True).wall_time
    frames = round(config.protocol.t_end / config.output.movie_interval) + 1
    print(f"movie: {(with_movie - without) / frames * 1e3:.0f} ms per frame ({frames} frames)")


if __name__ == "__main__":
    main()
