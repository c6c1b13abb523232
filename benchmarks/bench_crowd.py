"""Cost of a crowd: 20 small free camphor disks, or a ring of 16 boats, against the same
surface without bodies.

Twenty free disks (pill radius rho = 0.1, no plate, mass 1e-3, friction 1, so that they
stay slow: the friction relaxation rate mu pi rho^2 / m = 31 and a speed of order
|F| / (mu pi rho^2) ~ 0.02) spread over a dish of radius 4 on the paper's grid
(dx = 0.025, dt = 1e-4) on rings that keep them apart, one disk at the dish's centre, and the same
surface's field update without bodies (:func:`pde_rotor.kernels.body_fields.euler_body_fields`
with no body runs: Eqs. (eqc), (eqv) alone). Each is timed alternately with the others
(`--repeats` rounds, least kept) over `--steps` steps after a compiling warm-up, in CPU
time of the stepping thread; printed: ms/step of each and the ratios to the surface
without bodies (goal: 20 disks <= 1.5x), and each round's ratio of the crowd to the
surface without bodies (its spread: how much the machine's load moved the timing).
With `--profile`, the phases of the 20 disks' step per body
(``benchmarks/bench_bodies.py``'s profile: drawing, area integrals, spline window and
contour nodes, field update over the bodies' runs).

``--case ring``: 16 camphor boats (strip plates 0.6 x 0.3, one pill 0.05 ahead of the
centre, mass 0.05, friction 1, at rest, heading along the channel) evenly spaced on the
mid circle of an annular channel (``grid.vessel``, radii 4.3 and 6.5, both walls no-flux,
the paper's grid dx = 0.025), 2.12 apart so that their footprints (reach 1.03) do not
meet and stay 1.1 from each wall; one boat alone; and the same
vessel's field update without bodies
(:func:`pde_rotor.kernels.wall.euler_walled_fields` on its cut cells with no body runs);
goal: 16 boats <= 2x.

``--case sweep``: the ring sweep's own boats (`configs/sweeps/crowd_ring.yaml` at N = 16
and N = 1, mu = 0.05, flow off, or on with ``--flow on``, as the sweep runs both:
strips 0.3 x 0.15 on their track, contact on), on its grid
or on the one of ``--dx``, ``--smoothing``, ``--dt`` (the scheme: ``--scheme``), stepped by
forward Euler so that each step is one evaluation, as the vessel's field update it is
timed against (the sweep's Heun step is two of each).

``--footprint W ...`` (``--case disks`` or ``sweep``): the 20 disks' (the 16 boats')
crowd once per footprint ``numerics.footprint_widths`` = W (default: 20 alone, the
saturated footprint), all timed alternately in the same rounds against the one bare
surface (vessel); ``--contour-nodes N ...``
likewise for the consistent scheme's ``numerics.contour_nodes`` (a circle's arc nodes are
4 N).

Run:  NUMBA_NUM_THREADS=1 python benchmarks/bench_crowd.py [--steps 300] [--repeats 3]
      [--scheme paper consistent] [--case disks ring sweep] [--profile]
      [--dx DX --smoothing DELTA --dt DT] [--footprint 20 8 6] [--contour-nodes 32 16]
      [--flow on]
"""

from __future__ import annotations

import argparse
import math
import time
from functools import partial

import numpy as np
from bench_bodies import profile

from pde_rotor import RotorConfig
from pde_rotor.kernels import body_fields, wall
from pde_rotor.solver.bodies import make_bodies_stepper
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.plan import Sweep

SWEEP = "configs/sweeps/crowd_ring.yaml"

RINGS = [(0.0, 1), (1.25, 6), (2.6, 13)]
"""(radius, count) of the rings the 20 disks sit on: neighbours >= 1.2 apart (a disk's
footprint, pill and smoothing reach, is 0.6), 0.8 from the rim of the dish of radius 4."""


