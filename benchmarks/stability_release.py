"""The compiled rotor released from the exact rest state: lambda fitted as the decision
tables fit it, against the linearisation's prediction (benchmarks/stability_rotor.py
--table-fit).

The rest state of the held rotor at phi0 (:func:`pde_rotor.stability.rest_state`) is put
into a noise-free simulation; two releases, free and from omega = 0.01, are recorded every
0.01 for 0.6 and fitted by :func:`pde_rotor.decision.runs.fit_response` (t >= 0.25, |omega|
< 3). What differs from the linear model's fit is the nonlinear response as |omega| grows to 3.

Run: ``python benchmarks/stability_release.py DX SCHEME`` (e.g. 0.025 consistent).
"""

from __future__ import annotations

import sys

import numpy as np

from pde_rotor.config import RotorConfig
from pde_rotor.decision.runs import fit_response
from pde_rotor.solver.simulation import Simulation
from pde_rotor.stability import DiscreteModel, rest_state

KICK, INTERVAL, SAMPLES = 0.01, 0.01, 60


def main(dx: float, scheme: str) -> None:
    """Print the fitted lambda and C of the two releases."""
    dt = 1e-4
    config = RotorConfig.model_validate(
        {
            "grid": {"dx": dx, "dt": dt},
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "solver": {"threads": 1},
        }
    )
    rest = rest_state(DiscreteModel(config))
    records = []
    for kick in (0.0, KICK):
        sim = Simulation(config)
        sim.state[0].data[...] = rest.c
        sim.rotor.phi, sim.rotor.omega = config.rotor.phi0, kick
        omegas = []
        for k in range(1, SAMPLES + 1):
            sim.run(round(k * INTERVAL / dt) * dt)
            omegas.append(sim.rotor.omega)
        records.append(np.array(omegas))
    times = INTERVAL * np.arange(1, SAMPLES + 1)
    lam, amplitude, samples = fit_response(times, records[0], records[1], KICK)
    print(f"dx={dx:g} {scheme}: release from rest lambda = {lam:.4f}, C = {amplitude:.4f} "
          f"({samples} samples)")  # fmt: skip


if __name__ == "__main__":
    main(float(sys.argv[1]), sys.argv[2])
