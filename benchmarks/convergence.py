"""Convergence table of docs/model.md: omega_ss, asymmetry and memory torques vs dx and dt.

At the paper's fixed delta = 0.025, for each scheme variant (:data:`VARIANTS`: the
``paper`` scheme, the ``consistent`` scheme with its default prefilters, and with
Gaussian (``gaussian``) or sharpened (``sharpened``) prefilters of both F and G,
``numerics.*``) and each grid
dx in {1/30, 1/40, 1/60, 1/80} with dt in {limit/2, limit/4, limit/8} (limit: the explicit
stability limit, ``RotorConfig.dt_limit``, rounded down to a divisor of 0.01 so that every
protocol time is a whole number of steps), one run of the paper's rotor without noise:

* omega_ss: omega(8) after the paper's spin-up from omega0 = 0.1, Eq. (eq_motion);
* memory torques: the plate is then stopped at the first angle phi = pi/24 (mod pi/6)
  (the lattice torque of the paper's scheme is largest near there; a fixed angle makes
  the runs comparable) and T, Eq. (torque), is read after 0.5, 1, 2 and 3 of the stop,
  i.e. the end-of-stop torque of stops of those lengths;

plus, per scheme and dx, the static asymmetry torques T(Delta) - T(0) for Delta = 2e-5,
1e-4 and the rms lattice torque, over 12 angles (sparse steady solves, no dt). The
paper's own step (dx = 0.025, dt = 1e-4) is run as well, for the omega_ss goal.

Each case is stored as it finishes, as JSON under data/convergence/<variant>/, with the
numerics it ran with; ``run`` skips cases already stored with the same numerics, so an
interrupted table resumes on any machine with nothing recomputed. ``report`` prints the
table with Richardson limits and observed orders (in dt at each dx, then in dx for the
dt -> 0 limits of the three finest grids).

Run:  python benchmarks/convergence.py run [--variants paper gaussian] [--workers 2]
                                           [--grids 30 40 60 80] [--dry-run]
      python benchmarks/convergence.py report
"""

from __future__ import annotations

import argparse
import json
import math
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

import numpy as np

from pde_rotor import RotorConfig, Simulation
from pde_rotor.config import NumericsConfig
from pde_rotor.io.output import write_text_atomic
from pde_rotor.model.analysis import stopped_torque

STORE = Path(__file__).resolve().parents[1] / "data" / "convergence"
SMOOTHING = 0.025
GRIDS = (30, 40, 60, 80)
"""1/dx of the table's grids."""
DIVISORS = (2, 4, 8)
"""dt = stability limit / divisor (rounded down to a divisor of 0.01)."""
PAPER_STEP = (40, 0)
"""(1/dx, divisor 0): the paper's dx = 0.025 with its dt = 1e-4."""
T_SPIN = 8.0
STOPS = (0.5, 1.0, 2.0, 3.0)
STOP_ANGLE = math.pi / 24
PERIOD = math.pi / 6
ASYMMETRIES = (2e-5, 1e-4)


def filters(plate: tuple[str, float], pill: tuple[str, float]) -> dict[str, Any]:
    """The consistent scheme with these prefilters (kernel, kappa) of F and G."""
    return {
        "scheme": "consistent",
        "plate_filter_kernel": plate[0],
        "plate_filter_width": plate[1],
        "pill_filter_kernel": pill[0],
        "pill_filter_width": pill[1],
    }


VARIANTS: dict[str, dict[str, Any]] = {
    "paper": {"scheme": "paper"},
    "consistent": filters(("gaussian", 0.7), ("sharpened", 0.95)),
    "gaussian": filters(("gaussian", 0.7), ("gaussian", 0.7)),
    "sharpened": filters(("sharpened", 1.4), ("sharpened", 1.4)),
}
"""The numerics of each variant of the table (the rest: the schema's defaults);
``consistent`` is the schema's default scheme, the other two its earlier candidates."""
STATIC_ANGLES = 12


