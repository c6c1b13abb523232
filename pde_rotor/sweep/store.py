"""The store of a sweep: a directory of run files, one JSON file per finished run.

A sweep directory holds ``sweep.yaml`` (the specification, base inlined), ``runs/``
with ``<run key>.json`` per finished run and ``report.nc``. A run key is a hash of what
determines the run's result (:func:`pde_rotor.sweep.plan.run_key`), never of a path, a
machine or the scheduler, so the directory can be committed to the repository (the
default is ``data/sweeps/<name>``) and a sweep resumed from a clone on another machine
recomputes nothing that is stored. Every file is written atomically
(:func:`pde_rotor.io.output.write_text_atomic`): a file with its final name is complete.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from ..io.output import write_text_atomic
from .plan import SPEC_FILE, Run, Sweep
from .spec import SweepError

RUNS_DIR = "runs"
"""Sub-directory of a sweep directory holding one JSON file per finished run."""
REPORT_FILE = "report.nc"
"""NetCDF file written by :func:`pde_rotor.sweep.reporting.report`."""
DEFAULT_ROOT = Path("data") / "sweeps"
"""Sweep directories default to data/sweeps/<name of the sweep file>: in the repository,
so that committed results travel with a clone and a sweep resumes from them."""


def run_path(sweep_dir: str | Path, key: str) -> Path:
    """File of the run with hash `key`."""
    return Path(sweep_dir) / RUNS_DIR / f"{key}.json"


def write_run(sweep_dir: str | Path, content: Mapping[str, Any]) -> Path:
    """Write a run file (compact JSON, atomically) named by the run key in `content`."""
    path = run_path(sweep_dir, content["key"])
    write_text_atomic(path, json.dumps(content, separators=(",", ":"), allow_nan=True) + "\n")
    return path


def load_run(path: Path) -> dict[str, Any] | None:
    """Content of a run file, or None if it is missing or unreadable."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def finished(sweep_dir: str | Path, runs: Sequence[Run]) -> set[str]:
    """Keys of the runs whose result file exists (and is complete JSON with that key)."""
    done = set()
    for run in runs:
        content = load_run(run_path(sweep_dir, run.key))
        if content is not None and content.get("key") == run.key:
            done.add(run.key)
    return done


def holds(design: Sweep, sweep: Sweep) -> bool:
    """Whether every run of `sweep` is a run of `design` (same run keys: a subset of its
    axis values or samples, everything else equal)."""
    keys = {run.key for run in design.runs()}
    return all(run.key in keys for run in sweep.runs())


def prepare(sweep: Sweep, sweep_dir: str | Path) -> Path:
    """Create the sweep directory and record the design (base inlined) in its sweep.yaml.

    A design already recorded there that holds every run of `sweep` (:func:`holds`) is
    kept: a run of a subset (``--set axes.KEY=[...]``) adds runs to the directory without
    narrowing its design, so the directory's report and a resume from a clone still
    cover the whole design. Any other sweep (or an unreadable sweep.yaml) replaces it.
    """
    sweep_dir = Path(sweep_dir)
    (sweep_dir / RUNS_DIR).mkdir(parents=True, exist_ok=True)
    spec_path = sweep_dir / SPEC_FILE
    if spec_path.is_file():
        try:
            if holds(Sweep.load(spec_path), sweep):
                return sweep_dir
        except SweepError:
            pass  # a record that no longer loads is replaced by this sweep's
    text = yaml.safe_dump(sweep.spec.model_dump(mode="json"), sort_keys=False)
    write_text_atomic(spec_path, text)
    return sweep_dir