def disk(x: float, y: float) -> dict:
    """One small free camphor disk at (x, y), at rest."""
    return {
        "plate": {"shape": "none"},
        "pills": [{"radius": 0.1}],
        "motion": {"kind": "free", "mass": 1e-3, "inertia": 5e-6, "friction": 1.0},
        "start": {"x": x, "y": y},
    }


def places(count: int) -> list[tuple[float, float]]:
    """The first `count` places on :data:`RINGS`."""
    spots = [
        (r * math.cos(2 * math.pi * m / n), r * math.sin(2 * math.pi * m / n))
        for r, n in RINGS
        for m in range(n)
    ]
    return spots[:count]


def config(count: int, scheme: str, numerics: dict | None = None) -> RotorConfig:
    """`count` free disks on the paper's dish and grid, `scheme`, and the ``numerics``
    keys of `numerics` (e.g. ``footprint_widths``)."""
    bodies = [{**disk(x, y), "name": f"disk{k}"} for k, (x, y) in enumerate(places(count))]
    return RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 4.0, "dx": 0.025, "dt": 1e-4},
            "numerics": {"scheme": scheme, **(numerics or {})},
            "protocol": {"t_ini": 100.0, "cycles": 0},
            "bodies": bodies,
        }
    )


RING = (4.3, 6.5, 16)
"""Inner and outer radius of the annular channel, and the number of boats on its mid circle."""


def boat(angle: float, radius: float) -> dict:
    """One camphor boat at rest on the circle of `radius`, at polar `angle`, heading along
    the circle (counter-clockwise)."""
    return {
        "plate": {"shape": "strip", "length": 0.6, "width": 0.3},
        "pills": [{"x": 0.05, "y": 0.0}],
        "motion": {"kind": "free", "mass": 0.05, "inertia": 0.005, "friction": 1.0},
        "start": {
            "x": radius * math.cos(angle),
            "y": radius * math.sin(angle),
            "angle": angle + math.pi / 2,
        },
    }


def ring_config(count: int, scheme: str) -> RotorConfig:
    """`count` boats (of :data:`RING`'s number, in its places) in the annular channel."""
    inner, outer, boats = RING
    middle = 0.5 * (inner + outer)
    bodies = [{**boat(2 * math.pi * k / boats, middle), "name": f"boat{k}"} for k in range(count)]
    return RotorConfig.model_validate(
        {
            "grid": {
                "domain_radius": outer,
                "dx": 0.025,
                "dt": 1e-4,
                "vessel": {
                    "shape": "annulus",
                    "inner_radius": inner,
                    "outer_radius": outer,
                    "inner_wall": "no_flux",
                    "outer_wall": "no_flux",
                },
            },
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": 100.0, "cycles": 0},
            "bodies": bodies,
        }
    )


def sweep_config(
    count: int, scheme: str, grid: dict, numerics: dict | None = None, flow: bool = False
) -> RotorConfig:
    """The ring sweep's resolved config with `count` boats (mu = 0.05, the flow off unless
    `flow`), `scheme`, forward Euler, the grid's changes in `grid` (dx, dt, smoothing; None:
    the sweep's) and the ``numerics`` keys of `numerics` (e.g. ``footprint_widths``)."""
    overrides = [
        f"axes.crowd.count=[{count}]",
        "axes.crowd.body.motion.friction=[0.05]",
        f"axes.flow.enabled=[{str(flow).lower()}]",
    ]
    data = Sweep.load(SWEEP, overrides).runs()[0].config
    data["numerics"].update(scheme=scheme, integrator="euler", **(numerics or {}))
    for key in ("dx", "dt"):
        if grid[key] is not None:
            data["grid"][key] = grid[key]
    if grid["smoothing"] is not None:
        data["geometry"]["smoothing"] = grid["smoothing"]
    data["protocol"] = {"t_ini": 100.0, "cycles": 0}
    return RotorConfig.model_validate(data)