def base_config(variant: str, inv_dx: int, dt: float, **geometry: float) -> dict[str, Any]:
    """The paper's configuration at this grid, delta = 0.025, no noise, no stops."""
    return {
        "grid": {"dx": 1.0 / inv_dx, "dt": dt},
        "geometry": {"smoothing": SMOOTHING, **geometry},
        "numerics": VARIANTS[variant],
        "protocol": {"cycles": 0},
        "output": {"progress": False},
    }


def step_of(inv_dx: int, divisor: int) -> float:
    """dt of a case: 1e-4 for divisor 0, else limit/divisor rounded down to 0.01/N."""
    if divisor == 0:
        return 1e-4
    config = RotorConfig.model_validate(base_config("paper", inv_dx, 1e-6))
    coarsest = 0.01 / math.ceil(0.01 * 2 / config.dt_limit())
    return coarsest * 2 / divisor


def numerics_of(variant: str, inv_dx: int) -> dict[str, Any]:
    """The numerics a case runs with (a stored case with other numerics is stale)."""
    config = RotorConfig.model_validate(base_config(variant, inv_dx, step_of(inv_dx, 8)))
    return config.numerics.acting()


def relevant(numerics: dict[str, Any]) -> dict[str, Any]:
    """The numerics settings of a stored case that change a result of its scheme."""
    return NumericsConfig.model_validate(numerics).acting()


def case_path(variant: str, name: str) -> Path:
    return STORE / variant / f"{name}.json"


def dynamic_case(variant: str, inv_dx: int, divisor: int) -> dict[str, Any]:
    """omega(8), then the torques after 0.5, 1, 2, 3 of a stop at phi = pi/24 (mod pi/6)."""
    start = time.perf_counter()
    dt = step_of(inv_dx, divisor)
    spin = Simulation(RotorConfig.model_validate(base_config(variant, inv_dx, dt)))
    spin.run(T_SPIN)
    phi, omega = spin.rotor.phi, spin.rotor.omega
    wait = round(((STOP_ANGLE - phi) % PERIOD) / (omega * dt))
    t_ini = T_SPIN + wait * dt
    protocol = {"t_ini": t_ini, "t_stop": STOPS[-1], "t_release": 1.0, "cycles": 1}
    config = RotorConfig.model_validate({**base_config(variant, inv_dx, dt), "protocol": protocol})
    stop = spin.branch(config)
    torques = []
    for length in STOPS:
        stop.run(t_ini + length)
        torques.append(stop.rotor.torque)
    phi_stop = stop.rotor.phi
    static = stopped_torque(config, np.array([phi_stop]))[0]
    return {
        "variant": variant,
        "inv_dx": inv_dx,
        "divisor": divisor,
        "dt": dt,
        "omega_ss": omega,
        "phi_stop": phi_stop,
        "stop_offset": (phi_stop - STOP_ANGLE + PERIOD / 2) % PERIOD - PERIOD / 2,
        "memory_torque": dict(zip([str(s) for s in STOPS], torques, strict=True)),
        "static_torque_at_stop": float(static),
        "steps": round((t_ini + STOPS[-1]) / dt),
        "wall_s": time.perf_counter() - start,
        "numerics": numerics_of(variant, inv_dx),
    }


def static_case(variant: str, inv_dx: int) -> dict[str, Any]:
    """Asymmetry torques (mean over 12 angles) and the rms lattice torque, steady solves."""
    start = time.perf_counter()
    phis = np.arange(STATIC_ANGLES) * PERIOD / STATIC_ANGLES
    dt = step_of(inv_dx, DIVISORS[0])
    symmetric = stopped_torque(RotorConfig.model_validate(base_config(variant, inv_dx, dt)), phis)
    asym = {}
    for delta in ASYMMETRIES:
        config = RotorConfig.model_validate(base_config(variant, inv_dx, dt, asymmetry=delta))
        asym[format(delta, "g")] = float((stopped_torque(config, phis) - symmetric).mean())
    return {
        "variant": variant,
        "inv_dx": inv_dx,
        "asymmetry_torque": asym,
        "lattice_rms": float(np.sqrt(np.mean(symmetric**2))),
        "wall_s": time.perf_counter() - start,
        "numerics": numerics_of(variant, inv_dx),
    }


