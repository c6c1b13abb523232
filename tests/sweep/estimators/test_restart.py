"""pde_rotor.sweep.estimators.restart: spin-up, stop draw, timing and the release's outcome."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.sweep.estimators.restart import (
    Timing,
    check_spin_up,
    draw_stop,
    period_steps,
    release_outcome,
    restart_result,
    spin_up,
    stop_period,
    warm_states,
)
from pde_rotor.sweep.spec import RestartEstimator

from .rigid import RigidRotor, rigid_sweep

ESTIMATOR = RestartEstimator(warmup=0.1, check_interval=0.01, commit_fraction=0.5)


@pytest.fixture(scope="module")
def config() -> RotorConfig:
    return RotorConfig.model_validate(rigid_sweep("restart").runs()[0].config)


def test_the_spin_up_ignores_the_noise_and_keeps_the_direction(config):
    key, data = spin_up(config, ESTIMATOR, 1)
    noisy = config.model_copy(deep=True)
    noisy.noise.sigma, noisy.noise.seed = 1e-3, 99
    assert spin_up(noisy, ESTIMATOR, 1)[0] == key
    assert spin_up(config, ESTIMATOR, -1)[0] != key
    assert data["rotor"]["omega0"] == ESTIMATOR.spinup_omega
    assert (data["protocol"]["t_ini"], data["protocol"]["cycles"]) == (ESTIMATOR.warmup, 0)
    assert data["noise"]["sigma"] == 0.0
    check_spin_up(3.0, 1, ESTIMATOR)
    with pytest.raises(RuntimeError, match="not in the requested direction"):
        check_spin_up(-3.0, 1, ESTIMATOR)


def test_timing_counts_the_steps_of_one_stop(config):
    timing = Timing.of(config, ESTIMATOR, 1000)
    assert (timing.n0, timing.n_stop, timing.n_cap, timing.n_check) == (1000, 50, 125, 25)
    assert timing.release == 1050
    one_stop = timing.protocol(config).protocol
    assert (one_stop.t_ini, one_stop.t_stop, one_stop.cycles) == pytest.approx((0.4, 0.02, 1))


def test_the_stop_is_drawn_over_one_period_from_the_seeds(config):
    """At omega = 2 pi / N per unit time a period is 2500 steps; a restart's draw comes
    from its noise seed, a bank run's from the stop seed (its noise then restarts)."""
    omega = stop_period(config)
    assert period_steps(config, omega) == 2500
    draws = {draw_stop(config, ESTIMATOR, omega, 250).extra for _ in range(3)}
    assert len(draws) == 1  # the same seed, the same stop
    seeds = [
        config.model_copy(update={"noise": config.noise.model_copy(update={"seed": s})})
        for s in range(200)
    ]
    extras = np.array([draw_stop(c, ESTIMATOR, omega, 250).extra for c in seeds])
    assert extras.min() >= 0 and extras.max() < 2500
    assert 800 < extras.mean() < 1700  # uniform over 0..2499: mean 1250, sd of mean 51
    bank = [draw_stop(c, ESTIMATOR, omega, 250, stop_seed=7) for c in seeds[:3]]
    assert len({stop.extra for stop in bank}) == 1
    assert bank[0].timing.n0 == 250 + bank[0].extra
    expected = np.random.default_rng(seeds[1].noise.seed).standard_normal(4)
    np.testing.assert_array_equal(bank[1].rng.standard_normal(4), expected)


@pytest.mark.parametrize(
    ("after", "inverted", "committed", "commit_check"),
    [
        (lambda n: 4.0, False, True, 1),  # never slows: commits at the first check
        (lambda n: -4.0 if n >= 1100 else 0.5, True, True, 2),  # turns at step 1100
        (lambda n: 0.5, False, False, None),  # never reaches half of omega_before
    ],
)
def test_the_release_is_classified_by_the_one_rule(
    config, after, inverted, committed, commit_check
):
    timing = Timing.of(config, ESTIMATOR, 1000)
    release = release_outcome(after, timing, ESTIMATOR, 2.0, config.grid.dt)
    assert (release["inverted"], release["committed"]) == (inverted, committed)
    assert release["direction_before"] == 1
    if committed:
        assert release["t_commit"] == pytest.approx(commit_check * 25 * config.grid.dt)
    else:
        assert math.isnan(release["t_commit"]) and release["direction_after"] == 0


def test_the_result_keeps_the_stop_angle_modulo_the_period(config):
    release = {"inverted": False}
    result = restart_result(release, config, 3 * stop_period(config) + 0.25, 17, torque_end=-2)
    assert result["phi_stop"] == pytest.approx(0.25)
    assert (result["extra_steps"], result["torque_end"]) == (17, -2.0)
    assert "torque_end" not in restart_result(release, config, 0.0, 0)


def test_steady_states_are_spun_up_once_per_process(rigid: RigidRotor):
    """Runs that share their spin-up (point without protocol and noise, direction) are
    spun up as one ensemble member, and a second call computes nothing."""
    runs = rigid_sweep("restart").runs()
    configs = [RotorConfig.model_validate(r.config) for r in runs]
    states = warm_states(runs, configs, ESTIMATOR, rigid)
    assert [call["members"] for call in rigid.calls] == [4]  # 2 points x 2 directions
    for run, (_, rotor, step) in zip(runs, states, strict=True):
        assert step == 250
        assert rotor[1] == run.direction * ESTIMATOR.spinup_omega
    warm_states(runs, configs, ESTIMATOR, rigid)
    assert len(rigid.calls) == 1
