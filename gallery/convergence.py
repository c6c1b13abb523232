"""Convergence page: how omega, the lattice torque and inversion outcomes move with dx.

The paper gives results at one resolution (dx = delta = 0.025, dt = 1e-4). This page adds
what it does not give, always with delta = dx (the paper's choice):

(a) the angular velocity omega at t = 8 of the free rotor (Eq. (eq_motion), spun up from
    the paper's initial state) against dx, for a fixed small dt (a spatial study: full
    5e-5, quick 1e-4) and for (dx, dt) pairs on the paper's ratio dt D / dx^2 = 0.16:
    (0.05, 4e-4) [the quick grid], (1/30, 2e-4) [ratio 0.18: the nearest dt on which
    every protocol time is a whole number of steps], (0.025, 1e-4) [the paper], (1/60, 4e-5);
(b) the spurious torque on a stopped symmetric plate (Delta = 0), Eq. (torque), from the
    steady camphor field (:func:`pde_rotor.model.analysis.stopped_torque`, as in
    benchmarks/lattice_torque.py): rms and max over one period pi/6 of the plate angle,
    against dx, next to the asymmetry torques T(Delta) - T(0) of Delta = 2e-5 and 1e-4;
(c) that lattice torque against the plate angle for each dx;
(d) the inversion probability at (t_stop, Delta) in {0.5, 3} x {0, 2e-5, 1e-4} against
    dx at the calibrated noise, with 95 % intervals, from bank-estimator sweeps
    (:mod:`pde_rotor.sweep`) at the paper-ratio (dx, dt) pairs; at the paper's pair
    (0.025, 1e-4) the points of the stored Fig. 5 and 7 reports (data/fig5.nc,
    data/fig7a.nc, data/fig7b.nc) are used where they hold the same model, since they
    are larger (200 stops per point).
    dx = 1/60 is left out of (d): a restart costs about 5 times the paper's there.

Numbers are also written to convergence.csv next to the figure.

Run: ``python gallery/convergence.py [--quick | --tiny]``. Full: dx up to 1/60 and
longer sweeps (hours on one core); quick: about ten minutes on 2 cores.
"""

from __future__ import annotations

import csv
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pde_rotor.config import CALIBRATED_SIGMA, RotorConfig
from pde_rotor.gallery import common
from pde_rotor.gallery.common import (
    PAPER_CONFIG,
    SWEEP_RUNS,
    Fidelity,
    add_footer,
    fidelity_label,
    new_figure,
    parse_args,
    save,
)
from pde_rotor.io.output import atomic_path
from pde_rotor.model.analysis import stopped_torque
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep import stored
from pde_rotor.units import OMEGA_UNITS

NAME = "convergence"
PAPER_PAIRS = ((0.05, 4e-4), (1 / 30, 2e-4), (0.025, 1e-4), (1 / 60, 4e-5))
"""(dx, dt) near the paper's dt D / dx^2 = 0.16 (see module docstring)."""
PAPER_OMEGA = 176.0
"""The paper's steady angular velocity ("~176", section Numerical results)."""
T_OMEGA = 8.0
"""Time at which omega is read (steady to 1e-3 on every grid here)."""
ASYMMETRIES = (2e-5, 1e-4)
"""Delta of the asymmetry torques compared with the lattice torque."""
POINTS_T_STOP = (0.5, 3.0)
POINTS_DELTA = (0.0, 2e-5, 1e-4)
STORED_SWEEPS = ("fig5", "fig7b", "fig7a")
"""Sweeps whose stored reports (data/<name>.nc) hold the panel (d) points at the paper's
grid: the t_stop curves of Delta = 0, 2e-5 and 1e-4."""


