"""pde_rotor.sweep.estimators.releases: restarts and bank runs as ensembles read at the
steps the rules name, whichever way the backend advances."""

from __future__ import annotations

import math
from collections import OrderedDict

import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.sweep.estimators import releases, restart
from pde_rotor.sweep.estimators.bank import DelayedNoise
from pde_rotor.sweep.estimators.restart import stop_period
from pde_rotor.sweep.spec import RestartEstimator

from .rigid import RigidRotor, rigid_sweep


def same_runs(first: list[dict], second: list[dict]) -> bool:
    """Equal results; the stop angle to rounding (the rigid rotor sums phi per call)."""
    for a, b in zip(first, second, strict=True):
        assert a.pop("phi_stop") == pytest.approx(b.pop("phi_stop"), rel=1e-12, abs=1e-12)
    return first == second


@pytest.mark.parametrize("kind", ["restart", "bank"])
def test_a_rotor_that_never_slows_never_inverts(rigid: RigidRotor, kind):
    """Each run reads omega and phi just before its drawn stop (phi = omega t from the
    spin-up at t = 0) and commits at the first check, the way it turned."""
    runs = rigid_sweep(kind).runs()
    estimator = RestartEstimator.model_validate({**runs[0].estimator, "kind": "restart"})
    results, backend = releases.restart_runs(runs, rigid, every_step=False)
    assert backend == "rigid"
    for run, result in zip(runs, results, strict=True):
        config = RotorConfig.model_validate(run.config)
        omega = run.direction * estimator.spinup_omega
        n0 = round(estimator.warmup / config.grid.dt) + result["extra_steps"]
        assert result["omega_before"] == omega
        assert (result["inverted"], result["committed"]) == (False, True)
        assert result["t_commit"] == pytest.approx(estimator.check_interval)
        phi = math.remainder(omega * n0 * config.grid.dt - result["phi_stop"], stop_period(config))
        assert phi == pytest.approx(0.0, abs=1e-9)
        assert ("torque_end" in result) == (kind == "bank")


@pytest.mark.parametrize("kind", ["restart", "bank"])
def test_every_step_records_and_read_steps_give_the_same_runs(monkeypatch, kind):
    """The GPU's way (every step recorded, one call per phase) and the CPU's (advance from
    one read step to the next, end once all committed) store the same results; the CPU's
    computes fewer steps."""
    runs = rigid_sweep(kind).runs()
    outcomes, steps = [], []
    for every_step in (True, False):
        monkeypatch.setattr(restart, "_WARM", OrderedDict())
        rigid = RigidRotor()
        outcomes.append(releases.restart_runs(runs, rigid, every_step)[0])
        steps.append(sum(c["members"] * c["steps"] for c in rigid.calls[1:]))  # after spin-up
    assert same_runs(outcomes[0], outcomes[1])
    assert steps[1] < steps[0]


def test_a_bank_approaches_its_stops_noise_free_once_per_stop(rigid: RigidRotor):
    """A noise axis: runs of the same point, sample and direction share their stop, so the
    noise-free approach computes one member per stop, and each release's noise is
    delayed to the end of its stop."""
    runs = rigid_sweep("bank", axes={"noise.sigma": [1e-7, 2e-7, 3e-7]}).runs()
    releases.restart_runs(runs, rigid, every_step=True)
    approach, release = rigid.calls[1], rigid.calls[2]
    assert approach["rngs"] is None and approach["members"] == len(runs) // 3
    assert release["members"] == len(runs)
    assert all(isinstance(rng, DelayedNoise) for rng in release["rngs"])


def test_ensembles_are_split_to_fit_the_record_budget(monkeypatch, rigid: RigidRotor):
    """With room for one member's records per call, every restart is its own ensemble,
    and the results are those of one ensemble."""
    runs = rigid_sweep("restart").runs()
    together = releases.restart_runs(runs, RigidRotor(), every_step=True)[0]
    monkeypatch.setattr(releases, "RECORD_BUDGET", 300)  # a restart records about 230
    alone = releases.restart_runs(runs, rigid, every_step=True)[0]
    assert same_runs(alone, together)
    assert rigid.calls and {c["members"] for c in rigid.calls} == {1}  # spun up already
