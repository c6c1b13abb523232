"""Level crossings of measured curves (the decay point and the onset)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import xarray as xr

from pde_rotor.statistics.crossing import (
    DECAY_LEVEL,
    level_crossing,
    partial_points,
    report_crossing,
    report_crossings,
)
from pde_rotor.statistics.proportions import wilson_interval


def decay(t: np.ndarray) -> np.ndarray:
    """A Fig. 5-like curve: 1 at short stops, 0.5 at long ones, 0.75 at t = 1.8."""
    return 0.5 + 0.5 / (1.0 + np.exp((t - 1.8) / 0.15))


def measured(t: np.ndarray, rng: np.random.Generator, n: int = 200) -> tuple[np.ndarray, ...]:
    k = rng.binomial(n, decay(t))
    bounds = np.array([wilson_interval(int(i), n) for i in k])
    return k / n, bounds[:, 0], bounds[:, 1]


def test_the_estimate_is_the_straight_line_crossing() -> None:
    x = np.array([1.0, 1.5, 2.0, 2.5])
    p = 1.0 - 0.2 * (x - 1.0)
    crossing = level_crossing(x, p, p - 0.01, p + 0.01, 0.75)
    assert crossing.value == pytest.approx(2.25)
    assert crossing.low == pytest.approx(2.2) and crossing.high == pytest.approx(2.3)
    rising = level_crossing(x, 1.0 - p, 0.99 - p, 1.01 - p, 0.25, falling=False)
    assert rising.value == pytest.approx(2.25) and rising.low == pytest.approx(2.2)


def test_the_interval_covers_the_true_crossing() -> None:
    """Binomial ensembles of 200 stops on points 0.125 apart: the band's interval holds
    the true 0.75 crossing (1.8) in at least 95 % of 300 repetitions (it is
    conservative), and its typical width is that of the points' intervals."""
    rng = np.random.default_rng(14)
    t = np.arange(1.0, 2.75, 0.125)
    hits, widths = [], []
    for _ in range(300):
        crossing = level_crossing(t, *measured(t, rng), DECAY_LEVEL)
        assert crossing.low is not None and crossing.high is not None
        hits.append(crossing.low <= 1.8 <= crossing.high)
        widths.append(crossing.high - crossing.low)
    assert np.mean(hits) >= 0.95
    assert 0.05 < np.median(widths) < 0.4


def test_the_monotone_interval_spans_the_points_wholly_on_either_side() -> None:
    """Assuming only that P falls: after the last point whose interval lies above the
    level, before the first whose interval lies below; a point whose interval holds the
    level says nothing."""
    x = np.array([1.0, 1.5, 2.0, 2.5, 3.0])
    p = np.array([0.95, 0.85, 0.76, 0.70, 0.55])
    low, high = p - 0.05, p + 0.05
    crossing = level_crossing(x, p, low, high, 0.75)
    assert crossing.monotone == (1.5, 3.0)  # 2.0 and 2.5 hold 0.75 within their intervals
    assert crossing.low is not None and crossing.monotone[0] <= crossing.low
    assert crossing.high is not None and crossing.high <= crossing.monotone[1]
    rising = level_crossing(x, 1 - p, 1 - high, 1 - low, 0.25, falling=False)
    assert rising.monotone == (1.5, 3.0)


@pytest.mark.parametrize(
    "curve",
    [
        lambda t: np.clip(1.0 - 0.45 * (t - 1.2) ** 2 / 0.36, 0.5, 1.0),  # parabolic, kinked
        lambda t: 0.5 + 0.5 * np.exp(-((np.maximum(t - 1.2, 0) / 0.8) ** 3)),  # skewed
    ],
    ids=["kinked", "skewed"],
)
def test_the_monotone_interval_covers_any_falling_curve(curve) -> None:
    """Non-logistic, asymmetric falling curves with binomial points 0.25 apart: the
    monotone interval holds the true 0.75 crossing at least 95 % of the time whatever
    the shape between the points (the interpolated one assumes straight lines there)."""
    from scipy.optimize import brentq

    truth = brentq(lambda t: curve(t) - 0.75, 1.2, 3.0)
    rng = np.random.default_rng(7)
    t = np.arange(1.0, 3.01, 0.25)
    hits = []
    for _ in range(300):
        k = rng.binomial(200, curve(t))
        bounds = np.array([wilson_interval(int(i), 200) for i in k])
        crossing = level_crossing(t, k / 200, bounds[:, 0], bounds[:, 1], DECAY_LEVEL)
        before, after = crossing.monotone
        hits.append((before is None or before <= truth) and (after is None or truth <= after))
    assert np.mean(hits) >= 0.95


