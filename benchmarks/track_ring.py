"""Boats on a circular track: what a run's bodies.nc says about the ring.

For a run of track bodies (``motion: {kind: track}``, e.g. configs/bodies/boats_in_ring.yaml)
prints, from `--from` time units on: each boat's mean arc speed w = omega R and its range,
the largest spread of w between boats, the smallest gap between neighbouring footprints
along the ring (the contact spring acts below ``contact.range``), and the largest distance
of a boat from its circle and of its heading from the tangent over the whole run.

Run:  python benchmarks/track_ring.py RUN_DIR [--from 2.0]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
import xarray as xr

from pde_rotor.config import load_config


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="the run directory")
    parser.add_argument("--from", dest="start", type=float, default=2.0, help="skip this time")
    args = parser.parse_args()
    config = load_config(args.run / "config.yaml")
    bodies = config.body_list()
    reach = np.array([b.reach(config.geometry.smoothing) for b in bodies])
    radius = np.array([b.motion.radius for b in bodies])
    centre = np.array([b.motion.centre for b in bodies])
    sign = np.array([b.motion.sign for b in bodies])
    data = xr.open_dataset(args.run / "bodies.nc")
    x = data.x.values - centre[:, 0]
    y = data.y.values - centre[:, 1]
    theta = np.arctan2(y, x)
    off = np.abs(np.hypot(x, y) - radius).max()
    gap = np.remainder(data.phi.values - theta - sign * math.pi / 2 + math.pi, 2 * math.pi)
    heading = np.abs(gap - math.pi).max()
    late = data.time.values >= args.start
    speed = (data.omega.values * radius)[late]
    print(f"run {args.run}: {len(bodies)} boats, t = {data.time.values[-1]:g}")
    for k, body in enumerate(bodies):
        w = speed[:, k]
        print(f"  {body.name}: mean w = {w.mean():.4f}, range [{w.min():.4f}, {w.max():.4f}]")
    print(f"  largest spread of w between boats: {np.ptp(speed, axis=1).max():.3g}")
    if len(bodies) > 1:
        order = np.argsort(theta[late], axis=1)
        ordered = np.take_along_axis(theta[late], order, axis=1)
        steps = np.diff(ordered, axis=1, append=ordered[:, :1] + 2 * math.pi)
        chord = 2 * radius[0] * np.sin(steps / 2)
        print(f"  smallest footprint gap: {(chord - 2 * reach.max()).min():.4g}")
    print(f"  largest | |X - C| - R |: {off:.3g}; heading off the tangent: {heading:.3g}")
    print(f"  status: {data.attrs.get('status')} ({data.attrs.get('message')})")


if __name__ == "__main__":
    main()
