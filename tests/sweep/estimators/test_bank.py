"""pde_rotor.sweep.estimators.bank: the delayed noise, the noise-free copies, the
members computed once."""

from __future__ import annotations

import numpy as np

from pde_rotor.backends.ensemble import EnsembleState
from pde_rotor.config import RotorConfig
from pde_rotor.sweep.estimators.bank import DelayedNoise, noise_free, run_distinct

from .rigid import RigidRotor, rigid_sweep


def test_delayed_noise_is_zero_in_the_stop_then_the_generators_stream():
    """Zeros for the steps left in the stop, then the draws the Generator would give,
    however the backend splits its requests."""
    delayed = DelayedNoise(np.random.default_rng(4), 5)
    draws = np.concatenate([delayed.standard_normal(n) for n in (3, 4, 6)])
    np.testing.assert_array_equal(draws[:5], 0.0)
    np.testing.assert_array_equal(draws[5:], np.random.default_rng(4).standard_normal(8))


def test_noise_free_copies_leave_the_configs_alone():
    configs = [RotorConfig.model_validate({"noise": {"sigma": s, "seed": 3}}) for s in (1e-7, 2e-7)]
    quiet = noise_free(configs)
    assert [q.noise.sigma for q in quiet] == [0.0, 0.0]
    assert [c.noise.sigma for c in configs] == [1e-7, 2e-7]
    assert quiet[0].model_dump(exclude={"noise"}) == configs[0].model_dump(exclude={"noise"})


def test_members_equal_but_for_the_noise_are_computed_once():
    """Four members: two noises of one point, one of another point, and a copy of the
    first with another state. Three distinct ones are computed; every member gets the
    rows of its own."""
    base = [RotorConfig.model_validate(r.config) for r in rigid_sweep("bank").runs()]
    a, b = base[0], next(c for c in base if c.geometry.asymmetry != base[0].geometry.asymmetry)
    louder = a.model_copy(update={"noise": a.noise.model_copy(update={"sigma": 1e-6})})
    configs = noise_free([a, louder, b, a])
    rotor = np.zeros((4, 5))
    rotor[:, 1] = [2.0, 2.0, 3.0, 5.0]
    state = EnsembleState(np.zeros((4, 3, 2, 2)), rotor, 0)
    rigid = RigidRotor()
    result = run_distinct(rigid, configs, state, 0.04, 0.004)
    assert [call["members"] for call in rigid.calls] == [3]
    np.testing.assert_array_equal(result.omega[:, -1], [2.0, 2.0, 3.0, 5.0])
    np.testing.assert_array_equal(result.phi[0], result.phi[1])
    np.testing.assert_array_equal(result.state.rotor[:, 1], [2.0, 2.0, 3.0, 5.0])
    assert result.configs == tuple(configs)
