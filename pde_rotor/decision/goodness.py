"""How well the decision model fits the ensembles: every conditional, tested.

The conditionals P(inv | CCW) and P(inv | CW) of a restart or bank ensemble are
binomial counts k of n stops; the decision model predicts each one's p (:mod:`.table`).
P itself is not: at Delta = 0 it pools the two, at Delta != 0 it is 2ab/(a+b) of them.
So the fit is tested on the conditionals alone, on every one of them (none is left out
for having few expected stops: the tails are where an overconfident model shows):

* **per conditional**, the exact two-sided binomial test of k against Bin(n, p) (the
  p-value sums the probabilities of the counts no likelier than k); the number of
  conditionals that fail it at 5 % is set against its exact null distribution, the sum
  of independent Bernoulli variables, each with the probability that its own test
  rejects (at most 5 %, less for a discrete count);
* **combined**, Pearson's X^2 = sum (k - n p)^2 / (n p (1 - p)) and the likelihood-ratio
  G^2 = 2 sum [k ln(k / n p) + (n - k) ln((n - k) / n (1 - p))] over the conditionals with
  q = min(p, 1 - p) >= ``min_q``, each with a p-value from a **simulated null
  distribution**: a parametric bootstrap that draws every k from Bin(n, p) of the model
  ``draws`` times (seeded), so that no chi-square approximation is needed where few
  stops are expected;
* **calibration by bins** of q, the predicted probability of the less likely
  direction: the stops that went that way against the expected sum of n q, with the
  95 % range of that count under the model (a sum of independent binomials, from the
  same draws; its variance is sum n q (1 - q), not the Poisson sum n q).

Conditionals with q = 0 (a noise-free prediction of certainty) enter no statistic; an
outcome there that the model calls impossible is counted apart. The classical test over
the conditionals with at least :data:`MIN_EXPECTED` stops expected each way, on the
chi-square law, is kept as a secondary line. The interval counts of
:meth:`.check.Comparison.coverage` stay a secondary summary.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.special import xlogy
from scipy.stats import binom, binomtest, chi2, norm

from .check import Comparison

MIN_EXPECTED = 5.0
"""Expected stops each way of the classical chi-square test's conditionals."""

BINS = (0.0, 1e-3, 0.05, 0.2, 0.5)
"""Edges of the calibration bins in q = min(p, 1 - p), the less likely direction's
predicted probability."""

LEVEL = 0.05
"""Level of the exact per-conditional tests."""

DRAWS = 10_000
"""Parametric-bootstrap draws of the simulated null distribution."""

SEED = 0
"""Seed of the parametric bootstrap."""


@dataclass(frozen=True)
class CalibrationBin:
    """Stops that went the less likely way, in one bin of its predicted probability.

    Attributes:
        low, high: the bin's range of q.
        conditionals: conditionals in the bin.
        observed: stops that went the less likely way.
        expected: their expected number, sum of n q.
        range: the 95 % range of that count under the model (2.5 % and 97.5 %
            quantiles of the simulated sums of binomials).
        scatter: the rms error in x = Phi^-1(p) that the conditionals' spread beyond
            the binomial's implies (:func:`x_scatter`; 0 where there is none).
    """

    low: float
    high: float
    conditionals: int
    observed: int
    expected: float
    range: tuple[int, int]
    scatter: float = 0.0

    @property
    def holds(self) -> bool:
        """Whether the observed count lies in its 95 % range."""
        return self.range[0] <= self.observed <= self.range[1]


@dataclass(frozen=True)
class Conditional:
    """One conditional against the model.

    Attributes:
        inverted, stops: the ensemble's count k of n.
        predicted: the model's p.
        p_value: the exact two-sided binomial test of k against Bin(n, p).
        label: where it is (report, t_stop, Delta, sigma, direction).
    """

    inverted: int
    stops: int
    predicted: float
    p_value: float
    label: str

    @property
    def expected(self) -> float:
        """n p."""
        return self.stops * self.predicted


