"""Camphor boats on a ring in 1D: the exact theory against a direct solve.

The canonical case: ring length 6 pi, boats of length 0.3, D = a = 1, k s0 = 1, evaporation
everywhere (pde_rotor.theory.ring). For camphor from the rear end, for each N and mu: the
speed V of N evenly spaced boats (theory :func:`travelling_speed`; direct: the mean speed
after `--settle` time units from rest, c = 0, even spacing) and the leading growth rate of
each spacing mode m (theory :func:`spacing_rates`; direct: the boats are then displaced by
a random vector of size `--kick` d and each mode's amplitude sum_i x_i e^{-2 pi i m i / N} is
fitted to e^{lambda t} from `--skip` time units on, while above 1e-8 of its start). For
camphor from the centre: the critical friction of each N (the pitchfork of moving together
and the Hopf friction of each mode, :func:`rest_critical_friction`), checked by the growth
rate of the critical mode at mu_c (1 -+ `--margin`), interpolated linearly to zero and
compared with the theory's rates at the same frictions interpolated alike (lambda is not
linear in mu over the bracket, so the interpolation alone moves the zero): the boats rest
`--settle` time units, are displaced by 1e-6 d at random and watched for 6 / |lambda| (20 to
150); the common speed's rate is fitted to log |V| (m = 0), a spacing mode's two exponents
by linear prediction (Prony) and the larger kept.

Run:  OPENBLAS_NUM_THREADS=1 python benchmarks/ring_1d.py [--modes 512] [--dt 0.04]
          [--count 1 2 3 4 6 8 12] [--mu 0.05 0.1 0.2] [--variant rear|centre|both]
          [--skip-direct]

Hold BLAS to one thread (a matrix-vector product per step): on a loaded machine its threads
wait on each other and a run takes up to 40 times longer.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from pde_rotor.theory.ring import (
    RingBoats,
    rest_critical_friction,
    rest_hopf_friction,
    rest_pitchfork_friction,
    spacing_rates,
    spacing_roots,
    travelling_speed,
)
from pde_rotor.theory.ring_solve import RingSolver, fitted_rate, mode_amplitudes

LENGTH = 6 * math.pi
BOAT = 0.3


def fmt(z: complex | None) -> str:
    if z is None:
        return "< -0.98"
    if abs(z.imag) < 5e-5:
        return f"{z.real:.4f}"
    return f"{z.real:.4f} ± {abs(z.imag):.4f}i"


def measured(times: np.ndarray, amp: np.ndarray, skip: float) -> complex:
    """lambda of one complex exponential, fitted from `skip` on while above 1e-8 of its start."""
    keep = (times >= times[0] + skip) & (np.abs(amp) > 1e-8 * np.abs(amp[0]))
    return fitted_rate(times[keep], amp[keep])


def rear(args) -> None:
    print(
        "| N | mu | V theory | V direct | rel. diff | mode m | lambda theory "
        "| lambda direct | rel. diff (Re) |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    rng = np.random.default_rng(1)
    for n in args.count:
        for mu in args.mu:
            boats = RingBoats(LENGTH, BOAT, n, mu)
            v = travelling_speed(boats)
            rates = spacing_rates(boats, v)
            if args.skip_direct:
                for m in range(n // 2 + 1):
                    print(f"| {n} | {mu} | {v:.6f} | | | {m} | {fmt(rates[m])} | | |")
                continue
            t0 = time.perf_counter()
            solver = RingSolver(boats, args.modes, boats.spacing * np.arange(n))
            run = solver.run(args.settle, args.dt, every=10)
            vd = run.velocities[-1].mean()
            solver.positions = solver.positions + args.kick * boats.spacing * rng.standard_normal(n)
            run = solver.run(args.watch, args.dt, every=5)
            amps = mode_amplitudes(run, boats.spacing)
            for m in range(n // 2 + 1):
                theory = rates[m]
                if m == 0:
                    dv = np.abs(run.velocities.mean(axis=1) - vd)
                    keep = (run.times > run.times[0] + 0.5) & (run.times < run.times[0] + 3)
                    direct = np.polyfit(run.times[keep], np.log(dv[keep]), 1)[0]
                    text, diff = f"mean speed: {direct:.2f}", ""
                else:
                    lam = measured(run.times, amps[:, m], args.skip)
                    text = fmt(lam)
                    diff = f"{(lam.real - theory.real) / abs(theory.real):+.2%}"
                vcell = f"{vd:.6f} | {(vd - v) / v:+.1e}" if m == 0 else " | "
                vt = f"{v:.6f}" if m == 0 else ""
                print(
                    f"| {n} | {mu} | {vt} | {vcell} | {m} | {fmt(theory)} | {text} | {diff} |",
                    flush=True,
                )
            print(f"<!-- N={n} mu={mu}: {time.perf_counter() - t0:.1f} s -->", flush=True)


def prony(times: np.ndarray, amp: np.ndarray) -> np.ndarray:
    """The two exponents of amp ~ A e^{l1 t} + B e^{l2 t} (linear prediction, least squares)."""
    rows = np.column_stack([amp[1:-1], amp[:-2]])
    coef = np.linalg.lstsq(rows, amp[2:], rcond=None)[0]
    roots = np.roots([1.0, -coef[0], -coef[1]])
    return np.log(roots.astype(complex)) / (times[1] - times[0])


def centre(args) -> None:
    print(
        "| N | pitchfork mu | Hopf mu (m, omega) | mu_c theory | critical mode "
        "| mu_c direct | diff. from the theory's rates interpolated alike |"
    )
    print("|---|---|---|---|---|---|---|")
    rng = np.random.default_rng(2)
    for n in args.count:
        boats = RingBoats(LENGTH, BOAT, n, 1.0, source="centre")
        fork = rest_pitchfork_friction(boats)
        hopf = [rest_hopf_friction(boats, m) for m in range(n)]
        best_m = max(range(n), key=lambda m: hopf[m][0])
        mu_c = rest_critical_friction(boats)
        critical = 0 if fork >= hopf[best_m][0] else best_m
        hopf_text = (
            f"{hopf[best_m][0]:.5f} ({best_m}, {hopf[best_m][1]:.4f})"
            if hopf[best_m][0] > 0
            else "none"
        )
        row = f"| {n} | {fork:.5f} | {hopf_text} | {mu_c:.5f} | {critical} |"
        if args.skip_direct:
            print(row + " | |")
            continue
        found = []
        for factor in (1 - args.margin, 1 + args.margin):
            b = RingBoats(LENGTH, BOAT, n, mu_c * factor, source="centre")
            theory = spacing_roots(b, 0.0, critical)[0]
            watch = float(np.clip(6.0 / abs(theory.real), 20.0, 150.0))
            solver = RingSolver(b, args.modes, b.spacing * np.arange(n))
            solver.run(args.settle, args.dt, every=1000)
            solver.positions = solver.positions + 1e-6 * b.spacing * rng.standard_normal(n)
            run = solver.run(watch, args.dt, every=5)
            late = run.times >= run.times[0] + args.skip
            if critical == 0:  # the common speed: one exponential (the shift's root is 0)
                speed = np.abs(run.velocities.mean(axis=1))
                lam = np.polyfit(run.times[late], np.log(speed[late]), 1)[0]
            else:  # a pair of roots of the mode: its two exponents, the larger kept
                stride = max(1, round(0.5 / (run.times[1] - run.times[0])))
                amp = mode_amplitudes(run, b.spacing)[late, critical][::stride]
                lam = max(prony(run.times[late][::stride], amp), key=lambda z: z.real).real
            found.append((mu_c * factor, float(lam), theory.real))
            print(
                f"<!-- N={n} mu={mu_c * factor:.5f}: Re lambda direct {lam:.5f}, "
                f"theory {theory.real:.5f} (watched {watch:.0f}) -->",
                flush=True,
            )
        (m1, r1, t1), (m2, r2, t2) = found
        direct = m1 - r1 * (m2 - m1) / (r2 - r1)
        same = m1 - t1 * (m2 - m1) / (t2 - t1)  # the theory's rates interpolated alike
        print(f"{row} {direct:.5f} | {(direct - same) / same:+.2%} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--modes", type=int, default=512)
    parser.add_argument("--dt", type=float, default=0.04)
    parser.add_argument("--count", type=int, nargs="+", default=[1, 2, 3, 4, 6, 8, 12])
    parser.add_argument("--mu", type=float, nargs="+", default=[0.05, 0.1, 0.2])
    parser.add_argument("--settle", type=float, default=30.0)
    parser.add_argument("--watch", type=float, default=40.0)
    parser.add_argument("--skip", type=float, default=8.0)
    parser.add_argument("--kick", type=float, default=1e-3)
    parser.add_argument("--margin", type=float, default=0.05)
    parser.add_argument("--variant", choices=["rear", "centre", "both"], default="both")
    parser.add_argument("--skip-direct", action="store_true", help="theory only")
    args = parser.parse_args()
    if args.variant in ("rear", "both"):
        rear(args)
    if args.variant in ("centre", "both"):
        print()
        centre(args)


if __name__ == "__main__":
    main()