def ms_per_step(sim: Simulation, steps: int) -> float:
    """Milliseconds of the thread's CPU time per step over `steps` steps of `sim`."""
    start = time.thread_time()
    sim.run(sim.t + steps * sim.config.grid.dt)
    return 1e3 * (time.thread_time() - start) / steps


def bare_surface(sim: Simulation):
    """A timer of the field update of `sim`'s surface without bodies: returns
    ms_per_step(steps), the thread CPU time of `steps` updates."""
    pde = sim.pde
    step = make_bodies_stepper(pde, sim.config.grid.dt, np.random.default_rng(0))
    p = step._record.view(np.recarray)[0]
    domain = pde.domain.arrays()[:3]
    runs = (np.zeros(domain[0].size + 1, np.int64), np.zeros((3, 0), np.int64))
    cur = np.ascontiguousarray(sim.state.data).reshape(-1).copy()
    nxt = np.zeros_like(cur)
    F, G = pde.F.reshape(-1), pde.G.reshape(-1)
    pose = sim.bodies.poses.copy()
    coef = body_fields._rate_coefficients(p)

    def timer(steps: int) -> float:
        nonlocal cur, nxt
        start = time.thread_time()
        for _ in range(steps):
            body_fields.euler_body_fields(cur, nxt, F, G, pose, domain, runs, coef, p.dt, p.flow)
            cur, nxt = nxt, cur
        return 1e3 * (time.thread_time() - start) / steps

    return timer


def bare_vessel(sim: Simulation):
    """A timer of the field update of `sim`'s vessel without bodies (its cut cells, no body
    rows), as :func:`bare_surface`."""
    pde = sim.pde
    step = make_bodies_stepper(pde, sim.config.grid.dt, np.random.default_rng(0))
    p = step._record.view(np.recarray)[0]
    domain = pde.domain.arrays()[:3]
    n = domain[0].size
    maps = (
        pde.F.reshape(-1),
        pde.G.reshape(-1),
        (np.zeros(n + 1, np.int64), np.zeros((3, 0), np.int64)),
    )
    cur = np.ascontiguousarray(sim.state.data).reshape(-1).copy()
    nxt = np.zeros_like(cur)
    rhs = np.zeros(n * n)
    pose = sim.bodies.poses.copy()
    coef = body_fields._rate_coefficients(p)
    cells = step._wall

    def timer(steps: int) -> float:
        nonlocal cur, nxt
        start = time.thread_time()
        for _ in range(steps):
            wall.euler_walled_fields((cur, nxt), maps, domain, cells, coef, p.dt, pose, p.flow, rhs)
            cur, nxt = nxt, cur
        return 1e3 * (time.thread_time() - start) / steps

    return timer


def footprint_cases(
    case: str, scheme: str, grid: dict, widths: list[float], nodes: list[int], flow: bool
) -> tuple[dict, Simulation]:
    """The timers of the crowd of `case` (``disks``: 20 disks, ``sweep``: the ring sweep's
    16 boats) at each footprint in `widths` and (``consistent``) each contour node count in
    `nodes`, one body at the first, and the bare surface or vessel; and the first crowd's
    run. `flow`: the sweep's boats with the flow on."""
    if case == "sweep":
        count, what, bare = 16, "boats", bare_vessel
        make = lambda k, numerics: sweep_config(k, scheme, grid, numerics, flow)  # noqa: E731
    else:
        count, what, bare = 20, "disks", bare_surface
        make = lambda k, numerics: config(k, scheme, numerics)  # noqa: E731
    runs = {}
    crowds = []
    for w in widths:
        for n in nodes if scheme == "consistent" else nodes[:1]:
            label = f"{count} {what} w={w:g}" + (f" N={n}" if scheme == "consistent" else "")
            crowds.append(Simulation(make(count, {"footprint_widths": w, "contour_nodes": n})))
            runs[label] = partial(ms_per_step, crowds[-1])
    one = Simulation(make(1, {"footprint_widths": widths[0], "contour_nodes": nodes[0]}))
    runs[f"1 {what[:-1]}"] = partial(ms_per_step, one)
    runs["no bodies"] = bare(one)
    return runs, crowds[0]


