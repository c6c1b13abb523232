"""Only wet cells cost: the step of a narrow annulus against the full box that bounds it.

The walled step walks each row's runs of wet cells (two across an annulus' hole), so a
vessel's step should cost in proportion to the cells it wets. A no-flux annulus R1 < r <
R2 whose area pi (R2^2 - R1^2) is `--fraction` of its bounding box (2 R2)^2 and the
no-flux tank |x|, |y| < R2 (the whole box, walls on the cell faces) run on the same grid
(half side R2, dx), each with one fixed camphor disk in the channel and the flow on; the
printed cost is the wall-clock time per step of the compiled bodies step (best of
`--repeat` calls of `--steps` steps each, after 50 steps that compile), and the ratio
annulus / box.

Run:  python benchmarks/vessel_cost.py [--outer 7.5] [--fraction 0.15] [--dx 0.025]
      [--steps 50] [--repeat 3]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.solver.bodies import make_bodies_stepper
from pde_rotor.solver.simulation import Simulation


def vessel_config(vessel: dict, outer: float, dx: float, start: float) -> RotorConfig:
    """One fixed camphor disk at (start, 0) in `vessel` on the grid of half side `outer`."""
    return RotorConfig.model_validate(
        {
            "grid": {"domain_radius": outer, "dx": dx, "dt": 1e-4, "vessel": vessel},
            "geometry": {"smoothing": dx / 2},
            "bodies": [
                {"name": "disk", "pills": [{}], "motion": {"kind": "fixed"}, "start": {"x": start}}
            ],
        }
    )


def step_cost(config: RotorConfig, steps: int, repeat: int) -> tuple[float, float]:
    """(seconds per step of the compiled bodies step, best of `repeat`; fraction of the
    grid's cells that are wet)."""
    sim = Simulation(config)
    sim.run(50 * config.grid.dt)  # compiles, and c spreads from the disk
    stepper = make_bodies_stepper(sim.pde, config.grid.dt, np.random.default_rng(0))
    data, bodies = sim.state.data, sim.bodies
    best = math.inf
    for r in range(repeat):
        begin = time.perf_counter()
        stepper(data, bodies, 50 + r * steps, steps)
        best = min(best, (time.perf_counter() - begin) / steps)
    cells = sim.pde.domain.cut_cells
    return best, float(cells.mask.mean())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--outer", type=float, default=7.5)
    parser.add_argument("--fraction", type=float, default=0.15)
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    outer = args.outer
    inner = outer * math.sqrt(1 - 4 * args.fraction / math.pi)
    middle = (inner + outer) / 2
    ring = {"shape": "annulus", "inner_radius": inner, "outer_radius": outer}
    box = {"shape": "rectangle", "half_widths": [outer, outer]}
    costs = {}
    for name, vessel in (("annulus", ring), ("box", box)):
        config = vessel_config(vessel, outer, args.dx, middle)
        costs[name], wet = step_cost(config, args.steps, args.repeat)
        print(
            f"{name}: {1e3 * costs[name]:.3f} ms per step, wet cells {100 * wet:.1f} % of the grid"
        )
    print(
        f"annulus {inner:.4g} < r < {outer:g} ({100 * args.fraction:g} % of its bounding box), "
        f"dx = {args.dx:g}: cost ratio annulus / box = {costs['annulus'] / costs['box']:.3f}"
    )


if __name__ == "__main__":
    main()
