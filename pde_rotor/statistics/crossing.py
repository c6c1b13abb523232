"""Where a measured probability curve crosses a level, with a 95 % interval.

Two numbers of the paper are wanted as the model really has them: the
Δ = 0 decay point, the t_stop at which P of Fig. 5 falls through 0.75 (the paper:
"It decayed around t_stop = 1.4"), and the Δ = 1e-4 onset, where P of Fig. 7(a)
falls through 0.5 (the paper: near 1). Both are read from ensemble points with
Wilson intervals (:func:`pde_rotor.statistics.proportions.wilson_interval`), without a model of the
curve's shape. Two intervals are given, because they assume different things:

* **interpolated**: the estimate is where the straight lines between the measured P
  cross the level, and the interval is where the lines between the interval bounds do
  (for a falling curve the lower bounds cross first, the upper bounds last). This
  inverts the pointwise band, and it assumes that P, and each bound, runs straight
  between neighbouring points: between two points a curved P can cross elsewhere.
* **monotone**: assuming only that P falls (rises) with t_stop, the crossing lies after
  every point whose interval lies wholly above the level and before every point whose
  interval lies wholly below it. Nothing is assumed between the points, so this
  interval is wider; its ends are measured points.

An end that the band does not close within the measured points is open (None). Where
the measured curve does not cross the level at all the estimate is None, but the band
may still bound the crossing from one side: the lower end where the bounds cross
within the points.

A sweep's report may hold a point that is still being computed (a sweep stopped and
resumed across sessions): its interval is honest but wide, and as an interior point of
the band it would widen the crossing's interval to its own. :func:`report_crossing`
therefore reads only complete points (``runs_done == runs_expected``) and says how
many partial ones it left out.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import xarray as xr

DECAY_LEVEL = 0.75
"""P that marks the Δ = 0 decay point (halfway from certain inversion, 1, to the coin
toss, 0.5, that long stops of a symmetric rotor give)."""

DECAY_START_LEVEL = 0.95
"""P that marks where the Δ = 0 decay starts: the other reading of the paper's "decayed
around t_stop = 1.4" (P falls from 1 through 0.95)."""

ONSET_LEVEL = 0.5
"""P that marks the Δ ≠ 0 onset (halfway from 1 to the long-stop plateau near 0)."""


@dataclass(frozen=True)
class Crossing:
    """A level crossing of a measured curve.

    Attributes:
        level: the P crossed.
        value: where the measured P crosses it (None: not within the points).
        low: lower end of the 95 % interval (None: below the first point).
        high: upper end (None: beyond the last point).
        points: number of curve points behind it.
        partial: measured points left out because their runs are not all done.
        monotone: the interval assuming only that P is monotone (module doc); an end
            is None where no point's interval lies wholly on that side of the level.
    """

    level: float
    value: float | None
    low: float | None
    high: float | None
    points: int
    partial: int = 0
    monotone: tuple[float | None, float | None] = (None, None)

    def describe(self, name: str = "t_stop") -> str:
        """One line: ``P = 0.75 at t_stop = 1.86 [1.79, 1.93] (95 %)``, open ends as
        ``open``, and the partial points left out, if any."""
        if self.value is None:
            text = f"P does not cross {self.level:g} within the {self.points} points"
            if self.low is not None:
                text += f"; the crossing lies beyond {name} = {self.low:.3g} (95 %)"
        else:
            low = "open" if self.low is None else f"{self.low:.3g}"
            high = "open" if self.high is None else f"{self.high:.3g}"
            text = (
                f"P = {self.level:g} at {name} = {self.value:.3g} [{low}, {high}] (95 %, "
                "straight lines between points)"
            )
            before, after = ("open" if v is None else f"{v:.3g}" for v in self.monotone)
            text += f"; [{before}, {after}] assuming only that P is monotone"
        if self.partial:
            points = "point" if self.partial == 1 else "points"
            text += f"; {self.partial} partial {points} left out"
        return text


def _first_crossing(x: np.ndarray, y: np.ndarray, level: float, falling: bool) -> float | None:
    """The first x where the polyline through (x, y) passes `level` in the curve's
    direction; x[0] where it starts past the level, None where it never gets there."""
    past = y < level if falling else y > level
    if not past.any():
        return None
    i = int(np.argmax(past))
    if i == 0:
        return float(x[0])
    t = (y[i - 1] - level) / (y[i - 1] - y[i])
    return float(x[i - 1] + t * (x[i] - x[i - 1]))


