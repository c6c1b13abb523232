"""Why the decision model fails the full test: the candidates, one number each.

`pde-rotor predict check` over every stored flow ensemble of the default scheme fails
(docs/decision.md): the conditionals scatter beyond their binomial spread, most where
the model gives the less likely direction 0.1 % to 5 %. From the committed runs
(data/sweeps/*/runs, data/decision/*.nc) only, this script measures each candidate:

* **the stop angle, down to the sub-cell position of the plate**: every bank run stores
  its own torque at the end of its stop, at a uniformly random angle. The model with each
  stop's own torque (beta shifted by (T_end - mean of the table's angles) / I) against
  the table's mean over 8 angles, in the tail bin; and the spread of T_end over the
  random stops against the spread over the table's 8 angles.
* **the spread of beta between stops**: the spread of omega before the stop over every
  run (the state the stop starts from), and T_end's spread in units of sqrt(lambda Dw).
* **the commit rule's threshold**: the probability that a linear escape, once at
  |omega| = w, ever comes back through 0 is 2 (1 - Phi(w sqrt(lambda / Dw))) (unstable
  Ornstein-Uhlenbeck); with it, the range of thresholds that classify every release
  alike; and how many stored runs did not commit.
* **the noise's dt-dependence**: the Euler step's variance of the linear escape is
  Dw / (lambda (1 + lambda dt / 2)), so x grows by sqrt(1 + lambda dt / 2).
* **a global noise scale**: the full test with the model at kappa Dw, kappa from 0.8
  to 1.5 (a scale error moves every tail one way);
* **a misscaled part of beta**: separate factors on the asymmetry part (beta at Delta
  less beta at 0) and the rest (memory and lattice), fitted by maximum likelihood.

It also prints the scatter of x (:func:`pde_rotor.decision.goodness.x_scatter`) of each
ensemble: where the misfit sits.

Run:  python benchmarks/decision_tails.py   (about a minute; reads data/ only)
"""

from __future__ import annotations

import collections
import json
import math
from pathlib import Path

import numpy as np
from scipy.optimize import minimize
from scipy.special import ndtr

from pde_rotor.decision.check import (
    Comparison,
    compare,
    is_ensemble,
    report_config,
    stored_matches,
)
from pde_rotor.decision.goodness import goodness_of_fit, x_scatter
from pde_rotor.decision.table import DecisionTable, diffusion_of
from pde_rotor.sweep.stored import load_report

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"
SIGMA = 1.5e-7
"""The calibrated noise of the default scheme, where the commit and dt numbers are given."""


def stored_runs(name: str) -> list[dict]:
    """Every finished run of data/sweeps/NAME (its JSON Lines logs)."""
    runs = []
    for path in sorted((DATA / "sweeps" / name / "runs").glob("*.jsonl")):
        for line in path.read_text().splitlines():
            record = json.loads(line)
            if "result" in record:
                runs.append(record)
    return runs


def flow_pairs() -> list:
    """(report path, report, table path, table) of every default-scheme flow ensemble."""
    reports = [(p, load_report(p)) for p in sorted(DATA.glob("*.nc"))]
    reports = [
        (p, ds)
        for p, ds in reports
        if is_ensemble(ds)
        and report_config(ds).get("flow", {}).get("enabled", True)
        and report_config(ds)["numerics"]["scheme"] == "consistent"
    ]
    return stored_matches(reports, DATA / "decision")[0]


