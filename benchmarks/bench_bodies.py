"""Cost of K bodies: ms per step of the bodies' step with 1, 2, 3 and 4 rotors on one dish.

The paper's hexagon rotor (as a ``fixed_axis`` body, turning at omega = 150) placed 1, 2, 3
or 4 times on a dish of radius 4 at the paper's grid (dx = 0.025, dt = 1e-4), one thread,
each `--scheme` (both by default). Each count is timed alternately with the others
(`--repeats` rounds, minimum kept) over `--steps` steps after a warm-up, in CPU time of the
stepping thread (on a shared machine the wall-clock time also counts other processes);
printed: ms/step, its ratio to one body's step and the goal 1 + 0.3 K for K bodies.
With `--profile`, also the phases of the step (:func:`pde_rotor.kernels.bodies.advance_bodies`)
timed one by one on the four-body run, in ms per body: the redraw of F, G and the
owner map (filtered for ``consistent``), the spline window and the contour nodes
(``consistent``), the area integrals, and the field update's cost per body over the
body-free update.

Run:  NUMBA_NUM_THREADS=1 python benchmarks/bench_bodies.py [--steps 400] [--repeats 3]
      [--scheme paper consistent] [--profile]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.kernels import body_draw, body_fields, body_sums
from pde_rotor.physics.motion import N_INTEGRALS
from pde_rotor.solver.bodies import make_bodies_stepper
from pde_rotor.solver.simulation import Simulation

PLACES = [(-1.5, -1.5), (1.5, 1.5), (-1.5, 1.5), (1.5, -1.5)]
"""Axes of the rotors: footprints (radius 1.077) apart and inside the dish."""


def config(count: int, scheme: str) -> RotorConfig:
    """`count` paper rotors as bodies on a dish of radius 4, paper grid, `scheme`."""
    rotor = RotorConfig().body_list()[0].model_dump()
    bodies = []
    for k, (x, y) in enumerate(PLACES[:count]):
        body = {**rotor, "name": f"rotor{k}", "protocol": None}
        body["start"] = {**rotor["start"], "x": x, "y": y, "omega": 150.0}
        bodies.append(body)
    return RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 4.0},
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": 100.0, "cycles": 0},
            "bodies": bodies,
        }
    )


def ms_per_step(sim: Simulation, steps: int) -> float:
    """Milliseconds of the thread's CPU time per step, over `steps` steps from the
    simulation's time."""
    dt = sim.config.grid.dt
    start = time.thread_time()
    sim.run(sim.t + steps * dt)
    return 1e3 * (time.thread_time() - start) / steps


