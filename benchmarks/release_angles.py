"""Is the model's release amplitude right at every stop angle? Noise-free releases.

A decision table (docs/decision.md) takes the bias of a release from the torque on a
plate held at rest, scaled by one release amplitude r that its check releases measured at
the first stop angle and the reference Delta only. This script repeats the table's stops
(its config with the case's Delta, the warm state and the table's stop angles,
:func:`pde_rotor.decision.runs.measure_table`) for each case (t_stop, Delta, direction
before the stop), releases every angle's stopped state without noise, and prints per angle
the amplitude m = lim omega e^{-lambda t} against the model's r C beta / lambda, both in
units of the noise's C sqrt(Dw / lambda) at `--sigma` (the model's x), and the probability
of the less likely direction from each: the model's, and the one the measured amplitudes
give (mean over the angles of Phi(-|m| / (C sqrt(Dw / lambda)))).

Run:  python benchmarks/release_angles.py --case 1.75 3e-5 1 --case 2.5 4e-5 -1
      --case 1.5 0 -1   (the paper's grid: about 5 minutes per warm state and 10 s per
      angle on a loaded core)
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.special import ndtr

from pde_rotor import RotorConfig
from pde_rotor.decision.runs import _one_stop, release_amplitude, release_record
from pde_rotor.decision.table import DIRECTIONS, DecisionTable, diffusion_of, load_table
from pde_rotor.sweep.estimators import period_steps
from pde_rotor.sweep.spec import RestartEstimator
from pde_rotor.sweep.tasks import warm_state


def one_case(
    table: DecisionTable, t_stop: float, asymmetry: float, direction: int, sigma: float
) -> None:
    """Print every angle's measured and modelled release amplitude of one case."""
    config = RotorConfig.model_validate_json(table.attrs["config"])
    config.geometry.asymmetry = asymmetry
    estimator = RestartEstimator(warmup=float(table.attrs["warmup"]))
    d = DIRECTIONS.index(direction)
    dt = config.grid.dt
    interval = float(table.time[1] - table.time[0])
    every = max(1, round(interval / dt))
    j = round(t_stop / interval)
    n_angles = table.torque.shape[1]
    model = table.release_bias(table.time[j], asymmetry)[d] * table.response / table.growth_rate
    noise = table.response * math.sqrt(diffusion_of(sigma, table.inertia) / table.growth_rate)
    start = time.perf_counter()
    warm = warm_state(config, estimator, direction)
    n_period = period_steps(config, warm.rotor.omega)
    n_warm = round(warm.t / dt)
    print(
        f"case t_stop = {table.time[j]:g}, Delta = {asymmetry:g}, direction {direction:+d}: "
        f"warm state ({time.perf_counter() - start:.0f} s)",
        flush=True,
    )
    measured = np.empty(n_angles)
    for k in range(n_angles):
        n_start = n_warm + (k * n_period) // n_angles
        stop = warm.branch(_one_stop(config, n_start, (table.time.size - 1) * every + 1))
        stop.run((n_start + j * every + 1) * dt)
        times, omega = release_record(stop.branch(), n_start, 0.0, interval)
        measured[k] = release_amplitude(times, omega, table.growth_rate)
        print(
            f"  angle {k}: x measured {measured[k] / noise:+.3f}, model {model[k] / noise:+.3f}"
            f" ({time.perf_counter() - start:.0f} s)",
            flush=True,
        )
    # the less likely direction: the one against the model's mean bias
    sign = np.sign(model.mean())
    q_model = float(np.mean(ndtr(-sign * model / noise)))
    q_measured = float(np.mean(ndtr(-sign * measured / noise)))
    print(
        f"  less likely direction at sigma = {sigma:g}: q = {q_model:.4g} (model), "
        f"{q_measured:.4g} (measured amplitudes); x error measured - model: mean "
        f"{np.mean(measured - model) / noise:+.3f}, sd {np.std(measured - model) / noise:.3f}"
    )


def main() -> None:
    """Run every --case."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--table", default="data/decision/dx40.nc")
    parser.add_argument("--sigma", type=float, default=1.5e-7)
    parser.add_argument(
        "--case",
        nargs=3,
        type=float,
        action="append",
        metavar=("T_STOP", "DELTA", "DIRECTION"),
        required=True,
        help="stop duration, Delta and direction before the stop (1 CCW, -1 CW)",
    )
    args = parser.parse_args()
    table = load_table(args.table)
    for t_stop, asymmetry, direction in args.case:
        one_case(table, t_stop, asymmetry, int(direction), args.sigma)


if __name__ == "__main__":
    main()
