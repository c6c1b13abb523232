"""Inversion statistics: Wilson intervals, the two estimators and their agreement test.

The paper (section "Numerical results") defines the inversion probability as the number
of inversions divided by the number M of stop-and-release operations of one run
(M = 100 for Figs. 5, 7, 8 and 9). pde_rotor estimates it in two ways:

* **paper protocol** (:func:`protocol_counts`): one run of M cycles; the direction of
  rotation is the sign of omega just before each stop and at the end of the run, and a
  cycle is an inversion when the direction after its release differs from the one
  before its stop. P = inversions / M. This is the rule of :mod:`pde_rotor.statistics.inversion`
  with one check per release, at its end, and commit_fraction = 0; it differs from a
  run's events (checked every ``output.event_interval`` with ``output.commit_fraction``)
  only for a release that has not committed by its end, or that commits and reverses
  again before the next stop.
* **independent restarts** (:func:`restart_counts`, :func:`two_state_chain`): many
  independent single stops, each from a steady rotating state of known direction. They
  estimate the two conditional probabilities P(inversion | CCW) and P(inversion | CW).
  The paper's P is the long-run fraction of inversions of the two-state Markov chain
  CCW <-> CW with these transition probabilities, i.e. the average of the two with the
  chain's stationary weights:

      pi_CCW = P(inv | CW) / (P(inv | CCW) + P(inv | CW)),   pi_CW = 1 - pi_CCW,
      P = pi_CCW P(inv | CCW) + pi_CW P(inv | CW)
        = 2 P(inv | CCW) P(inv | CW) / (P(inv | CCW) + P(inv | CW)).

  For a symmetric rotor (Delta = 0) both conditionals are equal and P is their value;
  for an asymmetric rotor (Delta != 0) they differ (favourable and unfavourable
  direction), and the harmonic mean above is what M sequential cycles measure.

Every probability comes with a Wilson score interval (:func:`wilson_interval`) and its
sample count. Directions: omega > 0 is counter-clockwise (CCW), omega < 0 clockwise (CW);
the paper's asymmetric rotor with Delta > 0 favours CW.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from itertools import pairwise

import numpy as np
from scipy import stats as sps

from .inversion import classify_release

CONFIDENCE = 0.95
"""Confidence level of every interval reported by pde_rotor."""

CCW, CW = 1, -1
"""Direction codes: sign of omega (counter-clockwise positive)."""


def wilson_interval(k: int, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion k / n.

    scipy's ``binomtest(k, n).proportion_ci(method="wilson")``: (p + z^2/2n -/+
    z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n) with p = k/n and z the two-sided normal
    quantile, exactly 0 at k = 0 and 1 at k = n. Unlike the Wald interval it stays inside
    [0, 1] and is not degenerate at k = 0 or k = n (the paper's P = 1 at short t_stop).

    Args:
        k: number of successes (inversions), 0 <= k <= n.
        n: number of trials; n = 0 gives the uninformative interval (0, 1).
        confidence: coverage, default 0.95.

    Returns:
        (low, high).

    Raises:
        ValueError: k or n out of range, or `confidence` outside (0, 1).
    """
    if n < 0 or k < 0 or k > n:
        msg = f"need 0 <= k <= n, got k = {k}, n = {n}"
        raise ValueError(msg)
    if not 0 < confidence < 1:
        msg = f"confidence must lie in (0, 1), got {confidence}"
        raise ValueError(msg)
    if n == 0:
        return 0.0, 1.0
    ci = sps.binomtest(int(k), int(n)).proportion_ci(confidence_level=confidence, method="wilson")
    return float(ci.low), float(ci.high)


@dataclass(frozen=True)
class Proportion:
    """k successes out of n trials, with its Wilson interval.

    Attributes:
        k: successes (inversions).
        n: trials (stops).
    """

    k: int
    n: int

    @property
    def p(self) -> float:
        """Point estimate k / n (nan if n = 0)."""
        return self.k / self.n if self.n else math.nan

    def interval(self, confidence: float = CONFIDENCE) -> tuple[float, float]:
        """Wilson score interval, :func:`wilson_interval`."""
        return wilson_interval(self.k, self.n, confidence)

    def __add__(self, other: Proportion) -> Proportion:
        return Proportion(self.k + other.k, self.n + other.n)


@dataclass(frozen=True)
class DirectionCounts:
    """Inversion counts split by the direction of rotation before the stop.

    Attributes:
        ccw: inversions out of stops that started from CCW rotation (omega > 0).
        cw: inversions out of stops that started from CW rotation (omega < 0).
    """

    ccw: Proportion = Proportion(0, 0)
    cw: Proportion = Proportion(0, 0)

    @property
    def total(self) -> Proportion:
        """All stops pooled (the paper's inversions / M for a protocol run)."""
        return self.ccw + self.cw

    def __add__(self, other: DirectionCounts) -> DirectionCounts:
        return DirectionCounts(self.ccw + other.ccw, self.cw + other.cw)