def stop_torques(table: DecisionTable) -> None:
    """The model with each bank stop's own end-of-stop torque against the table's angles."""
    fixed = {
        "noise_law": {},
        "science_calibration": {"geometry.asymmetry": 2e-5},
        "science_one_intensity_plateau": {"geometry.asymmetry": 2e-5, "protocol.t_stop": 3.0},
        "science_one_intensity_decay": {"geometry.asymmetry": 0.0, "protocol.t_stop": 1.4},
    }
    tail = np.zeros(3)
    ratios = []
    for name, base in fixed.items():
        groups = collections.defaultdict(list)
        for run in stored_runs(name):
            c = {**base, **run["coords"]}
            key = (c["protocol.t_stop"], c["geometry.asymmetry"], c["noise.sigma"])
            groups[(*key, run["direction"])].append(run["result"])
        for (t_stop, delta, sigma, direction), results in groups.items():
            d = 0 if direction == 1 else 1
            j = int(np.argmin(abs(table.time - t_stop)))
            angles = table.torque_at(delta)[d, :, j]
            t_end = np.array([r["torque_end"] for r in results])
            if sigma == 0:
                ratios.append(t_end.std() / angles.std())
                continue
            beta = table.release_bias(t_stop, delta)[d]
            scale = math.sqrt(table.growth_rate * diffusion_of(sigma, table.inertia))
            own = beta.mean() + table.amplitude_scale * (t_end - angles.mean()) / table.inertia
            p_table, p_own = float(np.mean(ndtr(beta / scale))), float(np.mean(ndtr(own / scale)))
            if 1e-3 <= min(p_table, 1 - p_table) < 0.05:
                plus = sum(r["direction_after"] == 1 for r in results)
                n = len(results)
                minority = plus if p_table < 0.5 else n - plus
                q_own = p_own if p_table < 0.5 else 1 - p_own
                tail += [minority, n * min(p_table, 1 - p_table), n * q_own]
    print(
        "stop angle: bank conditionals with q in [0.001, 0.05): "
        f"{tail[0]:.0f} stops went the less likely way, the table's 8 angles expect "
        f"{tail[1]:.2f}, each stop's own end-of-stop torque {tail[2]:.2f}"
    )
    if ratios:
        print(
            "stop angle: sd of T_end over the noise-free bank stops (random angles) / sd "
            f"over the table's 8 angles: {min(ratios):.2f} to {max(ratios):.2f}"
        )


def spread_between_stops(table: DecisionTable, pairs: list) -> None:
    """omega before the stop over the runs of every ensemble on `table`'s grid (by
    sweep, direction and dx), and T_end's spread over random stops in x units."""
    before, t_end = collections.defaultdict(list), collections.defaultdict(list)
    for name in sorted({ds.attrs["sweep"] for _, ds, path, _ in pairs if path.name == "dx40.nc"}):
        for run in stored_runs(name):
            dx = run["coords"].get("grid.dx", table_dx(table))
            if not math.isclose(dx, table_dx(table), rel_tol=1e-6):
                continue
            before[(name, run["direction"])].append(run["result"]["omega_before"])
            if "torque_end" in run["result"] and name == "noise_law":
                c = run["coords"]
                t_end[(c["protocol.t_stop"], c["geometry.asymmetry"], run["direction"])].append(
                    run["result"]["torque_end"]
                )
    relative = max(np.std(v) / abs(np.mean(v)) for v in before.values())
    runs = sum(len(v) for v in before.values())
    scale = math.sqrt(table.growth_rate * diffusion_of(SIGMA, table.inertia))
    spread = [np.std(np.unique(v)) / table.inertia / scale for v in t_end.values()]
    print(
        f"spread between stops: omega before the stop varies by at most {relative:.1g} "
        f"(sd / mean) within a sweep and direction, over {runs} runs on dx40.nc's grid; "
        f"sd of T_end / I over random stops = {min(spread):.2f} to {max(spread):.2f} "
        f"sqrt(lambda Dw) at sigma = {SIGMA:g}"
    )


def table_dx(table: DecisionTable) -> float:
    """The grid spacing of `table`."""
    return float(json.loads(table.attrs["config"])["grid"]["dx"])


def commit_threshold(table: DecisionTable) -> None:
    """The linear escape's return probability from |omega| = w, and stored commits."""
    dw = diffusion_of(SIGMA, table.inertia)
    lam = table.growth_rate
    for w in (0.01, 0.02, 0.05):
        back = 2 * ndtr(-w * math.sqrt(lam / dw))
        print(f"commit threshold: from |omega| = {w:g}, P(back through 0) = {back:.2g}")
    runs = [r["result"] for p in sorted((DATA / "sweeps").iterdir()) for r in stored_runs(p.name)]
    uncommitted = sum(not r["committed"] for r in runs)
    first = min(r["t_commit"] for r in runs if r["committed"])
    print(
        f"commit threshold: {uncommitted} of {len(runs)} stored runs never committed; the "
        f"earliest commit came {first:g} after its release"
    )


def noise_step(table: DecisionTable) -> None:
    """The Euler step's factor on x at the stored time steps."""
    for dt in (1e-4, 5e-5):
        factor = math.sqrt(1 + table.growth_rate * dt / 2)
        q = ndtr(-2.5 * factor) / ndtr(-2.5)
        print(
            f"noise dt: dt = {dt:g}: x times {factor:.5f}; q at x = 2.5 times {q:.4f} "
            "(against the continuous escape)"
        )