@dataclass(frozen=True)
class Plan:
    """What one fidelity computes.

    Attributes:
        omega_dx: dx of the fixed-dt series of omega(t = 8).
        omega_dt: that fixed dt.
        pairs: (dx, dt) of the paper-ratio series of omega.
        t_omega: time at which omega is read.
        torque_dx: dx of the lattice-torque panels.
        angles: plate angles per period pi/6.
        sweep_pairs: (dx, dt) of the inversion sweeps.
        t_stops, deltas: axes of the inversion sweeps.
        samples: restarts per direction and point.
        warmup: spin-up time of the restart estimator.
    """

    omega_dx: tuple[float, ...]
    omega_dt: float
    pairs: tuple[tuple[float, float], ...]
    t_omega: float
    torque_dx: tuple[float, ...]
    angles: int
    sweep_pairs: tuple[tuple[float, float], ...]
    t_stops: tuple[float, ...]
    deltas: tuple[float, ...]
    samples: int
    warmup: float


def plan(fid: Fidelity) -> Plan:
    """The computation of each fidelity (see module docstring)."""
    if fid.name == "full":
        return Plan(
            omega_dx=tuple(p[0] for p in PAPER_PAIRS),
            omega_dt=5e-5,
            pairs=PAPER_PAIRS,
            t_omega=T_OMEGA,
            torque_dx=tuple(p[0] for p in PAPER_PAIRS),
            angles=24,
            sweep_pairs=PAPER_PAIRS[:3],
            t_stops=POINTS_T_STOP,
            deltas=POINTS_DELTA,
            samples=40,
            warmup=8.0,
        )
    if fid.name == "quick":
        return Plan(
            omega_dx=tuple(p[0] for p in PAPER_PAIRS[:3]),
            omega_dt=1e-4,
            pairs=PAPER_PAIRS[:3],
            t_omega=T_OMEGA,
            torque_dx=tuple(p[0] for p in PAPER_PAIRS),
            angles=24,
            sweep_pairs=PAPER_PAIRS[:2],
            t_stops=POINTS_T_STOP,
            deltas=POINTS_DELTA,
            samples=6,
            warmup=8.0,
        )
    return Plan(
        omega_dx=(0.05, 1 / 30),
        omega_dt=1e-4,
        pairs=PAPER_PAIRS[:2],
        t_omega=0.4,
        torque_dx=(0.05, 1 / 30),
        angles=3,
        sweep_pairs=PAPER_PAIRS[:1],
        t_stops=(0.4,),
        deltas=POINTS_DELTA,
        samples=1,
        warmup=2.0,
    )


def grid_config(fid: Fidelity, dx: float, dt: float, *overrides: str) -> RotorConfig:
    """Paper config with dx, dt and delta = dx (domain of the fidelity)."""
    radius = [s for s in fid.grid if s.startswith("grid.domain_radius")]
    return fid.config(
        PAPER_CONFIG,
        *radius,
        f"grid.dx={dx!r}",
        f"grid.dt={dt!r}",
        f"geometry.smoothing={dx!r}",
        *overrides,
    )


def steady_omega(fid: Fidelity, dx: float, dt: float, t_end: float) -> tuple[float, float]:
    """omega at t_end of the free symmetric rotor, and the wall time."""
    config = grid_config(fid, dx, dt, "protocol.cycles=0", f"protocol.t_ini={t_end!r}")
    start = time.perf_counter()
    sim = Simulation(config)
    sim.run(t_end)
    return sim.rotor.omega, time.perf_counter() - start


def torque_dt(dx: float) -> float:
    """A stable dt for dx (the steady solve does not use it; the config checks it)."""
    return min(dt for d, dt in PAPER_PAIRS if d >= dx - 1e-12)


def lattice_torques(fid: Fidelity, dx: float, phis: np.ndarray) -> dict[str, np.ndarray]:
    """T(phi) for Delta = 0 and T(Delta) - T(0) for each Delta of :data:`ASYMMETRIES`."""
    dt = torque_dt(dx)
    out = {"0": stopped_torque(grid_config(fid, dx, dt, "geometry.asymmetry=0.0"), phis)}
    for delta in ASYMMETRIES:
        torque = stopped_torque(grid_config(fid, dx, dt, f"geometry.asymmetry={delta!r}"), phis)
        out[f"{delta:g}"] = torque - out["0"]
    return out