def _directions(omegas: Sequence[float] | np.ndarray) -> np.ndarray:
    signs = np.sign(np.asarray(omegas, dtype=float))
    if signs.ndim != 1:
        msg = "expected a one-dimensional sequence of angular velocities"
        raise ValueError(msg)
    if not np.isfinite(signs).all() or (signs == 0).any():
        bad = int(np.flatnonzero(~np.isfinite(signs) | (signs == 0))[0])
        msg = (
            f"omega[{bad}] = {omegas[bad]!r} has no direction of rotation "
            "(zero or not finite); the rotor did not rotate"
        )
        raise ValueError(msg)
    return signs.astype(int)


def protocol_counts(omegas: Sequence[float] | np.ndarray) -> DirectionCounts:
    """Inversion counts of one paper-protocol run from its angular velocities.

    The paper's definition: cycle m is classified by
    :func:`pde_rotor.statistics.inversion.classify_release` with omega just before stop m, one
    check, omega at the end of release m (just before stop m + 1), and
    commit_fraction = 0, so every release commits to the sign of omega at its end.

    Args:
        omegas: M + 1 values of omega: just before each of the M stops, then at the end
            of the last release (each release ends where the next stop begins).

    Returns:
        Counts by the direction before each stop; ``.total`` is inversions / M, the
        paper's estimator.

    Raises:
        ValueError: fewer than two values, or an omega without a sign.
    """
    signs = _directions(omegas)
    if signs.size < 2:
        msg = "need the direction before at least one stop and after its release"
        raise ValueError(msg)
    before = signs[:-1]
    inverted = np.array(
        [classify_release(w, [after], 0.0).inverted for w, after in pairwise(omegas)], dtype=bool
    )
    return DirectionCounts(
        ccw=Proportion(int(inverted[before == CCW].sum()), int((before == CCW).sum())),
        cw=Proportion(int(inverted[before == CW].sum()), int((before == CW).sum())),
    )


def restart_counts(
    before: Iterable[int] | np.ndarray, after: Iterable[int] | np.ndarray
) -> DirectionCounts:
    """Inversion counts of independent single stops.

    Args:
        before: direction (+1 CCW, -1 CW) of each sample just before its stop.
        after: direction after its release, committed (+1, -1); 0 marks a sample that did
            not commit to a direction within the time cap and counts as not inverted.

    Returns:
        Counts by the direction before the stop.
    """
    b = np.asarray(list(before) if not isinstance(before, np.ndarray) else before, dtype=int)
    a = np.asarray(list(after) if not isinstance(after, np.ndarray) else after, dtype=int)
    if b.shape != a.shape:
        msg = f"before and after differ in length ({b.size} != {a.size})"
        raise ValueError(msg)
    if not np.isin(b, (CCW, CW)).all() or not np.isin(a, (CCW, CW, 0)).all():
        msg = "directions must be +1 (CCW) or -1 (CW) (after: also 0, not committed)"
        raise ValueError(msg)
    inverted = a == -b
    return DirectionCounts(
        ccw=Proportion(int(inverted[b == CCW].sum()), int((b == CCW).sum())),
        cw=Proportion(int(inverted[b == CW].sum()), int((b == CW).sum())),
    )


def chain_probability(p_ccw: float, p_cw: float) -> float:
    """Long-run inversion fraction of the two-state chain, 2 a b / (a + b).

    Args:
        p_ccw: P(inversion | CCW before the stop).
        p_cw: P(inversion | CW before the stop).

    Returns:
        pi_CCW p_ccw + pi_CW p_cw with the stationary weights pi_CCW = p_cw / (p_ccw + p_cw);
        0 when both are 0 (the chain never leaves its initial direction).
    """
    total = p_ccw + p_cw
    if total == 0:
        return 0.0
    return 2.0 * p_ccw * p_cw / total


def stationary_ccw(p_ccw: float, p_cw: float) -> float:
    """Stationary fraction of CCW rotation, p_cw / (p_ccw + p_cw) (nan if both are 0)."""
    total = p_ccw + p_cw
    return p_cw / total if total > 0 else math.nan


@dataclass(frozen=True)
class ChainEstimate:
    """Inversion probability of the two-state chain from conditional counts.

    Attributes:
        p: long-run inversion fraction, :func:`chain_probability`.
        low, high: confidence interval of p (see :func:`two_state_chain`).
        pi_ccw: stationary fraction of CCW rotation.
        counts: the conditional counts it was computed from.
    """

    p: float
    low: float
    high: float
    pi_ccw: float
    counts: DirectionCounts


def two_state_chain(counts: DirectionCounts, confidence: float = CONFIDENCE) -> ChainEstimate:
    """Combine P(inv | CCW) and P(inv | CW) into the paper's P with a confidence interval.

    The combination 2 a b / (a + b) increases in both a and b, so plugging the lower
    (upper) bounds of both conditional intervals gives a lower (upper) bound of P. Each
    conditional interval is a Wilson interval at level 1 - (1 - confidence) / 2
    (Bonferroni), so the probability that the true P lies below the lower bound is at
    most (1 - confidence) / 2, and the same above: the interval covers with at least
    `confidence` (it is conservative).

    Args:
        counts: inversion counts from CCW and from CW starts (both n > 0 for a finite p).
        confidence: coverage of the returned interval.

    Returns:
        The estimate; p and pi_ccw are nan if one direction has no sample.
    """
    a, b = counts.ccw, counts.cw
    level = 1 - (1 - confidence) / 2
    a_lo, a_hi = a.interval(level)
    b_lo, b_hi = b.interval(level)
    if a.n == 0 or b.n == 0:
        p = pi = math.nan
    else:
        p = chain_probability(a.p, b.p)
        pi = stationary_ccw(a.p, b.p)
    return ChainEstimate(
        p=p,
        low=chain_probability(a_lo, b_lo),
        high=chain_probability(a_hi, b_hi),
        pi_ccw=pi,
        counts=counts,
    )


