"""The paper's rotor released from rest: its leading eigenvalue on both schemes, with and
without flow, on three grids, against the decision tables' lambda (docs/results.md).

For each grid, scheme and flow: the leading eigenvalue of the co-moving linearisation
(the angle's stiffness dropped) and of the full one (the angle an unknown), the stiffness
K, the residual, and the thread CPU time of linearisation plus eigenvalues. Euler's step
multiplies a mode by 1 + dt lambda, so the growth rate a run measures is
ln(1 + dt lambda) / dt, printed beside lambda.

With ``--table-fit`` it also measures lambda the way the decision tables do
(:func:`pde_rotor.decision.runs.fit_response`): the response of the linearised model with
the angle (the released plate turns) to a kick of omega = 0.01, stepped by forward Euler
at the run's dt, fitted over t >= 0.25 while |omega| < 3, sampled every 0.01.

Run: ``python benchmarks/stability_rotor.py [--table-fit] [DX ...]`` (default 0.05 0.025
0.0166666667; one thread: OMP_NUM_THREADS=1).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from pde_rotor.config import RotorConfig
from pde_rotor.decision.runs import fit_response
from pde_rotor.stability import DiscreteModel, Linearisation, leading_modes, linearise

KICK, INTERVAL, SPAN = 0.01, 0.01, 0.6


def table_fit(lin: Linearisation, dt: float) -> float:
    """lambda fitted as the decision tables fit it, to the linear model's kick response."""
    lin = lin.with_positions(True)
    x = np.zeros(lin.size)
    x[-1] = KICK
    every = round(INTERVAL / dt)
    times, omegas = [], []
    for n in range(1, round(SPAN / dt) + 1):
        x = x + dt * lin.matvec(x)
        if n % every == 0:
            times.append(n * dt)
            omegas.append(x[-1])
    times, omegas = np.array(times), np.array(omegas)
    return fit_response(times, np.zeros_like(omegas), omegas, KICK)[0]


def main(argv: list[str]) -> None:
    """Print one line per grid, scheme and flow."""
    fit = "--table-fit" in argv
    grids = [float(a) for a in argv if a != "--table-fit"] or [0.05, 0.025, 0.0166666667]
    for dx in grids:
        dt = 1e-4 if dx >= 0.025 else 5e-5
        for scheme in ("consistent", "paper"):
            for flow in (True, False):
                config = RotorConfig.model_validate(
                    {
                        "grid": {"dx": dx, "dt": dt},
                        "numerics": {"scheme": scheme},
                        "flow": {"enabled": flow},
                    }
                )
                start = time.thread_time()
                lin = linearise(DiscreteModel(config))
                spectrum = leading_modes(lin, k=4)
                cpu = time.thread_time() - start
                lam = spectrum.leading.real
                full = leading_modes(lin.with_positions(True), k=4).leading.real
                stepped = math.log1p(dt * lam) / dt
                fitted = f" table-fit {table_fit(lin, dt):.4f}" if fit else ""
                print(
                    f"dx={dx:.4g} {scheme:10s} flow={flow!s:5s} lambda={lam:.4f} "
                    f"(Euler step {stepped:.4f}) with angle {full:.4f} "
                    f"K={lin.stiffness[0, 0]:+.4f} residual={spectrum.residuals[0]:.1e} "
                    f"cpu={cpu:.1f}s{fitted}",
                    flush=True,
                )


if __name__ == "__main__":
    main(sys.argv[1:])