def execute(task: tuple[str, str, int, int]) -> tuple[str, str]:
    """Run one case in a worker and store it; returns (variant, name)."""
    kind, variant, inv_dx, divisor = task
    if kind == "static":
        name, result = f"static_dx{inv_dx}", static_case(variant, inv_dx)
    else:
        name, result = f"dx{inv_dx}_dt{divisor}", dynamic_case(variant, inv_dx, divisor)
    path = case_path(variant, name)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(path, json.dumps(result, indent=1) + "\n")
    return variant, name


def load(variant: str, name: str) -> dict[str, Any] | None:
    """A stored case if its numerics are today's, else None."""
    path = case_path(variant, name)
    if not path.exists():
        return None
    content = json.loads(path.read_text())
    if relevant(content["numerics"]) != numerics_of(variant, content["inv_dx"]):
        return None
    return content


def ms_per_step(variant: str, inv_dx: int) -> float:
    """Wall time of one step on this machine (200 steps after a warm-up)."""
    sim = Simulation(RotorConfig.model_validate(base_config(variant, inv_dx, step_of(inv_dx, 8))))
    sim.run(20 * sim.config.grid.dt)
    start = time.perf_counter()
    sim.run(sim.t + 200 * sim.config.grid.dt)
    return (time.perf_counter() - start) / 200 * 1e3


def tasks_of(variants: list[str], grids: list[int]) -> list[tuple[str, str, int, int]]:
    """The missing or stale cases, cheapest first."""
    tasks = []
    for variant in variants:
        for inv_dx in grids:
            if load(variant, f"static_dx{inv_dx}") is None:
                tasks.append(("static", variant, inv_dx, 0))
            divisors = (*DIVISORS, 0) if inv_dx == PAPER_STEP[0] else DIVISORS
            for divisor in divisors:
                if load(variant, f"dx{inv_dx}_dt{divisor}") is None:
                    tasks.append(("dynamic", variant, inv_dx, divisor))
    return sorted(tasks, key=lambda t: (t[0] == "dynamic", t[2], t[3]))


def run(args: argparse.Namespace) -> None:
    """Estimate the cost of the missing cases, then run them (unless --dry-run)."""
    tasks = tasks_of(args.variants, args.grids)
    timed = sorted({(variant, inv_dx) for kind, variant, inv_dx, _ in tasks if kind == "dynamic"})
    rates = {key: ms_per_step(*key) for key in timed}
    total = 0.0
    for kind, variant, inv_dx, divisor in tasks:
        if kind == "dynamic":
            steps = (T_SPIN + STOPS[-1]) / step_of(inv_dx, divisor)
            total += steps * rates[variant, inv_dx] / 3.6e6
    print(f"{len(tasks)} cases missing; dynamic runs: {total:.2f} core-hours on this machine")
    for (variant, inv_dx), ms in rates.items():
        print(f"  {variant:>10} dx = 1/{inv_dx}: {ms:.3f} ms/step")
    if args.dry_run or not tasks:
        return
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        futures = [pool.submit(execute, task) for task in tasks]
        for future in as_completed(futures):
            variant, name = future.result()
            print(f"stored {variant}/{name}", flush=True)


def richardson(values: list[float], ratios: list[float]) -> tuple[float, float]:
    """Observed order p and limit from three values at spacings h1 > h2 > h3.

    Solves (v1 - v2) / (v2 - v3) = (h1^p - h2^p) / (h2^p - h3^p) for p (ratios holds
    h1/h3 and h2/h3), then v = v3 - C h3^p extrapolated to h = 0. Returns (nan, nan)
    when the differences change sign (no monotone convergence to extrapolate).
    """
    v1, v2, v3 = values
    r1, r2 = ratios
    d12, d23 = v1 - v2, v2 - v3
    if d12 * d23 <= 0:
        return math.nan, math.nan
    target = d12 / d23
    lo, hi = 0.05, 8.0
    f = lambda p: (r1**p - r2**p) / (r2**p - 1) - target  # noqa: E731
    if f(lo) * f(hi) > 0:
        return math.nan, math.nan
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(lo) * f(mid) > 0 else (lo, mid)
    p = 0.5 * (lo + hi)
    return p, v3 - d23 / (r2**p - 1)


