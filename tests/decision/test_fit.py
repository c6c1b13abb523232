"""The noise fit: κ recovered from releases drawn from the model itself, and the stores
it reads.

Releases are drawn from the synthetic table's conditionals at κ_true Dw; the fit must
find κ_true inside its 95 % range, and the calibrated Dw must give the target P in the
model at κ Dw.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtri

from pde_rotor.decision.fit import Outcome, fit_noise, sweep_outcomes
from pde_rotor.decision.table import DIRECTIONS, diffusion_of
from pde_rotor.sweep.store import RunLog, prepare
from tests.decision.test_table import synthetic
from tests.sweep.test_sweep import tiny_sweep

SIGMAS = (0.0, 7e-8, 1e-7, 1.4e-7, 2e-7, 2.8e-7)


def drawn(kappa: float, stops: int, seed: int = 1) -> list[Outcome]:
    """Bank-like releases at t_stop = 3, Δ = 2e-5: every stop released at every sigma,
    inverted with the model's probability at κ Dw."""
    table = synthetic()
    rng = np.random.default_rng(seed)
    out = []
    for sigma in SIGMAS:
        a, b = table.conditionals(3.0, 2e-5, kappa * diffusion_of(sigma, table.inertia))
        for direction, p in zip(DIRECTIONS, (float(a), float(b)), strict=True):
            hits = rng.random(stops) < p
            out += [Outcome(3.0, 2e-5, sigma, direction, i, bool(h)) for i, h in enumerate(hits)]
    return out


@pytest.mark.parametrize("kappa", [1.0, 3.0])
def test_the_fit_recovers_the_scale_the_releases_were_drawn_with(kappa: float) -> None:
    """Over 20 ensembles the 95 % range holds κ_true in about 19 (at least 16: a binomial
    tail of 1.6 % for a true coverage of 0.95) and the estimates centre on it."""
    fits = [fit_noise(synthetic(), drawn(kappa, 200, seed), resamples=200) for seed in range(20)]
    inside = sum(f.scale_range[0] < kappa < f.scale_range[1] for f in fits)
    assert inside >= 16
    assert np.median([f.scale for f in fits]) == pytest.approx(kappa, rel=0.05)
    assert all(f.scale_range[1] / f.scale_range[0] < 3 for f in fits)
    assert fits[0].stops == 2 * 200
    assert fits[0].groups == 2 * (len(SIGMAS) - 1)  # noise-free releases carry no κ


def test_one_count_is_fitted_where_the_model_meets_its_fraction() -> None:
    """One (point, direction): the likelihood is largest where the model's P(inv) is k/n,
    P(inv | CW) = Φ(β / sqrt(λ κ Dw)), so κ = (β / (sqrt(λ Dw) Φ⁻¹(k/n)))² in closed
    form (every angle of the synthetic table has the same β)."""
    table = synthetic()
    sigma, n, k = 1.4e-7, 200, 28
    outcomes = [Outcome(3.0, 2e-5, sigma, -1, i, i < k) for i in range(n)]
    beta = table.bias(3.0, 2e-5)[DIRECTIONS.index(-1)]
    assert np.ptp(beta) == 0
    dw = diffusion_of(sigma, table.inertia)
    expected = (beta[0] / (np.sqrt(table.growth_rate * dw) * ndtri(k / n))) ** 2
    fit = fit_noise(table, outcomes, resamples=20)
    assert 1.2 < expected < 1.8  # inside the range, away from a grid point
    assert fit.scale == pytest.approx(expected, rel=1e-5)


