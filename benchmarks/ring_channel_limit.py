"""Camphor boats in a narrowing no-flux ring channel against the 1D theory of docs/ring.md.

The 1D theory (`pde_rotor/theory/ring.py`) averages Eq. (eqc) across a channel of width w
much narrower than the decay length sqrt(D/a) = 1, and pulls a boat that spans the channel
by k [c(rear) - c(front)]. The 2D model of the same boat: a strip plate l x b (l = 0.3,
b = 0.1) on a circular track of radius R = 3 (ring length L = 6 pi) in the annulus
R - w/2 < r < R + w/2 with both walls no-flux, its camphor from a pill of radius 0.05 at
the rear, touching the plate's rear edge (centre x = -0.1: a pill must lie inside its
plate), D = a = k = 1. Matching the two:

* supply: the width-averaged c of a pill of supply S is S/w times the 1D Green's
  function, so the 1D k s0 = k S / w: each rung sets S = w (k s0 = 1);
* friction: a strip of width b feels k b [c(rear) - c(front)] and the friction
  mu_2D A V, A = int F dA = l b + pi^2 delta^2 / 3 (the smoothed rectangle), so the 1D
  mu = mu_2D A / b: each rung sets mu_2D = mu b / A (mu = 0.1 by default);
* the source: the 1D point source at the pill's centre, 0.05 ahead of the rear end
  (:func:`theory_speed`; the theory's ``source="rear"``, 0.05 further back, is printed
  beside it);
* the boats: N evenly spaced on the ring, released from rest (c = v = 0); the mass
  1e-3 relaxes the speed within m / (mu_2D A) ~ 0.1, so the steady speed is the
  overdamped theory's.

A body's footprint (plate and pills plus 20 delta, a disk about its centre,
`BodyConfig.reach`) must lie inside the channel: w > 2 hypot(l/2 + 20 delta, b/2 + 20 delta).
Each rung halves dx, takes delta = dx/2 and dt = 0.16 dx^2 (the coarse grid's 4e-4 at
dx = 0.05), and the narrowest channel that fits with a margin of about one tenth; the
channel can therefore never be narrower than the boat is long (w -> 2 hypot(l/2, b/2) =
0.32 as delta -> 0): the footprint's shape, not the cost, bounds the ladder.

``--theory`` prints, for the rungs' widths and narrower ones down to w = b, the exact 2D
steady speed of the same boat in a straight channel (`pde_rotor/theory/ring_channel.py`),
which tends to the 1D theory's as b / w -> 1 (the width average is exact for a boat that
spans the channel): the part of the 2D-1D difference that the channel's width makes, and
what the ladder cannot reach.

``--span`` runs the same ladder with a boat that spans the channel (``motion.spans``,
docs/bodies.md): a strip l = 0.3 long and w + 2 (20 delta + 2 dx) wide, its plate past
both no-flux walls, so that the water wets its full front and rear edges, the 1D model's
boat. The width average of Eq. (eqc) is then exact in a straight channel at any width,
and what is left between the 2D ring and the 1D theory is the channel's curvature w / R,
the grid, and the plate, under which the 2D model stops the evaporation (Eq. (eqc):
-a (1 - F) c) while the 1D theory evaporates everywhere. Matching: S = w (k s0 = 1) and
mu_2D = mu / l (the wet plate's area A = l w, its force k w [c(rear) - c(front)]), and
the pill's supply divided by the smoothed pill's excess on the grid (:func:`pill_excess`:
its sum of G dA is pi rho^2 times 1.202, 1.051, 1.013, 1.003 on the rungs), so that the
camphor each boat gives the water is w, as the 1D theory's k s0 = 1 asks.
The pill's footprint (rho + 20 delta + dx) must lie inside both walls, which sets each
rung's narrowest channel: (dx, w) = (0.05, 1.25), (0.025, 0.7), (0.0125, 0.4),
(0.00625, 0.25). Printed beside the 1D theory: the 1D model with the evaporation
stopped under the plate (:func:`plate_theory_speed`, a direct periodic solve of the
co-moving steady state), the 1D limit the 2D spanning boat tends to.

Printed per run: the mean arc speed of the boats over [t_from, t_end] (and over its two
halves, the drift), the 1D theory's speed V at the matched parameters, V_2D / V_1D, and the straight
channel's exact speed at the rung's width with V_2D over it.
``--dry-run`` prints every rung's cells, steps and estimated cost (``pde_rotor/sweep/cost.py``,
one idle core; the ring's estimate was measured 25-30 % low, docs/results.md) and the total
in core-hours.

Estimated (``--dry-run``, N = 1 and 8, flow off and on, t_end = 6): rungs 0 and 1 about
0.11 core-hours, rung 2 1.0, rung 3 10.9, rung 4 142; the whole ladder 154 core-hours.
Run (the narrow strip's rungs 0 and 1 and the spanning boat's rungs 0 to 3 were run,
docs/results.md 2026-11-28; rung 3 with ``--span`` took 2.0 core-hours for N = 1, 4, 8
with and without flow; the straight channel alone takes seconds):
    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/ring_channel_limit.py --dry-run
    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/ring_channel_limit.py \
        --rungs 2 3 --count 1 8 --flow off on
    PYTHONPATH=. python benchmarks/ring_channel_limit.py --theory
    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/ring_channel_limit.py --span \
        --rungs 0 1 --count 1 4 --flow off on --t-end 4.5
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq
from scipy.sparse.linalg import spsolve

from pde_rotor import RotorConfig
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep.cost import estimate_run
from pde_rotor.theory.ring import RingBoats, bloch_green, travelling_speed
from pde_rotor.theory.ring_channel import ChannelBoats, channel_speed

LENGTH, WIDTH, PILL = 0.3, 0.1, 0.05
"""The boat: strip length l, width b, pill radius (the pill touching the rear edge)."""
SOURCE = -LENGTH / 2 + PILL
"""sigma, the pill's centre relative to the boat's centre."""
RADIUS = 3.0
"""R, the track's radius (ring length 6 pi, the canonical case)."""
RUNGS = [(0.05, 1.9), (0.025, 1.1), (0.0125, 0.72), (0.00625, 0.53), (0.003125, 0.44)]
"""(dx, w) of each rung: delta = dx / 2, dt = 0.16 dx^2, w the narrowest channel the footprint
fits in with a margin (footprint diameters 1.70, 1.00, 0.65, 0.48, 0.40)."""
MASS = 1e-3
SPAN_RUNGS = [(0.05, 1.25), (0.025, 0.7), (0.0125, 0.4), (0.00625, 0.25)]
"""(dx, w) of each rung of the spanning boat: the narrowest channel that holds the pill's
footprint, rho + 20 delta + dx, inside both walls."""


