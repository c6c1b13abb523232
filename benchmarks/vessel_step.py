"""The vessel's cut-cell step without bodies: ms per step, ns per wet cell, and what a
narrow annulus costs against the full box.

Three no-flux vessels on the ring sweep's grid (dx = 0.05, 226 x 226 cells, dt = 4e-4):
the sweep's annulus 3.6 < r < 5.6 (``configs/sweeps/crowd_ring.yaml``), a narrow annulus
5.09 < r < 5.6 that wets about 15 % of its bounding box, and a square tank filling that
box; and the dish r < 5.6 behind a no-flux wall (``grid.wall: no_flux``). Each is
:func:`pde_rotor.kernels.wall.euler_walled_fields` (Eqs. (eqc), (eqv) on the cut cells, its
implicit clusters included) called `steps` times in a compiled loop on a positive c and a
random v, flow off and on, thread CPU time, the least of `rounds`, and with the flow on its
ratio to the step without flow; for scale, the same for the open update of the dish behind
the paper's absorbing wall (:func:`pde_rotor.kernels.body_fields.euler_body_fields`, no
apertures, no implicit clusters).
With ``--against PATH`` the same loop also runs the ``wall.py`` at PATH (another
checkout's, loaded as a sibling module so that it compiles against this checkout's
physics), the two timed in turn in each round; set ``NUMBA_CACHE_DIR`` to a scratch
folder so that no cache is written beside PATH. Where that kernel takes its implicit
clusters in another form, ``--against-model MODEL`` names the other checkout's
``pde_rotor/model/wall.py`` (loaded the same way), whose ``implicit_blocks`` then gives
the last four arrays of the `wall` the other kernel takes. ``--split`` also times each
kernel's step with its implicit clusters emptied (its ``NO_WALL``'s) and prints the
clusters' part, the difference. ``--agree STEPS`` steps both kernels STEPS times from the
same state and prints the largest difference in c, relative to the largest c.
``--alone`` also times this checkout's clusters outside the step, each in a compiled loop
on the state one step left: the gather of kappa c' onto their cells (``cluster_rhs``, the
flow-on step's) and their solve (``implicit_clusters``, less the copy that restores its
right-hand side each time), so that their cost in the step can be told from their own.

Run:  NUMBA_NUM_THREADS=1 python benchmarks/vessel_step.py [--steps 100] [--rounds 3]
      [--against /path/to/other/pde_rotor/kernels/wall.py
       [--against-model /path/to/other/pde_rotor/model/wall.py] [--agree 1000]] [--split]
      [--alone]
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys
import time
from types import ModuleType

import numba as nb
import numpy as np

from pde_rotor.config.vessel import AnnulusVessel, RectangleVessel
from pde_rotor.kernels import wall
from pde_rotor.kernels.body_fields import euler_body_fields
from pde_rotor.model.geometry import support_rows
from pde_rotor.model.vessel import make_vessel_cells
from pde_rotor.model.wall import CutCells, make_cut_cells

DX, DT, N = 0.05, 4.0e-4, 226
VESSELS = {
    "ring sweep's annulus 3.6 < r < 5.6": AnnulusVessel(
        shape="annulus", inner_radius=3.6, outer_radius=5.6
    ),
    "narrow annulus 5.09 < r < 5.6": AnnulusVessel(
        shape="annulus", inner_radius=5.09, outer_radius=5.6
    ),
    "full box |x|, |y| < 5.6": RectangleVessel(shape="rectangle", half_widths=(5.6, 5.6)),
}
DISH = "dish r < 5.6"
COEF = (1.0 / DX**2, 0.5 / DX, 1.0, 1.0, 10.0, 1.0, 0.1, 0.5)
"""The rates' coefficients (1/dx^2, 1/(2 dx), D, a, source, eta, eta_b, D_eta)."""


