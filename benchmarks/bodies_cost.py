"""Cost of bodies runs: the estimate of `pde-rotor check` against the measured step.

Each shipped bodies config (or those named) is built as a Simulation, stepped `--warm`
steps (compiling the kernel the first time), then `--steps` steps timed in the stepping
thread's CPU time (on a shared machine the wall-clock time also counts other processes).
Printed per config: the measured ms/step, the estimate's ms/step
(:func:`pde_rotor.sweep.cost.estimate_run` over its steps, the movie left out) and their
ratio. `check`'s estimates are for one idle core: run with NUMBA_NUM_THREADS=1.

With ``--parts``, instead the runs the constants of :mod:`pde_rotor.sweep.cost` come from
(paper grid dx = 0.025, dt = 1e-4, paper scheme unless named): one small fixed pill in a
dish of radius 2, 3 and 4, with and without flow, with the no-flux wall; the paper's
hexagon (two pills) turning at omega = 150, held fixed, twice; a free disk moving; the
hexagon and the pill on the consistent scheme.

Run:  NUMBA_NUM_THREADS=1 python benchmarks/bodies_cost.py [--steps 400] [--parts] [CONFIG ...]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pde_rotor import RotorConfig
from pde_rotor.config import load_config
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.cost import estimate_run

CONFIGS = ["two_rotors", "free_disk", "rotor_and_source", "disk_in_dish", "two_disk_rotor"]

PILL = {"plate": {"shape": "none"}, "pills": [{"radius": 0.1}], "motion": {"kind": "fixed"}}
HEXAGON = {
    "plate": {"shape": "polygon", "n_corners": 6, "radius": 0.5},
    "pills": [{"x": 0.167265, "y": 0.289711}, {"x": -0.334530, "y": 0.0}],
    "motion": {"kind": "fixed_axis"},
    "start": {"x": -1.5, "omega": 150.0},
}
HELD = {**HEXAGON, "motion": {"kind": "fixed"}, "start": {"x": -1.5}}
SECOND = {**HEXAGON, "start": {"x": 1.5, "omega": -150.0}}
DISK = {
    "plate": {"shape": "none"},
    "pills": [{"radius": 0.1}],
    "motion": {"kind": "free", "mass": 1e-3, "friction": 0.1},
    "start": {"x": 1.5, "velocity": [1.0, 0.0]},
}
NO_FLOW = {"flow": {"enabled": False}}
PARTS = {
    "pill, L = 4, flow": ([PILL], 4.0, {}),
    "pill, L = 2, flow": ([PILL], 2.0, {}),
    "pill, L = 4, no flow": ([PILL], 4.0, NO_FLOW),
    "pill, L = 3, no flow": ([PILL], 3.0, NO_FLOW),
    "pill, L = 2, no flow, no-flux wall": ([PILL], 2.0, {**NO_FLOW, "wall": "no_flux"}),
    "pill, L = 4, no flow, no-flux wall": ([PILL], 4.0, {**NO_FLOW, "wall": "no_flux"}),
    "hexagon turning, L = 4, flow": ([HEXAGON], 4.0, {}),
    "hexagon held fixed, L = 4, flow": ([HELD], 4.0, {}),
    "two hexagons turning, L = 4, flow": ([HEXAGON, SECOND], 4.0, {}),
    "free disk moving, L = 4, flow": ([DISK], 4.0, {}),
    "hexagon turning, L = 4, flow, consistent": ([HEXAGON], 4.0, {"scheme": "consistent"}),
    "pill, L = 4, flow, consistent": ([PILL], 4.0, {"scheme": "consistent"}),
}
"""The runs behind the constants: bodies, dish radius, and flow / wall / scheme."""


def part_config(bodies: list[dict], radius: float, extra: dict) -> RotorConfig:
    grid = {"dx": 0.025, "dt": 1e-4, "domain_radius": radius}
    if "wall" in extra:
        grid["wall"] = extra["wall"]
    return RotorConfig.model_validate(
        {
            "grid": grid,
            "numerics": {"scheme": extra.get("scheme", "paper")},
            "geometry": {"smoothing": 0.025},
            "flow": extra.get("flow", {"enabled": True}),
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "bodies": bodies,
        }
    )


def ms_per_step(cfg: RotorConfig, warm: int, steps: int, repeats: int) -> float:
    """The least thread CPU time per step over `repeats` rounds of `steps`, after `warm`."""
    sim = Simulation(cfg)
    dt = cfg.grid.dt
    sim.run(warm * dt)
    best = float("inf")
    for _ in range(repeats):
        start = time.thread_time()
        sim.run(sim.t + steps * dt)
        best = min(best, 1e3 * (time.thread_time() - start) / steps)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("configs", nargs="*", default=CONFIGS)
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--warm", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--parts", action="store_true", help="the runs behind the constants")
    args = parser.parse_args()
    if args.parts:
        print("| run | measured ms/step | estimate ms/step |")
        print("|---|---|---|")
        for name, (bodies, radius, extra) in PARTS.items():
            cfg = part_config(bodies, radius, extra)
            estimate = estimate_run(cfg, movie=False)
            measured = ms_per_step(cfg, args.warm, args.steps, args.repeats)
            guess = 1e3 * estimate.seconds / estimate.steps
            print(f"| {name} | {measured:.3f} | {guess:.3f} |", flush=True)
        return
    root = Path(__file__).resolve().parents[1] / "configs" / "bodies"
    print("| config | measured ms/step | estimate ms/step | estimate / measured |")
    print("|---|---|---|---|")
    for name in args.configs:
        cfg = load_config(root / f"{name}.yaml")
        estimate = estimate_run(cfg, movie=False)
        per_step = 1e3 * estimate.seconds / estimate.steps
        best = ms_per_step(cfg, args.warm, args.steps, args.repeats)
        print(f"| {name} | {best:.3f} | {per_step:.3f} | {per_step / best:.2f} |", flush=True)


if __name__ == "__main__":
    main()