def pill_excess(dx: float, places: int = 64) -> float:
    """The smoothed pill's supply over its nominal one, sum_cells G dx^2 / (pi rho^2) with
    G = 1/2 [1 + tanh((rho - |r - P|) / delta)] on the grid (Sommerfeld: about
    1 + pi^2 delta^2 / (12 rho^2), 1.21 at delta = rho / 2), averaged over `places` pill
    centres P along the track (the lattice's share)."""
    delta = smoothing(dx)
    span = PILL + 20 * delta
    total = 0.0
    for m in range(places):
        angle = 2 * math.pi * (m + 0.5) / places
        px, py = RADIUS * math.cos(angle), RADIUS * math.sin(angle)
        ix = np.arange(math.floor((px - span) / dx), math.ceil((px + span) / dx) + 1)
        iy = np.arange(math.floor((py - span) / dx), math.ceil((py + span) / dx) + 1)
        x, y = np.meshgrid((ix + 0.5) * dx, (iy + 0.5) * dx, indexing="ij")
        g = 0.5 * (1 + np.tanh((PILL - np.hypot(x - px, y - py)) / delta))
        total += g.sum() * dx**2 / (math.pi * PILL**2)
    return total / places


def rung_of(rung: int, span: bool) -> tuple[float, float]:
    """(dx, w) of a rung of the ladder (`span`: the spanning boat's)."""
    return (SPAN_RUNGS if span else RUNGS)[rung]


