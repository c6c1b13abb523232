"""The three exact onsets of pde_rotor.theory from the discrete model's eigenvalues.

On each grid, the critical friction where the leading eigenvalue's real part crosses 0
(scipy brentq, relative tolerance 1e-5), no flow, paper scheme, delta = 0.025:

* a free camphor disk (radius 0.1, mass 2e-3) at the centre of an absorbing dish of
  radius 3: a pitchfork at mu_c; theory 0.17635 (sharp), K_delta(0) / A_delta at delta;
* the two-disk rotor (configs/bodies/two_disk_rotor.yaml, l = 0.5): a pitchfork;
  theory 0.1382 (rotor_critical_friction at delta = 0.025; 0.1399 at delta = 0.005);
* a free disk (mass 1e-4) at the centre of a no-flux dish of radius 3
  (configs/bodies/disk_in_dish.yaml): a Hopf pair; theory mu_c = 0.1781, omega_c = 0.274
  (sharp).

With three grids the script prints the Richardson limit dx -> 0 (order from the three
values) and the paper grid's error against it.

Run: ``python benchmarks/stability_onsets.py [--grids 0.05 0.025 0.0166666667]
[--systems free rotor dish] [--radius 3]`` (one thread: OMP_NUM_THREADS=1).
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Any

from pde_rotor.config import read_config_data
from pde_rotor.stability import critical_value
from pde_rotor.theory import (
    CamphorDisk,
    Wall,
    dish_hopf_onset,
    free_disk_critical_friction,
    free_disk_smoothed_coefficients,
    rotor_critical_friction,
)

KEY = "bodies[0].motion.friction"
DELTA = 0.025


def system(name: str, dx: float, radius: float = 3.0) -> tuple[dict[str, Any], tuple[float, float]]:
    """The config (as a mapping) and the friction bracket of one system on one grid, in a
    dish of `radius`."""
    grid = {"domain_radius": radius, "dx": dx, "dt": 1e-4 if dx >= 0.025 else 5e-5}
    if name == "free":
        data = read_config_data("configs/bodies/free_disk.yaml")
        data["bodies"][0]["motion"].update({"mass": 2e-3, "inertia": 1e-5})
        bracket = (0.15, 0.19)
    elif name == "rotor":
        data = read_config_data("configs/bodies/two_disk_rotor.yaml")
        bracket = (0.11, 0.15)
    else:
        data = read_config_data("configs/bodies/disk_in_dish.yaml")
        data["bodies"][0]["start"] = {"x": 0.0, "y": 0.0}
        grid["wall"] = "no_flux"
        bracket = (0.15, 0.19)
    data["grid"] = grid
    data["flow"] = {"enabled": False}
    data["geometry"] = {"smoothing": DELTA}
    return data, bracket


def theory(name: str, radius: float = 3.0) -> str:
    """The onset of theory/, sharp and (where available) at delta."""
    disk = CamphorDisk(1.0, 1.0, 1.0, 1.0, 0.1)
    if name == "free":
        force, area = free_disk_smoothed_coefficients(disk, DELTA)
        return f"sharp {free_disk_critical_friction(disk):.5f}, delta {force / area:.5f}"
    if name == "rotor":
        return (
            f"delta {rotor_critical_friction(disk, 0.5, DELTA):.5f}, "
            f"delta 0.005 {rotor_critical_friction(disk, 0.5):.5f}"
        )
    mu, omega = dish_hopf_onset(disk, Wall(radius, "no_flux"), 1e-4)
    return f"sharp mu_c {mu:.5f} omega_c {omega:.5f}"


def main() -> None:
    """Print the critical friction of each system on each grid, then the limits."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", type=float, nargs="+", default=[0.05, 0.025, 0.0166666667])
    parser.add_argument("--systems", nargs="+", default=["free", "rotor", "dish"])
    parser.add_argument("--radius", type=float, default=3.0, help="dish radius L")
    args = parser.parse_args()
    for name in args.systems:
        values = []
        for dx in args.grids:
            data, (lo, hi) = system(name, dx, args.radius)
            start = time.thread_time()
            cross = critical_value(data, KEY, lo, hi, rtol=1e-5, k=6)
            values.append(cross.value)
            print(
                f"{name} dx={dx:.4g}: mu_c = {cross.value:.5f} +- {cross.tolerance:.1e} "
                f"{cross.kind} omega = {cross.frequency:.4f} ({cross.direction}) "
                f"cpu {time.thread_time() - start:.0f}s; theory {theory(name, args.radius)}",
                flush=True,
            )
        if len(values) == 3:
            h = args.grids
            ratio = (values[0] - values[1]) / (values[1] - values[2])
            order = math.log(abs(ratio)) / math.log(h[0] / h[1]) if ratio > 0 else float("nan")
            p = order if math.isfinite(order) else 2.0
            limit = values[2] + (values[2] - values[1]) / ((h[1] / h[2]) ** p - 1)
            print(
                f"{name}: order {order:.2f}, dx -> 0 limit {limit:.5f}, paper-grid error "
                f"{values[1] - limit:+.5f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
