"""pde_rotor.statistics.proportions: Wilson intervals, both estimators, the chain, agreement.

The estimators are checked on synthetic processes whose inversion probability is known
exactly (Bernoulli trials and two-state Markov chains), not on simulation output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats as sps

from pde_rotor.statistics.proportions import (
    CCW,
    CW,
    DirectionCounts,
    Proportion,
    chain_probability,
    compare_estimators,
    protocol_counts,
    restart_counts,
    stationary_ccw,
    two_proportion_test,
    two_state_chain,
    wilson_interval,
)

# Newcombe, Statistics in Medicine 17, 857 (1998), Table I, method 3 (Wilson score, no
# continuity correction), 95 % intervals
NEWCOMBE_1998 = [
    ((81, 263), (0.2553, 0.3662)),
    ((15, 148), (0.0624, 0.1605)),
    ((0, 20), (0.0, 0.1611)),
    ((1, 29), (0.0061, 0.1718)),
]


@pytest.mark.parametrize(("kn", "expected"), NEWCOMBE_1998)
def test_wilson_matches_published_values(kn, expected):
    low, high = wilson_interval(*kn)
    assert low == pytest.approx(expected[0], abs=6e-5)
    assert high == pytest.approx(expected[1], abs=6e-5)


def test_wilson_closed_form_at_the_boundaries():
    """k = 0: (0, z^2 / (n + z^2)); k = n: the mirror image; n = 0: no information."""
    z = sps.norm.ppf(0.975)
    for n in (1, 5, 100):
        assert wilson_interval(0, n) == pytest.approx((0.0, z * z / (n + z * z)))
        assert wilson_interval(n, n) == pytest.approx((n / (n + z * z), 1.0))
    assert wilson_interval(0, 0) == (0.0, 1.0)


@pytest.mark.parametrize("confidence", [0.5, 0.95, 0.975])
def test_wilson_bounds_are_where_the_score_test_just_rejects(confidence):
    """The Wilson interval is the set of p that the score test accepts: each inner bound
    solves (k - n p)^2 = z^2 n p (1 - p), the definition, not the closed form."""
    z = sps.norm.ppf(0.5 + confidence / 2)
    for n in (1, 2, 7, 40, 100, 263, 1000):
        for k in range(1, n):
            for bound in wilson_interval(k, n, confidence):
                score = (k - n * bound) / math.sqrt(n * bound * (1 - bound))
                assert abs(score) == pytest.approx(z, rel=1e-9), (k, n, bound)


def test_wilson_rejects_a_confidence_outside_the_unit_interval():
    for confidence in (0.0, 1.0, 1.5):
        with pytest.raises(ValueError, match="confidence"):
            wilson_interval(3, 10, confidence)


def test_wilson_is_symmetric_and_nested():
    for n in (7, 40):
        for k in range(n + 1):
            low, high = wilson_interval(k, n)
            mlow, mhigh = wilson_interval(n - k, n)
            assert low == pytest.approx(1 - mhigh) and high == pytest.approx(1 - mlow)
            assert low <= k / n <= high
            wide = wilson_interval(k, n, 0.99)
            assert wide[0] <= low and high <= wide[1]


@pytest.mark.parametrize("p", [0.05, 0.3, 0.5])
def test_wilson_coverage_is_close_to_nominal(p):
    """Exact coverage (sum of the binomial pmf over the k whose interval holds p)."""
    n = 60
    ks = np.arange(n + 1)
    covered = np.array(
        [wilson_interval(int(k), n)[0] <= p <= wilson_interval(int(k), n)[1] for k in ks]
    )
    coverage = sps.binom.pmf(ks, n, p)[covered].sum()
    assert 0.92 <= coverage <= 0.99


def test_wilson_rejects_impossible_counts():
    for k, n in ((3, 2), (-1, 4), (0, -1)):
        with pytest.raises(ValueError):
            wilson_interval(k, n)


def markov_chain_omegas(p_ccw: float, p_cw: float, m: int, rng: np.random.Generator) -> np.ndarray:
    """Synthetic paper-protocol run: omega before M stops and at the end, a two-state chain."""
    signs = np.empty(m + 1)
    signs[0] = CCW
    uniform = rng.random(m)
    for i in range(m):
        flip = p_ccw if signs[i] == CCW else p_cw
        signs[i + 1] = -signs[i] if uniform[i] < flip else signs[i]
    return signs * rng.uniform(150.0, 180.0, m + 1)


def test_protocol_estimator_recovers_known_chain_probability():
    """Inversions / M of a long chain converges to 2ab / (a + b), with conditionals a, b."""
    rng = np.random.default_rng(1)
    a, b = 0.2, 0.8
    counts = protocol_counts(markov_chain_omegas(a, b, 40_000, rng))
    total = counts.total
    assert total.n == 40_000
    truth = chain_probability(a, b)
    assert truth == pytest.approx(0.32)
    low, high = total.interval(0.999)
    assert low <= truth <= high
    for prop, p in ((counts.ccw, a), (counts.cw, b)):
        lo, hi = prop.interval(0.999)
        assert lo <= p <= hi
    # the fraction of stops from CCW is the stationary weight
    assert counts.ccw.n / total.n == pytest.approx(stationary_ccw(a, b), abs=0.02)


def test_protocol_estimator_counts_sign_changes():
    counts = protocol_counts([170.0, -160.0, -171.0, 165.0, 172.0])
    assert counts.total == Proportion(2, 4)
    assert counts.ccw == Proportion(1, 2) and counts.cw == Proportion(1, 2)
    with pytest.raises(ValueError, match="no direction"):
        protocol_counts([170.0, 0.0, 160.0])
    with pytest.raises(ValueError):
        protocol_counts([170.0])


def test_restart_estimator_on_bernoulli_samples():
    rng = np.random.default_rng(2)
    a, b, n = 0.9, 0.3, 3000
    before = np.repeat([CCW, CW], n)
    flips = rng.random(2 * n) < np.where(before == CCW, a, b)
    after = np.where(flips, -before, before)
    after[:5] = 0  # not committed: never an inversion
    counts = restart_counts(before, after)
    assert counts.ccw.n == counts.cw.n == n
    assert counts.ccw.k == int(flips[5:n].sum())
    chain = two_state_chain(counts)
    assert chain.low <= chain_probability(a, b) <= chain.high
    assert chain.pi_ccw == pytest.approx(b / (a + b), abs=0.03)
    with pytest.raises(ValueError):
        restart_counts([CCW, 2], [CW, CW])


def test_chain_combination_limits():
    assert chain_probability(0.4, 0.4) == pytest.approx(0.4)  # symmetric rotor
    assert chain_probability(0.0, 0.0) == 0.0  # never leaves the first direction
    assert chain_probability(1.0, 1.0) == 1.0  # perfect inversion (short t_stop)
    assert chain_probability(0.0, 1.0) == 0.0  # always ends in the favourable direction
    # long t_stop without memory: after = favourable with probability q, whatever before
    q = 0.8
    assert chain_probability(1 - q, q) == pytest.approx(2 * q * (1 - q))
    chain = two_state_chain(DirectionCounts(Proportion(3, 3), Proportion(0, 0)))
    assert math.isnan(chain.p) and chain.high == 1.0


def test_chain_interval_covers_at_least_nominal():
    """Repeated synthetic restart experiments: the chain interval holds the truth >= 95 %."""
    rng = np.random.default_rng(3)
    a, b, n, reps = 0.25, 0.7, 40, 600
    truth = chain_probability(a, b)
    k_a = rng.binomial(n, a, reps)
    k_b = rng.binomial(n, b, reps)
    hits = 0
    for ka, kb in zip(k_a, k_b, strict=True):
        est = two_state_chain(DirectionCounts(Proportion(int(ka), n), Proportion(int(kb), n)))
        hits += est.low <= truth <= est.high
    assert hits / reps >= 0.95


def test_two_proportion_test_false_alarm_rate_and_power():
    rng = np.random.default_rng(4)
    n, reps = 80, 300
    same = [
        two_proportion_test(Proportion(int(k1), n), Proportion(int(k2), n)).agree
        for k1, k2 in zip(rng.binomial(n, 0.4, reps), rng.binomial(n, 0.4, reps), strict=True)
    ]
    # Fisher's test is conservative: at most ~5 % false alarms
    assert np.mean(same) >= 0.94
    different = two_proportion_test(Proportion(16, n), Proportion(64, n))
    assert not different.agree and not different.overlap and different.z < 0
    boundary = two_proportion_test(Proportion(40, 40), Proportion(100, 100))
    assert boundary.agree and boundary.p_value == 1.0 and boundary.z == 0.0


def test_compare_estimators_on_synthetic_chains():
    rng = np.random.default_rng(5)
    a, b = 0.3, 0.6
    protocol = protocol_counts(markov_chain_omegas(a, b, 400, rng))
    before = np.repeat([CCW, CW], 300)
    flips = rng.random(600) < np.where(before == CCW, a, b)
    restart = restart_counts(before, np.where(flips, -before, before))
    result = compare_estimators(protocol, restart)
    assert result.agree and result.overlap
    assert result.ccw is not None and result.cw is not None
    # a restart estimator with the conditionals swapped must be rejected
    wrong = restart_counts(
        before, np.where(rng.random(600) < np.where(before == CCW, b, a), -before, before)
    )
    assert not compare_estimators(protocol, wrong).agree
