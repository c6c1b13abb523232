"""The rocking and the density waves of symmetric boats in the ring channel: their spatial
mode, frequency and kind.

Runs one point of a ring sweep of symmetric boats (``--sweep``, default
`configs/sweeps/crowd_ring_symmetric.yaml`; `crowd_ring_waves.yaml` adds the start speed)
to ``--t-end``, the same resolved config as the sweep's run, its placement and seed
included: each of ``--count``, ``--friction``, ``--flow``, ``--speed`` that is given pins
that axis (a flow axis is pinned off unless ``--flow`` is given). It records every boat's
arc speed w_k = (X x U) / |X| and angle each ``--record``, and from ``--from`` on analyses
the boats' speeds as a wave on the ring (boats numbered counter-clockwise):

* the ring's mode over the analysed records, by the sweep's rule (``ring.ring_mode``, its
  measures: the spacing spread, the gap mobility, the mean |w| and the mean signed w), and
  the rms of w;
* the power of each spatial mode m = 0 .. N/2 of w_k (its discrete Fourier transform over
  k), and the leading one;
* its angular frequency Omega (the peak of the time spectrum of that mode's amplitude)
  and whether it travels: a wave e^{i(2 pi m k / N - Omega t)} puts its power at one sign
  of the frequency, a standing wave (boats rocking in place, neighbours against each
  other) at both; printed is the share of the larger side, 1 for a travelling wave, 1/2
  for a standing one;
* each boat's swing, the rms of its arc displacement from its mean path, against the mean
  spacing;
* the kind of a density wave: the share of a boat's time spent halted (|w_k| below
  :data:`HALT` times the mean |w|: boats that queue in a jam and leave it, a stop-and-go
  or discrete wave, against a continuous one whose boats only slow down; a sinusoidal
  rocking spends 4 % of its time so), and each boat's least and largest w_k over the mean
  |w|, averaged over the boats;
* the contact: the least distance between neighbours' centres over the mean spacing, and
  the share of records in which some neighbours' footprints (``BodyConfig.reach``) are
  closer than ``contact.range``, where the contact spring pushes them apart
  (docs/bodies.md, "Contact").

With ``--windows W``, also each window of length W from t = 0 on its own line: its mode,
mean |w|, mean signed w and spacing spread, to tell a settled state from a slow transient.

Compare with the 1D theory of the symmetric boat (docs/ring.md, "Onset of the symmetric
boat": the alternating mode m = N/2 goes unstable first, by a Hopf bifurcation).

Run:  NUMBA_NUM_THREADS=1 python benchmarks/ring_oscillation.py --count 8 --friction 0.2
      [--flow on] [--sweep configs/sweeps/crowd_ring_waves.yaml --speed 0.5]
      [--t-end 60] [--record 0.05] [--from 30] [--windows 30]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.collective import ring
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.plan import Sweep

SWEEP = "configs/sweeps/crowd_ring_symmetric.yaml"
HALT = 0.1
"""|w_k| below this fraction of the mean |w| counts as halted."""
PINS = {
    "count": "crowd.count",
    "friction": "crowd.body.motion.friction",
    "flow": "flow.enabled",
    "speed": "crowd.body.motion.speed",
}
"""The options that pin an axis of the sweep, and the axis each pins."""


def sweep_point(sweep: str, pins: dict[str, str], t_end: float) -> RotorConfig:
    """The sweep's resolved config with the axes `pins` (axis: value) pinned, run to
    `t_end`; the sweep's axes left unpinned must have one value."""
    overrides = [f"axes.{axis}=[{value}]" for axis, value in pins.items()]
    runs = Sweep.load(sweep, overrides).runs()
    if len(runs) != 1:
        raise SystemExit(f"{sweep}: pin every axis with more than one value ({len(runs)} runs)")
    data = runs[0].config
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
        speeds.append(ring.angular_velocity(x, y, p[:, 3], p[:, 4])[1])
        angles.append(ring.ring_angles(x, y, (0.0, 0.0)))
        times.append(float(t))
    return np.array(times), np.array(speeds), np.unwrap(np.array(angles), axis=0)


