"""Benchmark of the fused solver against the same equations built from py-pde operators.

Prints, at the paper's resolution (dx = 0.025, dt = 1e-4: 242 x 242 cells, 45 244 of them
inside the disk of radius 3):

(a) ms/step of the fused kernel (pde_rotor.solver.rotor) with the ``paper`` scheme, single
    thread, full physics;
(b) ms/step of make_operator_stepper (benchmarks/operator_stepper.py), the equations
    composed from py-pde's compiled operators (grid.make_operator) with F and G
    evaluated on the whole grid;
their ratio, the largest relative difference of the two states after the same steps;
(c) ms/step of the fused kernel with the ``consistent`` scheme (numerics.scheme, the
    default) and its ratio to (a) against the goal 1.4: (a) and (c) are timed in turn,
    in --chunks chunks of their steps each, wall-clock and the thread's CPU time, and
    the ratio is the median of the chunks' ratios of CPU time, so that a change of the
    machine's load falls on both alike;
(d) for each scheme, ms per call of the parts of a step (the thread's CPU time, the
    least of PART_REPEATS rounds of --part-calls calls), each called alone (the
    compiled functions of pde_rotor.kernels): F and G at a new angle, the rotor integrals
    of Eq. (eq_motion) (with, for ``consistent``, the spline window of c and the contour
    torque), the Euler update of Eqs. (eqc), (eqv); then as the step calls them: the
    fused pass over the rows (F and G, the integrals' row sums, the Euler update and the
    spline's row pass), the same pass of a stopped plate (F and G kept), and for
    ``consistent`` the spline's columns with the contour nodes: where a step's time goes;
and the steady angular velocity omega(t = 8) without noise for each scheme (paper: ~176;
an independent implementation: 176.06) with its wall time, to four decimals and in full.
Every step runs on one thread (solver.threads: 1; benchmarks/bench_threads.py times more).

Run:  python benchmarks/bench_solver.py [--steps 4000] [--chunks 10] [--skip-steady]
      [--part-calls 300]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from operator_stepper import make_operator_stepper

from pde_rotor import RotorConfig, Simulation
from pde_rotor.kernels.cpu import contour_torque, euler_fields, rotor_integrals, sweep_rows
from pde_rotor.kernels.indicators import update_indicators
from pde_rotor.kernels.records import make_record
from pde_rotor.kernels.spline import spline_window

PART_REPEATS = 5
"""Rounds of calls per part in (d); the least is kept, which other processes delay least."""


def time_fused(sims: list[Simulation], n_steps: int, chunks: int) -> np.ndarray:
    """Seconds per step of each fused stepper, (2, chunks, len(sims)): wall-clock time
    and the CPU time of the calling thread (which runs every step on one thread, and
    which the machine's other processes delay less). The simulations advance in turn,
    n_steps / chunks steps each (after compilation and a warm-up)."""
    for sim in sims:
        sim.run(sim.t + 50 * sim.config.grid.dt)
    steps = max(1, n_steps // chunks)
    seconds = np.empty((2, chunks, len(sims)))
    for chunk in range(chunks):
        for k, sim in enumerate(sims):
            wall, cpu = time.perf_counter(), time.thread_time()
            sim.run(sim.t + steps * sim.config.grid.dt)
            seconds[0, chunk, k] = (time.perf_counter() - wall) / steps
            seconds[1, chunk, k] = (time.thread_time() - cpu) / steps
    return seconds


def time_operator(sim: Simulation, n_steps: int) -> tuple[float, float]:
    """Seconds per step of the py-pde operator stepper and its deviation from the fused one.

    Both start from the fused simulation's current state and advance `n_steps` steps.

    Returns:
        (seconds per step, max relative difference of the fields after the steps)
    """
    step = make_operator_stepper(sim.pde, sim.config.grid.dt)
    data = sim.state.data.copy()
    rotor = np.array([sim.rotor.phi, sim.rotor.omega])
    step(data.copy(), rotor.copy(), 1)  # compile
    start = time.perf_counter()
    step(data, rotor, n_steps)
    seconds = (time.perf_counter() - start) / n_steps
    sim.run(sim.t + n_steps * sim.config.grid.dt)
    scale = np.abs(sim.state.data).max(axis=(1, 2), keepdims=True)
    deviation = float(np.max(np.abs(data - sim.state.data) / scale))
    return seconds, deviation


def time_parts(sim: Simulation, calls: int) -> dict[str, float]:
    """ms per call of each compiled part of a step, on the state of `sim`."""
    pde, dom, scheme = sim.pde, sim.pde.domain, sim.pde.scheme
    F, G = pde.F.reshape(-1), pde.G.reshape(-1)
    tab = np.empty((4, pde.shape.n_corners))
    tables = scheme.kernel_tables()
    domain = dom.arrays()
    params = make_record(sim.setup)
    cur = sim.state.data.reshape(-1).copy()
    nxt = cur.copy()
    n = dom.coords.size
    coef = np.zeros(n * n)
    lo, hi = scheme.window
    angles = sim.rotor.phi + 1e-3 * np.arange(calls + 1)

    def timed(func) -> float:
        func(0)
        best = math.inf
        for _ in range(PART_REPEATS):
            start = time.thread_time()
            for k in range(1, calls + 1):
                func(k)
            best = min(best, time.thread_time() - start)
        return best / calls * 1e3

    sums = np.zeros((n, 3))
    pair_sums = np.zeros(tab.shape[1] * tables[0].shape[1])
    omega = sim.rotor.omega
    parts = {
        "F and G": timed(lambda k: update_indicators(F, G, domain, params, tab, tables, angles[k])),
        "rotor integrals": timed(
            lambda k: rotor_integrals(cur, F, domain, params, tab, tables, coef)
        ),
        "Euler update": timed(lambda k: euler_fields(cur, nxt, F, G, domain, params, omega)),
    }
    if scheme.contour:
        t_lo, t_hi = scheme.taps
        parts["of which spline window"] = timed(
            lambda k: spline_window(cur, coef, n, lo, hi, t_lo, t_hi)
        )
    bufs = (cur, nxt, F, G)
    parts["fused pass over rows"] = timed(
        lambda k: sweep_rows(bufs, domain, params, tables, (tab, True, omega), (coef, sums), 1)
    )
    parts["same, plate stopped"] = timed(
        lambda k: sweep_rows(bufs, domain, params, tables, (tab, False, omega), (coef, sums), 1)
    )
    if scheme.contour:
        parts["columns, contour nodes"] = timed(
            lambda k: contour_torque(coef, dom.coords, params, tab, tables, pair_sums, 1)
        )
    return parts


def main() -> None:
    """Run the benchmark and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20000, help="steps timed for (a), (c)")
    parser.add_argument("--chunks", type=int, default=10, help="turns of (a) and (c)")
    parser.add_argument("--operator-steps", type=int, default=200, help="steps timed for (b)")
    parser.add_argument("--skip-steady", action="store_true", help="skip the t = 8 run")
    parser.add_argument("--part-calls", type=int, default=300, help="calls timed per part (d)")
    args = parser.parse_args()

    config = RotorConfig.model_validate(
        {"protocol": {"cycles": 0}, "numerics": {"scheme": "paper"}, "solver": {"threads": 1}}
    )
    consistent = config.model_copy(
        update={"numerics": config.numerics.model_copy(update={"scheme": "consistent"})}
    )
    sim = Simulation(config)
    n = sim.pde.domain.grid.shape[0]
    print(f"grid {n} x {n} cells, {int(sim.pde.domain.interior_mask.sum())} inside the disk")
    seconds = time_fused([sim, Simulation(consistent)], args.steps, args.chunks)
    fused, fused_consistent = seconds[0].mean(axis=0)
    cpu, cpu_consistent = seconds[1].mean(axis=0)
    operator, deviation = time_operator(sim, args.operator_steps)
    print(f"(a) fused solver        : {fused * 1e3:8.4f} ms/step ({cpu * 1e3:.4f} CPU)")
    print(f"(b) py-pde operators    : {operator * 1e3:8.4f} ms/step")
    print(f"speed-up (b)/(a)        : {operator / fused:8.2f}x")
    print(f"max rel. difference a-b : {deviation:.2e} after {args.operator_steps} steps")
    print(
        f"(c) fused, consistent   : {fused_consistent * 1e3:8.4f} ms/step "
        f"({cpu_consistent * 1e3:.4f} CPU)"
    )
    ratios = seconds[1, :, 1] / seconds[1, :, 0]
    print(
        f"ratio (c)/(a)           : {np.median(ratios):8.2f} (goal <= 1.4; median of "
        f"{args.chunks} turns' CPU times, range {ratios.min():.2f}-{ratios.max():.2f}; "
        f"wall {np.median(seconds[0, :, 1] / seconds[0, :, 0]):.2f})"
    )
    for cfg in (config, consistent):
        part_sim = Simulation(cfg)
        part_sim.run(50 * cfg.grid.dt)
        for name, ms in time_parts(part_sim, args.part_calls).items():
            print(f"(d) {cfg.numerics.scheme:>10}, {name:<22}: {ms:8.4f} ms/call")
    if not args.skip_steady:
        for cfg in (config, consistent):
            sim = Simulation(cfg)
            start = time.perf_counter()
            sim.run(8.0)
            wall = time.perf_counter() - start
            per_step = wall / round(8.0 / cfg.grid.dt) * 1e3
            scheme = cfg.numerics.scheme
            print(f"omega(t=8), {scheme:>10} : {sim.rotor.omega:.4f} ({sim.rotor.omega!r})")
            print(f"wall time of that run   : {wall:.1f} s ({per_step:.4f} ms/step incl. compile)")


if __name__ == "__main__":
    main()