def profile(sim: Simulation, steps: int) -> dict[str, float]:
    """ms per body of each phase of the bodies' step of `sim` (see the module docstring).

    The step's kernels called one by one from here, in the step's order, on the run's
    arrays, the bodies turning by a step's angle each step, each call timed in the thread's
    CPU time (so that each phase meets the caches as the step leaves them). The spline
    window is timed once more on its own (the contour's time is the rest of
    ``body_contour``'s), and the field update once more without bodies (the base).
    """
    pde = sim.pde
    step = make_bodies_stepper(pde, sim.config.grid.dt, np.random.default_rng(0))
    record, body, pills, tables = step._record, step._bodies, step._pills, step._tables
    coords, lo, hi, _, _ = pde.domain.arrays()
    n = coords.size
    domain = (coords, lo, hi)
    cur = np.ascontiguousarray(sim.state.data).reshape(-1).copy()
    nxt = np.zeros_like(cur)
    F, G, owner = pde.F.reshape(-1), pde.G.reshape(-1), pde.owner.reshape(-1)
    pose = sim.bodies.poses.copy()
    pose[:, :2] -= pde.domain.centre
    box, normals, centres = pde.box, step._normals, step._centres
    p = record.view(np.recarray)[0]
    rates = body_fields._rate_coefficients(p)
    count = len(body)
    out = np.zeros(N_INTEGRALS)
    chords = np.zeros((2, len(body), n), np.int64)
    work = (np.empty((body_draw.SCRATCH_ROWS, n)), np.empty(n, np.uint64), chords,
            np.zeros((2, n), np.int64))  # fmt: skip
    bodies = (body, pills, pose, pose[:, :3].copy(), box, normals, centres, tables)
    for k in range(len(body)):
        body_draw.footprint_rows(coords, k, bodies, chords)
    segments = (np.zeros(n + 1, np.int64), np.zeros((3, count * n), np.int64))
    bare = (np.zeros(n + 1, np.int64), np.zeros((3, 0), np.int64))
    times = dict.fromkeys(
        ["draw (F, G, owner)", "area integrals", "spline window",
         "contour nodes", "field update over the bodies' runs"], 0.0
    )  # fmt: skip

    def timed(phase: str, kernel: Callable[..., object], *args: object) -> None:
        start = time.thread_time()
        kernel(*args)
        times[phase] += time.thread_time() - start

    base = 0.0
    for _ in range(steps):
        pose[:, 2] += pose[:, 5] * sim.config.grid.dt
        for k in range(count):
            timed("draw (F, G, owner)", body_draw.draw_body, F, G, owner, domain, k, bodies,
                  p, work, False)  # fmt: skip
        body_fields.body_segments(bodies, chords, segments)
        for k in range(count):
            timed("area integrals", body_sums.body_integrals, cur, F, coords, k,
                  (bodies, chords), p, out)  # fmt: skip
            if p.contour:
                half = int(body[k]["window_half"])
                window, taps = body_sums.spline_bounds(pose[k, 0], pose[k, 1], half, coords)
                timed("spline window", body_sums.spline_box, cur, tables[7], n, window, taps,
                      tables[8])  # fmt: skip
                timed("contour nodes", body_sums.body_contour, cur, coords, k, bodies, p,
                      out)  # fmt: skip
        timed("field update over the bodies' runs", body_fields.euler_body_fields, cur, nxt,
              F, G, pose, domain, segments, rates, p.dt, p.flow)  # fmt: skip
        start = time.thread_time()
        body_fields.euler_body_fields(cur, nxt, F, G, pose, domain, bare, rates, p.dt,
                                      p.flow)  # fmt: skip
        base += time.thread_time() - start
        cur, nxt = nxt, cur
    times["contour nodes"] -= times["spline window"]
    times["field update over the bodies' runs"] -= base
    result = {phase: 1e3 * t / steps / count for phase, t in times.items() if t != 0.0}
    result["per body, all phases"] = sum(result.values())
    result["field update without bodies (base)"] = 1e3 * base / steps
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--scheme", nargs="+", default=["paper", "consistent"])
    parser.add_argument("--profile", action="store_true", help="time each phase per body")
    args = parser.parse_args()
    for scheme in args.scheme:
        sims = {k: Simulation(config(k, scheme)) for k in (1, 2, 3, 4)}
        for sim in sims.values():
            ms_per_step(sim, 20)  # compile and warm up
        best = {k: float("inf") for k in sims}
        for _ in range(args.repeats):
            for k, sim in sims.items():
                best[k] = min(best[k], ms_per_step(sim, args.steps))
        one = best[1]
        cells = sims[1].pde.domain.coords.size
        print(f"paper grid, dish L = 4 ({cells}^2 cells), {scheme} scheme, thread CPU time")
        for k, ms in best.items():
            print(
                f"K = {k}: {ms:.3f} ms/step, {ms / one:.2f} x one body's step "
                f"(goal 1 + 0.3 K = {1 + 0.3 * k:.1f})"
            )
        if args.profile:
            print(f"phases of the step, ms per body (K = 4, {scheme} scheme, thread CPU time)")
            for phase, ms in profile(sims[4], args.steps).items():
                print(f"  {phase:36s} {ms:.4f}")


if __name__ == "__main__":
    main()