def load_wall(path: str, package: str = "kernels") -> ModuleType:
    """The ``wall.py`` at `path` as a module of this checkout's `package`."""
    spec = importlib.util.spec_from_file_location(f"pde_rotor.{package}.wall_against", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # numba's cache finds the module by its name
    spec.loader.exec_module(module)
    return module


def vessel_cells(coords: np.ndarray, name: str) -> tuple[CutCells, float]:
    """The cut cells of the vessel (or dish) `name` and the half width of its box."""
    if name == DISH:
        return make_cut_cells(coords, 5.6), 5.6
    vessel = VESSELS[name]
    return make_vessel_cells(coords, vessel), vessel.extent()


def compiled_loop(module: ModuleType):
    """`steps` calls of `module`'s walled step, compiled as one loop."""
    step = module.euler_walled_fields

    @nb.njit
    def run(steps, states, maps, domain, cells, coef, dt, pose, flow, rhs):
        for _ in range(steps):
            step(states, maps, domain, cells, coef, dt, pose, flow, rhs)

    return run


def step_difference(loops: dict, state: tuple) -> str:
    """The largest difference of c, v_x and v_y after one step of each loop from the same
    state, relative to the largest magnitude of the field after the ``--against`` step."""
    bare, domain, arrays, coef, dt, pose, flow, cur = state
    after = {}
    for key in ("against", "this"):
        nxt = np.zeros_like(cur)
        loops[key](1, (cur, nxt), bare, domain, arrays[key], coef, dt, pose, flow, np.zeros(N * N))
        after[key] = nxt.reshape(3, -1)
    scale = np.abs(after["against"]).max(axis=1)
    worst = np.abs(after["this"] - after["against"]).max(axis=1) / np.where(scale > 0, scale, 1)
    fields = zip(("c", "v_x", "v_y"), worst, strict=True)
    return ", ".join(f"{field} {d:.1e}" for field, d in fields)


@nb.njit
def open_loop(steps, states, fields, pose, domain, segments, coef, dt, flow):
    """`steps` open updates of the dish (absorbing wall) without bodies."""
    cur, nxt = states
    for _ in range(steps):
        euler_body_fields(cur, nxt, fields, fields, pose, domain, segments, coef, dt, flow)


@nb.njit
def gather_loop(steps, nxt, rhs, volume, index):
    """`steps` gathers of kappa c' onto the clusters' cells (``cluster_rhs``)."""
    for _ in range(steps):
        wall.cluster_rhs(nxt, rhs, volume, index)


@nb.njit
def solve_loop(steps, nxt, rhs, index, factor, start, solve):
    """`steps` restores of `rhs` from `start`, each followed (with `solve`) by the
    clusters' solve (``implicit_clusters``)."""
    for _ in range(steps):
        rhs[:] = start
        if solve:
            wall.implicit_clusters(nxt, rhs, index, factor)


def time_alone(walls: tuple, state: tuple, steps: int, rounds: int) -> str:
    """The clusters' gather and solve outside the step, ms (least of `rounds`), on the
    fields and right-hand side one step of `state` = (bare, domain, flow, cur) leaves."""
    bare, domain, flow, cur = state
    nxt, rhs = np.zeros_like(cur), np.zeros(N * N)
    wall.euler_walled_fields(
        (cur, nxt), bare, domain, walls, COEF, DT, np.zeros((0, 13)), flow, rhs
    )
    volume, index, factor = walls[0], walls[9], walls[11]
    times = {"gather": [], "solve": []}
    for _ in range(rounds + 1):  # the first round compiles and warms
        clocks = []
        for run in (
            lambda: gather_loop(steps, nxt.copy(), rhs.copy(), volume, index),
            lambda: solve_loop(steps, nxt.copy(), rhs.copy(), index, factor, rhs, True),
            lambda: solve_loop(steps, nxt.copy(), rhs.copy(), index, factor, rhs, False),
        ):
            start = time.thread_time()
            run()
            clocks.append(1e3 * (time.thread_time() - start) / steps)
        times["gather"].append(clocks[0])
        times["solve"].append(clocks[1] - clocks[2])
    gather, solve = (min(times[key][1:]) for key in ("gather", "solve"))
    return f" alone ({index.shape[0]} rows): gather {gather:.4f} ms, solve {solve:.4f} ms;"


def time_open(coords: np.ndarray, steps: int, rounds: int, rng: np.random.Generator) -> None:
    """Print the open update's ms per step on the dish r < 5.6, flow off and on."""
    lo, hi = support_rows(coords, 5.6)
    domain, cells = (coords, lo, hi), int((hi - lo).sum())
    inside = np.zeros((N, N), bool)
    for i in range(N):
        inside[i, lo[i] : hi[i]] = True
    fields = np.concatenate([1.0 + rng.random(N * N), 0.1 * rng.normal(size=2 * N * N)])
    cur = fields * np.tile(inside.reshape(-1), 3)
    empty, pose = np.zeros(N * N), np.zeros((0, 13))
    segments = (np.zeros(N + 1, np.int64), np.zeros((3, 0), np.int64))
    least = {}
    for flow in (False, True):
        times = []
        for _ in range(rounds + 1):  # the first round compiles and warms
            states = (cur, np.zeros_like(cur))
            start = time.thread_time()
            open_loop(steps, states, empty, pose, domain, segments, COEF, DT, flow)
            times.append(1e3 * (time.thread_time() - start) / steps)
        least[flow] = best = min(times[1:])
        print(f"open update of the {DISH}, {cells} cells, flow {flow}: {best:.4f} ms", flush=True)
    a, b = least[True], least[False]
    print(f"open update of the {DISH}: flow on / off = {a:.4f} / {b:.4f} = {a / b:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--against", help="another checkout's pde_rotor/kernels/wall.py")
    parser.add_argument(
        "--against-model", help="the same checkout's pde_rotor/model/wall.py (its clusters)"
    )
    parser.add_argument(
        "--split", action="store_true", help="also time each step without its implicit clusters"
    )
    parser.add_argument(
        "--alone", action="store_true", help="also time the clusters outside the step"
    )
    parser.add_argument(
        "--agree", type=int, default=0, help="steps after which to compare c with --against's"
    )
    args = parser.parse_args()
    if args.against_model and not args.against:
        parser.error("--against-model needs --against")
    if args.agree and not args.against:
        parser.error("--agree needs --against")
    modules = {"this": wall}
    if args.against:
        modules = {"against": load_wall(args.against), **modules}
    loops = {key: compiled_loop(module) for key, module in modules.items()}
    if args.split:  # the same loop, the clusters emptied: what is left is the explicit part
        loops.update({f"{key} without clusters": loops[key] for key in modules})
    model = load_wall(args.against_model, "model") if args.against_model else None
    coords = (np.arange(N) - (N - 1) / 2) * DX
    rng = np.random.default_rng(0)
    empty = np.zeros(N * N)
    bare = (empty, empty, (np.zeros(N + 1, np.int64), np.zeros((3, 0), np.int64)))
    domain = (coords, np.zeros(N, np.int64), np.zeros(N, np.int64))
    pose = np.zeros((0, 13))
    least = {}
    for name in [*VESSELS, DISH]:
        cells, half = vessel_cells(coords, name)
        arrays = {key: cells.arrays(DT / DX**2) for key in loops}
        if model is not None:
            arrays["against"] = arrays["against"][:9] + model.implicit_blocks(cells, DT / DX**2)
        if args.split:
            for key, module in modules.items():
                arrays[f"{key} without clusters"] = arrays[key][:9] + module.NO_WALL[9:]
        wet = int((arrays["this"][7] - arrays["this"][6]).sum())
        box = round(2 * half / DX) ** 2
        fields = np.concatenate([1.0 + rng.random(N * N), 0.1 * rng.normal(size=2 * N * N)])
        cur = fields * np.tile(cells.mask.reshape(-1), 3)
        for flow in (False, True):
            state = (bare, domain, arrays, COEF, DT, pose, flow, cur)
            times = {key: [] for key in loops}
            for _ in range(args.rounds + 1):  # the first round compiles and warms
                for key, loop in loops.items():
                    states, rhs = (cur, np.zeros_like(cur)), np.zeros(N * N)
                    start = time.thread_time()
                    walls = arrays[key]
                    loop(args.steps, states, bare, domain, walls, COEF, DT, pose, flow, rhs)
                    times[key].append(1e3 * (time.thread_time() - start) / args.steps)
            line = f"{name}, {wet} wet cells ({wet / box:.1%} of its box), flow {flow}:"
            for key, values in times.items():
                least[name, flow, key] = best = min(values[1:])
                line += f" {key} {best:.4f} ms ({1e6 * best / wet:.2f} ns a wet cell);"
            if args.against:
                pairs = zip(times["against"][1:], times["this"][1:], strict=True)
                ratios = [t / a for a, t in pairs]
                line += " this / against each round " + ", ".join(f"{r:.3f}" for r in ratios)
            if args.against:
                line += " one step's largest difference " + step_difference(loops, state)
            for key in modules if args.split else ():
                implicit = least[name, flow, key] - least[name, flow, f"{key} without clusters"]
                line += f" {key}: implicit clusters {implicit:.4f} ms;"
            if args.alone:
                line += time_alone(
                    arrays["this"], (bare, domain, flow, cur), 10 * args.steps, args.rounds
                )
            if args.agree:
                c = {}
                for key in modules:
                    states, rhs = (cur.copy(), np.zeros_like(cur)), np.zeros(N * N)
                    for _ in range(args.agree):
                        loops[key](1, states, bare, domain, arrays[key], COEF, DT, pose, flow, rhs)
                        states = states[::-1]
                    c[key] = states[0][: N * N]
                change = np.abs(c["this"] - c["against"]).max() / np.abs(c["against"]).max()
                line += f" after {args.agree} steps max |c - c against| / max |c| = {change:.1e};"
            print(line, flush=True)
    for name in [*VESSELS, DISH]:
        for key in modules:
            a, b = least[name, True, key], least[name, False, key]
            print(f"{name}, {key}: flow on / off = {a:.4f} / {b:.4f} = {a / b:.2f}")
    narrow, full = list(VESSELS)[1:]
    for flow in (False, True):
        for key in modules:
            a, b = least[narrow, flow, key], least[full, flow, key]
            print(
                f"flow {flow}, {key}: narrow annulus / full box = {a:.4f} / {b:.4f} = {a / b:.3f}"
            )
    time_open(coords, args.steps, args.rounds, rng)
    print("load average", " ".join(f"{x:.1f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
