"""Where does a release decide? Many noisy releases of one stopped state, read twice.

The decision model (docs/decision.md) says that after a release ω e^{-λt} tends to
C (β/λ + N(0, Dw/λ)): a Gaussian whose sign is the direction. This script stops the
rotor once (noise-free, as the restart and bank estimators do), releases the stopped
state `--releases` times with independent noise, and records for each release

* the linear amplitude A = ω(t_a) e^{-λ t_a} at `--t-amplitude` (|ω| still small), and
* the direction it commits to (the estimators' rule: |ω| >= commit_fraction |ω_before|).

It prints the mean and standard deviation of A against the model's C β/λ and
C sqrt(Dw/λ), the fraction of releases whose A points the less likely way against
Φ(-|β|/sqrt(λ Dw)), the tail fractions of A/sd against the Gaussian's, and how many
releases commit against the sign of their A (a decision after the linear phase).

Run:  python benchmarks/release_distribution.py --t-stop 1.5 --direction -1 --releases 300
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.stats import norm

from pde_rotor import RotorConfig
from pde_rotor.decision.runs import _one_stop
from pde_rotor.decision.table import diffusion_of, load_table
from pde_rotor.sweep.estimators.restart import period_steps
from pde_rotor.sweep.spec import RestartEstimator
from pde_rotor.sweep.tasks import warm_state


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--t-stop", type=float, default=1.5)
    parser.add_argument("--asymmetry", type=float, default=0.0)
    parser.add_argument("--sigma", type=float, default=1.5e-7)
    parser.add_argument("--direction", type=int, default=-1, help="+1 CCW, -1 CW before")
    parser.add_argument("--angle", type=float, default=0.0, help="stop angle, fraction of 2 pi/N")
    parser.add_argument("--releases", type=int, default=300)
    parser.add_argument("--t-amplitude", type=float, default=0.25)
    parser.add_argument("--table", default="data/decision/dx40.nc")
    parser.add_argument("--seed", type=int, default=20261126)
    args = parser.parse_args()

    config = RotorConfig()
    config.geometry.asymmetry = args.asymmetry
    estimator = RestartEstimator()
    table = load_table(args.table)
    lam, response = table.growth_rate, table.response
    dw = diffusion_of(args.sigma, table.inertia)
    dt = config.grid.dt

    quiet = config.model_copy(deep=True)
    warm = warm_state(quiet, estimator, args.direction)
    omega_before = warm.rotor.omega
    n_start = round(warm.t / dt) + round(args.angle * period_steps(quiet, omega_before))
    n_stop = round(args.t_stop / dt)
    stop = warm.branch(_one_stop(quiet, n_start, n_stop))
    stop.run((n_start + n_stop) * dt)
    t_release = stop.t

    noisy = _one_stop(quiet, n_start, n_stop)
    noisy.noise.sigma = args.sigma
    check = estimator.check_interval
    commit = estimator.commit_fraction * abs(omega_before)
    rng = np.random.default_rng(args.seed)
    amplitudes, directions = [], []
    start = time.perf_counter()
    for _ in range(args.releases):
        sim = stop.branch(noisy, rng=np.random.default_rng(rng.integers(2**63)))
        sim.run(t_release + args.t_amplitude)
        amplitude = sim.rotor.omega * math.exp(-lam * args.t_amplitude)
        linear = abs(sim.rotor.omega) < 3.0
        k = 0
        while abs(sim.rotor.omega) < commit and k < 60:
            k += 1
            sim.run(t_release + args.t_amplitude + k * check)
        amplitudes.append(amplitude if linear else math.copysign(math.inf, amplitude))
        directions.append(int(np.sign(sim.rotor.omega)) if abs(sim.rotor.omega) >= commit else 0)
    wall = time.perf_counter() - start
    a = np.array(amplitudes)
    d = np.array(directions)

    beta = table.bias(args.t_stop, args.asymmetry)[0 if args.direction > 0 else 1]
    k_angle = args.angle * beta.size
    beta_here = float(np.interp(k_angle, np.arange(beta.size + 1), np.append(beta, beta[0])))
    mean_model = response * beta_here / lam
    sd_model = response * math.sqrt(dw / lam)
    x = beta_here / math.sqrt(lam * dw)
    finite = np.isfinite(a)
    print(
        f"t_stop = {args.t_stop:g}, Delta = {args.asymmetry:g}, sigma = {args.sigma:g}, "
        f"direction before {args.direction:+d}, angle {args.angle:g}: {args.releases} "
        f"releases in {wall:.0f} s; lambda = {lam:.4g}, C = {response:.4g}"
    )
    print(
        f"A at t = {args.t_amplitude:g}: mean {a[finite].mean():.4g} (model C beta/lambda "
        f"{mean_model:.4g}), sd {a[finite].std(ddof=1):.4g} (model C sqrt(Dw/lambda) "
        f"{sd_model:.4g}); {int((~finite).sum())} left the linear range by then"
    )
    minority = -np.sign(beta_here)
    print(
        f"x = beta/sqrt(lambda Dw) = {x:.3f}: model P(less likely way) = {norm.cdf(-abs(x)):.4f}; "
        f"A points that way in {np.mean(np.sign(a) == minority):.4f}, commits that way in "
        f"{np.mean(d == minority):.4f} ({int(np.sum(d == minority))} of {d.size}); "
        f"never committed {int(np.sum(d == 0))}"
    )
    z = (a[finite] - a[finite].mean()) / a[finite].std(ddof=1)
    for level in (1.5, 2.0, 2.5):
        print(
            f"  |A - mean| > {level} sd: {np.mean(np.abs(z) > level):.4f} "
            f"(Gaussian {2 * norm.sf(level):.4f})"
        )
    against = np.sum((d != 0) & finite & (np.sign(a) != d))
    print(f"commit against the sign of A: {int(against)} of {int(np.sum(finite & (d != 0)))}")


if __name__ == "__main__":
    main()
