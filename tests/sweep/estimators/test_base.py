"""pde_rotor.sweep.estimators.base: the divergence check and the record of a run."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.sweep.estimators.base import check_finite, timed_contents
from pde_rotor.sweep.plan import SCHEMA_VERSION

from .rigid import RigidRotor, rigid_sweep


def test_check_finite_names_the_first_diverged_run():
    configs = [RotorConfig.model_validate(r.config) for r in rigid_sweep("protocol").runs()[:3]]
    result = RigidRotor()(configs, 0.01, record_interval=0.01)
    check_finite(result, ["a", "b", "c"])  # nothing diverged: no error
    result.diverged_at[1:] = [0.25, 0.5]
    with pytest.raises(ValueError, match=r"^run b diverged at t = 0\.25$"):
        check_finite(result, ["a", "b", "c"])


def test_timed_contents_splits_the_wall_time_evenly(monkeypatch):
    runs = rigid_sweep("restart").runs()[:4]
    calls = []  # the process's CPU clock: 1.0 at the start, 1.5 after the compute

    def process_clock():
        calls.append(None)
        return 1.0 if len(calls) == 1 else 1.5

    def compute():
        time.sleep(0.02)
        return [{"k": n} for n in range(4)], "rigid"

    monkeypatch.setattr(time, "process_time", process_clock)

    records = timed_contents(runs, compute)
    assert [r["key"] for r in records] == [r.key for r in runs]
    assert [r["result"] for r in records] == [{"k": n} for n in range(4)]
    shares = [r["wall_time"] for r in records]
    assert len(set(shares)) == 1 and shares[0] >= 0.02 / 4
    cpu = [r["cpu_time"] for r in records]  # the process clock's 0.5, not the wall's
    assert cpu == [0.125] * 4
    first = records[0]
    assert first["schema"] == SCHEMA_VERSION and first["backend"] == "rigid"
    assert (first["coords"], first["sample"], first["direction"]) == (
        runs[0].coords,
        runs[0].sample,
        runs[0].direction,
    )
    assert math.isfinite(np.sum(shares))


def test_timed_contents_refuses_a_result_count_that_is_not_the_runs():
    runs = rigid_sweep("restart").runs()[:2]
    with pytest.raises(ValueError):
        timed_contents(runs, lambda: ([{}], "rigid"))
