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


def run_content(
    run: Run, result: dict, wall_time: float, backend: str, cpu_time: float | None = None
) -> dict[str, Any]:
    """What the record of `run` in the store holds: its key, point, sample, result and cost.

    The resolved config is not repeated: the run key is its hash, and the sweep file in
    the sweep directory resolves it again. `cpu_time`, where given, is the CPU time of the
    computing process (a worker's, all its threads): on a loaded machine the wall time is
    longer, and the cost estimates of :mod:`pde_rotor.sweep.cost` are of one idle core.
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
    } | ({} if cpu_time is None else {"cpu_time": cpu_time})


def timed_contents(
    runs: Sequence[Run], compute: Callable[[], tuple[list[dict], str]]
) -> list[dict[str, Any]]:
    """Compute the results of `runs` and return their records; the wall time and the
    CPU time of this process are split evenly among the runs.

    Args:
        runs: the runs computed together.
        compute: returns one result per run and the backend that computed them.
    """
    start, cpu = time.perf_counter(), time.process_time()
    results, backend = compute()
    share = (time.perf_counter() - start) / len(runs)
    cpu_share = (time.process_time() - cpu) / len(runs)
    pairs = zip(runs, results, strict=True)
    return [run_content(run, result, share, backend, cpu_share) for run, result in pairs]
