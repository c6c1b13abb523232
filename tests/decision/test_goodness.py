"""The decision model's goodness of fit: the aggregate test and the calibration by bins,
checked on counts drawn from known probabilities."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import chi2

from pde_rotor.decision.check import Comparison
from pde_rotor.decision.goodness import BINS, MIN_EXPECTED, goodness_of_fit


def comparison(k: np.ndarray, n: np.ndarray, p: np.ndarray) -> Comparison:
    """Rows of conditionals with counts k of n and predicted p (and a P row without)."""
    rows = [
        {"column": "P_ccw", "inverted": int(a), "stops": int(b), "predicted": float(c)}
        for a, b, c in zip(k, n, p, strict=True)
    ]
    rows.append({"column": "P", "inverted": None, "stops": None, "predicted": 0.5})
    return Comparison(rows)


PREDICTED = np.concatenate([np.linspace(0.002, 0.05, 40), np.linspace(0.05, 0.95, 160)])
STOPS = np.full(PREDICTED.size, 100)


def test_counts_drawn_from_the_model_pass_and_the_statistic_is_pearsons():
    rng = np.random.default_rng(1)
    k = rng.binomial(STOPS, PREDICTED)
    fit = goodness_of_fit(comparison(k, STOPS, PREDICTED))
    used = np.minimum(STOPS * PREDICTED, STOPS * (1 - PREDICTED)) >= MIN_EXPECTED
    expected_x2 = np.sum(
        (k[used] - STOPS[used] * PREDICTED[used]) ** 2
        / (STOPS[used] * PREDICTED[used] * (1 - PREDICTED[used]))
    )
    assert fit.conditionals == used.sum() < PREDICTED.size  # the tail is left to the bins
    assert fit.pearson == pytest.approx(expected_x2, rel=1e-12)
    assert fit.pearson_p == pytest.approx(chi2.sf(expected_x2, used.sum()), rel=1e-12)
    assert fit.pearson_p > 0.01 and fit.g_p > 0.01
    assert all(b.holds for b in fit.bins)
    assert sum(b.conditionals for b in fit.bins) == PREDICTED.size  # P rows are not counted


def test_an_overconfident_tail_fails_its_bin_and_only_that_one():
    """Stops go the unlikely way three times as often as predicted where q < 5 %: the
    lowest bin's count lies above its Poisson range, the others hold."""
    rng = np.random.default_rng(2)
    truth = np.where(PREDICTED < 0.05, 3 * PREDICTED, PREDICTED)
    k = rng.binomial(STOPS, truth)
    fit = goodness_of_fit(comparison(k, STOPS, PREDICTED))
    tail = next(b for b in fit.bins if b.low == BINS[1])
    assert not tail.holds and tail.observed > tail.range[1]
    assert all(b.holds for b in fit.bins if b is not tail)
    assert "(outside)" in "\n".join(fit.describe())


def test_a_biased_model_fails_the_aggregate_test():
    rng = np.random.default_rng(3)
    k = rng.binomial(STOPS, np.clip(PREDICTED + 0.08, 0, 1))
    fit = goodness_of_fit(comparison(k, STOPS, PREDICTED))
    assert fit.pearson_p < 1e-6 and fit.g_p < 1e-6


def test_the_less_likely_way_is_counted_on_either_side_of_one_half():
    """A conditional predicted at p = 0.99 counts its non-inversions as the unlikely way."""
    fit = goodness_of_fit(
        comparison(np.array([97, 3]), np.array([100, 100]), np.array([0.99, 0.01]))
    )
    tail = next(b for b in fit.bins if b.low == BINS[1])
    assert tail.conditionals == 2
    assert tail.observed == 6 and tail.expected == pytest.approx(2.0)


def test_reports_without_counts_are_refused():
    rows = [{"column": "P", "inverted": None, "stops": None, "predicted": 0.5}]
    with pytest.raises(ValueError, match="no conditional with its counts"):
        goodness_of_fit(Comparison(rows))
