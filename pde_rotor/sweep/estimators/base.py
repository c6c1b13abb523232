"""What every sweep estimator shares: the divergence check and the record of a run.

A run is computed either by a per-run task on a dask worker (:mod:`pde_rotor.sweep.tasks`)
or as a member of an ensemble batch (:mod:`pde_rotor.sweep.batch`); both check each
member's state (:func:`check_finite`) and store its result with its share of the wall
time (:func:`timed_contents`, :func:`run_content`), whichever estimator computed it.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ...backends.ensemble import EnsembleResult
from ..plan import SCHEMA_VERSION, Run


def check_finite(result: EnsembleResult, keys: Sequence[str]) -> None:
    """Raise if a member's state stopped being finite, naming its run.

    Raises:
        ValueError: the first diverged member, with its run key and time.
    """
    for m, key in enumerate(keys):
        if np.isfinite(result.diverged_at[m]):
            msg = f"run {key} diverged at t = {result.diverged_at[m]:g}"
            raise ValueError(msg)


def run_content(run: Run, result: dict, wall_time: float, backend: str) -> dict[str, Any]:
    """What the record of `run` in the store holds: its key, point, sample, result and cost.

    The resolved config is not repeated: the run key is its hash, and the sweep file in
    the sweep directory resolves it again.
    """
    return {
        "key": run.key,
        "schema": SCHEMA_VERSION,
        "coords": run.coords,
        "sample": run.sample,
        "direction": run.direction,
        "result": result,
        "wall_time": wall_time,
        "backend": backend,
    }


def timed_contents(
    runs: Sequence[Run], compute: Callable[[], tuple[list[dict], str]]
) -> list[dict[str, Any]]:
    """Compute the results of `runs` and return their records; the wall time is split
    evenly among the runs.

    Args:
        runs: the runs computed together.
        compute: returns one result per run and the backend that computed them.
    """
    start = time.perf_counter()
    results, backend = compute()
    share = (time.perf_counter() - start) / len(runs)
    pairs = zip(runs, results, strict=True)
    return [run_content(run, result, share, backend) for run, result in pairs]
