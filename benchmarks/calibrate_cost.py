"""Calibrate the bodies' cost constants of :mod:`pde_rotor.sweep.cost` from measured steps.

Every case is built as a Simulation, stepped `--warm` steps (compiling the kernel the
first time), then `--repeats` rounds of `--steps` steps are timed in the stepping thread's
CPU time (on a shared machine the wall-clock time also counts other processes), and the
median round is kept. The cases:

* every config of configs/bodies/, with forward Euler and with Heun's method;
* runs of the crowd sweeps (configs/sweeps/crowd_dish.yaml: 30 disks, flow off and on;
  configs/sweeps/crowd_ring.yaml: 4, 6, 11 and 16 boats, flow off and on), with the
  integrator each sweep sets;
* the runs of ``benchmarks/bodies_cost.py --parts`` (single bodies in dishes of radius 2 to
  4, with and without flow and the no-flux wall, fixed, turning, held in a stop, moving;
  paper and consistent schemes), which separate the per-cell and per-body terms.

It then fits :data:`pde_rotor.sweep.cost.BODIES_STEP_COSTS` to them (non-negative least
squares of the relative errors, the terms of :func:`pde_rotor.sweep.cost.bodies_step_terms`
of each case, its bodies moving as in the timed steps) and prints, per case, the measured
ms/step, the estimate with the committed constants and with the fitted ones, and the fitted
constants in the form of cost.py; for each config and crowd run also the whole run's
estimate (`pde-rotor check`, the crowd sweeps' `--dry-run`) beside its measured step times
its steps. A key no case exercises keeps its committed value. Run with one thread, as the
estimates are of one core:

Run:  NUMBA_NUM_THREADS=1 python benchmarks/calibrate_cost.py [--steps 300] [--repeats 3]
      [--only NAME ...] [--no-parts]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from bodies_cost import HEXAGON, PARTS, part_config
from scipy.optimize import nnls

from pde_rotor import RotorConfig
from pde_rotor.config import load_config
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep import Sweep
from pde_rotor.sweep.cost import BODIES_STEP_COSTS, bodies_step_terms, estimate_run, steps

ROOT = Path(__file__).resolve().parents[1]
CROWDS = {
    "crowd_dish": [{"crowd.body.motion.friction": 0.2}],
    "crowd_ring": [
        {"crowd.count": count, "crowd.body.motion.friction": 0.05} for count in (4, 6, 11, 16)
    ],
}
"""The crowd sweeps and the coordinates of the runs timed (every value of the other axes):
the dish's 30 disks; the ring's 4 to 16 boats, which part the vessel's wet cells from the
boats' boxes."""
HELD_PART = {
    "hexagon held in a stop, L = 4, flow": (
        [{**HEXAGON, "protocol": {"t_ini": 0.0, "t_stop": 10.0, "t_release": 1.0, "cycles": 1}}],
        4.0,
        {},
    )
}
"""A turning body held from the start: its integrals without its redraw."""


def cases(parts: bool) -> dict[str, RotorConfig]:
    """Every case's config, by name."""
    found = {}
    for path in sorted((ROOT / "configs" / "bodies").glob("*.yaml")):
        config = load_config(path)
        for integrator in ("euler", "heun"):
            numerics = config.numerics.model_copy(update={"integrator": integrator})
            found[f"{path.stem}, {integrator}"] = config.model_copy(update={"numerics": numerics})
    for sweep_name, points in CROWDS.items():
        for run in Sweep.load(ROOT / "configs" / "sweeps" / f"{sweep_name}.yaml").runs():
            if any(all(run.coords[key] == value for key, value in coords.items())
                   for coords in points):  # fmt: skip
                flow = "flow" if run.coords["flow.enabled"] else "no flow"
                name = f"{sweep_name}, N = {len(run.config['bodies'])}, {flow}"
                found[name] = RotorConfig.model_validate(run.config)
    if parts:
        for name, (bodies, radius, extra) in {**PARTS, **HELD_PART}.items():
            found[f"part: {name}"] = part_config(bodies, radius, extra)
    return found


