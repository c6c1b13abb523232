"""Sweep runs in batches on an ensemble backend (:func:`pde_rotor.backends.run_ensemble`).

A batch is a list of runs of one estimator on one grid; they advance together as the
members of one ensemble and go to the estimators of :mod:`.estimators`, the code the
per-run tasks (:mod:`.tasks`) call with the CPU backend, so a stored run means the same
whichever backend computed it. A batch records every step of a restart's ensemble in
one call per phase (:func:`.estimators.releases.restart_runs` with ``every_step``): a call is
costly on a GPU.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

from ..backends.base import EnsembleRunner
from ..config import RotorConfig
from .estimators.base import timed_contents
from .estimators.collective import collective_runs
from .estimators.protocol import protocol_runs
from .estimators.releases import restart_runs
from .plan import Run


def batches(runs: Sequence[Run], size: int) -> list[list[Run]]:
    """Split runs into batches of at most `size` members sharing grid and numerics."""
    by_grid: dict[str, list[Run]] = {}
    for run in runs:
        shared = json.dumps([run.config["grid"], run.config["numerics"]], sort_keys=True)
        by_grid.setdefault(shared, []).append(run)
    return [group[i : i + size] for group in by_grid.values() for i in range(0, len(group), size)]


def execute_batch(runs: Sequence[Run], ensemble: EnsembleRunner) -> list[dict[str, Any]]:
    """Compute runs of one estimator as ensembles; their run-file contents.

    Protocol runs go to :func:`.estimators.protocol.protocol_runs`, restart and bank runs
    to :func:`.estimators.releases.restart_runs`, recorded at every step; collective runs
    (bodies) to :func:`.estimators.collective.collective_runs` on the GPU, one member
    each (their bodies' layouts differ from run to run).

    Args:
        runs: runs sharing grid and numerics (:func:`batches`).
        ensemble: the backend's ``run_ensemble``; the backend its result names is
            recorded in each run's record.

    Raises:
        ValueError: a member whose state diverged.
        RuntimeError: a spin-up that ends in the other direction.
    """
    if runs[0].estimator["kind"] == "collective":
        return timed_contents(runs, lambda: collective_runs(runs, backend="gpu"))
    if runs[0].estimator["kind"] == "protocol":
        configs = [RotorConfig.model_validate(run.config) for run in runs]
        keys = [run.key for run in runs]
        return timed_contents(runs, lambda: protocol_runs(configs, keys, ensemble))
    return timed_contents(runs, lambda: restart_runs(runs, ensemble, every_step=True))
