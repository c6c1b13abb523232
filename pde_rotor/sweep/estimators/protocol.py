"""The protocol estimator: the paper's stop-and-release protocol, M cycles in one run.

The runs of one grid advance as one ensemble from t = 0 on any ensemble backend
(:class:`pde_rotor.backends.base.EnsembleRunner`: the dask tasks call it with the CPU
backend, the batches with theirs); omega is read before every stop and at the end
(:func:`protocol_steps`) and counted by
:func:`pde_rotor.statistics.proportions.protocol_counts` (:func:`protocol_result`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ...backends.base import EnsembleRunner
from ...config import RotorConfig
from ...model.protocol import steps_of
from ...statistics.proportions import protocol_counts
from .base import check_finite


def protocol_steps(config: RotorConfig) -> list[int]:
    """Global steps after which the protocol estimator reads omega: before every stop,
    and at the end."""
    p, dt = config.protocol, config.grid.dt
    n_ini, n_period = steps_of(p.t_ini, dt), steps_of(p.t_stop + p.t_release, dt)
    return [n_ini + m * n_period for m in range(p.cycles + 1)]


def protocol_result(omegas: Sequence[float]) -> dict:
    """The stored result of a protocol run: the omegas and the counts of
    :func:`~pde_rotor.statistics.proportions.protocol_counts`."""
    counts = protocol_counts(omegas)
    return {
        "omegas": [float(w) for w in omegas],
        "inversions_ccw": counts.ccw.k,
        "n_ccw": counts.ccw.n,
        "inversions_cw": counts.cw.k,
        "n_cw": counts.cw.n,
    }


def protocol_runs(
    configs: Sequence[RotorConfig], keys: Sequence[str], ensemble: EnsembleRunner
) -> tuple[list[dict], str]:
    """The protocol estimator: runs of one grid as one ensemble from t = 0.

    omega is recorded at the gcd of the steps it is read at (:func:`protocol_steps`).

    Args:
        configs: the runs' configurations.
        keys: their run keys (named if a run diverges).
        ensemble: the backend's ``run_ensemble``.

    Returns:
        One :func:`protocol_result` per run, and the backend that computed them.

    Raises:
        ValueError: a member whose state diverged.
    """
    reads = [protocol_steps(config) for config in configs]
    every = math.gcd(*(s for member in reads for s in member))
    dt = configs[0].grid.dt
    result = ensemble(configs, max(m[-1] for m in reads) * dt, record_interval=every * dt)
    check_finite(result, keys)
    outcomes = [
        protocol_result([result.omega[m, s // every] for s in member])
        for m, member in enumerate(reads)
    ]
    return outcomes, result.backend