def moving_now(config: RotorConfig) -> list[float]:
    """Each body's moving share in the timed steps, at the start of the run: 0 if
    ``fixed`` or held by a stop of its own from t = 0, else 1."""
    shares = []
    for body in config.bodies or []:
        held = body.protocol is not None and body.protocol.t_ini == 0 and body.protocol.cycles
        shares.append(0.0 if body.motion.kind == "fixed" or held else 1.0)
    return shares


def ms_per_step(config: RotorConfig, warm: int, n_steps: int, repeats: int) -> float:
    """The median thread CPU time per step over `repeats` rounds of `n_steps`, after
    `warm` (a run that ends early keeps the rounds it finished)."""
    sim = Simulation(config.model_copy(update={"output": config.output.model_copy(
        update={"progress": False})}))  # fmt: skip
    dt = config.grid.dt
    sim.run(warm * dt)
    rounds = []
    for _ in range(repeats):
        start = time.thread_time()
        try:
            sim.run(sim.t + n_steps * dt)
        except RuntimeError as error:  # a body that left the dish or met another
            print(f"  (ended early: {error})")
            break
        rounds.append(1e3 * (time.thread_time() - start) / n_steps)
    return statistics.median(rounds) if rounds else float("nan")


def fit(rows: list[dict[str, float]], measured: list[float]) -> dict[str, float]:
    """BODIES_STEP_COSTS fitted to the cases: non-negative least squares of the relative
    errors; keys no case exercises keep their committed values."""
    keys = [key for key in BODIES_STEP_COSTS if any(row[key] for row in rows)]
    matrix = np.array([[row[key] for key in keys] for row in rows]) / np.array(measured)[:, None]
    scale = matrix.max(axis=0)
    solution, _ = nnls(matrix / scale, np.ones(len(rows)))
    fitted = dict(BODIES_STEP_COSTS)
    for key, value, size in zip(keys, solution, scale, strict=True):
        fitted[key] = 1e-3 * value / size
    return fitted


def estimate(terms: dict[str, float], costs: dict[str, float]) -> float:
    """ms per step of `terms` priced by `costs`."""
    return 1e3 * sum(costs[key] * count for key, count in terms.items())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--warm", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--only", nargs="*", help="cases whose names contain one of these")
    parser.add_argument("--no-parts", action="store_true", help="configs and crowds only")
    args = parser.parse_args()
    chosen = {
        name: config
        for name, config in cases(not args.no_parts).items()
        if not args.only or any(word in name for word in args.only)
    }
    names, rows, measured = [], [], []
    for name, config in chosen.items():
        ms = ms_per_step(config, args.warm, args.steps, args.repeats)
        print(f"measured {name}: {ms:.4f} ms/step", flush=True)
        if np.isfinite(ms):
            names.append(name)
            rows.append(bodies_step_terms(config, moving_now(config)))
            measured.append(ms)
    fitted = fit(rows, measured)
    print("\n| case | measured ms/step | committed estimate | ratio | fitted estimate | ratio |")
    print("|---|---|---|---|---|---|")
    for name, row, ms in zip(names, rows, measured, strict=True):
        old, new = estimate(row, BODIES_STEP_COSTS), estimate(row, fitted)
        print(f"| {name} | {ms:.4f} | {old:.4f} | {old / ms:.2f} | {new:.4f} | {new / ms:.2f} |")
    print("\nWhole runs (committed constants; measured: the timed step times the run's steps):")
    print("| case | steps | estimate s | measured step x steps, s | ratio |")
    print("|---|---|---|---|---|")
    for name, ms in zip(names, measured, strict=True):
        if name.startswith("part:"):
            continue
        config = chosen[name]
        n = steps(config.protocol.t_end, config)
        seconds = estimate_run(config, movie=False).seconds
        whole = ms * n / 1e3
        print(f"| {name} | {n} | {seconds:.1f} | {whole:.1f} | {seconds / whole:.2f} |")
    print("\nBODIES_STEP_COSTS fitted:")
    print("BODIES_STEP_COSTS: dict[str, float] = {")
    for key, value in fitted.items():
        print(f'    "{key}": {value:.3g},')
    print("}")


if __name__ == "__main__":
    main()
