"""The phases of the crowd's step, each in a compiled loop: ns per owned cell.

The 20 disks of ``bench_crowd.py`` (free camphor disks, rho = 0.1, the paper's grid),
run 5 steps; then each phase's kernel is called `steps` times in a compiled loop on that
state (so that no Python call is timed, unlike ``bench_crowd.py --profile``), in thread
CPU time, the least of 3 rounds: the drawing of every body (each nudged by 1e-7 along x
and back, so that it moves), the rows' runs, the area sums, the contour form
(``consistent``), and the field update over the bodies' runs against the same update
without bodies. Printed: ms per step and ns per owned cell (per interior cell for the
bare update).

``--footprint W`` draws the disks to ``numerics.footprint_widths`` = W (default 20) and
``--contour-nodes N`` sets ``numerics.contour_nodes`` (default 32: 4 N directions a circle).

Run:  NUMBA_NUM_THREADS=1 python benchmarks/crowd_phases.py [--scheme paper] [--steps 300]
      [--footprint 20] [--contour-nodes 32]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numba as nb
import numpy as np
from bench_crowd import config

from pde_rotor.kernels import body_draw, body_fields, body_sums
from pde_rotor.physics.motion import N_INTEGRALS
from pde_rotor.solver.bodies import make_bodies_stepper
from pde_rotor.solver.simulation import Simulation


@nb.njit
def _draw(steps, maps, domain, bodies, p, work):
    F, G, owner = maps
    pose = bodies[2]
    for s in range(steps):
        for k in range(bodies[0].shape[0]):
            body_draw.draw_body(F, G, owner, domain, k, bodies, p, work, True)
            pose[k, 0] += 1e-7 * (1 - 2 * (s % 2))


@nb.njit
def _segments(steps, bodies, chords, segments):
    for _ in range(steps):
        body_fields.body_segments(bodies, chords, segments)


@nb.njit
def _sums(steps, cur, F, coords, bodies, p, out):
    for _ in range(steps):
        for k in range(bodies[0][0].shape[0]):
            body_sums.body_integrals(cur, F, coords, k, bodies, p, out)


@nb.njit
def _contour(steps, cur, coords, bodies, p, out):
    for _ in range(steps):
        for k in range(bodies[0].shape[0]):
            body_sums.body_contour(cur, coords, k, bodies, p, out)


@nb.njit
def _fields(steps, states, maps, pose, domain, segments, coef, p):
    cur, nxt = states
    F, G = maps
    for _ in range(steps):
        body_fields.euler_body_fields(cur, nxt, F, G, pose, domain, segments, coef, p.dt, p.flow)


def phases(scheme: str, steps: int, numerics: dict) -> tuple[dict[str, float], int, int]:
    """ms per step of each phase, the owned and the interior cells; `numerics`: the
    crowd's ``numerics`` keys beside the scheme."""
    sim = Simulation(config(20, scheme, numerics))
    sim.run(sim.t + 5 * sim.config.grid.dt)
    pde = sim.pde
    step = make_bodies_stepper(pde, sim.config.grid.dt, np.random.default_rng(0))
    coords, lo, hi = pde.domain.arrays()[:3]
    n, count = coords.size, len(step._bodies)
    domain = (coords, lo, hi)
    cur = np.ascontiguousarray(sim.state.data).reshape(-1).copy()
    nxt = np.zeros_like(cur)
    F, G, owner = pde.F.reshape(-1), pde.G.reshape(-1), pde.owner.reshape(-1)
    pose = sim.bodies.poses.copy()
    pose[:, :2] -= pde.domain.centre
    p = step._record.view(np.recarray)[0]
    coef = body_fields._rate_coefficients(p)
    out = np.zeros(N_INTEGRALS)
    chords = np.zeros((2, count, n), np.int64)
    work = (np.empty((body_draw.SCRATCH_ROWS, n)), np.empty(n, np.uint64), chords,
            np.zeros((2, n), np.int64))  # fmt: skip
    bodies = (step._bodies, step._pills, pose, pose[:, :3].copy(), pde.box, step._normals,
              step._centres, step._tables)  # fmt: skip
    for k in range(count):
        body_draw.footprint_rows(coords, k, bodies, chords)
    segments = (np.zeros(n + 1, np.int64), np.zeros((3, count * n), np.int64))
    bare = (np.zeros(n + 1, np.int64), np.zeros((3, 0), np.int64))
    body_fields.body_segments(bodies, chords, segments)
    runs = segments[1][:, : segments[0][n]]
    owned = int((runs[1] - runs[0]).sum())

    def timed(kernel: Callable[..., None], *args: object) -> float:
        kernel(1, *args)
        best = np.inf
        for _ in range(3):
            start = time.thread_time()
            kernel(steps, *args)
            best = min(best, time.thread_time() - start)
        return 1e3 * best / steps

    result = {
        "drawing (F, G, owner, chords)": timed(_draw, (F, G, owner), domain, bodies, p, work),
        "rows' runs": timed(_segments, bodies, chords, segments),
        "area sums": timed(_sums, cur, F, coords, (bodies, chords), p, out),
    }
    if p.contour:
        result["contour form"] = timed(_contour, cur, coords, bodies, p, out)
    states, maps = (cur, nxt), (F, G)
    with_bodies = timed(_fields, states, maps, pose, domain, segments, coef, p)
    result["bare update"] = timed(_fields, states, maps, pose, domain, bare, coef, p)
    result["update's plate runs"] = with_bodies - result["bare update"]
    return result, owned, int((hi - lo).sum())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scheme", default="paper", choices=["paper", "consistent"])
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--footprint", type=float, default=20.0)
    parser.add_argument("--contour-nodes", type=int, default=32)
    args = parser.parse_args()
    numerics = {"footprint_widths": args.footprint, "contour_nodes": args.contour_nodes}
    result, owned, interior = phases(args.scheme, args.steps, numerics)
    print(f"{args.scheme}: {owned} owned cells ({owned / 20:.0f} a disk), {interior} interior")
    for phase, ms in result.items():
        cells = interior if phase == "bare update" else owned
        print(f"  {phase:30s} {ms:.4f} ms/step  {1e6 * ms / cells:.2f} ns a cell")


if __name__ == "__main__":
    main()
