"""Onset friction of N symmetric boats at rest in the ring channel, from the linearisation.

The channel of ``configs/sweeps/crowd_ring.yaml`` (annulus 3.6 < r < 5.6, no-flux walls,
dx = 0.05, dt = 4e-4, delta = 0.025, the consistent scheme, contact on, flow off unless
``--flow``), with N boats evenly spaced on the track of radius 4.6, each a strip 0.3 x
0.15 (mass 1e-3) whose camphor pill (radius 0.05) sits at its centre (the sweep's sits at
x = -0.1): the boats can rest. For each N: the leading eigenvalues along the boats'
common friction (``bodies[*].motion.friction`` at `--values`,
:func:`pde_rotor.stability.continuation.follow`, the default frame: the boats' relative
positions kept, their common turn co-moving), the critical mu_c where the leading real
part crosses 0 and its kind (pitchfork or Hopf, frequency), and the mode m of the
critical eigenvector (the largest |sum_k w_k e^{-2 pi i m k / N}| of the boats' arc
speeds w_k: m = 0 the boats moving together, m = N/2 alternating). Besides: the
linearisation's time, the rest acceleration (0 by symmetry) and |K g|, the lattice's
stiffness along the common turn, which the default frame drops; for N > 1 the stiffness
matrix K (d acceleration_k / d s_j at the rest field moved with the boats) split into its
row sums (0 in the continuum, where moving every boat together moves nothing: the
lattice's part) and a boat's coupling to its neighbours (the camphor's).

``--lattice``: instead, one boat alone at 0, 30, 45, 60 and 90 degrees about the centre:
its stiffness K along the track (the lattice's spring, 0 in the continuum) and its
acceleration at rest; the boats of N = 3 and 6 sit at angles of both signs of K.

Run (one thread): ``NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python
benchmarks/stability_ring.py --counts 1 2 3 4 6 8 [--flow] [--dx 0.05] [--values 0.05 0.1
0.2 0.4] [--rtol 1e-4] [--time-only] [--positions] [--scan 0.2 0.22 11] [--lattice]``.
``--scan`` replaces the branch by each |m|'s leading eigenvalue on a grid of frictions
(the modes that move no boat skipped), the crossings of each |m| by linear interpolation:
the onsets that the leading eigenvalue hides.
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Any

import numpy as np

from pde_rotor.config import validate_config
from pde_rotor.stability import DiscreteModel, follow, leading_modes, linearise
from pde_rotor.stability.continuation import spectrum_at
from pde_rotor.sweep.placement import CrowdSpec, place

KEY = "bodies[*].motion.friction"
TRACK_RADIUS = 4.6


def ring_data(count: int, friction: float, flow: bool, dx: float = 0.05) -> dict[str, Any]:
    """The ring channel with `count` symmetric boats evenly spaced (module docstring), on a
    grid of spacing `dx` (dt scaled with dx^2 from the sweep's 4e-4 at 0.05)."""
    boat = {
        "name": "boat",
        "plate": {"shape": "strip", "length": 0.3, "width": 0.15},
        "pills": [{"x": 0.0, "y": 0.0, "radius": 0.05}],
        "motion": {"kind": "track", "mass": 1e-3, "friction": friction},
    }
    crowd = {"count": count, "body": boat, "placement": {"kind": "ring", "radius": TRACK_RADIUS}}
    bodies = place(CrowdSpec.model_validate(crowd), (0.0, 0.0), 0)
    return {
        "grid": {
            "domain_radius": 5.6,
            "dx": dx,
            "dt": 4e-4 * (dx / 0.05) ** 2,
            "vessel": {
                "shape": "annulus",
                "inner_radius": 3.6,
                "outer_radius": 5.6,
                "inner_wall": "no_flux",
                "outer_wall": "no_flux",
            },
        },
        "geometry": {"smoothing": 0.025},
        "numerics": {"scheme": "consistent", "integrator": "euler"},
        "flow": {"enabled": flow},
        "contact": {"enabled": True, "range": 0.05, "damping": 0.05},
        "bodies": bodies,
    }


def mode_number(w: np.ndarray) -> int:
    """The |m| of largest |sum_k w_k e^{-2 pi i m k / N}| (m and N - m, waves travelling
    either way, are one |m| <= N / 2)."""
    j = int(np.argmax(np.abs(np.fft.fft(w))))
    return min(j, w.size - j)


def mode_scan(data: dict[str, Any], values: np.ndarray, k: int) -> None:
    """For each |m|, the largest Re lambda among the boats' modes of that |m| at each
    friction of `values`, and where it crosses 0 (linear interpolation between values)."""
    count = len(data["bodies"])
    table: dict[int, list[complex]] = {}
    for value in values:
        lin = linearise(DiscreteModel(validate_config(_at(data, value))))
        spectrum = leading_modes(lin, k=k)
        best: dict[int, complex] = {}
        for j, lam in enumerate(spectrum.eigenvalues):
            w = lin.split(spectrum.vectors[:, j], lam)["dp"]
            if np.abs(w).max() < 1e-6 * np.abs(spectrum.vectors[:, j]).max():
                continue  # a field mode
            m = mode_number(w)
            if m not in best or lam.real > best[m].real:
                best[m] = complex(lam)
        for m in range(count // 2 + 1):
            table.setdefault(m, []).append(best.get(m, complex(np.nan, np.nan)))
    for m, lams in sorted(table.items()):
        rates = np.array([z.real for z in lams])
        shown = ", ".join(f"{z.real:+.5f}{abs(z.imag):+.4f}i" for z in lams)
        print(f"  |m| = {m}: {shown}", flush=True)
        for i in np.nonzero(np.sign(rates[:-1]) * np.sign(rates[1:]) < 0)[0]:
            a, b = rates[i], rates[i + 1]
            cross = values[i] + (values[i + 1] - values[i]) * a / (a - b)
            freq = abs(lams[i].imag) + (abs(lams[i + 1].imag) - abs(lams[i].imag)) * a / (a - b)
            print(f"  |m| = {m} crosses at mu = {cross:.5f}, frequency {freq:.4f}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--counts", type=int, nargs="+", default=[1, 2, 3, 4, 6, 8])
    parser.add_argument("--values", type=float, nargs="+", default=[0.05, 0.1, 0.2, 0.4])
    parser.add_argument("--flow", action="store_true")
    parser.add_argument("--dx", type=float, default=0.05, help="grid spacing (the sweep's)")
    parser.add_argument("--rtol", type=float, default=1e-4)
    parser.add_argument("--k", type=int, default=6)
    parser.add_argument("--time-only", action="store_true", help="one linearisation only")
    parser.add_argument(
        "--positions",
        action="store_true",
        help="every coordinate an unknown (the common turn too: the lattice's spring)",
    )
    parser.add_argument(
        "--scan",
        type=float,
        nargs=3,
        metavar=("A", "B", "POINTS"),
        help="instead of follow: each |m|'s leading Re lambda at POINTS frictions in [A, B]",
    )
    parser.add_argument("--lattice", action="store_true", help="a lone boat's K by angle")
    args = parser.parse_args()
    if args.lattice:
        for degrees in (0, 30, 45, 60, 90):
            data = ring_data(1, args.values[0], args.flow, args.dx)
            angle = math.radians(degrees)
            data["bodies"][0]["start"] = {
                "x": TRACK_RADIUS * math.cos(angle),
                "y": TRACK_RADIUS * math.sin(angle),
                "angle": math.remainder(angle + math.pi / 2, 2 * math.pi),
            }
            lin = linearise(DiscreteModel(validate_config(data)))
            print(
                f"dx = {args.dx:g}, one boat at {degrees} degrees: K = {lin.stiffness[0, 0]:+.4g}, "
                f"d(acceleration)/ds {lin.coordinate_rows[0, 0]:.4g}, rest acceleration "
                f"{lin.rest_acceleration[0]:+.2e}",
                flush=True,
            )
        return
    for count in args.counts:
        data = ring_data(count, args.values[0], args.flow, args.dx)
        start = time.perf_counter()
        lin = linearise(DiscreteModel(validate_config(data)))
        built = time.perf_counter() - start
        leading_modes(lin, k=args.k)
        solved = time.perf_counter() - start - built
        turn = lin.stiffness @ lin.frame[:, 0] if lin.frame.shape[1] else np.zeros(1)
        print(
            f"N = {count} (flow {args.flow}): {lin.n_fields} field unknowns, "
            f"{lin.small.shape[0]} mechanical ({lin.frame_name}); linearisation {built:.1f} s, "
            f"eigenvalues {solved:.1f} s; rest acceleration "
            f"{np.abs(lin.rest_acceleration).max():.1e}; |K g| {np.abs(turn).max():.3g}, "
            f"d(acceleration)/ds {np.abs(lin.coordinate_rows).max():.3g}",
            flush=True,
        )
        if count > 1:
            rows = lin.stiffness.sum(axis=1)
            print(
                f"  stiffness K: row sums (the lattice's part) {np.round(rows, 4)}; a boat's "
                f"pull by its neighbour ahead K_01 {lin.stiffness[0, 1]:+.4g} and behind "
                f"K_0,N-1 {lin.stiffness[0, count - 1]:+.4g}",
                flush=True,
            )
        if args.time_only:
            continue
        if args.scan:
            lo, hi, points = args.scan
            mode_scan(data, np.linspace(lo, hi, int(points)), max(args.k, 2 * count + 4))
            continue
        start = time.perf_counter()
        positions = True if args.positions else None
        branch = follow(data, KEY, args.values, k=args.k, rtol=args.rtol, positions=positions)
        for value, lam in zip(branch.values, branch.eigenvalues, strict=True):
            shown = ", ".join(f"{x.real:+.5f}{x.imag:+.5f}i" for x in lam[:4])
            print(f"  mu = {value:g}: {shown}", flush=True)
        if not branch.crossings:
            print("  no crossing in the range", flush=True)
        for cross in branch.crossings:
            at = spectrum_at(data, KEY, cross.value, k=args.k, positions=positions)
            model = DiscreteModel(validate_config(_at(data, cross.value)))
            lin = linearise(model, positions=positions)
            parts = lin.split(at.vectors[:, 0], at.eigenvalues[0])
            m = mode_number(parts["dp"])
            print(
                f"  mu_c = {cross.value:.6g} +- {cross.tolerance:.1e}: {cross.kind}, "
                f"frequency {cross.frequency:.5g}, mode m = {m} (|w_k| "
                f"{np.round(np.abs(parts['dp']) / np.abs(parts['dp']).max(), 3)}), "
                f"{cross.direction}; {time.perf_counter() - start:.0f} s",
                flush=True,
            )


def _at(data: dict[str, Any], friction: float) -> dict[str, Any]:
    """`data` with every boat's friction set."""
    out = {**data, "bodies": [dict(b) for b in data["bodies"]]}
    for body in out["bodies"]:
        body["motion"] = {**body["motion"], "friction": friction}
    return out


if __name__ == "__main__":
    main()
