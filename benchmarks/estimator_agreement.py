"""Does the independent-restart estimator agree with the paper's protocol?

Runs, on the same parameters, (a) the paper's protocol, `--runs` runs of t_ini = 10 and
M = 100 stop-and-release cycles with t_release = 10, and (b) the restart estimator,
`--samples` independent stops from CCW and as many from CW rotation, both as resumable
sweeps (pde_rotor.sweep) on a LocalCluster. It then compares P(inversion | CCW) and
P(inversion | CW) of the two estimators with Fisher's exact test (Holm-corrected), and
the protocol's inversions / M with the restarts' two-state-chain combination by the
overlap of their 95 % intervals (pde_rotor.statistics.proportions.compare_estimators).

Default case: coarse grid (the shipped base pde_rotor/bases/coarse.yaml), Delta = 1e-4 and
t_stop = 3, where the two conditional probabilities differ (Delta > 0 favours CW), so
that the chain combination is tested, not only a single proportion. About 20 minutes on
2 cores (the protocol runs dominate: 3.25e6 steps each).

    python benchmarks/estimator_agreement.py [--out runs/agreement] [--workers 2]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import yaml

from pde_rotor.statistics.proportions import DirectionCounts, Proportion, compare_estimators
from pde_rotor.sweep import Sweep, SweepSpec, gather, run_sweep, shipped_base

ROOT = Path(__file__).resolve().parents[1]
BASE = shipped_base("coarse")


def counts_of(ds) -> DirectionCounts:
    """Conditional inversion counts of a sweep without axes."""
    return DirectionCounts(
        Proportion(int(ds["inversions_ccw"]), int(ds["stops_ccw"])),
        Proportion(int(ds["inversions_cw"]), int(ds["stops_cw"])),
    )


def fmt(prop: Proportion) -> str:
    lo, hi = prop.interval()
    return f"{prop.k}/{prop.n} = {prop.p:.3f} [{lo:.3f}, {hi:.3f}]"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("runs/agreement"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--asymmetry", type=float, default=1e-4)
    parser.add_argument("--t-stop", type=float, default=3.0)
    parser.add_argument("--sigma", type=float, default=1e-6)
    parser.add_argument("--runs", type=int, default=2, help="protocol runs of M = 100 cycles")
    parser.add_argument("--samples", type=int, default=100, help="restarts per direction")
    parser.add_argument("--seed", type=int, default=4242)
    args = parser.parse_args()

    base = yaml.safe_load(BASE.read_text(encoding="utf-8"))
    point = {
        "geometry.asymmetry": args.asymmetry,
        "protocol.t_stop": args.t_stop,
        "noise.sigma": args.sigma,
    }
    common = {"base": base, "set": point, "seed": args.seed}
    protocol = Sweep.from_spec(
        SweepSpec.model_validate(
            {**common, "name": "protocol", "estimator": {"kind": "protocol"}, "samples": args.runs}
        )
    )
    restart = Sweep.from_spec(
        SweepSpec.model_validate(
            {
                **common,
                "name": "restart",
                "estimator": {"kind": "restart"},
                "samples": args.samples,
            }
        )
    )
    results = {}
    for sweep in (restart, protocol):
        target = args.out / sweep.spec.name
        outcome = run_sweep(sweep, target, workers=args.workers)
        if outcome.failed:
            raise SystemExit(f"{len(outcome.failed)} runs failed: {outcome.failed[0]}")
        results[sweep.spec.name] = gather(sweep, target)

    comparison = compare_estimators(counts_of(results["protocol"]), counts_of(results["restart"]))
    grid = base["grid"]
    print(
        f"case: dx = {grid['dx']}, dt = {grid['dt']}, Delta = {args.asymmetry:g}, "
        f"t_stop = {args.t_stop:g}, sigma = {args.sigma:g}"
    )
    print(f"{'':24}{'paper protocol':>34}{'restarts':>34}")
    for name in ("ccw", "cw"):
        test = getattr(comparison, name)
        if test is None:
            print(f"P(inv | {name.upper()}): no samples in one estimator")
            continue
        print(
            f"P(inv | {name.upper()}){'':13}{fmt(test.first):>34}{fmt(test.second):>34}"
            f"   Fisher p (Holm) = {test.p_value:.3f}"
        )
    chain = comparison.restart
    print(
        f"P{'':23}{fmt(comparison.protocol_p):>34}"
        f"{f'{chain.p:.3f} [{chain.low:.3f}, {chain.high:.3f}]':>34}"
        f"   intervals overlap: {comparison.overlap}"
    )
    print(
        f"mean |omega| before stops: protocol {float(results['protocol']['mean_abs_omega']):.2f}"
        f", restarts {float(results['restart']['mean_abs_omega']):.2f}"
    )
    print(f"agree (alpha = 0.05): {comparison.agree}")


if __name__ == "__main__":
    main()