def span_width(rung: int) -> float:
    """The spanning boat's plate width: the channel and 20 delta + 2 dx past each wall."""
    dx, w = SPAN_RUNGS[rung]
    return w + 2 * (20 * smoothing(dx) + 2 * dx)


def smoothing(dx: float) -> float:
    """delta of a rung."""
    return 0.5 * dx


def friction_2d(mu: float, dx: float) -> float:
    """mu_2D whose matched 1D friction mu_2D A / b is `mu`."""
    area = LENGTH * WIDTH + math.pi**2 * smoothing(dx) ** 2 / 3
    return mu * WIDTH / area


def config(
    rung: int, count: int, flow: bool, mu: float, t_end: float, span: bool = False
) -> RotorConfig:
    """The rung's channel with `count` evenly spaced boats (`span`: spanning boats)."""
    dx, w = rung_of(rung, span)
    width, friction = (span_width(rung), mu / LENGTH) if span else (WIDTH, friction_2d(mu, dx))
    supply = w / pill_excess(dx) if span else w
    motion = {"kind": "track", "mass": MASS, "friction": friction, "spans": span}
    reach = math.hypot(LENGTH / 2 + 20 * smoothing(dx), width / 2 + 20 * smoothing(dx))
    bodies = [
        {
            "name": f"boat{k}",
            "plate": {"shape": "strip", "length": LENGTH, "width": width},
            "pills": [{"x": SOURCE, "y": 0.0, "radius": PILL, "supply": supply}],
            "motion": motion,
            "start": {
                "x": RADIUS * math.cos(2 * math.pi * k / count),
                "y": RADIUS * math.sin(2 * math.pi * k / count),
            },
        }
        for k in range(count)
    ]
    return RotorConfig.model_validate(
        {
            "grid": {
                "domain_radius": RADIUS + (reach + 2 * dx if span else w / 2),
                "dx": dx,
                "dt": 0.16 * dx**2,
                "vessel": {
                    "shape": "annulus",
                    "inner_radius": RADIUS - w / 2,
                    "outer_radius": RADIUS + w / 2,
                    "inner_wall": "no_flux",
                    "outer_wall": "no_flux",
                },
            },
            "numerics": {"scheme": "paper"},
            "geometry": {"smoothing": smoothing(dx)},
            "flow": {"enabled": flow},
            "protocol": {"t_ini": t_end, "cycles": 0},
            "output": {"progress": False},
            "bodies": bodies,
        }
    )


def theory_speed(count: int, mu: float, source: float = SOURCE) -> float:
    """The 1D travelling state's speed at the matched parameters, the point source at
    `source` from the boat's centre: the largest root of mu V = k s0 [G_d(e_r) - G_d(e_f)]
    (docs/ring.md), e_r = -l/2 - sigma, e_f = l/2 - sigma."""
    boats = RingBoats(2 * math.pi * RADIUS, LENGTH, count, mu, source="rear")
    if source == -LENGTH / 2:
        return travelling_speed(boats)
    rear, front = -LENGTH / 2 - source, LENGTH / 2 - source

    def excess(v: float) -> float:
        args = (boats.spacing, v, 1.0)
        return (bloch_green(rear, *args) - bloch_green(front, *args)).real - mu * v

    top = 2 * (1 / boats.spacing + 0.5) / mu + 1
    grid = np.geomspace(1e-6, top, 2000)
    values = [excess(v) for v in grid]
    roots = [
        brentq(excess, lo, hi, xtol=1e-13)
        for lo, hi, f_lo, f_hi in zip(grid[:-1], grid[1:], values[:-1], values[1:], strict=True)
        if f_lo * f_hi < 0
    ]
    return roots[-1] if roots else 0.0