@dataclass(frozen=True)
class Agreement:
    """Result of :func:`two_proportion_test`.

    Attributes:
        first, second: the two proportions compared.
        p_value: two-sided p-value of Fisher's exact test of equal proportions.
        z: pooled two-proportion z statistic (0 when both are 0 or both are 1).
        overlap: whether the two Wilson intervals overlap.
        agree: p_value >= alpha (no significant difference at level alpha).
    """

    first: Proportion
    second: Proportion
    p_value: float
    z: float
    overlap: bool
    agree: bool


def two_proportion_test(
    first: Proportion, second: Proportion, alpha: float = 1 - CONFIDENCE
) -> Agreement:
    """Test whether two inversion proportions are compatible.

    Fisher's exact test on the 2 x 2 table (inversions, non-inversions) x (estimator),
    two-sided; it is exact also at the boundaries P = 0 and P = 1 where the z test
    degenerates. The pooled z statistic and the overlap of the Wilson intervals are
    reported alongside.

    Args:
        first: one proportion (n > 0).
        second: the other proportion (n > 0).
        alpha: significance level.
    """
    if first.n == 0 or second.n == 0:
        msg = "both proportions need at least one trial"
        raise ValueError(msg)
    table = [[first.k, first.n - first.k], [second.k, second.n - second.k]]
    p_value = float(sps.fisher_exact(table, alternative="two-sided").pvalue)
    pooled = (first.k + second.k) / (first.n + second.n)
    var = pooled * (1 - pooled) * (1 / first.n + 1 / second.n)
    z = (first.p - second.p) / math.sqrt(var) if var > 0 else 0.0
    lo1, hi1 = first.interval(1 - alpha)
    lo2, hi2 = second.interval(1 - alpha)
    overlap = lo1 <= hi2 and lo2 <= hi1
    return Agreement(first, second, min(1.0, p_value), z, overlap, p_value >= alpha)


@dataclass(frozen=True)
class EstimatorComparison:
    """Paper protocol against independent restarts on the same parameters.

    Attributes:
        ccw, cw: tests of P(inv | CCW) and P(inv | CW) (Holm-adjusted p-values).
        protocol_p: paper-protocol inversions / M with its Wilson interval.
        restart: the restart estimate combined by :func:`two_state_chain`.
        overlap: whether the intervals of protocol_p and restart overlap.
        agree: both conditional tests pass at level alpha after Holm's correction.
    """

    ccw: Agreement | None
    cw: Agreement | None
    protocol_p: Proportion
    restart: ChainEstimate
    overlap: bool
    agree: bool


def compare_estimators(
    protocol: DirectionCounts, restart: DirectionCounts, alpha: float = 1 - CONFIDENCE
) -> EstimatorComparison:
    """Statistical agreement of the paper protocol and the restart estimator.

    The protocol run's cycles split by the direction before each stop give samples of
    the same conditional probabilities P(inv | CCW), P(inv | CW) that the restarts
    estimate. Each is compared by :func:`two_proportion_test` (directions for which
    either estimator has no sample are skipped); the p-values are Holm-corrected for the
    number of tests. The pooled protocol P and the chain combination of the restarts
    are compared by the overlap of their intervals.

    Args:
        protocol: counts of one or more paper-protocol runs (:func:`protocol_counts`).
        restart: counts of the restart samples (:func:`restart_counts`).
        alpha: family-wise significance level.
    """
    raw: dict[str, Agreement | None] = {}
    for name in ("ccw", "cw"):
        a, b = getattr(protocol, name), getattr(restart, name)
        raw[name] = two_proportion_test(a, b, alpha) if a.n and b.n else None
    tested = sorted((t.p_value, name) for name, t in raw.items() if t is not None)
    adjusted: dict[str, Agreement | None] = dict.fromkeys(raw)
    running = 0.0
    for rank, (p_value, name) in enumerate(tested):
        running = max(running, min(1.0, (len(tested) - rank) * p_value))
        test = raw[name]
        assert test is not None
        adjusted[name] = Agreement(
            test.first, test.second, running, test.z, test.overlap, running >= alpha
        )
    chain = two_state_chain(restart, 1 - alpha)
    total = protocol.total
    lo, hi = total.interval(1 - alpha)
    overlap = lo <= chain.high and chain.low <= hi
    agree = bool(tested) and all(t.agree for t in adjusted.values() if t is not None)
    return EstimatorComparison(adjusted["ccw"], adjusted["cw"], total, chain, overlap, agree)