def test_scale_and_range_match_a_brute_force_stratified_bootstrap() -> None:
    """κ maximises the likelihood on a fine grid of κ written here from the table's
    conditionals, and its 95 % range is the 2.5 and 97.5 % percentiles of that maximum
    over resamples of the stops drawn within each direction (to the Monte Carlo scatter
    of 4000 resamples on either side, about 0.5 %)."""
    table, outcomes = synthetic(), drawn(1.5, 200, seed=3)
    fit = fit_noise(table, outcomes, resamples=4000, seed=5)
    sigmas = [s for s in SIGMAS if s > 0]
    kappas = np.geomspace(fit.scale / 2, fit.scale * 2, 4001)
    p = np.array(  # (sigma, direction) x kappa
        [
            [table.conditionals(3.0, 2e-5, k * diffusion_of(s, table.inertia))[d] for k in kappas]
            for s in sigmas
            for d in range(len(DIRECTIONS))
        ]
    )
    log_p, log_q = np.log(p), np.log(1 - p)
    hits = np.zeros((len(DIRECTIONS), 200, p.shape[0]))  # direction x stop x group
    tries = np.zeros_like(hits)
    for o in outcomes:
        if o.sigma > 0:
            d = DIRECTIONS.index(o.direction)
            group = sigmas.index(o.sigma) * len(DIRECTIONS) + d
            hits[d, o.sample, group] = o.inverted
            tries[d, o.sample, group] = 1

    def brute(picks: list[np.ndarray]) -> float:
        k = sum(hits[d, pick].sum(axis=0) for d, pick in enumerate(picks))
        n = sum(tries[d, pick].sum(axis=0) for d, pick in enumerate(picks))
        best = int(np.argmax(k @ log_p + (n - k) @ log_q))
        assert 0 < best < kappas.size - 1  # a maximum inside the window
        return float(kappas[best])

    everyone = [np.arange(200)] * len(DIRECTIONS)
    assert fit.scale == pytest.approx(brute(everyone), rel=4e-4)  # grid spacing 3.5e-4
    rng = np.random.default_rng(11)
    boot = [brute([rng.integers(0, 200, 200) for _ in DIRECTIONS]) for _ in range(4000)]
    low, high = np.quantile(boot, [0.025, 0.975])
    assert fit.scale_range[0] == pytest.approx(low, rel=0.02)
    assert fit.scale_range[1] == pytest.approx(high, rel=0.02)


def test_a_wrong_scale_is_excluded() -> None:
    fit = fit_noise(synthetic(), drawn(4.0, 200), resamples=200)
    assert fit.scale_range[0] > 1.5


def test_calibrated_diffusion_gives_the_target_where_the_ensemble_is() -> None:
    table = synthetic()
    fit = fit_noise(table, drawn(2.0, 100), target=0.2, resamples=50)
    assert fit.diffusion == pytest.approx(fit.model_diffusion / fit.scale)
    # the ensemble at Dw behaves as the model at κ Dw
    p = float(table.probability(3.0, 2e-5, fit.scale * fit.diffusion))
    assert p == pytest.approx(0.2, abs=1e-6)
    low, high = fit.diffusion_range
    assert low < fit.diffusion < high


def test_releases_without_noise_leave_the_scale_undetermined() -> None:
    quiet = [o for o in drawn(1.0, 20) if o.sigma == 0]
    with pytest.raises(ValueError, match="no release with noise"):
        fit_noise(synthetic(), quiet)


def test_outcomes_are_read_from_a_sweep_store(tmp_path) -> None:
    """Stored runs of a restart sweep become outcomes with the run's own coordinates;
    runs not stored are left out."""
    sweep = tiny_sweep(axes={"noise.sigma": [0.0, 1e-6]})
    prepare(sweep, tmp_path)
    runs = sweep.runs()
    with RunLog(tmp_path) as log:
        for run in runs[:-1]:
            result = {"direction_before": run.direction, "direction_after": -run.direction}
            log.append({"key": run.key, "result": result})
    outcomes = sweep_outcomes(tmp_path)
    assert len(outcomes) == len(runs) - 1
    assert all(o.inverted for o in outcomes)
    assert {o.sigma for o in outcomes} == {0.0, 1e-6}
    assert {(o.direction, o.sample) for o in outcomes} == {(r.direction, r.sample) for r in runs}


def test_a_protocol_sweep_is_refused(tmp_path) -> None:
    sweep = tiny_sweep(estimator={"kind": "protocol"})
    prepare(sweep, tmp_path)
    with pytest.raises(ValueError, match="protocol sweep"):
        sweep_outcomes(tmp_path)