def inversion_sweep(fid: Fidelity, p: Plan, dx: float, dt: float, out: Path):
    """Bank-estimator sweep over (t_stop, Delta) at (dx, dt), calibrated noise; its report."""
    from pde_rotor.sweep import Sweep, SweepSpec, report, run_sweep

    base = grid_config(fid, dx, dt, f"noise.sigma={CALIBRATED_SIGMA!r}").model_dump(mode="json")
    base.pop("output", None)
    spec = SweepSpec.model_validate(
        {
            "name": f"convergence_{fid.name}_dx{dx:.4f}",
            "description": "gallery/convergence.py: inversion outcome against dx",
            "base": base,
            "axes": {
                "protocol.t_stop": list(p.t_stops),
                "geometry.asymmetry": list(p.deltas),
            },
            "estimator": {
                "kind": "bank",
                "warmup": p.warmup,
                "release_cap": 10 * max(p.t_stops),
            },
            "samples": p.samples,
            "seed": 20200501,
        }
    )
    sweep = Sweep.from_spec(spec)
    root = out / "sweeps" if fid.is_tiny else SWEEP_RUNS
    sweep_dir = root / spec.name
    outcome = run_sweep(
        sweep,
        sweep_dir,
        scheduler=common.SCHEDULER,
        workers=1 if fid.is_tiny else None,
        progress=not fid.is_tiny,
    )
    if outcome.failed:
        key, message = outcome.failed[0]
        msg = f"convergence sweep at dx = {dx:g}: {len(outcome.failed)} failed, {key}: {message}"
        raise RuntimeError(msg)
    return report(sweep_dir, echo=not fid.is_tiny)


