"""The accuracy price of a cut footprint: the crowd of 20 disks at ``numerics.footprint_widths``
= w against the saturated footprint (w = 20), beside the discretisation error.

The crowd of ``benchmarks/bench_crowd.py`` (20 free camphor disks, rho = 0.1, on the
paper's dish and grid, dx = 0.025, dt = 1e-4, delta = 0.025) runs from rest for `--time`
at each w of `--widths` on each scheme of `--scheme`. Printed for each w: the largest
difference over the disks, against w = 20, of the position X, the velocity U and the
tension force f (the area or contour integral, Eq. (eq_motion)), each over the largest
|U| or |f| of the crowd, and of c over its largest value. The discretisation error is
measured the same way at w = 20 on the grid of spacing 2 dx (same dt and delta): for a
second-order scheme the difference between the two grids is about 3 times the error at
dx, so that difference over 3 estimates the error on the paper's grid. ``--contour-nodes
N ...`` adds, on the consistent scheme, each w with ``numerics.contour_nodes`` = N (4 N
directions a circle) against w = 20 and the default 32.

Run:  NUMBA_NUM_THREADS=1 python benchmarks/footprint_error.py [--time 0.3]
      [--widths 20 10 8 6] [--scheme paper consistent] [--contour-nodes 32 16]
"""

from __future__ import annotations

import argparse

import numpy as np
from bench_crowd import config

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation

FORCE = slice(6, 8)
"""The tension force (x, y) among a body's pose columns."""


def crowd(scheme: str, widths: float, dx: float, nodes: int = 32) -> RotorConfig:
    """The 20 disks at footprint `widths` and `nodes` contour nodes on the grid of
    spacing `dx`."""
    numerics = {"footprint_widths": widths, "contour_nodes": nodes}
    data = config(20, scheme, numerics).model_dump(mode="json")
    data["grid"]["dx"] = dx
    return RotorConfig.model_validate(data)


def final(cfg: RotorConfig, time: float) -> tuple[np.ndarray, np.ndarray]:
    """The bodies' pose columns and c after `time`."""
    sim = Simulation(cfg)
    sim.run(time)
    return sim.bodies.poses.copy(), np.asarray(sim.state.data[0]).copy()


def differences(a: tuple, b: tuple, coarse: bool = False) -> dict[str, float]:
    """Largest differences of X, U, f (relative to the crowd's largest |U|, |f|) and of c
    (relative to max c) between two runs' ends; `coarse`: b on the grid of twice the
    spacing, c compared on b's cells (every second cell centre of a lies between them,
    so only the bodies are compared)."""
    (pa, ca), (pb, cb) = a, b
    speed = np.abs(pa[:, 3:5]).max()
    force = np.abs(pa[:, FORCE]).max()
    out = {
        "X": float(np.abs(pa[:, 0:2] - pb[:, 0:2]).max()),
        "U/|U|": float(np.abs(pa[:, 3:5] - pb[:, 3:5]).max() / speed),
        "f/|f|": float(np.abs(pa[:, FORCE] - pb[:, FORCE]).max() / force),
    }
    if not coarse:
        out["c/max c"] = float(np.abs(ca - cb).max() / np.abs(ca).max())
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--time", type=float, default=0.3)
    parser.add_argument("--widths", type=float, nargs="+", default=[20.0, 10.0, 8.0, 6.0])
    parser.add_argument("--scheme", nargs="+", default=["paper", "consistent"])
    parser.add_argument("--contour-nodes", type=int, nargs="+", default=[32])
    args = parser.parse_args()
    dx = 0.025
    for scheme in args.scheme:
        full = final(crowd(scheme, 20.0, dx), args.time)
        poses = full[0]
        print(
            f"{scheme}: t = {args.time:g}, max |U| = {np.abs(poses[:, 3:5]).max():.4g}, "
            f"max |f| = {np.abs(poses[:, FORCE]).max():.4g}, max c = {full[1].max():.4g}"
        )
        nodes = args.contour_nodes if scheme == "consistent" else [32]
        for w in args.widths:
            for n in nodes:
                if (w, n) == (20.0, 32):
                    continue
                cut = final(crowd(scheme, w, dx, n), args.time)
                tail = 1.0 / (1.0 + np.exp(2.0 * w))
                shown = ", ".join(f"{k} {v:.3g}" for k, v in differences(full, cut).items())
                label = f"w = {w:g}" + (f", N = {n}" if n != 32 else "")
                print(f"  {label} (tail {tail:.2g}) against w = 20: {shown}")
        coarse = final(crowd(scheme, 20.0, 2 * dx), args.time)
        shown = ", ".join(f"{k} {v:.3g}" for k, v in differences(full, coarse, True).items())
        print(f"  dx = {2 * dx:g} against dx = {dx:g} (w = 20; error at dx about 1/3): {shown}")


if __name__ == "__main__":
    main()