def plate_theory_speed(count: int, mu: float, points: int = 40000, stopped: bool = True) -> float:
    """The 1D travelling state's speed with the evaporation stopped under the plate
    (|x - X| < l/2), as the 2D model stops it under F: the co-moving steady state
    D c'' + V c' - a (1 - chi) c + k s0 delta(x - X - sigma) = 0 on the ring of length
    d = L / N (periodic, central differences on `points` nodes, the source split
    linearly between its two nodes), the boat pulled by c(rear end) - c(front end)
    (linear interpolation), and the largest root of mu V = that force near the 1D
    theory's speed (D = a = k s0 = 1). `stopped` False: evaporation everywhere, the 1D
    theory's own case (the check of the solve against the closed form)."""
    spacing = 2 * math.pi * RADIUS / count
    h = spacing / points
    x = -spacing / 2 + h * np.arange(points)
    decay = np.where(stopped & (np.abs(x) < LENGTH / 2), 0.0, 1.0)
    rhs = np.zeros(points)
    at = (SOURCE + spacing / 2) / h
    i = math.floor(at)
    rhs[i], rhs[i + 1] = -(1 - (at - i)) / h, -(at - i) / h

    def sample(c: np.ndarray, point: float) -> float:
        u = (point + spacing / 2) / h
        j = math.floor(u)
        return (1 - (u - j)) * c[j] + (u - j) * c[j + 1]

    def excess(v: float) -> float:
        ahead, behind = 1 / h**2 + v / (2 * h), 1 / h**2 - v / (2 * h)
        matrix = sp.diags(
            [np.full(points, -2 / h**2) - decay, np.full(points - 1, ahead),
             np.full(points - 1, behind), [behind], [ahead]],
            [0, 1, -1, points - 1, -(points - 1)],
            format="csc",
        )  # fmt: skip
        c = spsolve(matrix, rhs)
        return sample(c, -LENGTH / 2) - sample(c, LENGTH / 2) - mu * v

    guess = theory_speed(count, mu)
    return brentq(excess, 0.5 * guess, 2 * guess, xtol=1e-10)


def straight_speed(width: float, count: int, mu: float) -> float:
    """The exact 2D steady speed of the same boats in a straight channel of `width`
    (`pde_rotor/theory/ring_channel.py`: sharp strip, evaporation also under the plate)."""
    boats = ChannelBoats(2 * math.pi * RADIUS, count, width, LENGTH, WIDTH, PILL, SOURCE, mu)
    guess = theory_speed(count, mu)
    return channel_speed(boats, guess / 20, 20 * guess)


def arc_speeds(sim: Simulation) -> np.ndarray:
    """Each boat's arc speed (U . e_theta) about the vessel's centre."""
    p = sim.bodies.poses
    theta = np.arctan2(p[:, 1], p[:, 0])
    return -p[:, 3] * np.sin(theta) + p[:, 4] * np.cos(theta)


