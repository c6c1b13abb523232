"""The decision model's goodness of fit on counts drawn from known probabilities: a
model that is the truth passes at the nominal rate, a biased or overconfident one fails;
the statistics, the exact tests and the binomial ranges against their definitions."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtr
from scipy.stats import binom, binomtest

from pde_rotor.decision.check import Comparison
from pde_rotor.decision.goodness import (
    BINS,
    LEVEL,
    MIN_EXPECTED,
    count_at_least,
    exact_p_value,
    goodness_of_fit,
    rejection_probability,
    x_scatter,
)


def comparison(k: np.ndarray, n: np.ndarray, p: np.ndarray) -> Comparison:
    """Rows of conditionals with counts k of n and predicted p (and a P row without)."""
    rows = [
        {"column": "P_ccw", "inverted": int(a), "stops": int(b), "predicted": float(c)}
        for a, b, c in zip(k, n, p, strict=True)
    ]
    rows.append({"column": "P", "inverted": None, "stops": None, "predicted": 0.5})
    return Comparison(rows)


# the fitted ensembles' shape: tails down to q = 2e-4, both sides of one half
PREDICTED = np.concatenate(
    [np.geomspace(2e-4, 0.05, 30), np.linspace(0.05, 0.95, 40), 1 - np.geomspace(2e-4, 0.05, 10)]
)
STOPS = np.full(PREDICTED.size, 100)


def test_the_statistics_are_pearsons_and_the_likelihood_ratio_over_every_conditional():
    rng = np.random.default_rng(1)
    k = rng.binomial(STOPS, PREDICTED)
    fit = goodness_of_fit(comparison(k, STOPS, PREDICTED), draws=200)
    n, p = STOPS, PREDICTED
    pearson = np.sum((k - n * p) ** 2 / (n * p * (1 - p)))
    with np.errstate(divide="ignore", invalid="ignore"):
        g = 2 * np.sum(
            np.where(k > 0, k * np.log(k / (n * p)), 0)
            + np.where(n > k, (n - k) * np.log((n - k) / (n * (1 - p))), 0)
        )
    assert fit.tested == len(fit.conditionals) == PREDICTED.size  # the tails are in
    assert fit.pearson == pytest.approx(pearson, rel=1e-12)
    assert fit.g == pytest.approx(g, rel=1e-12)
    informative = np.minimum(n * p, n * (1 - p)) >= MIN_EXPECTED
    assert fit.informative == informative.sum() < PREDICTED.size
    assert sum(b.conditionals for b in fit.bins) == PREDICTED.size  # P rows are not counted


def test_min_q_leaves_the_far_tail_out_of_the_combined_tests_only():
    k = np.random.default_rng(2).binomial(STOPS, PREDICTED)
    fit = goodness_of_fit(comparison(k, STOPS, PREDICTED), min_q=1e-3, draws=200)
    assert fit.tested == np.sum(np.minimum(PREDICTED, 1 - PREDICTED) >= 1e-3)
    assert len(fit.conditionals) == PREDICTED.size


def test_a_true_model_passes_at_the_nominal_rate():
    """200 ensembles drawn from the model itself: each test rejects about 5 % of them
    (a binomial count of 200 at 0.05 lies in [3, 19] with probability 0.997)."""
    rng = np.random.default_rng(3)
    p_values = np.array(
        [
            (fit.pearson_p, fit.g_p, fit.failing_p)
            for fit in (
                goodness_of_fit(
                    comparison(rng.binomial(STOPS, PREDICTED), STOPS, PREDICTED),
                    draws=400,
                    seed=int(seed),
                )
                for seed in range(200)
            )
        ]
    )
    rejected = np.sum(p_values < 0.05, axis=0)
    assert np.all((rejected >= 3) & (rejected <= 19)), rejected


def test_the_failing_count_has_its_exact_expectation():
    """The mean number of conditionals failing their exact test over 300 draws from the
    model agrees with the sum of the exact rejection probabilities (at most 5 % each)."""
    rng = np.random.default_rng(4)
    fit = goodness_of_fit(comparison(rng.binomial(STOPS, PREDICTED), STOPS, PREDICTED), draws=10)
    # each conditional's rejection region over k = 0 ... 100, by the exact test itself
    rejects = np.array(
        [[exact_p_value(k, 100, float(b)) <= LEVEL for k in range(101)] for b in PREDICTED]
    )
    draws = rng.binomial(STOPS, PREDICTED, size=(300, PREDICTED.size))
    counts = rejects[np.arange(PREDICTED.size), draws].sum(axis=1)
    assert fit.failing_expected <= LEVEL * PREDICTED.size
    assert np.mean(counts) == pytest.approx(fit.failing_expected, abs=4 * np.std(counts) / 17)


def test_an_overconfident_tail_fails_every_test():
    """Stops go the unlikely way three times as often as predicted where q < 5 %: the
    tail bin lies above its range and X2, G2 and the failing count reject."""
    rng = np.random.default_rng(5)
    q = np.minimum(PREDICTED, 1 - PREDICTED)
    truth = np.where(q < 0.05, np.where(PREDICTED < 0.5, 3 * PREDICTED, 1 - 3 * q), PREDICTED)
    fit = goodness_of_fit(comparison(rng.binomial(STOPS, truth), STOPS, PREDICTED), draws=2000)
    tail = next(b for b in fit.bins if b.low == BINS[1])
    assert not tail.holds and tail.observed > tail.range[1]
    assert max(fit.pearson_p, fit.g_p, fit.failing_p) < 0.01
    assert not fit.passes
    assert "(outside)" in "\n".join(fit.describe())


def test_a_biased_model_fails_the_combined_tests():
    rng = np.random.default_rng(6)
    k = rng.binomial(STOPS, np.clip(PREDICTED + 0.08, 0, 1))
    fit = goodness_of_fit(comparison(k, STOPS, PREDICTED), draws=2000)
    assert fit.pearson_p < 1e-3 and fit.g_p < 1e-3 and fit.failing_p < 1e-3


def test_the_bootstrap_is_seeded():
    k = np.random.default_rng(7).binomial(STOPS, PREDICTED)
    one, two = (goodness_of_fit(comparison(k, STOPS, PREDICTED), draws=300, seed=9) for _ in "ab")
    assert (one.pearson_p, one.g_p) == (two.pearson_p, two.g_p)
    assert "300 parametric-bootstrap draws of the model (seed 9)" in one.describe()[0]


def test_the_ranges_are_binomial_not_poisson():
    """Near q = 1/2 a bin's count is Bin(n, 1/2), of variance n/4: its 95 % range is that
    binomial's, much narrower than a Poisson count's of the same mean."""
    p = np.full(20, 0.45)
    n = np.full(20, 100)
    fit = goodness_of_fit(comparison(np.full(20, 45), n, p), draws=20000)
    bin_ = next(b for b in fit.bins if b.low == BINS[3])
    low, high = binom.interval(0.95, 2000, 0.45)
    assert abs(bin_.range[0] - low) <= 2 and abs(bin_.range[1] - high) <= 2
    assert bin_.range[1] - bin_.range[0] < 0.8 * 2 * 1.96 * np.sqrt(900)


def test_the_less_likely_way_is_counted_on_either_side_of_one_half():
    """A conditional predicted at p = 0.99 counts its non-inversions as the unlikely way."""
    fit = goodness_of_fit(
        comparison(np.array([97, 3]), np.array([100, 100]), np.array([0.99, 0.01])), draws=100
    )
    tail = next(b for b in fit.bins if b.low == BINS[1])
    assert tail.conditionals == 2
    assert tail.observed == 6 and tail.expected == pytest.approx(2.0)


def test_exact_tests_against_scipy_and_their_rejection_probability():
    for n, p in ((100, 0.03), (100, 0.5), (60, 0.0035), (200, 0.2)):
        k = np.arange(n + 1)
        rejecting = [binomtest(int(j), n, p).pvalue <= LEVEL for j in k]
        want = binom.pmf(k, n, p)[rejecting].sum()
        assert rejection_probability(n, p) == pytest.approx(want, rel=1e-9, abs=1e-15)
        assert rejection_probability(n, p) <= LEVEL
    assert exact_p_value(3, 100, 0.0035) == pytest.approx(binomtest(3, 100, 0.0035).pvalue)
    assert count_at_least(np.array([0.5, 0.5]), 1) == pytest.approx(0.75)


def test_an_outcome_the_model_calls_impossible_fails():
    """A noise-free prediction (p = 0) with one inversion: counted, and the fit fails."""
    fit = goodness_of_fit(
        comparison(np.array([1, 50]), np.array([100, 100]), np.array([0.0, 0.5])), draws=100
    )
    assert fit.impossible == 1 and not fit.passes


def test_the_scatter_of_x_is_recovered():
    """Counts whose true x = Phi^-1(p) is the model's plus N(0, 0.3^2) give a scatter
    near 0.3; counts from the model itself give one near 0."""
    rng = np.random.default_rng(8)
    x = rng.uniform(-2.5, 2.5, 4000)
    p = ndtr(x)
    n = np.full(x.size, 100)
    assert x_scatter(rng.binomial(n, p).astype(float), n.astype(float), p) < 0.05
    truth = ndtr(x + rng.normal(0, 0.3, x.size))
    assert x_scatter(rng.binomial(n, truth).astype(float), n.astype(float), p) == (
        pytest.approx(0.3, abs=0.05)
    )


def test_reports_without_counts_are_refused():
    rows = [{"column": "P", "inverted": None, "stops": None, "predicted": 0.5}]
    with pytest.raises(ValueError, match="no conditional with its counts"):
        goodness_of_fit(Comparison(rows))
