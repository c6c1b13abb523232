"""pde_rotor.sweep.estimators.protocol: the steps read, the counts, one ensemble per grid."""

from __future__ import annotations

import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.sweep.estimators.protocol import protocol_result, protocol_runs, protocol_steps

from .rigid import RigidRotor, rigid_sweep


def test_omega_is_read_before_every_stop_and_at_the_end():
    config = RotorConfig.model_validate(rigid_sweep("protocol").runs()[0].config)
    assert protocol_steps(config) == [125, 125 + 175, 125 + 2 * 175]


def test_the_result_counts_each_stop_by_the_direction_before_it():
    """Stops between +, -, -, +: a CCW stop that inverted, a CW stop that did not, a CW
    stop that did."""
    result = protocol_result([2.0, -1.5, -1.0, 3.0])
    assert result["omegas"] == [2.0, -1.5, -1.0, 3.0]
    assert (result["inversions_ccw"], result["n_ccw"]) == (1, 1)
    assert (result["inversions_cw"], result["n_cw"]) == (1, 2)


def test_runs_of_one_grid_are_one_ensemble_read_at_the_gcd_of_their_steps(rigid: RigidRotor):
    """Rotors that never slow never invert: every stop counted, none inverted, in one call
    recorded every 25 steps (the gcd of 125 and 175)."""
    runs = rigid_sweep("protocol").runs()
    configs = [RotorConfig.model_validate(r.config) for r in runs]
    outcomes, backend = protocol_runs(configs, [r.key for r in runs], rigid)
    assert backend == "rigid"
    assert [(call["members"], call["steps"]) for call in rigid.calls] == [(len(runs), 475)]
    for config, outcome in zip(configs, outcomes, strict=True):
        assert outcome["omegas"] == pytest.approx([config.rotor.omega0] * 3)
        assert outcome["inversions_ccw"] + outcome["inversions_cw"] == 0
        assert outcome["n_ccw"] + outcome["n_cw"] == 2
