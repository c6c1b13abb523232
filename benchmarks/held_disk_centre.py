"""The force on a free camphor disk held at the dish's centre, where it should vanish.

A free disk (radius 0.1, no plate) held by a stop of its own at the centre of a dish of radius 2,
coarse grid dx = delta = 0.05, dt = 4e-4, flow on: the largest |f_x|, |f_y| over ten samples
up to t = 0.4 on each scheme given. Then how far the grid's cell centres are from mirror
images of each other, and where 1 / dx from cell 0's centre puts the dish's centre. Then
the cubic spline's prefilter
(:func:`pde_rotor.kernels.spline.spline_window`) on a field exactly symmetric about the
centre of a symmetric 60 x 60 window: the largest asymmetry of its coefficients. Then, on
the consistent scheme at t = 0.04, the contour force
(:func:`pde_rotor.kernels.body_sums.body_contour`) on the run's c and on c made exactly
mirror-symmetric: what the nodes and taps leave when c and its coefficients are symmetric.
Last, with ``--calls``, the cost of that contour force: ms per call of ``body_contour``
on the held disk (the spline window and its circle's nodes, the least of five rounds of
`--calls` calls, the thread's CPU time), and ms per step of the held disk's run on the
consistent scheme (the least of five rounds of 100 steps).

Run:  python benchmarks/held_disk_centre.py [--schemes [paper] [consistent]] [--calls 2000]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.kernels.body_sums import body_contour
from pde_rotor.kernels.spline import spline_window
from pde_rotor.model.surface import SurfacePDE
from pde_rotor.physics.motion import N_INTEGRALS
from pde_rotor.solver.bodies import make_bodies_stepper
from pde_rotor.solver.simulation import Simulation


def held_config(scheme: str) -> RotorConfig:
    disk = {
        "name": "disk",
        "plate": {"shape": "none"},
        "pills": [{"x": 0.0, "y": 0.0, "radius": 0.1}],
        "motion": {"kind": "free", "mass": 2e-3, "friction": 0.2, "inertia": 1e-5},
        "protocol": {"t_ini": 0.0, "t_stop": 0.4, "t_release": 1.0, "cycles": 1},
    }
    return RotorConfig.model_validate(
        {
            "grid": {"dx": 0.05, "dt": 4e-4, "domain_radius": 2.0},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": 0.4, "cycles": 0},
            "bodies": [disk],
        }
    )


def held_force(scheme: str) -> tuple[float, float]:
    sim = Simulation(held_config(scheme))
    forces = []
    for t in np.arange(0.04, 0.41, 0.04):
        sim.run(t)
        forces.append(sim.bodies.poses[0, 6:8].copy())
    return tuple(np.abs(np.array(forces)).max(axis=0))


def grid_mirror() -> tuple[float, float, float]:
    """(largest |x_i + x_(n-1-i)| of the cell centres, the dish's centre in cells from
    cell 0's centre as the contour once placed it, the grid's middle (n - 1) / 2)."""
    coords = SurfacePDE(held_config("consistent")).domain.coords
    centre = (0.0 - coords[0]) / (coords[1] - coords[0])
    return float(np.abs(coords + coords[::-1]).max()), float(centre), (coords.size - 1) / 2


def prefilter_asymmetry(n: int = 80, lo: int = 10, hi: int = 70) -> tuple[float, float]:
    x = (np.arange(n) - (n - 1) / 2) * 0.05
    xx, yy = np.meshgrid(x, x, indexing="ij")
    cur = (0.44 * np.exp(-(xx**2 + yy**2))).reshape(-1)
    coef = np.zeros_like(cur)
    spline_window(cur, coef, n, lo, hi, lo, hi)
    window = coef.reshape(n, n)[lo:hi, lo:hi]
    return float(np.abs(window - window[::-1, ::-1]).max()), float(window.max())


def contour_call(sim: Simulation) -> tuple[np.ndarray, tuple, np.recarray]:
    """The arguments of ``body_contour`` for the held disk of `sim` at its pose, but the
    state: (coords, bodies, the parameter record)."""
    pde = sim.pde
    step = make_bodies_stepper(pde, sim.config.grid.dt, np.random.default_rng(0))
    pose = sim.bodies.poses.copy()
    pose[:, :2] -= pde.domain.centre
    bodies = (step._bodies, step._pills, pose, pose[:, :3].copy(), pde.box, step._normals,
              step._centres, step._tables)  # fmt: skip
    return pde.domain.coords, bodies, step._record.view(np.recarray)[0]


def contour_forces(t: float = 0.04) -> list[tuple[float, np.ndarray]]:
    """(mirror asymmetry of c, contour force (x, y)) on the run's c at `t` and on c made
    exactly mirror-symmetric, the held disk on the consistent scheme."""
    sim = Simulation(held_config("consistent"))
    sim.run(t)
    coords, bodies, p = contour_call(sim)
    c = sim.state.data[0]
    mirrored = 0.25 * ((c + c[::-1, :]) + (c[:, ::-1] + c[::-1, ::-1]))
    results = []
    for field in (c, mirrored):
        data = sim.state.data.copy()
        data[0] = field
        out = np.zeros(N_INTEGRALS)
        body_contour(data.reshape(-1), coords, 0, bodies, p, out)
        results.append((float(np.abs(field - field[::-1, :]).max()), out[:2].copy()))
    return results


def contour_cost(calls: int, rounds: int = 5) -> tuple[float, float]:
    """(ms per ``body_contour`` call, ms per step of the run) of the held disk on the
    consistent scheme at t = 0.04, the least of `rounds` rounds (thread CPU time)."""
    sim = Simulation(held_config("consistent"))
    sim.run(0.04)
    coords, bodies, p = contour_call(sim)
    cur = sim.state.data.reshape(-1).copy()
    out = np.zeros(N_INTEGRALS)
    body_contour(cur, coords, 0, bodies, p, out)  # compiled by the run; warm the caches
    per_call = per_step = float("inf")
    dt = sim.config.grid.dt
    for _ in range(rounds):
        start = time.thread_time()
        for _ in range(calls):
            body_contour(cur, coords, 0, bodies, p, out)
        per_call = min(per_call, 1e3 * (time.thread_time() - start) / calls)
        start = time.thread_time()
        sim.run(sim.t + 100 * dt)
        per_step = min(per_step, 1e3 * (time.thread_time() - start) / 100)
    return per_call, per_step


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--schemes", nargs="*", default=["paper", "consistent"])
    parser.add_argument("--calls", type=int, default=0, help="time the contour force")
    args = parser.parse_args()
    for scheme in args.schemes:
        fx, fy = held_force(scheme)
        print(f"{scheme}: largest |f_x| {fx:.3g}, |f_y| {fy:.3g}", flush=True)
    mirror, centre, middle = grid_mirror()
    print(
        f"grid: cell centres mirror images to {mirror:.3g}; the dish's centre {centre!r} cells "
        f"from cell 0's centre, the middle {middle}"
    )
    asym, top = prefilter_asymmetry()
    print(
        f"prefilter on a symmetric field: coefficients asymmetric by {asym:.3g} (largest {top:.3g})"
    )
    for name, (asym_c, force) in zip(("run's c", "mirrored c"), contour_forces(), strict=True):
        print(
            f"consistent, t = 0.04, {name} (asymmetric by {asym_c:.3g}): "
            f"contour force {abs(force[0]):.3g}, {abs(force[1]):.3g}"
        )
    if args.calls:
        per_call, per_step = contour_cost(args.calls)
        print(
            f"consistent, held disk: body_contour {per_call:.4f} ms per call, "
            f"the run {per_step:.4f} ms per step (thread CPU time, least of 5 rounds)"
        )


if __name__ == "__main__":
    main()
