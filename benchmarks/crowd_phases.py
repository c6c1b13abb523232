"""The phases of the crowd's step, each in a compiled loop: ns per owned cell.

The 20 disks of ``bench_crowd.py`` (free camphor disks, rho = 0.1, the paper's grid), or
with ``--case sweep`` the ring sweep's 16 boats of ``bench_crowd.py --case sweep``
(`configs/sweeps/crowd_ring.yaml`, mu = 0.05, no flow, on the vessel's cut cells), run 5
steps; then each phase's kernel is called `steps` times in a compiled loop on that state
(so that no Python call is timed, unlike ``bench_crowd.py --profile``), in thread CPU
time, the least of 3 rounds: the drawing of every body (a disk nudged by 1e-7 along x
and back; a boat carried along its track by a sailing boat's arc a step, 14 dt, and
turned with it, so that each drawing frees and claims cells as the run's do), the rows'
runs, the area sums, the contour form (``consistent``: the spline window and the contour
nodes, each timed), the contact forces (with contact on), and the field update over the
bodies' runs against the same update without bodies (Eqs. (eqc), (eqv); on the cut
cells for the vessel). Printed: ms per step and ns per owned cell (per interior cell,
wet cell for the vessel, for the bare update); for the vessel also its implicit
clusters' share of the bare update (the bare update less the same update without them),
and the open update (no cut cells) on the rows of
the disk the vessel's grid covers, per cell.

``--footprint W`` draws the disks (the boats) to ``numerics.footprint_widths`` = W
(default 20) and ``--contour-nodes N`` sets ``numerics.contour_nodes`` (default 32: 4 N
directions a circle, N Gauss-Legendre nodes along each of a boat's four edges).

Run:  NUMBA_NUM_THREADS=1 python benchmarks/crowd_phases.py [--scheme paper] [--steps 300]
      [--case disks | sweep] [--footprint 20] [--contour-nodes 32]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numba as nb
import numpy as np
from bench_crowd import config, sweep_config

from pde_rotor.kernels import bodies as body_step
from pde_rotor.kernels import body_draw, body_fields, body_sums, wall
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
def _sail(steps, maps, domain, bodies, p, work, turn):
    F, G, owner = maps
    pose = bodies[2]
    c, s_ = np.cos(turn), np.sin(turn)
    for _ in range(steps):
        for k in range(bodies[0].shape[0]):
            body_draw.draw_body(F, G, owner, domain, k, bodies, p, work, True)
        for k in range(bodies[0].shape[0]):  # all boats on, so that none meets another
            x, y = pose[k, 0], pose[k, 1]
            pose[k, 0], pose[k, 1] = c * x - s_ * y, s_ * x + c * y
            pose[k, 2] += turn


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
def _windows(steps, cur, coords, bodies):
    body, pose, tables = bodies[0], bodies[2], bodies[7]
    n = coords.size
    for _ in range(steps):
        for k in range(body.shape[0]):
            bounds = body_sums.spline_bounds(pose[k, 0], pose[k, 1], body[k].window_half, coords)
            body_sums.spline_box(cur, tables[7], n, bounds[0], bounds[1], tables[8])


@nb.njit
def _contact(steps, body, pose, p, loads):
    for _ in range(steps):
        body_step._contact(body, pose, p, loads)


@nb.njit
def _fields(steps, states, maps, pose, domain, segments, coef, p):
    cur, nxt = states
    F, G = maps
    for _ in range(steps):
        body_fields.euler_body_fields(cur, nxt, F, G, pose, domain, segments, coef, p.dt, p.flow)


@nb.njit
def _walled(steps, states, maps, pose, domain, cells, coef, p, rhs):
    for _ in range(steps):
        wall.euler_walled_fields(states, maps, domain, cells, coef, p.dt, pose, p.flow, rhs)


SAIL = 14.0
"""A sailing boat's arc speed in the ring sweep (about 14.2 at mu = 0.05): the drawing's
boats move by SAIL dt a step."""


def phases(case: str, scheme: str, steps: int, numerics: dict) -> tuple[dict[str, float], int, int]:
    """ms per step of each phase of `case` (``disks`` or ``sweep``), the owned and the
    interior (wet) cells; `numerics`: the crowd's ``numerics`` keys beside the scheme."""
    grid = dict.fromkeys(("dx", "dt", "smoothing"))
    crowd = (
        sweep_config(16, scheme, grid, numerics)
        if case == "sweep"
        else config(20, scheme, numerics)
    )
    sim = Simulation(crowd)
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

    maps = (F, G, owner)
    if case == "sweep":
        radius = float(np.hypot(*pose[0, :2]))
        drawing = timed(_sail, maps, domain, bodies, p, work, SAIL * p.dt / radius)
    else:
        drawing = timed(_draw, maps, domain, bodies, p, work)
    body_fields.body_segments(bodies, chords, segments)
    result = {
        "drawing (F, G, owner, chords)": drawing,
        "rows' runs": timed(_segments, bodies, chords, segments),
        "area sums": timed(_sums, cur, F, coords, (bodies, chords), p, out),
    }
    if p.contour:
        result["spline window"] = timed(_windows, cur, coords, bodies)
        result["contour nodes"] = timed(_contour, cur, coords, bodies, p, out)
        result["contour nodes"] -= result["spline window"]
    if p.contact_range > 0.0:
        loads = np.zeros((count, body_step.N_LOADS))
        result["contact"] = timed(_contact, step._bodies, pose, p, loads)
    states = (cur, nxt)
    if case == "sweep":
        cells, rhs = step._wall, np.zeros(n * n)
        with_bodies = timed(_walled, states, (F, G, segments), pose, domain, cells, coef, p, rhs)
        result["bare update"] = timed(_walled, states, (F, G, bare), pose, domain, cells, coef,
                                      p, rhs)  # fmt: skip
        wet = int((cells[7] - cells[6]).sum())
        explicit = cells[:9] + wall.NO_WALL[9:]  # the same update without the clusters
        implicit = result["bare update"] - timed(
            _walled, states, (F, G, bare), pose, domain, explicit, coef, p, rhs
        )
        open_rows = timed(_fields, states, (F, G), pose, domain, bare, coef, p)
        print(f"the vessel's bare update: {implicit:.4f} ms/step its implicit clusters; the open "
              f"update of Eq. (eqc) on the disk's rows, no cut cells, {int((hi - lo).sum())} "
              f"cells: {open_rows:.4f} ms/step, {1e6 * open_rows / (hi - lo).sum():.2f} ns a "
              "cell")  # fmt: skip
    else:
        with_bodies = timed(_fields, states, (F, G), pose, domain, segments, coef, p)
        result["bare update"] = timed(_fields, states, (F, G), pose, domain, bare, coef, p)
        wet = int((hi - lo).sum())
    result["update's plate runs"] = with_bodies - result["bare update"]
    return result, owned, wet


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scheme", default="paper", choices=["paper", "consistent"])
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--case", default="disks", choices=["disks", "sweep"])
    parser.add_argument("--footprint", type=float, default=20.0)
    parser.add_argument("--contour-nodes", type=int, default=32)
    args = parser.parse_args()
    numerics = {"footprint_widths": args.footprint, "contour_nodes": args.contour_nodes}
    result, owned, interior = phases(args.case, args.scheme, args.steps, numerics)
    count, what = (16, "a boat") if args.case == "sweep" else (20, "a disk")
    print(f"{args.case}, {args.scheme}: {owned} owned cells ({owned / count:.0f} {what}), "
          f"{interior} {'wet' if args.case == 'sweep' else 'interior'}")  # fmt: skip
    total = sum(ms for phase, ms in result.items() if phase != "bare update")
    result["all the bodies' phases"] = total
    for phase, ms in result.items():
        cells = interior if phase == "bare update" else owned
        print(f"  {phase:30s} {ms:.4f} ms/step  {1e6 * ms / cells:.2f} ns a cell")


if __name__ == "__main__":
    main()
