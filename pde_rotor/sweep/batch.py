"""Sweep runs in batches on an ensemble backend (:func:`pde_rotor.backends.run_ensemble`).

A batch is a list of protocol runs on one grid; they advance together as the members of
one ensemble, and each run's omega just before every stop and at the end is read from
the ensemble's records. The result is the one :func:`pde_rotor.sweep.tasks.run_protocol`
returns, so the report does not depend on where a run was computed.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..backends import EnsembleResult
from ..config import RotorConfig
from ..protocol import steps_of
from ..stats import protocol_counts
from .plan import Run
from .tasks import run_content

EnsembleRunner = Callable[..., EnsembleResult]
"""``run_ensemble(configs, t_end, *, record_interval=...)`` of a backend."""

BATCH_ESTIMATORS = ("protocol",)
"""Estimators whose runs an ensemble backend computes in batches."""


def _stop_steps(config: RotorConfig) -> list[int]:
    """Steps after which omega is read: before each of the M stops, then at the end."""
    p, dt = config.protocol, config.grid.dt
    n_ini, n_period = steps_of(p.t_ini, dt), steps_of(p.t_stop + p.t_release, dt)
    return [n_ini + m * n_period for m in range(p.cycles + 1)]


def batches(runs: Sequence[Run], size: int) -> list[list[Run]]:
    """Split runs into batches of at most `size` members sharing grid and numerics."""
    by_grid: dict[str, list[Run]] = {}
    for run in runs:
        shared = json.dumps([run.config["grid"], run.config["numerics"]], sort_keys=True)
        by_grid.setdefault(shared, []).append(run)
    return [group[i : i + size] for group in by_grid.values() for i in range(0, len(group), size)]


def execute_batch(runs: Sequence[Run], ensemble: EnsembleRunner) -> list[dict[str, Any]]:
    """Compute protocol runs as one ensemble; their run-file contents.

    Args:
        runs: protocol runs sharing grid and numerics (:func:`batches`).
        ensemble: the backend's ``run_ensemble``; the backend its result names is
            recorded in each run file.

    Raises:
        ValueError: a run of another estimator, or a member whose state diverged.
    """
    start = time.perf_counter()
    if any(run.estimator["kind"] not in BATCH_ESTIMATORS for run in runs):
        msg = f"ensemble batches compute the {', '.join(BATCH_ESTIMATORS)} estimator only"
        raise ValueError(msg)
    configs = [RotorConfig.model_validate(run.config) for run in runs]
    steps = [_stop_steps(config) for config in configs]
    every = math.gcd(*(s for member in steps for s in member))
    dt = configs[0].grid.dt
    t_end = max(member[-1] for member in steps) * dt
    result = ensemble(configs, t_end, record_interval=every * dt)
    share = (time.perf_counter() - start) / len(runs)
    contents = []
    for m, (run, member) in enumerate(zip(runs, steps, strict=True)):
        if np.isfinite(result.diverged_at[m]):
            msg = f"run {run.key} diverged at t = {result.diverged_at[m]:g}"
            raise ValueError(msg)
        omegas = [float(result.omega[m, s // every]) for s in member]
        counts = protocol_counts(omegas)
        outcome = {
            "omegas": omegas,
            "inversions_ccw": counts.ccw.k,
            "n_ccw": counts.ccw.n,
            "inversions_cw": counts.cw.k,
            "n_cw": counts.cw.n,
        }
        contents.append(run_content(run, outcome, share, result.backend))
    return contents