def level_crossing(
    x: Sequence[float],
    p: Sequence[float],
    low: Sequence[float],
    high: Sequence[float],
    level: float,
    falling: bool = True,
) -> Crossing:
    """Where the curve P(x) crosses `level`, with the band's interval (module doc).

    Points are sorted by x and NaN points (not yet measured) are left out. The curve
    falls by default (P against t_stop: the decay and the onset); the direction is
    given, not read from the points, which near a crossing may go either way by chance.

    Raises:
        ValueError: fewer than two measured points, or the arrays differ in length.
    """
    arrays = [np.asarray(a, dtype=float) for a in (x, p, low, high)]
    if len({a.shape for a in arrays}) != 1:
        msg = "x, p, low and high must have one length"
        raise ValueError(msg)
    keep = np.all([np.isfinite(a) for a in arrays], axis=0)
    order = np.argsort(arrays[0][keep])
    xs, ps, lows, highs = (a[keep][order] for a in arrays)
    if len(xs) < 2:
        msg = f"a crossing needs two measured points, the curve has {len(xs)}"
        raise ValueError(msg)
    value = _first_crossing(xs, ps, level, falling)
    # falling: the lower bounds pass the level first, the upper bounds last
    first, last = (lows, highs) if falling else (highs, lows)
    start = _first_crossing(xs, first, level, falling)
    # monotone only: after every point wholly on the start side, before every point
    # wholly on the end side
    start_side = lows > level if falling else highs < level
    end_side = highs < level if falling else lows > level
    monotone = (
        float(xs[start_side].max()) if start_side.any() else None,
        float(xs[end_side].min()) if end_side.any() else None,
    )
    return Crossing(
        level=level,
        value=value,
        low=None if start is None or start == xs[0] else start,
        high=None if value is None else _first_crossing(xs, last, level, falling),
        points=len(xs),
        monotone=monotone,
    )


def partial_points(ds: xr.Dataset) -> np.ndarray:
    """Boolean mask of the report's measured points whose runs are not all done
    (``runs_done < runs_expected``; all False where the report does not count runs)."""
    p = np.asarray(ds["P"].values, dtype=float)
    if "runs_done" not in ds or "runs_expected" not in ds:
        return np.zeros(p.shape, dtype=bool)
    return np.isfinite(p) & (ds["runs_done"].values < ds["runs_expected"].values)


def report_crossing(
    ds: xr.Dataset, level: float, x_dim: str = "t_stop", falling: bool = True
) -> Crossing:
    """:func:`level_crossing` of a one-curve report (:func:`pde_rotor.sweep.stored.curve`)
    along `x_dim`, P falling along it unless `falling` is False (P(3, 2e-5) against
    sigma rises).

    Where the report counts its runs (``runs_done``, ``runs_expected``), points with
    runs still to do are left out (module doc) and counted in ``Crossing.partial``.

    Raises:
        ValueError: fewer than two complete measured points.
    """
    partial = partial_points(ds)
    left_out = int(partial.sum())
    values = [np.where(partial, np.nan, ds[k].values) for k in ("P", "P_low", "P_high")]
    try:
        found = level_crossing(ds[x_dim].values, *values, level, falling)
    except ValueError as err:
        if not left_out:
            raise
        msg = f"{err} complete ({left_out} partial left out)"
        raise ValueError(msg) from err
    return replace(found, partial=left_out)


def report_crossings(
    ds: xr.Dataset, level: float, x_dim: str = "t_stop", falling: bool = True
) -> list[tuple[dict[str, Any], Crossing | str]]:
    """The crossing of every curve of a report along `x_dim` (P falling along it, as
    along t_stop in Figs. 5, 7(a), 7(b) and 8, unless `falling` is False): one per
    combination of its other dimensions (their coordinates first), or the reason a curve
    has none (fewer than two measured points).

    Raises:
        ValueError: the report has no dimension `x_dim`.
    """
    if x_dim not in ds.dims:
        msg = f"report has no dimension {x_dim!r} (dimensions: {', '.join(ds.dims) or 'none'})"
        raise ValueError(msg)
    others = [d for d in ds["P"].dims if d != x_dim]
    found: list[tuple[dict[str, Any], Crossing | str]] = []
    for values in itertools.product(*(ds[d].values for d in others)):
        where = {d: v.item() for d, v in zip(others, values, strict=True)}
        try:
            found.append((where, report_crossing(ds.sel(where), level, x_dim, falling)))
        except ValueError as err:
            found.append((where, str(err)))
    return found
