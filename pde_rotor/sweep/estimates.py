"""The statistics of one sweep point, and the paired comparison of a bank's noise values.

The inversion probability P of a point, by estimator and asymmetry Delta:

* ``protocol``: inversions / stops of the paper's protocol runs (inversions / M), all
  stops pooled, with its Wilson 95 % interval;
* ``restart``, ``bank`` with Delta = 0: the pooled fraction inversions / stops of both
  directions (both directions estimate one probability), Wilson 95 % interval;
* ``restart``, ``bank`` with Delta != 0: the two-state chain value 2 a b / (a + b) of
  the per-direction inversion fractions a = P(inv | CCW), b = P(inv | CW), with the
  Bonferroni-Wilson plug-in interval: 2 a b / (a + b) at the 97.5 % Wilson bounds of a
  and of b (it increases in both, so the interval covers with at least 95 %).

Bank runs that differ only in their noise share their stops: the values of a noise
axis are a paired design, compared by McNemar's exact test (:func:`mcnemar_p`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy import stats as sps

from ..statistics.proportions import DirectionCounts, Proportion, restart_counts, two_state_chain

POOLED, CHAIN = 0, 1
"""Codes of the variable ``P_estimator``: which definition P holds at a point."""
P_DEFINITIONS = {
    POOLED: "pooled inversions / stops of both directions (Wilson 95 % interval)",
    CHAIN: (
        "two-state chain 2ab/(a+b), a = P(inv|CCW), b = P(inv|CW) (Bonferroni-Wilson "
        "interval: 2ab/(a+b) at the 97.5 % Wilson bounds of a and b)"
    ),
}
"""What P is, by code of ``P_estimator``."""


def inverted(content: dict[str, Any]) -> bool:
    """Whether a restart or bank run inverted (committed against its direction)."""
    res = content["result"]
    return bool(res["direction_after"] == -res["direction_before"])


def point_statistics(
    kind: str, asymmetry: float, contents: Sequence[dict[str, Any]], expected: int
) -> dict[str, float]:
    """P and its interval, counts, the pooled and chain values and run bookkeeping.

    Args:
        kind: the estimator (protocol, restart, bank).
        asymmetry: Delta of the point (restart, bank: pooled at 0, chain otherwise).
        contents: the records of the point's runs found in the store.
        expected: number of runs of the point.
    """
    counts = DirectionCounts()
    omegas: list[float] = []
    uncommitted = 0
    commit_times: list[float] = []
    if kind == "protocol":
        for c in contents:
            res = c["result"]
            counts += DirectionCounts(
                Proportion(res["inversions_ccw"], res["n_ccw"]),
                Proportion(res["inversions_cw"], res["n_cw"]),
            )
            omegas.extend(abs(w) for w in res["omegas"][:-1])
    elif contents:
        counts = restart_counts(
            [c["result"]["direction_before"] for c in contents],
            [c["result"]["direction_after"] for c in contents],
        )
        for c in contents:
            res = c["result"]
            omegas.append(abs(res["omega_before"]))
            if res["committed"]:
                commit_times.append(res["t_commit"])
            else:
                uncommitted += 1
    total = counts.total
    pooled_low, pooled_high = total.interval()
    chain = two_state_chain(counts)
    use_chain = kind != "protocol" and asymmetry != 0
    out = {
        "P": chain.p if use_chain else total.p,
        "P_low": chain.low if use_chain else pooled_low,
        "P_high": chain.high if use_chain else pooled_high,
        "P_estimator": CHAIN if use_chain else POOLED,
        "P_pooled": total.p,
        "P_pooled_low": pooled_low,
        "P_pooled_high": pooled_high,
        "P_chain": chain.p,
        "P_chain_low": chain.low,
        "P_chain_high": chain.high,
        "inversions": total.k,
        "stops": total.n,
        "pi_ccw": chain.pi_ccw,
        "mean_abs_omega": float(np.mean(omegas)) if omegas else math.nan,
        "uncommitted": uncommitted,
        "mean_commit_time": float(np.mean(commit_times)) if commit_times else math.nan,
        "runs_done": len(contents),
        "runs_expected": expected,
    }
    for name in ("ccw", "cw"):
        prop: Proportion = getattr(counts, name)
        low, high = prop.interval()
        out.update(
            {
                f"P_{name}": prop.p,
                f"P_{name}_low": low,
                f"P_{name}_high": high,
                f"inversions_{name}": prop.k,
                f"stops_{name}": prop.n,
            }
        )
    return out


def mcnemar_p(first: dict[Any, bool], second: dict[Any, bool]) -> float:
    """McNemar's exact test of paired outcomes: two-sided p-value of equal inversion rates.

    Args:
        first: inverted or not, by pair (the shared stop: direction, sample); pairs
            present in only one of `first` and `second` are left out.
        second: the same for the other value of the paired axis.

    Returns:
        The binomial test of the discordant pairs (inverted in one, not the other)
        against 1/2 (:func:`scipy.stats.binomtest`); 1 without discordant pairs, nan
        without pairs.
    """
    pairs = first.keys() & second.keys()
    if not pairs:
        return math.nan
    only_first = sum(first[k] and not second[k] for k in pairs)
    only_second = sum(second[k] and not first[k] for k in pairs)
    n = only_first + only_second
    if n == 0:
        return 1.0
    return float(sps.binomtest(only_first, n, 0.5).pvalue)