@dataclass(frozen=True)
class GoodnessOfFit:
    """The tests and the calibration of the model against ensemble conditionals.

    Attributes:
        conditionals: every conditional with its counts, sorted by label (:func:`counted`).
        min_q: the smallest q of the combined tests' conditionals.
        tested: conditionals in the combined tests (0 < q and q >= min_q).
        pearson, pearson_p: Pearson's X^2 and its simulated p-value.
        g, g_p: the likelihood-ratio G^2 and its simulated p-value.
        draws, seed: size and seed of the parametric bootstrap.
        failing: conditionals whose exact test rejects at :data:`LEVEL`.
        failing_expected: their expected number under the model (sum of each test's
            exact rejection probability).
        failing_p: P(at least `failing` rejections) under the model (exact).
        failing_bound_p: P(at least `failing` rejections) of Bin(tested, LEVEL), the
            bound every exact test meets (conservative).
        impossible: conditionals with q = 0 whose count the model calls impossible.
        informative: conditionals with at least :data:`MIN_EXPECTED` stops expected
            each way (the classical test's).
        classical_pearson: their Pearson X^2.
        classical_pearson_p: its p-value on the chi-square law.
        classical_g: their G^2.
        classical_g_p: its p-value on the chi-square law.
        bins: the calibration, one :class:`CalibrationBin` per bin.
    """

    conditionals: tuple[Conditional, ...]
    min_q: float
    tested: int
    pearson: float
    pearson_p: float
    g: float
    g_p: float
    draws: int
    seed: int
    failing: int
    failing_expected: float
    failing_p: float
    failing_bound_p: float
    impossible: int
    informative: int
    classical_pearson: float
    classical_pearson_p: float
    classical_g: float
    classical_g_p: float
    bins: tuple[CalibrationBin, ...]

    @property
    def passes(self) -> bool:
        """Whether every combined test holds at 5 %: X^2, G^2 and the failing count."""
        return min(self.pearson_p, self.g_p, self.failing_p) >= LEVEL and not self.impossible

    def worst(self, count: int = 5) -> list[Conditional]:
        """The `count` conditionals with the smallest exact p-values."""
        return sorted(self.conditionals, key=lambda c: c.p_value)[:count]

    def describe(self, worst: int = 5) -> list[str]:
        """The lines ``pde-rotor predict check`` prints as its headline."""
        n = len(self.conditionals)
        lines = [
            f"goodness of fit over {self.tested} of {n} conditionals P(inv | direction) "
            f"(every one with q = min(p, 1 - p) "
            + (f">= {self.min_q:g}" if self.min_q > 0 else "> 0")
            + "): Pearson X2 = "
            f"{self.pearson:.1f} (p = {self.pearson_p:.3g}), G2 = {self.g:.1f} "
            f"(p = {self.g_p:.3g}); p-values from {self.draws} parametric-bootstrap "
            f"draws of the model (seed {self.seed})",
            f"exact binomial test per conditional: {self.failing} of {n} fail at "
            f"{LEVEL:.0%}, {self.failing_expected:.1f} expected; P(>= {self.failing}) = "
            f"{self.failing_p:.3g} (against at most {LEVEL * self.tested:g} of the "
            f"{self.tested} tested: {self.failing_bound_p:.3g})"
            + (f"; {self.impossible} outcomes the model calls impossible" * bool(self.impossible)),
            f"classical test over the {self.informative} conditionals with >= {MIN_EXPECTED:g} "
            f"stops expected each way (chi-square law): X2 = {self.classical_pearson:.1f} "
            f"(p = {self.classical_pearson_p:.3g}), G2 = {self.classical_g:.1f} "
            f"(p = {self.classical_g_p:.3g}) on {self.informative} degrees of freedom",
            "calibration: stops that went the less likely way, by its predicted probability q",
        ]
        for b in self.bins:
            if not b.conditionals:
                continue
            lines.append(
                f"  q in [{b.low:g}, {b.high:g}): {b.observed} observed, {b.expected:.2f} "
                f"expected [{b.range[0]}, {b.range[1]}] (95 % binomial range) in "
                f"{b.conditionals} conditionals, scatter of x {b.scatter:.2f}"
                + ("" if b.holds else "  (outside)")
            )
        if worst:
            lines.append("least likely conditionals under the model (exact binomial p):")
            lines += [
                f"  {c.label}: {c.inverted}/{c.stops} inverted, {c.expected:.2f} expected, "
                f"p = {c.p_value:.2g}"
                for c in self.worst(worst)
            ]
        return lines