def analyse(
    t: np.ndarray, w: np.ndarray, theta: np.ndarray, radius: float, contact: tuple[float, float]
) -> dict:
    """The wave measures of the module docstring from the late records; `contact` =
    (a footprint's reach, ``contact.range``)."""
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
    mean_abs = np.abs(w).mean()
    spacing = 2 * math.pi * radius / n
    step = np.diff(theta, axis=1, append=theta[:, :1] + 2 * math.pi)
    distance = 2 * radius * np.abs(np.sin(step / 2))  # neighbours' centres, on the track
    reach, reach_range = contact
    touching = (distance - 2 * reach < reach_range).any(axis=1)
    spread = float(ring.spacing_spread(theta).mean())
    mobility = ring.gap_mobility(theta)
    return {
        "mode": ring.ring_mode(float(mean_abs), float(w.mean()), spread, mobility),
        "spacing spread": spread,
        "gap mobility": mobility,
        "mean |arc speed|": float(mean_abs),
        "mean signed arc speed": float(w.mean()),
        "rms arc speed": float(np.sqrt((w**2).mean())),
        "mode powers m = 0..N/2": np.array2string(power, precision=3),
        "leading m": m,
        "Omega": omega,
        "travelling share": travelling,
        "swing / spacing": swing / spacing,
        "halted share": float((np.abs(w) < HALT * mean_abs).mean()),
        "least w / mean |w|": float(w.min(axis=0).mean() / mean_abs),
        "largest w / mean |w|": float(w.max(axis=0).mean() / mean_abs),
        "least distance / spacing": float(distance.min() / spacing) if n > 1 else math.nan,
        "contact share": float(touching.mean()) if n > 1 else 0.0,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sweep", default=SWEEP)
    parser.add_argument("--count", type=int)
    parser.add_argument("--friction", type=float)
    parser.add_argument("--flow", choices=["off", "on"])
    parser.add_argument("--speed", type=float, help="the boats' start speed")
    parser.add_argument("--t-end", type=float, default=60.0)
    parser.add_argument("--record", type=float, default=0.05)
    parser.add_argument("--from", dest="start", type=float, default=30.0)
    parser.add_argument("--windows", type=float, help="also each window of this length")
    args = parser.parse_args()
    given = {name: getattr(args, name) for name in PINS if getattr(args, name) is not None}
    if "flow" not in given and PINS["flow"] in Sweep.load(args.sweep).axes:
        given["flow"] = "off"  # a sweep's flow axis is pinned off unless --flow says
    flow = {"on": "true", "off": "false"}
    pins = {PINS[name]: flow.get(value, value) for name, value in given.items()}
    config = sweep_point(args.sweep, pins, args.t_end)
    start, (cx, cy) = config.bodies[0].start, config.grid.domain_centre
    radius = math.hypot(start.x - cx, start.y - cy)  # the track's, about the vessel's centre
    contact = (config.bodies[0].reach(config.geometry.smoothing), config.contact.range)
    t, w, theta = record(Simulation(config), args.t_end, args.record)
    late = t >= args.start
    point = ", ".join(
        f"{name} {value:g}" if isinstance(value, float) else f"{name} {value}"
        for name, value in given.items()
    )
    print(f"{args.sweep}, {point}: records {late.sum()} from t = {args.start:g} to {args.t_end:g}")
    for name, value in analyse(t[late], w[late], theta[late], radius, contact).items():
        print(f"  {name}: {value:.4g}" if isinstance(value, float) else f"  {name}: {value}")
    for a in np.arange(0.0, args.t_end - 1e-9, args.windows) if args.windows else []:
        inside = (t > a) & (t <= a + args.windows)
        m = analyse(t[inside], w[inside], theta[inside], radius, contact)
        print(
            f"  t = {a:g} to {a + args.windows:g}: {m['mode']}, mean |w| "
            f"{m['mean |arc speed|']:.4g}, mean w {m['mean signed arc speed']:.4g}, "
            f"spread {m['spacing spread']:.3g}"
        )


if __name__ == "__main__":
    main()
