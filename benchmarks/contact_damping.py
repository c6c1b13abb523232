"""Forward Euler and the contact dashpot on the ring sweep's densest crowd.

The N = 16, mu = 0.05, flow-off point of configs/sweeps/crowd_ring.yaml (its resolved
config, ``Sweep.load(...).runs()``), stepped by forward Euler instead of the sweep's Heun
with ``contact.damping`` set (default: the least the Euler check accepts,
kappa dt - mu A / 4, rounded up to 1e-4; docs/bodies.md), or with ``--integrator heun``
as the sweep steps it (no dashpot unless given). Every ``--every`` of simulated time it
prints the footprints' gaps between neighbours on the ring (smallest, largest), the
smallest gap and the largest contact force along the track over the samples (every
``--sample``) since the last line, and the mean arc speed; at the end the CPU time.
Without the dashpot (refused since the check) the same run ended at t = 2.48, where two
footprints met (docs/results.md, "contact springs under forward Euler").

Run:  PYTHONPATH=. python benchmarks/contact_damping.py [--t-end 3] [--damping G]
          [--integrator heun]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.config.contact import euler_damping
from pde_rotor.model.surface import POSE_COLUMNS
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.plan import Sweep

SWEEP = Path(__file__).resolve().parents[1] / "configs" / "sweeps" / "crowd_ring.yaml"


def ring_point(count: int, friction: float) -> dict:
    """The resolved config of the sweep's point (crowd.count, friction), flow off."""
    for run in Sweep.load(SWEEP).runs():
        coords = run.coords
        if (
            coords["crowd.count"] == count
            and coords["crowd.body.motion.friction"] == friction
            and not coords["flow.enabled"]
        ):
            return run.config
    raise SystemExit(f"no point with count {count} and friction {friction} in {SWEEP}")


def gaps(config: RotorConfig, poses: np.ndarray) -> np.ndarray:
    """The gaps between neighbouring footprints round the ring (chord minus both reaches)."""
    reach = config.body_list()[0].reach(config.geometry.smoothing)
    order = np.argsort(np.arctan2(poses[:, 1], poses[:, 0]))
    ring = poses[order, :2]
    chords = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
    return chords - 2 * reach


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=3.0, help="simulated time")
    parser.add_argument("--every", type=float, default=0.5, help="time between lines")
    parser.add_argument("--sample", type=float, default=0.01, help="time between samples")
    parser.add_argument("--damping", type=float, default=None, help="contact.damping")
    parser.add_argument("--count", type=int, default=16, help="number of boats")
    parser.add_argument("--friction", type=float, default=0.05, help="mu")
    parser.add_argument(
        "--integrator", choices=("euler", "heun"), default="euler", help="heun: the sweep's"
    )
    args = parser.parse_args()
    data = ring_point(args.count, args.friction)
    data["numerics"] = {**data["numerics"], "integrator": args.integrator}
    data["protocol"] = {**data["protocol"], "t_ini": args.t_end}
    body = RotorConfig.model_validate({**data, "numerics": {"integrator": "heun"}}).body_list()[0]
    contact, dt = data["contact"], data["grid"]["dt"]
    least = euler_damping(contact.get("stiffness", 100.0), dt, args.friction * body.area())
    damping = math.ceil(least * 1e4) / 1e4 if args.integrator == "euler" else 0.0
    damping = args.damping if args.damping is not None else damping
    data["contact"] = {**contact, "damping": damping}
    config = RotorConfig.model_validate(data)
    print(f"N = {args.count}, mu = {args.friction}, {args.integrator}, dt = {dt:g}, kappa = "
          f"{config.contact.stiffness:g}, gamma = {damping:g} (least {least:.5f})")  # fmt: skip
    sim = Simulation(config)
    along = [POSE_COLUMNS.index("contact_x"), POSE_COLUMNS.index("contact_y")]
    start = time.process_time()
    steps = round(args.sample / dt)
    per_line = round(args.every / args.sample)
    smallest, force, n = np.inf, 0.0, 0
    while sim.t < args.t_end - dt / 2:
        sim.run(min(args.t_end, (round(sim.t / dt) + steps) * dt))
        poses = sim.bodies.poses
        theta = np.arctan2(poses[:, 1], poses[:, 0])
        tangent = np.stack([-np.sin(theta), np.cos(theta)], axis=1)
        smallest = min(smallest, float(gaps(config, poses).min()))
        force = max(force, float(np.abs(np.sum(poses[:, along] * tangent, axis=1)).max()))
        n += 1
        if n % per_line == 0 or sim.t >= args.t_end - dt / 2:
            g = gaps(config, poses)
            speed = float(np.mean(np.sum(poses[:, 3:5] * tangent, axis=1)))
            print(f"t = {sim.t:.2f}: gaps now {g.min():.5f} .. {g.max():.5f}, since the last "
                  f"line smallest {smallest:.5f}, largest contact force along the track "
                  f"{force:.4g}; mean arc speed {speed:.3f}")  # fmt: skip
            smallest, force = np.inf, 0.0
    print(f"CPU {time.process_time() - start:.1f} s")


if __name__ == "__main__":
    main()