def counted(comparison: Comparison) -> list[tuple[int, int, float, str]]:
    """(inverted, stops, predicted p, label) of every conditional that carries its counts,
    sorted by label (then counts): the bootstrap's draws, and so its p-values, do not
    depend on the order in which the reports were given."""
    rows = []
    for r in comparison.rows:
        if r["column"] == "P" or not r.get("stops"):
            continue
        dx = r.get("dx", math.nan)
        grid = f", dx = {dx:.4g}" if dx == dx else ""
        label = (
            f"{r.get('sweep', '?')} t_stop = {r.get('t_stop', math.nan):g}, Delta = "
            f"{r.get('asymmetry', math.nan):g}, sigma = {r.get('sigma', math.nan):g}{grid}, "
            f"{r['column']}"
        )
        rows.append((int(r["inverted"]), int(r["stops"]), float(r["predicted"]), label))
    return sorted(rows, key=lambda row: (row[3], row[0], row[1], row[2]))


def exact_p_value(k: int, n: int, p: float) -> float:
    """Two-sided exact binomial p-value of k of n against p (1 at p in {0, 1} if k fits,
    0 if it does not)."""
    if p <= 0.0 or p >= 1.0:
        return 1.0 if k == round(n * p) else 0.0
    return float(binomtest(k, n, p).pvalue)


def rejection_probability(n: int, p: float, level: float = LEVEL) -> float:
    """P(the exact two-sided test of a Bin(n, p) count rejects at `level`) under Bin(n, p)."""
    if p <= 0.0 or p >= 1.0:
        return 0.0
    k = np.arange(n + 1)
    pmf = binom.pmf(k, n, p)
    # the two-sided p-value of k sums the pmf of the counts no likelier than k (to
    # binomtest's relative tolerance)
    p_values = np.array([pmf[pmf <= v * (1 + 1e-7)].sum() for v in pmf])
    return float(pmf[p_values <= level].sum())


def count_at_least(probabilities: np.ndarray, count: int) -> float:
    """P(sum of independent Bernoulli(probabilities) >= count), by convolution."""
    dist = np.array([1.0])
    for a in probabilities:
        dist = np.convolve(dist, [1.0 - a, a])
    return float(dist[count:].sum())


def x_scatter(k: np.ndarray, n: np.ndarray, p: np.ndarray) -> float:
    """The rms error of the model's x = Phi^-1(p) that the spread of counts `k` implies.

    If each conditional's true x were the model's plus an error of rms s, its count
    would vary by n p (1 - p) + s^2 n^2 phi(x)^2 instead of n p (1 - p) (to first order),
    so the method of moments gives s^2 = sum (z^2 - 1) / sum n phi(x)^2 / (p (1 - p)),
    z = (k - n p) / sqrt(n p (1 - p)): 0 for a model whose only error is the binomial's.
    Conditionals with p in {0, 1} are left out.
    """
    keep = (p > 0) & (p < 1)
    k, n, p = k[keep], n[keep], p[keep]
    if not k.size:
        return 0.0
    z2 = (k - n * p) ** 2 / (n * p * (1 - p))
    weight = n * norm.pdf(norm.ppf(p)) ** 2 / (p * (1 - p))
    return float(math.sqrt(max(0.0, float(np.sum(z2 - 1) / np.sum(weight)))))