def inversion_points(
    fid: Fidelity, p: Plan, dx: float, dt: float, out: Path
) -> dict[tuple[float, float, float], tuple[float, float, float, int, str]]:
    """P, its bounds, stops and source per (dx, t_stop, Delta) at one (dx, dt) pair.

    Where the stored reports of :data:`STORED_SWEEPS` hold the model of this pair (same
    grid, scheme and noise as the bank sweep would run,
    :func:`pde_rotor.sweep.stored.curve_points`) their points are used (a point they
    lack is left out); otherwise the bank sweep runs.
    """
    sigma = CALIBRATED_SIGMA
    found = {}
    if not fid.is_tiny:
        like = grid_config(fid, dx, dt, f"noise.sigma={sigma!r}").model_dump(mode="json")
        for delta in p.deltas:
            pts = stored.curve_points(
                common.DATA, "t_stop", STORED_SWEEPS, like=like, asymmetry=delta, sigma=sigma
            )
            for t_stop in p.t_stops if pts is not None else ():
                match = np.isclose(pts["t_stop"].values, t_stop)
                if match.any():
                    row = pts.isel(t_stop=int(np.argmax(match)))
                    found[(dx, t_stop, delta)] = (
                        float(row["P"]),
                        float(row["P_low"]),
                        float(row["P_high"]),
                        int(row["stops"]),
                        f"stored data/{row['report'].item()}.nc",
                    )
        if found:
            return found
    ds = inversion_sweep(fid, p, dx, dt, out)
    for t_stop in p.t_stops:
        for delta in p.deltas:
            sel = ds.sel(t_stop=t_stop, asymmetry=delta)
            found[(dx, t_stop, delta)] = (
                float(sel["P"]),
                float(sel["P_low"]),
                float(sel["P_high"]),
                int(sel["stops"]),
                "computed",
            )
    return found


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Compute the four panels, write the figure (PNG, PDF) and convergence.csv."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    p = plan(fid)
    rows: list[dict[str, object]] = []
    start = time.perf_counter()

    # (a) omega(t = 8) against dx
    cache: dict[tuple[float, float], float] = {}
    for dx in p.omega_dx:
        cache[(dx, p.omega_dt)] = steady_omega(fid, dx, p.omega_dt, p.t_omega)[0]
    for dx, dt in p.pairs:
        if (dx, dt) not in cache:
            cache[(dx, dt)] = steady_omega(fid, dx, dt, p.t_omega)[0]
    for (dx, dt), omega in cache.items():
        rows.append({"quantity": f"omega(t={p.t_omega:g})", "dx": dx, "dt": dt, "value": omega})
        print(f"{NAME}: omega(t = {p.t_omega:g}) at dx = {dx:.4g}, dt = {dt:g}: {omega:.3f}")

    # (b), (c) lattice torque against dx and plate angle
    phis = np.arange(p.angles) * (math.pi / 6) / p.angles
    torques = {dx: lattice_torques(fid, dx, phis) for dx in p.torque_dx}
    for dx, t in torques.items():
        rms, peak = float(np.sqrt(np.mean(t["0"] ** 2))), float(np.abs(t["0"]).max())
        rows += [
            {"quantity": "lattice torque rms", "dx": dx, "dt": "", "value": rms},
            {"quantity": "lattice torque max", "dx": dx, "dt": "", "value": peak},
        ]
        line = f"{NAME}: dx = {dx:.4g}: lattice torque rms {rms:.3e}, max {peak:.3e}"
        for delta in ASYMMETRIES:
            asym = float(np.mean(t[f"{delta:g}"]))
            rows.append(
                {"quantity": f"asymmetry torque Delta={delta:g}", "dx": dx, "dt": "", "value": asym}
            )
            line += f"; T({delta:g}) - T(0) = {asym:.3e}"
        print(line)

    # (d) inversion probability against dx
    points: dict[tuple[float, float, float], tuple[float, float, float, int, str]] = {}
    for dx, dt in p.sweep_pairs:
        points.update(inversion_points(fid, p, dx, dt, args.out))
    for (dx, t_stop, delta), (pv, lo, hi, n, source) in sorted(points.items()):
        rows.append(
            {
                "quantity": f"P(t_stop={t_stop:g}, Delta={delta:g})",
                "dx": dx,
                "dt": dict(p.sweep_pairs)[dx],
                "value": pv,
                "low": lo,
                "high": hi,
                "stops": n,
            }
        )
        print(
            f"{NAME}: dx = {dx:.4g}, t_stop = {t_stop:g}, Delta = {delta:g}: "
            f"P = {pv:.3f} [{lo:.3f}, {hi:.3f}] ({n} stops, {source})"
        )
    wall = time.perf_counter() - start

    fig = new_figure(12.0, 9.0)
    (ax_w, ax_t), (ax_phi, ax_p) = fig.subplots(2, 2)
    fixed = [(dx, cache[(dx, p.omega_dt)]) for dx in p.omega_dx]
    ax_w.plot(*zip(*fixed, strict=True), "o-", label=f"fixed dt = {p.omega_dt:g}")
    paired = [(dx, cache[(dx, dt)]) for dx, dt in p.pairs]
    ax_w.plot(*zip(*paired, strict=True), "s--", label="paper-ratio (dx, dt) pairs")
    for dx, dt in p.pairs:
        ax_w.annotate(
            f"dt={dt:g}",
            (dx, cache[(dx, dt)]),
            xytext=(4, -10),
            textcoords="offset points",
            fontsize=7,
        )
    ax_w.axhline(PAPER_OMEGA, color="0.5", ls=":", label="paper: \u223c176")
    ax_w.set_xlabel("dx (= \u03b4)")
    ax_w.set_ylabel(f"\u03c9 at t = {p.t_omega:g} [{OMEGA_UNITS}]")
    ax_w.set_title("(a) steady angular velocity", fontsize=10)
    ax_w.legend(fontsize=8)
    ax_w.grid(alpha=0.3)

    dxs = np.array(sorted(torques))
    rms = [np.sqrt(np.mean(torques[dx]["0"] ** 2)) for dx in dxs]
    peak = [np.abs(torques[dx]["0"]).max() for dx in dxs]
    ax_t.loglog(dxs, rms, "o-", label="lattice torque, rms (\u0394 = 0)")
    ax_t.loglog(dxs, peak, "^-", label="lattice torque, max (\u0394 = 0)")
    for delta, marker in zip(ASYMMETRIES, "sD", strict=True):
        asym = [abs(np.mean(torques[dx][f"{delta:g}"])) for dx in dxs]
        ax_t.loglog(dxs, asym, marker + "--", label=f"|T(\u0394) \u2212 T(0)|, \u0394 = {delta:g}")
    ax_t.set_xlabel("dx (= \u03b4)")
    ax_t.set_ylabel("torque on the stopped plate")
    ax_t.set_title(f"(b) stopped-plate torques, {p.angles} angles per \u03c0/6", fontsize=10)
    ax_t.legend(fontsize=8)
    ax_t.grid(alpha=0.3, which="both")

    for dx in dxs:
        ax_phi.plot(phis, torques[dx]["0"], "o-", ms=3, label=f"dx = {dx:.4g}")
    ax_phi.axhline(0, color="0.5", lw=0.7)
    ax_phi.set_xlabel("plate angle \u03c6 modulo \u03c0/6 [rad]")
    ax_phi.set_ylabel("lattice torque T(\u03c6), \u0394 = 0")
    ax_phi.set_title("(c) lattice torque against the plate angle", fontsize=10)
    ax_phi.legend(fontsize=8)
    ax_phi.grid(alpha=0.3)

    # one slot per (dx, dt) pair, coarse to fine; the points side by side within a slot
    pairs = sorted(p.sweep_pairs, reverse=True)
    slots = np.arange(len(pairs), dtype=float)
    n_series = len(p.t_stops) * len(p.deltas)
    samples = []
    for k, (t_stop, delta) in enumerate((t, d) for t in p.t_stops for d in p.deltas):
        got = [points.get((dx, t_stop, delta)) for dx, _ in pairs]
        pv, lo, hi = (np.array([g[i] if g else np.nan for g in got]) for i in range(3))
        samples += [g[3] for g in got if g]
        ax_p.errorbar(
            slots + 0.1 * (k - (n_series - 1) / 2),
            pv,
            yerr=np.vstack([np.clip(pv - lo, 0, None), np.clip(hi - pv, 0, None)]),
            fmt="o:",
            capsize=3,
            label=f"t_stop = {t_stop:g}, \u0394 = {delta:g}",
        )
    ax_p.set_xticks(slots, [f"dx = {dx:.4g}\ndt = {dt:g}" for dx, dt in pairs])
    ax_p.set_xlim(-0.5, len(pairs) - 0.5)
    ax_p.set_ylim(-0.05, 1.35)
    ax_p.set_yticks(np.linspace(0, 1, 6))
    ax_p.set_xlabel("grid (\u03b4 = dx), dt on the paper ratio")
    ax_p.set_ylabel("inversion probability P (95 % CI)")
    n_stops = f"{min(samples)}" + (f"-{max(samples)}" if max(samples) > min(samples) else "")
    ax_p.set_title(
        f"(d) inversions at \u03c3 = {CALIBRATED_SIGMA:g}, {n_stops} stops per point",
        fontsize=10,
    )
    ax_p.legend(fontsize=8, loc="upper center", ncols=2)
    ax_p.grid(alpha=0.3)
    fig.suptitle("Convergence: \u03c9, lattice torque and inversions against dx (\u03b4 = dx)")
    config = grid_config(fid, 0.05, 4e-4)
    add_footer(
        fig,
        fidelity_label(
            fid,
            None,
            f"L = {config.grid.domain_radius:g}; (a)-(c) no noise, dt as labelled; (d) bank "
            f"estimator, \u03c3 = {CALIBRATED_SIGMA:g}, {p.samples} stops per direction "
            f"and point where computed, the stored Fig. 5 and 7 reports where they hold the model; "
            f"warm-up {p.warmup:g}; wall {wall:.0f} s",
        ),
    )
    written = save(fig, args.out, NAME)
    table = args.out / f"{NAME}.csv"
    with atomic_path(table) as tmp, tmp.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(
            handle, ["quantity", "dx", "dt", "value", "low", "high", "stops"], restval=""
        )
        writer.writeheader()
        writer.writerows(rows)
    return [*written, table]


if __name__ == "__main__":
    main()
