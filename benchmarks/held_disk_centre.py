"""The force on a free camphor disk held at the dish's centre, where it should vanish.

A free disk (radius 0.1, no plate) held by a stop of its own at the centre of a dish of radius 2,
coarse grid dx = delta = 0.05, dt = 4e-4, flow on: the largest |f_x|, |f_y| over ten samples
up to t = 0.4 on each scheme given. Then the cubic spline's prefilter
(:func:`pde_rotor.kernels.spline.spline_window`) on a field exactly symmetric about the
centre of a symmetric 60 x 60 window: the largest asymmetry of its coefficients. Last, on
the consistent scheme at t = 0.04, the contour force
(:func:`pde_rotor.kernels.bodies.body_contour`) on the run's c and on c made exactly
mirror-symmetric: what the nodes and taps leave when c and its coefficients are symmetric.

Run:  python benchmarks/held_disk_centre.py [--schemes paper consistent]
"""

from __future__ import annotations

import argparse

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.kernels.bodies import body_contour
from pde_rotor.kernels.records import make_body_records, make_body_tables, make_record
from pde_rotor.kernels.spline import spline_window
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


def prefilter_asymmetry(n: int = 80, lo: int = 10, hi: int = 70) -> tuple[float, float]:
    x = (np.arange(n) - (n - 1) / 2) * 0.05
    xx, yy = np.meshgrid(x, x, indexing="ij")
    cur = (0.44 * np.exp(-(xx**2 + yy**2))).reshape(-1)
    coef = np.zeros_like(cur)
    spline_window(cur, coef, n, lo, hi, lo, hi)
    window = coef.reshape(n, n)[lo:hi, lo:hi]
    return float(np.abs(window - window[::-1, ::-1]).max()), float(window.max())


def contour_forces(t: float = 0.04) -> list[tuple[float, np.ndarray]]:
    """(mirror asymmetry of c, contour force (x, y)) on the run's c at `t` and on c made
    exactly mirror-symmetric, the held disk on the consistent scheme."""
    cfg = held_config("consistent")
    sim = Simulation(cfg)
    sim.run(t)
    pde = sim.pde
    bodies, pills = make_body_records(pde.setup)
    n = pde.domain.coords.size
    tables = make_body_tables(pde.bodies, pde.body_scheme, bodies, n)
    record = make_record(pde.setup)[0]
    c = sim.state.data[0]
    mirrored = 0.25 * ((c + c[::-1, :]) + (c[:, ::-1] + c[::-1, ::-1]))
    results = []
    for field in (c, mirrored):
        data = np.zeros((3, n, n))
        data[0] = field
        out = np.zeros(12)
        scratch = (np.zeros((2, 1, 1)), np.zeros((2, max(1, len(pills)))))
        poses = sim.bodies.poses.copy()
        body_contour(
            data.reshape(-1),
            pde.domain.coords,
            0,
            bodies,
            pills,
            poses,
            *scratch,
            tables,
            record,
            out,
        )
        results.append((float(np.abs(field - field[::-1, :]).max()), out[:2].copy()))
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--schemes", nargs="+", default=["paper", "consistent"])
    args = parser.parse_args()
    for scheme in args.schemes:
        fx, fy = held_force(scheme)
        print(f"{scheme}: largest |f_x| {fx:.3g}, |f_y| {fy:.3g}", flush=True)
    asym, top = prefilter_asymmetry()
    print(
        f"prefilter on a symmetric field: coefficients asymmetric by {asym:.3g} (largest {top:.3g})"
    )
    for name, (asym_c, force) in zip(("run's c", "mirrored c"), contour_forces(), strict=True):
        print(
            f"consistent, t = 0.04, {name} (asymmetric by {asym_c:.3g}): "
            f"contour force {abs(force[0]):.3g}, {abs(force[1]):.3g}"
        )


if __name__ == "__main__":
    main()