def noise_scale(pairs: list) -> None:
    """The full test with the model at kappa Dw."""
    original = DecisionTable.conditionals
    try:
        for kappa in (0.8, 0.9, 1.0, 1.1, 1.2, 1.3, 1.5):

            def scaled(self, t_stop, asymmetry, diffusion, kappa=kappa):
                return original(self, t_stop, asymmetry, kappa * diffusion)

            DecisionTable.conditionals = scaled
            rows = [row for _, ds, _, table in pairs for row in compare(table, [ds]).rows]
            fit = goodness_of_fit(Comparison(rows))
            print(
                f"noise scale: kappa = {kappa:g}: X2 p = {fit.pearson_p:.3f}, G2 p = "
                f"{fit.g_p:.3f}, {fit.failing} conditionals fail (P = {fit.failing_p:.2g})"
            )
    finally:
        DecisionTable.conditionals = original


def by_ensemble(pairs: list) -> None:
    """The scatter of x over each ensemble's conditionals (q > 0)."""
    rows = collections.defaultdict(list)
    for _, ds, _, table in pairs:
        for row in compare(table, [ds]).rows:
            if row["column"] != "P" and row.get("stops") and 0 < row["predicted"] < 1:
                rows[row["sweep"]].append((row["inverted"], row["stops"], row["predicted"]))
    for name, values in sorted(rows.items()):
        k, n, p = (np.array(v, dtype=float) for v in zip(*values, strict=True))
        print(f"scatter of x: {name}: {x_scatter(k, n, p):.2f} over {k.size} conditionals")


def part_scales(pairs: list) -> None:
    """Separate factors on the asymmetry part of beta and the rest, by maximum likelihood,
    and the full test with them."""
    original = DecisionTable.release_bias
    counts = []
    for _, ds, _, table in pairs:
        for row in compare(table, [ds]).rows:
            if row["column"] == "P" or not row.get("stops") or row["sigma"] <= 0:
                continue
            t, delta = row["t_stop"], row["asymmetry"]
            full, rest = original(table, t, delta), original(table, t, 0.0)
            scale = math.sqrt(table.growth_rate * diffusion_of(row["sigma"], table.inertia))
            d = 0 if row["column"] == "P_ccw" else 1
            counts.append(
                ((full - rest)[d] / scale, rest[d] / scale, d, row["inverted"], row["stops"])
            )

    def minus_log_likelihood(factors: np.ndarray) -> float:
        total = 0.0
        for asym, rest, d, k, n in counts:
            plus = float(np.mean(ndtr(factors[0] * asym + factors[1] * rest)))
            p = np.clip(1 - plus if d == 0 else plus, 1e-15, 1 - 1e-15)
            total -= k * math.log(p) + (n - k) * math.log(1 - p)
        return total

    best = minimize(minus_log_likelihood, np.ones(2), method="Nelder-Mead").x

    def scaled(self, t_stop, asymmetry):
        rest = original(self, t_stop, 0.0)
        return best[0] * (original(self, t_stop, asymmetry) - rest) + best[1] * rest

    DecisionTable.release_bias = scaled
    try:
        rows = [row for _, ds, _, table in pairs for row in compare(table, [ds]).rows]
        fit = goodness_of_fit(Comparison(rows))
    finally:
        DecisionTable.release_bias = original
    print(
        f"parts of beta: asymmetry times {best[0]:.3f}, the rest times {best[1]:.3f} "
        f"(log-likelihood {minus_log_likelihood(np.ones(2)) - minus_log_likelihood(best):+.1f}):"
        f" X2 p = {fit.pearson_p:.3f}, G2 p = {fit.g_p:.3f}, {fit.failing} fail "
        f"(P = {fit.failing_p:.2g}), scatter of x in q in [0.001, 0.05) {fit.bins[1].scatter:.2f}"
    )


def main() -> None:
    """Print every candidate's number."""
    pairs = flow_pairs()
    table = next(t for _, _, path, t in pairs if path.name == "dx40.nc")
    stop_torques(table)
    spread_between_stops(table, pairs)
    commit_threshold(table)
    noise_step(table)
    noise_scale(pairs)
    part_scales(pairs)
    by_ensemble(pairs)


if __name__ == "__main__":
    main()