def cases(case: str, scheme: str, grid: dict, flow: bool) -> tuple[dict, Simulation]:
    """The timers of `case` (``disks``, ``ring`` or ``sweep``) on `scheme`, and the crowd's
    run. `flow`: the sweep's boats with the flow on."""
    if case == "sweep":
        crowd = Simulation(sweep_config(16, scheme, grid, flow=flow))
        one = Simulation(sweep_config(1, scheme, grid, flow=flow))
        names, bare = ("16 boats", "1 boat", "no bodies"), bare_vessel(one)
    elif case == "disks":
        crowd, one = Simulation(config(20, scheme)), Simulation(config(1, scheme))
        names, bare = ("20 disks", "1 disk", "no bodies"), bare_surface(one)
    else:
        crowd, one = Simulation(ring_config(RING[2], scheme)), Simulation(ring_config(1, scheme))
        names, bare = ("16 boats", "1 boat", "no bodies"), bare_vessel(one)
    runs = dict(
        zip(names, (partial(ms_per_step, crowd), partial(ms_per_step, one), bare), strict=True)
    )
    return runs, crowd


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--scheme", nargs="+", default=["paper", "consistent"])
    parser.add_argument("--case", nargs="+", default=["disks"], choices=["disks", "ring", "sweep"])
    parser.add_argument("--dx", type=float, help="--case sweep: grid.dx")
    parser.add_argument("--dt", type=float, help="--case sweep: grid.dt")
    parser.add_argument("--smoothing", type=float, help="--case sweep: delta")
    parser.add_argument("--profile", action="store_true", help="phases of the crowd's step")
    parser.add_argument(
        "--flow", choices=["off", "on"], default="off", help="--case sweep: flow.enabled"
    )
    parser.add_argument(
        "--footprint", type=float, nargs="+", help="--case disks, sweep: numerics.footprint_widths"
    )
    parser.add_argument(
        "--contour-nodes", type=int, nargs="+", default=[32], help="numerics.contour_nodes"
    )
    args = parser.parse_args()
    for case in args.case:
        for scheme in args.scheme:
            grid = {"dx": args.dx, "dt": args.dt, "smoothing": args.smoothing}
            if case != "ring" and args.footprint:
                runs, crowd = footprint_cases(
                    case, scheme, grid, args.footprint, args.contour_nodes, args.flow == "on"
                )
            else:
                runs, crowd = cases(case, scheme, grid, args.flow == "on")
            for run in runs.values():
                run(20)  # compile and warm up
            rounds = {name: [] for name in runs}
            for _ in range(args.repeats):
                for name, run in runs.items():
                    rounds[name].append(run(args.steps))
            best = {name: min(times) for name, times in rounds.items()}
            base = best["no bodies"]
            many = next(iter(best))
            cells = crowd.pde.domain.coords.size
            goal = 1.5 if case == "disks" else 2.0
            print(f"{case}: {cells}^2 cells, {scheme} scheme, thread CPU time")
            for name, ms in best.items():
                print(f"{name:>9}: {ms:.4f} ms/step, {ms / base:.3f} x the surface without bodies")
            for name in [name for name in best if name.startswith(("20 disks", "16 boats w="))] or [
                many
            ]:
                print(f"ratio {name} / no bodies = {best[name] / base:.3f} (goal <= {goal})")
                each = np.array(rounds[name]) / np.array(rounds["no bodies"])
                print(
                    f"  each round's ratio: {', '.join(f'{r:.3f}' for r in each)} (median "
                    f"{np.median(each):.3f}, spread {each.min():.3f} .. {each.max():.3f})"
                )
            if args.profile:
                print(f"phases of the {many}' step, ms per body ({scheme} scheme, thread CPU)")
                for phase, ms in profile(crowd, args.steps).items():
                    print(f"  {phase:36s} {ms:.4f}")


if __name__ == "__main__":
    main()
