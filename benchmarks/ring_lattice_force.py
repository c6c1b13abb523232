"""The lattice force on the boats of the ring sweep, against the force that drives them.

A boat on its circular track in the ring channel of `configs/sweeps/crowd_ring.yaml`
(16 boats evenly spaced, or one) sails at a steady speed that, by the ring's rotation
symmetry, the continuous model keeps constant, with a constant tension force along the
track equal to the friction mu A V (the driving force). On the grid the force varies as
the boats cross the cells: that variation is the lattice force. From rest the boats sail
to `--t-end`; from `--t-from` on, each boat's tangential tension force f(t) (Eq.
(eq_motion)'s s k int F grad c dA on e_theta) is sampled every step. Printed: the driving
force F (the mean of f over the boats and samples) and the lattice force, f less its
boat's mean and slow trend (a straight line in time per boat, which takes off what is
left of the start's relaxation): its rms and largest |.|, each over F; and the same for
the arc speed, which follows the force within m / (mu A).

The sweep's resolved config is that of one point (``--count``, ``--friction``, ``--flow``);
``--dx``, ``--smoothing``, ``--dt`` and ``--scheme`` change its grid and scheme, to find the
grid whose lattice force is below 1 % of F.

Run:  NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/ring_lattice_force.py
      [--count 16] [--friction 0.05] [--flow off] [--dx 0.05 --smoothing 0.025 --dt 4e-4]
      [--scheme paper] [--t-from 2 --t-end 3]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from pde.trackers import CallbackTracker

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.plan import Sweep

SWEEP = "configs/sweeps/crowd_ring.yaml"


def sweep_config(args: argparse.Namespace) -> RotorConfig:
    """The ring sweep's resolved config at one point, with the grid and scheme of `args`."""
    overrides = [
        f"axes.crowd.count=[{args.count}]",
        f"axes.crowd.body.motion.friction=[{args.friction}]",
        f"axes.flow.enabled=[{'true' if args.flow == 'on' else 'false'}]",
    ]
    data = Sweep.load(SWEEP, overrides).runs()[0].config
    grid, numerics = data["grid"], data["numerics"]
    for key, value in (("dx", args.dx), ("dt", args.dt)):
        if value is not None:
            grid[key] = value
    if args.smoothing is not None:
        data["geometry"]["smoothing"] = args.smoothing
    if args.scheme is not None:
        numerics["scheme"] = args.scheme
    data["protocol"] = {"t_ini": args.t_end, "cycles": 0}
    data["output"] = {"progress": False}
    return RotorConfig.model_validate(data)


def tangential(poses: np.ndarray, columns: tuple[int, int]) -> np.ndarray:
    """The pair of pose columns projected on each body's e_theta about the origin."""
    theta = np.arctan2(poses[:, 1], poses[:, 0])
    return -poses[:, columns[0]] * np.sin(theta) + poses[:, columns[1]] * np.cos(theta)


def lattice_part(series: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Each column of `series` less its straight-line fit in time."""
    design = np.stack([np.ones_like(times), times - times.mean()], axis=1)
    coef, *_ = np.linalg.lstsq(design, series, rcond=None)
    return series - design @ coef


def lattice_figures(series: np.ndarray, times: np.ndarray) -> tuple[float, float, float]:
    """(mean, rms, largest): the mean of `series` (samples x boats) over every boat and
    sample, and the rms and largest |.| of its lattice part (:func:`lattice_part`), each
    over |mean|."""
    mean = float(series.mean())
    part = lattice_part(series, times)
    return mean, float(np.sqrt((part**2).mean())) / abs(mean), float(np.abs(part).max()) / abs(mean)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=16)
    parser.add_argument("--friction", type=float, default=0.05)
    parser.add_argument("--flow", choices=["off", "on"], default="off")
    parser.add_argument("--dx", type=float)
    parser.add_argument("--dt", type=float)
    parser.add_argument("--smoothing", type=float)
    parser.add_argument("--scheme", choices=["paper", "consistent"])
    parser.add_argument("--t-from", type=float, default=2.0)
    parser.add_argument("--t-end", type=float, default=3.0)
    args = parser.parse_args()
    config = sweep_config(args)
    sim = Simulation(config)
    times: list[float] = []
    forces: list[np.ndarray] = []
    speeds: list[np.ndarray] = []

    def sample(state, t: float) -> None:
        if t >= args.t_from:
            times.append(t)
            forces.append(tangential(state.bodies.poses, (6, 7)))
            speeds.append(tangential(state.bodies.poses, (3, 4)))

    start = time.process_time()
    sim.run(args.t_end, trackers=[CallbackTracker(sample, interrupts=config.grid.dt)])
    cpu = time.process_time() - start
    t = np.array(times)
    f, v = np.array(forces), np.array(speeds)
    drive, rms, largest = lattice_figures(f, t)
    speed, rms_v, largest_v = lattice_figures(v, t)
    g = config.grid
    print(
        f"{args.count} boats, mu = {args.friction}, flow {args.flow}, {config.numerics.scheme} "
        f"scheme, dx = {g.dx}, delta = {config.geometry.smoothing}, dt = {g.dt}, "
        f"{len(t)} samples over t = {t[0]:.3f} .. {t[-1]:.3f} (cpu {cpu:.0f} s)"
    )
    print(f"  driving force F = {drive:.5g}, arc speed V = {speed:.5g}")
    print(
        f"  lattice force: rms {rms * abs(drive):.3g} = {rms:.3%} of F, largest "
        f"{largest * abs(drive):.3g} = {largest:.3%} of F"
    )
    print(
        f"  speed's lattice part: rms {rms_v:.3%} of V, largest {largest_v:.3%}; boats' mean "
        f"speeds differ by {np.ptp(v.mean(axis=0)) / abs(speed):.2e} of V"
    )


if __name__ == "__main__":
    main()
