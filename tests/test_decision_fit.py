"""The noise fit: κ recovered from releases drawn from the model itself, and the stores
it reads.

Releases are drawn from the synthetic table's conditionals at κ_true Dw; the fit must
find κ_true inside its 95 % range, and the calibrated Dw must give the target P in the
model at κ Dw.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_decision import synthetic
from test_sweep import tiny_sweep

from pde_rotor.decision import DIRECTIONS, diffusion_of
from pde_rotor.decision_fit import Outcome, fit_noise, sweep_outcomes
from pde_rotor.sweep.store import RunLog, prepare

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