def _statistics(k: np.ndarray, n: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pearson's X^2 and G^2 of counts `k` (..., m) against Bin(n, p), summed over m."""
    pearson = np.sum((k - n * p) ** 2 / (n * p * (1 - p)), axis=-1)
    g = 2 * np.sum(xlogy(k, k / (n * p)) + xlogy(n - k, (n - k) / (n * (1 - p))), axis=-1)
    return pearson, g


def goodness_of_fit(
    comparison: Comparison,
    bins: Sequence[float] = BINS,
    min_q: float = 0.0,
    draws: int = DRAWS,
    seed: int = SEED,
) -> GoodnessOfFit:
    """The tests and the calibration table of `comparison`'s conditionals.

    Args:
        comparison: rows of :func:`.check.compare`.
        bins: edges of the calibration bins in q.
        min_q: conditionals with q below it leave the combined X^2 and G^2 (they stay
            in the exact tests and the calibration); 0 keeps every one with q > 0.
        draws: parametric-bootstrap draws of the simulated null distribution.
        seed: the bootstrap's seed.

    Raises:
        ValueError: no conditional carries its counts (reports of the protocol
            estimator, or of a version that did not store them), or `draws` < 1.
    """
    rows = counted(comparison)
    if not rows:
        msg = "no conditional with its counts (restart or bank reports hold them)"
        raise ValueError(msg)
    if draws < 1:
        msg = f"draws = {draws}: the simulated null needs at least one draw"
        raise ValueError(msg)
    k = np.array([r[0] for r in rows], dtype=float)
    n = np.array([r[1] for r in rows], dtype=float)
    p = np.array([r[2] for r in rows], dtype=float)
    q = np.minimum(p, 1 - p)
    conditionals = tuple(
        Conditional(int(a), int(b), float(c), exact_p_value(int(a), int(b), float(c)), label)
        for a, b, c, label in rows
    )
    rejection = np.array([rejection_probability(int(a), float(b)) for _, a, b, _ in rows])
    failing = sum(c.p_value <= LEVEL for c in conditionals)
    certain = q <= 0
    impossible = int(sum(c.p_value == 0 for c, s in zip(conditionals, certain, strict=True) if s))

    rng = np.random.default_rng(seed)
    simulated = rng.binomial(n.astype(int), p, size=(draws, p.size)).astype(float)
    used = (q > 0) & (q >= min_q)
    pearson, g = _statistics(k[used], n[used], p[used])
    null_pearson, null_g = _statistics(simulated[:, used], n[used], p[used])

    informative = np.minimum(n * p, n * (1 - p)) >= MIN_EXPECTED
    c_pearson, c_g = _statistics(k[informative], n[informative], p[informative])
    dof = int(informative.sum())

    minority = np.where(p < 0.5, k, n - k)
    null_minority = np.where(p < 0.5, simulated, n - simulated)
    table = []
    for low, high in itertools.pairwise(bins):
        inside = (q >= low) & ((q < high) if high < 0.5 else (q <= high))
        sums = null_minority[:, inside].sum(axis=1)
        lo, hi = np.quantile(sums, [0.025, 0.975]) if inside.any() else (0.0, 0.0)
        table.append(
            CalibrationBin(
                low,
                high,
                int(inside.sum()),
                int(minority[inside].sum()),
                float(np.sum(n[inside] * q[inside])),
                (math.floor(lo), math.ceil(hi)),
                x_scatter(k[inside], n[inside], p[inside]),
            )
        )
    return GoodnessOfFit(
        conditionals=conditionals,
        min_q=min_q,
        tested=int(used.sum()),
        pearson=float(pearson),
        pearson_p=_simulated_p(float(pearson), null_pearson),
        g=float(g),
        g_p=_simulated_p(float(g), null_g),
        draws=draws,
        seed=seed,
        failing=int(failing),
        failing_expected=float(rejection.sum()),
        failing_p=count_at_least(rejection, int(failing)),
        failing_bound_p=float(binom.sf(failing - 1, int(used.sum()), LEVEL)),
        impossible=impossible,
        informative=dof,
        classical_pearson=float(c_pearson),
        classical_pearson_p=float(chi2.sf(c_pearson, dof)) if dof else math.nan,
        classical_g=float(c_g),
        classical_g_p=float(chi2.sf(c_g, dof)) if dof else math.nan,
        bins=tuple(table),
    )


def _simulated_p(observed: float, null: np.ndarray) -> float:
    """(1 + #{null >= observed}) / (1 + draws): the bootstrap p-value."""
    return float((1 + np.count_nonzero(null >= observed * (1 - 1e-12))) / (1 + null.size))
