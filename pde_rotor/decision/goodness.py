"""How well the decision model fits the ensembles: one test over every conditional.

The conditionals P(inv | CCW) and P(inv | CW) of a restart or bank ensemble are
independent binomial counts k of n stops; the decision model predicts each one's p
(:mod:`.table`). P itself is not: at Delta = 0 it pools the two, at Delta != 0 it is
2ab/(a+b) of them. So the fit is tested on the conditionals alone:

* **aggregate test** over the *informative* conditionals, those where the model expects
  at least :data:`MIN_EXPECTED` stops each way (n p and n (1 - p); the usual condition
  for the chi-square law of the statistics; a prediction near certainty, where one stop
  would decide a term, is tested by the calibration below instead):
  Pearson's X^2 = sum (k - n p)^2 / (n p (1 - p)) and the likelihood-ratio G^2 = 2 sum
  [k ln(k / n p) + (n - k) ln((n - k) / n (1 - p))], each on as many degrees of freedom
  as conditionals (no parameter is fitted to these counts);
* **calibration by bins** of the predicted probability q = min(p, 1 - p) of the less
  likely direction: the observed count of stops that went that way against the
  expected sum of n q, with the 95 % range of a Poisson count of that mean. A model
  that is overconfident in its tails shows as more observed than expected in the
  lowest bin.

The interval counts of :meth:`.check.Comparison.coverage` stay a secondary summary.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.special import xlogy
from scipy.stats import chi2, poisson

from .check import Comparison

MIN_EXPECTED = 5.0
"""Expected stops each way below which a conditional enters only the calibration."""

BINS = (0.0, 1e-3, 0.05, 0.2, 0.5)
"""Edges of the calibration bins in q = min(p, 1 - p), the less likely direction's
predicted probability."""


@dataclass(frozen=True)
class CalibrationBin:
    """Stops that went the less likely way, in one bin of its predicted probability.

    Attributes:
        low, high: the bin's range of q.
        conditionals: conditionals in the bin.
        observed: stops that went the less likely way.
        expected: their expected number, sum of n q.
        range: the 95 % range of a Poisson count with mean `expected`.
    """

    low: float
    high: float
    conditionals: int
    observed: int
    expected: float
    range: tuple[int, int]

    @property
    def holds(self) -> bool:
        """Whether the observed count lies in its 95 % range."""
        return self.range[0] <= self.observed <= self.range[1]


@dataclass(frozen=True)
class GoodnessOfFit:
    """The aggregate test and the calibration of the model against ensemble conditionals.

    Attributes:
        conditionals: informative conditionals in the aggregate test.
        pearson, pearson_p: Pearson's X^2 and its p-value (chi-square, as many degrees
            of freedom as conditionals).
        g, g_p: the likelihood-ratio G^2 and its p-value.
        bins: the calibration, one :class:`CalibrationBin` per bin of :data:`BINS`.
    """

    conditionals: int
    pearson: float
    pearson_p: float
    g: float
    g_p: float
    bins: tuple[CalibrationBin, ...]

    def describe(self) -> list[str]:
        """The lines ``pde-rotor predict check`` prints as its headline."""
        lines = [
            f"goodness of fit over {self.conditionals} informative conditionals P(inv | "
            f"direction) (at least {MIN_EXPECTED:g} stops expected each way): Pearson X2 = "
            f"{self.pearson:.1f} (p = {self.pearson_p:.3g}), G2 = {self.g:.1f} "
            f"(p = {self.g_p:.3g}), on {self.conditionals} degrees of freedom",
            "calibration: stops that went the less likely way, by its predicted probability q",
        ]
        for b in self.bins:
            if not b.conditionals:
                continue
            lines.append(
                f"  q in [{b.low:g}, {b.high:g}): {b.observed} observed, {b.expected:.1f} "
                f"expected [{b.range[0]}, {b.range[1]}] (95 % Poisson range) in "
                f"{b.conditionals} conditionals" + ("" if b.holds else "  (outside)")
            )
        return lines


def counted(comparison: Comparison) -> list[tuple[int, int, float]]:
    """(inverted, stops, predicted p) of every conditional that carries its counts."""
    return [
        (int(r["inverted"]), int(r["stops"]), float(r["predicted"]))
        for r in comparison.rows
        if r["column"] != "P" and r.get("stops")
    ]


def goodness_of_fit(comparison: Comparison, bins: Sequence[float] = BINS) -> GoodnessOfFit:
    """The aggregate test and the calibration table of `comparison`'s conditionals.

    Raises:
        ValueError: no conditional carries its counts (reports of the protocol estimator,
            or of a version that did not store them).
    """
    rows = counted(comparison)
    if not rows:
        msg = "no conditional with its counts (restart or bank reports hold them)"
        raise ValueError(msg)
    k, n, p = (np.array(column, dtype=float) for column in zip(*rows, strict=True))
    informative = np.minimum(n * p, n * (1 - p)) >= MIN_EXPECTED
    ki, ni, pi = k[informative], n[informative], p[informative]
    pearson = float(np.sum((ki - ni * pi) ** 2 / (ni * pi * (1 - pi))))
    g = float(2 * np.sum(xlogy(ki, ki / (ni * pi)) + xlogy(ni - ki, (ni - ki) / (ni * (1 - pi)))))
    dof = int(informative.sum())
    q = np.minimum(p, 1 - p)
    minority = np.where(p < 0.5, k, n - k)
    table = []
    for low, high in itertools.pairwise(bins):
        inside = (q >= low) & ((q < high) if high < 0.5 else (q <= high))
        expected = float(np.sum(n[inside] * q[inside]))
        lo, hi = poisson.interval(0.95, expected) if expected > 0 else (0.0, 0.0)
        table.append(
            CalibrationBin(
                low,
                high,
                int(inside.sum()),
                int(minority[inside].sum()),
                expected,
                (int(lo), int(hi)),
            )
        )
    return GoodnessOfFit(
        conditionals=dof,
        pearson=pearson,
        pearson_p=float(chi2.sf(pearson, dof)) if dof else math.nan,
        g=g,
        g_p=float(chi2.sf(g, dof)) if dof else math.nan,
        bins=tuple(table),
    )
