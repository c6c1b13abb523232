"""A camphor disk in a no-flux dish below and above its Hopf onset: which motion it settles on.

The disk of configs/bodies/disk_in_dish.yaml (no plate, rho = 0.1, m = 1e-4, no flow, dish
radius 3, no-flux wall) is held while c relaxes, dragged for `--drag` time units along the
ellipse (a cos w t, b sin w t) so that c takes that motion's wake
(:func:`pde_rotor.gallery.onsets.dragged_orbit`), and released. After `--time` time units
the script prints, per friction mu: the distance |X| from the centre (its range over the
last quarter of the run), the angular momentum per mass L = x U_y - y U_x (mean over the
last quarter, and its ratio to L at the first quarter's end) and the verdict: **rotation**
about the centre (|X| constant to 2 %, L steady and not small), motion **back and forth**
through the centre (L decaying towards 0 while |X| swings through the centre), or **rest**
(|X| below 0.05). b = a is a rotating wake, b = 0 a reciprocating one, b between them a
mix; a hold longer than the onset's growth time is needed for the verdict.

Run:  python benchmarks/dish_branches.py [--dx 0.05 --dt 4e-4] --mus 0.1675 0.17
          [--ellipse 0.1 0.01 0.3028] [--drag 42] [--time 80]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.gallery.onsets import disk_in_dish_config, dragged_orbit
from pde_rotor.theory import CamphorDisk, Wall, dish_hopf_onset

RELAX = 6.0


def verdict(rows: np.ndarray) -> tuple[str, float, float, float, float]:
    """(verdict, |X| min and max over the last quarter, mean L there, its ratio to the
    mean L over the first quarter) of the released disk's rows (x, y, U_x, U_y)."""
    rows = rows[np.all(np.isfinite(rows), axis=1)]
    quarter = max(1, len(rows) // 4)
    radius = np.hypot(rows[:, 0], rows[:, 1])
    momentum = rows[:, 0] * rows[:, 3] - rows[:, 1] * rows[:, 2]
    last_r, last_l = radius[-quarter:], momentum[-quarter:]
    ratio = float(np.mean(last_l) / np.mean(momentum[:quarter]))
    if last_r.max() < 0.05:
        name = "rest"
    elif np.ptp(last_r) < 0.02 * last_r.mean() and abs(np.mean(last_l)) > 0.1 * last_r.mean():
        name = "rotation"
    elif last_r.min() < 0.2 * last_r.max():
        name = "back and forth"
    else:
        name = "other"
    return name, float(last_r.min()), float(last_r.max()), float(np.mean(last_l)), ratio


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dx", type=float, default=0.05)
    parser.add_argument("--dt", type=float, default=4e-4)
    parser.add_argument("--mus", type=float, nargs="+", required=True, help="frictions mu")
    parser.add_argument(
        "--ellipse",
        type=float,
        nargs=3,
        default=[0.1, 0.01, 0.3028],
        metavar=("A", "B", "W"),
        help="the drag's ellipse and angular rate",
    )
    parser.add_argument("--drag", type=float, default=42.0, help="time dragged")
    parser.add_argument("--time", type=float, default=80.0, help="time after the release")
    args = parser.parse_args()
    mu_c, omega_c = dish_hopf_onset(
        CamphorDisk.from_config(RotorConfig()), Wall(3.0, "no_flux"), 1e-4
    )
    print(f"theory: mu_c = {mu_c:.5f}, omega_c = {omega_c:.4f}; dx = {args.dx:g}, dt = {args.dt:g}")
    a, b, w = args.ellipse
    print(
        f"dragged {args.drag:g} along ({a:g} cos {w:g}t, {b:g} sin {w:g}t), released, "
        f"run {args.time:g}"
    )
    times = np.arange(0.25, args.time + 1e-9, 0.25)
    for mu in args.mus:
        start = time.process_time()
        end = RELAX + args.drag + args.time + 0.1
        config = disk_in_dish_config(args.dx, args.dt, 3.0, 1e-4, mu, end, RELAX)
        rows = dragged_orbit(config, RELAX, (a, b, w), args.drag, times)
        name, r_min, r_max, momentum, ratio = verdict(rows)
        print(
            f"mu = {mu:.4f} ({mu / mu_c:.4f} mu_c): {name:14s} |X| {r_min:.4f} .. {r_max:.4f}, "
            f"L {momentum:+.3e} ({ratio:.3g} of the first quarter's)  "
            f"[{time.process_time() - start:.0f} s CPU]",
            flush=True,
        )


if __name__ == "__main__":
    main()