def run(
    rung: int, count: int, flow: bool, mu: float, times: tuple[float, float], span: bool
) -> None:
    """Run one case to times[1], average from times[0], and print its line."""
    t_from, t_end = times
    cfg = config(rung, count, flow, mu, t_end, span)
    sim = Simulation(cfg)
    every = 0.05
    times, speeds = [], []
    start = time.process_time()
    while sim.t < t_end - 1e-9:
        sim.run(min(t_end, sim.t + every))
        times.append(sim.t)
        speeds.append(arc_speeds(sim))
    cpu = time.process_time() - start
    t, v = np.array(times), np.array(speeds)
    late = t >= t_from
    middle = 0.5 * (t_from + t_end)
    mean = v[late].mean()
    halves = v[late & (t < middle)].mean(), v[t >= middle].mean()
    spread = np.ptp(v[late].mean(axis=0)) / mean
    dx, w = rung_of(rung, span)
    v1 = theory_speed(count, mu)
    if span:
        plate = plate_theory_speed(count, mu)
        print(
            f"span rung {rung} dx={dx:g} w={w:g} N={count} flow={'on' if flow else 'off'} "
            f"mu={mu:g}: V_2D={mean:.4f} (halves {halves[0]:.4f}, {halves[1]:.4f}; boats "
            f"differ by {spread:.1e}) V_1D={v1:.4f} V_2D / V_1D - 1 = {mean / v1 - 1:+.4f}; "
            f"1D with the plate's evaporation stopped V={plate:.4f}, V_2D / V - 1 = "
            f"{mean / plate - 1:+.4f}; cpu={cpu:.0f}s",
            flush=True,
        )
        return
    rear = theory_speed(count, mu, -LENGTH / 2)
    straight = straight_speed(w, count, mu)
    print(
        f"rung {rung} dx={dx:g} w={w:g} N={count} flow={'on' if flow else 'off'} mu={mu:g}: "
        f"V_2D={mean:.4f} (halves {halves[0]:.4f}, {halves[1]:.4f}; boats differ by "
        f"{spread:.1e}) V_1D={v1:.4f} ratio={mean / v1:.4f} (source at the rear end: "
        f"V_1D={rear:.4f}, ratio {mean / rear:.4f}); straight channel V={straight:.4f}, "
        f"V_2D / V = {mean / straight:.4f}; cpu={cpu:.0f}s",
        flush=True,
    )


def theory(args: argparse.Namespace) -> None:
    """Print the straight channel's exact 2D speed against the 1D theory's, w down to b."""
    for count in args.count:
        v1 = theory_speed(count, args.mu)
        for w in [*(w for _, w in RUNGS), 0.3, 0.2, 0.15, 0.12, WIDTH]:
            v = straight_speed(w, count, args.mu)
            print(
                f"N={count} w={w:g}: straight channel V={v:.4f}, V_1D={v1:.4f}, ratio {v / v1:.4f}"
            )


def dry_run(args: argparse.Namespace) -> None:
    """Print each case's estimated cost and the total."""
    total = 0.0
    for rung in args.rungs:
        for count in args.count:
            for flow in args.flow:
                cfg = config(rung, count, flow == "on", args.mu, args.t_end, args.span)
                est = estimate_run(cfg, movie=False)
                total += est.seconds
                dx, w = rung_of(rung, args.span)
                reach = cfg.body_list()[0].reach(cfg.geometry.smoothing)
                print(
                    f"rung {rung} dx={dx:g} w={w:g} (footprint {2 * reach:.3f}) N={count} "
                    f"flow={flow}: {est.cells} cells, {est.steps} steps, "
                    f"{est.seconds / 3600:.3f} core-h"
                )
    print(f"total {total / 3600:.2f} core-hours (estimate on one idle core)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rungs", type=int, nargs="+", default=list(range(len(RUNGS))))
    parser.add_argument("--count", type=int, nargs="+", default=[1, 8])
    parser.add_argument("--flow", nargs="+", default=["off", "on"], choices=["off", "on"])
    parser.add_argument("--mu", type=float, default=0.1, help="the 1D friction")
    parser.add_argument("--t-end", type=float, default=6.0)
    parser.add_argument("--t-from", type=float, default=3.0, help="start of the average")
    parser.add_argument("--dry-run", action="store_true")
    parser.add_argument("--theory", action="store_true", help="the straight channel only")
    parser.add_argument("--span", action="store_true", help="boats that span the channel")
    args = parser.parse_args()
    if args.theory and args.span:
        for count in args.count:
            v1, plate = theory_speed(count, args.mu), plate_theory_speed(count, args.mu)
            check = plate_theory_speed(count, args.mu, stopped=False)
            print(
                f"N={count}: V_1D={v1:.5f} (the periodic solve: {check:.5f}), with the "
                f"plate's evaporation stopped {plate:.5f}"
            )
        return
    if args.theory:
        theory(args)
        return
    if args.dry_run:
        dry_run(args)
        return
    for rung in args.rungs:
        for count in args.count:
            for flow in args.flow:
                run(rung, count, flow == "on", args.mu, (args.t_from, args.t_end), args.span)


if __name__ == "__main__":
    main()