def test_open_ends_and_no_crossing() -> None:
    x = np.array([1.0, 2.0, 3.0])
    p = np.array([0.8, 0.7, 0.6])
    start_open = level_crossing(x, p, p - 0.1, p + 0.1, 0.75)
    assert start_open.low is None and start_open.value == pytest.approx(1.5)
    assert start_open.high == pytest.approx(2.5)
    end_open = level_crossing(x, p, p - 0.02, p + 0.2, 0.75)
    assert end_open.high is None and "open]" in end_open.describe()
    never = level_crossing(x, p + 0.2, p + 0.15, p + 0.3, 0.75)
    assert never.value is None and never.low is None
    assert never.describe() == "P does not cross 0.75 within the 3 points"
    # above the level at every point, but the lower bounds cross between 1 and 2
    beyond = level_crossing(x, p + 0.2, p, p + 0.3, 0.75)
    assert beyond.value is None and beyond.high is None
    assert beyond.low == pytest.approx(1.5)
    assert beyond.describe().endswith("the crossing lies beyond t_stop = 1.5 (95 %)")
    # a falling curve measured rising by chance, both points above the level
    chance = level_crossing([1.75, 2.0], [0.81, 0.9], [0.75, 0.7], [0.86, 0.97], 0.75)
    assert chance.value is None


def test_unmeasured_points_are_left_out_and_two_are_needed() -> None:
    x = [2.0, 1.0, 3.0]
    p = [0.7, np.nan, 0.6]
    with pytest.raises(ValueError, match="two measured points, the curve has 1"):
        level_crossing(x, p, [0.6, np.nan, np.nan], [0.8, np.nan, 0.7], 0.75)
    with pytest.raises(ValueError, match="one length"):
        level_crossing(x, p, p, p[:2], 0.75)


def test_report_crossing_reads_a_report_curve() -> None:
    t = np.array([1.5, 1.75, 2.0])
    p = np.array([0.95, 0.8, 0.6])
    ds = xr.Dataset(
        {"P": ("t_stop", p), "P_low": ("t_stop", p - 0.05), "P_high": ("t_stop", p + 0.05)},
        coords={"t_stop": t},
    )
    crossing = report_crossing(ds, DECAY_LEVEL)
    assert crossing.value == pytest.approx(1.8125)
    assert crossing.points == 3
    assert crossing.describe().startswith(
        "P = 0.75 at t_stop = 1.81 [1.75, 1.88] (95 %, straight lines between points); ["
    )
    rising = ds.assign(P=1.0 - ds["P"], P_low=0.95 - ds["P"], P_high=1.05 - ds["P"])
    assert report_crossing(rising, 0.25, falling=False).value == pytest.approx(1.8125)
    assert report_crossing(rising, 0.25).value == 1.5  # read as falling: below from the start


def test_every_curve_of_a_report_gets_its_crossing() -> None:
    """One crossing per value of the other axes (here Delta); a curve with one measured
    point says so instead; a report without the axis is refused."""
    t = np.array([0.5, 1.0, 1.5])
    p = np.array([[1.0, 0.6, 0.2], [1.0, np.nan, np.nan]])
    ds = xr.Dataset(
        {
            name: (("asymmetry", "t_stop"), p + shift)
            for name, shift in (("P", 0.0), ("P_low", -0.05), ("P_high", 0.05))
        },
        coords={"asymmetry": [1e-4, 2e-5], "t_stop": t},
    )
    (first, crossing), (second, reason) = report_crossings(ds, 0.5)
    assert first == {"asymmetry": 1e-4} and crossing.value == pytest.approx(1.125)
    assert second == {"asymmetry": 2e-5} and "has 1" in reason
    with pytest.raises(ValueError, match="no dimension 'sigma'"):
        report_crossings(ds, 0.5, "sigma")


def test_partial_points_are_left_out_of_the_crossing() -> None:
    """A point whose runs are not all done (a sweep stopped mid-way) is an honest but
    wide point; inside the band it would widen the interval to its own. The crossing
    reads only the complete points and counts the partial one."""
    t = np.array([0.5, 0.75, 1.5, 1.75, 2.0])
    p = np.array([1.0, 1.0, 0.95, 0.8, 0.6])
    low = np.array([0.98, 0.21, 0.9, 0.74, 0.52])  # 0.75: one run done, interval [0.21, 1]
    ds = xr.Dataset(
        {
            "P": ("t_stop", p),
            "P_low": ("t_stop", low),
            "P_high": ("t_stop", np.minimum(p + 0.05, 1.0)),
            "runs_done": ("t_stop", [200, 1, 200, 200, 200]),
            "runs_expected": ("t_stop", [200] * 5),
        },
        coords={"t_stop": t},
    )
    assert partial_points(ds).tolist() == [False, True, False, False, False]
    complete = ds.drop_sel(t_stop=0.75).drop_vars(["runs_done", "runs_expected"])
    crossing = report_crossing(ds, DECAY_LEVEL)
    assert crossing == replace(report_crossing(complete, DECAY_LEVEL), partial=1)
    assert crossing.low == pytest.approx(1.5 + 0.25 * 0.15 / 0.16)  # with the partial: 0.575
    assert crossing.describe().endswith(
        "assuming only that P is monotone; 1 partial point left out"
    )
    counted = ds.assign(runs_done=ds["runs_expected"])
    assert report_crossing(counted, DECAY_LEVEL).low == pytest.approx(0.5 + 0.25 * 0.23 / 0.77)
    with pytest.raises(ValueError, match=r"has 1 complete \(1 partial left out\)"):
        report_crossing(ds.sel(t_stop=[0.5, 0.75]), DECAY_LEVEL)
