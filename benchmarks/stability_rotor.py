"""The paper's rotor released from rest: its leading eigenvalue on both schemes, with and
without flow, on three grids, against the decision tables' lambda (docs/results.md).

For each grid, scheme and flow: the leading eigenvalue of the co-moving linearisation
(the angle's stiffness dropped) and of the full one (the angle an unknown), the stiffness
K, the residual, and the thread CPU time of linearisation plus eigenvalues. Euler's step
multiplies a mode by 1 + dt lambda, so the growth rate a run measures is
ln(1 + dt lambda) / dt, printed beside lambda.

Run: ``python benchmarks/stability_rotor.py [DX ...]`` (default 0.05 0.025 0.0166666667;
one thread: OMP_NUM_THREADS=1).
"""

from __future__ import annotations

import math
import sys
import time

from pde_rotor.config import RotorConfig
from pde_rotor.stability import DiscreteModel, leading_modes, linearise


def main(argv: list[str]) -> None:
    """Print one line per grid, scheme and flow."""
    grids = [float(a) for a in argv] or [0.05, 0.025, 0.0166666667]
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
                print(
                    f"dx={dx:.4g} {scheme:10s} flow={flow!s:5s} lambda={lam:.4f} "
                    f"(Euler step {stepped:.4f}) with angle {full:.4f} "
                    f"K={lin.stiffness[0, 0]:+.4f} residual={spectrum.residuals[0]:.1e} "
                    f"cpu={cpu:.1f}s",
                    flush=True,
                )


if __name__ == "__main__":
    main(sys.argv[1:])
