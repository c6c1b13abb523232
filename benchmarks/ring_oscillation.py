"""The rocking of symmetric boats in the ring channel: its spatial mode, frequency and kind.

Runs one point of `configs/sweeps/crowd_ring_symmetric.yaml` (the same resolved config as
the sweep's run, its placement and seed included) to ``--t-end``, recording every boat's
arc speed w_k = (X x U) / |X| and angle each ``--record``, and from ``--from`` on
analyses the boats' speeds as a wave on the ring (boats numbered counter-clockwise):

* the mean signed arc speed and the rms of w (the ring's modes, docs/collective.md);
* the power of each spatial mode m = 0 .. N/2 of w_k (its discrete Fourier transform over
  k), and the leading one;
* its angular frequency Omega (the peak of the time spectrum of that mode's amplitude)
  and whether it travels: a wave e^{i(2 pi m k / N - Omega t)} puts its power at one sign
  of the frequency, a standing wave (boats rocking in place, neighbours against each
  other) at both; printed is the share of the larger side, 1 for a travelling wave, 1/2
  for a standing one;
* each boat's swing, the rms of its arc displacement from its mean path, against the mean
  spacing.

Compare with the 1D theory of the symmetric boat (docs/ring.md, "Onset of the symmetric
boat": the alternating mode m = N/2 goes unstable first, by a Hopf bifurcation).

Run:  NUMBA_NUM_THREADS=1 python benchmarks/ring_oscillation.py --count 8 --friction 0.2
      [--flow on] [--t-end 60] [--record 0.05] [--from 30]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.plan import Sweep

SWEEP = "configs/sweeps/crowd_ring_symmetric.yaml"


def sweep_point(count: int, friction: float, flow: bool, t_end: float) -> RotorConfig:
    """The sweep's resolved config at (count, friction, flow), run to `t_end`."""
    overrides = [
        f"axes.crowd.count=[{count}]",
        f"axes.crowd.body.motion.friction=[{friction}]",
        f"axes.flow.enabled=[{str(flow).lower()}]",
    ]
    data = Sweep.load(SWEEP, overrides).runs()[0].config
    data["protocol"]["t_ini"] = t_end
    return RotorConfig.model_validate(data)


def record(sim: Simulation, t_end: float, interval: float) -> tuple[np.ndarray, ...]:
    """(t, w, theta): the record times and each boat's arc speed and angle about the
    vessel's centre there."""
    cx, cy = sim.config.grid.domain_centre
    times, speeds, angles = [], [], []
    for t in np.arange(interval, t_end + 0.5 * interval, interval):
        sim.run(float(t))
        p = sim.bodies.poses
        x, y = p[:, 0] - cx, p[:, 1] - cy
        speeds.append((x * p[:, 4] - y * p[:, 3]) / np.hypot(x, y))
        angles.append(np.arctan2(y, x))
        times.append(float(t))
    return np.array(times), np.array(speeds), np.unwrap(np.array(angles), axis=0)


def analyse(t: np.ndarray, w: np.ndarray, theta: np.ndarray, radius: float) -> dict:
    """The wave measures of the module docstring from the late records."""
    n = w.shape[1]
    order = np.argsort(np.mod(theta[0], 2 * math.pi))
    w, theta = w[:, order], theta[:, order]
    spatial = np.fft.fft(w, axis=1) / n
    power = (np.abs(spatial) ** 2).mean(axis=0)[: n // 2 + 1]
    m = int(np.argmax(power[1:]) + 1) if n > 1 else 0
    amplitude = spatial[:, m] - spatial[:, m].mean()
    spectrum = np.abs(np.fft.fft(amplitude)) ** 2
    freqs = 2 * math.pi * np.fft.fftfreq(t.size, t[1] - t[0])
    peak = int(np.argmax(spectrum[1:]) + 1)
    omega = abs(freqs[peak])
    mirror = int(np.argmin(np.abs(freqs + freqs[peak])))
    travelling = max(spectrum[peak], spectrum[mirror]) / (spectrum[peak] + spectrum[mirror])
    arc = radius * theta
    path = arc - arc.mean(axis=1, keepdims=True)
    swing = float(np.sqrt(((path - path.mean(axis=0)) ** 2).mean()))
    return {
        "mean signed arc speed": float(w.mean()),
        "rms arc speed": float(np.sqrt((w**2).mean())),
        "mode powers m = 0..N/2": np.array2string(power, precision=3),
        "leading m": m,
        "Omega": omega,
        "travelling share": travelling,
        "swing / spacing": swing / (2 * math.pi * radius / n),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, required=True)
    parser.add_argument("--friction", type=float, required=True)
    parser.add_argument("--flow", choices=["off", "on"], default="off")
    parser.add_argument("--t-end", type=float, default=60.0)
    parser.add_argument("--record", type=float, default=0.05)
    parser.add_argument("--from", dest="start", type=float, default=30.0)
    args = parser.parse_args()
    config = sweep_point(args.count, args.friction, args.flow == "on", args.t_end)
    start, (cx, cy) = config.bodies[0].start, config.grid.domain_centre
    radius = math.hypot(start.x - cx, start.y - cy)  # the track's, about the vessel's centre
    t, w, theta = record(Simulation(config), args.t_end, args.record)
    late = t >= args.start
    print(
        f"N = {args.count}, mu = {args.friction:g}, flow {args.flow}: records {late.sum()} "
        f"from t = {args.start:g} to {args.t_end:g}"
    )
    for name, value in analyse(t[late], w[late], theta[late], radius).items():
        print(f"  {name}: {value:.4g}" if isinstance(value, float) else f"  {name}: {value}")


if __name__ == "__main__":
    main()