def fmt(value: float, digits: int = 4) -> str:
    return "—" if not math.isfinite(value) else f"{value:.{digits}g}"


def report(args: argparse.Namespace) -> None:
    """Print the markdown tables of docs/model.md from the stored cases."""
    quantities = [("omega_ss", lambda c: c["omega_ss"], 6)]
    quantities += [
        (f"T after stop {s:g} [1e-7]", lambda c, s=s: c["memory_torque"][str(s)] * 1e7, 4)
        for s in STOPS
    ]
    for variant in args.variants:
        print(f"\n### {variant}: {VARIANTS[variant]}\n")
        limits: dict[str, dict[int, float]] = {q: {} for q, _, _ in quantities}
        head = "| quantity | 1/dx | dt = limit/2 | limit/4 | limit/8 | order in dt | dt → 0 |"
        print(head + "\n|---|---|---|---|---|---|---|")
        for name, get, digits in quantities:
            for inv_dx in args.grids:
                cases = [load(variant, f"dx{inv_dx}_dt{k}") for k in DIVISORS]
                if any(c is None for c in cases):
                    continue
                values = [get(c) for c in cases]
                p, limit = richardson(values, [4.0, 2.0])
                limits[name][inv_dx] = limit
                cells = " | ".join(fmt(v, digits + 1) for v in values)
                print(f"| {name} | {inv_dx} | {cells} | {fmt(p, 2)} | {fmt(limit, digits + 1)} |")
        print("\n| quantity | dt → 0 at 1/dx = " + " | ".join(map(str, args.grids)), end="")
        print(" | order in dx (3 finest) | dx → 0 |")
        print("|---" * (len(args.grids) + 3) + "|")
        for name, _, digits in quantities:
            row = [limits[name].get(n, math.nan) for n in args.grids]
            p, limit = (math.nan, math.nan)
            if all(math.isfinite(v) for v in row[-3:]):
                h = [1.0 / n for n in args.grids[-3:]]
                p, limit = richardson(row[-3:], [h[0] / h[2], h[1] / h[2]])
            cells = " | ".join(fmt(v, digits + 1) for v in row)
            print(f"| {name} | {cells} | {fmt(p, 2)} | {fmt(limit, digits + 1)} |")
        print("\n| 1/dx | " + " | ".join(f"T(Δ={d:g}) - T(0)" for d in ASYMMETRIES), end="")
        print(" | rms lattice torque |\n|---|---|---|---|")
        for inv_dx in args.grids:
            static = load(variant, f"static_dx{inv_dx}")
            if static is not None:
                cells = " | ".join(
                    f"{static['asymmetry_torque'][format(d, 'g')]:.4e}" for d in ASYMMETRIES
                )
                print(f"| {inv_dx} | {cells} | {static['lattice_rms']:.2e} |")
        paper = load(variant, f"dx{PAPER_STEP[0]}_dt{PAPER_STEP[1]}")
        if paper is not None:
            print(f"\nomega_ss at the paper's dx = 0.025, dt = 1e-4: {paper['omega_ss']:.6g}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("action", choices=["run", "report"])
    parser.add_argument("--variants", nargs="+", choices=list(VARIANTS), default=list(VARIANTS))
    parser.add_argument("--grids", nargs="+", type=int, default=list(GRIDS), help="1/dx")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--dry-run", action="store_true", help="only the cost estimate")
    args = parser.parse_args()
    run(args) if args.action == "run" else report(args)


if __name__ == "__main__":
    main()
