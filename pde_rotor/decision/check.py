"""The decision model against ensembles: every point of stored sweep reports.

For each point of a report (a ``pde-rotor report`` NetCDF) the model's P, P(inv | CCW)
and P(inv | CW) at the point's t_stop, Δ and sigma are set beside the ensemble's values
and their 95 % intervals. The summary gives the coverage: the fraction of the
intervals that hold the prediction (about 0.95 if the model is right and the intervals
are exact; the chain intervals are conservative). It also gives the largest deviation.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..config import RotorConfig, physics_differences
from .table import DecisionTable, diffusion_of, load_table

COLUMNS = ("P", "P_ccw", "P_cw")
"""The report's probabilities that the model predicts (each with _low and _high)."""

MATCHED = (
    ("grid", "dx"),
    ("grid", "dt"),
    ("geometry", "smoothing"),
    ("flow", "enabled"),
    ("numerics", "scheme"),
)
"""Settings a report's base_config must share with the table where it names them."""


COUNTS = ("inversions_ccw", "stops_ccw", "inversions_cw", "stops_cw")
"""The counts behind the conditionals, where a report holds them (restart and bank)."""

PREDICTED = ("protocol.t_stop", "geometry.asymmetry", "noise.sigma")
"""The settings a table predicts over: every other physics setting is the table's own."""


DEFAULT_SCHEME = "consistent"
"""The scheme of a report in the estimators' format (with the ``design`` attribute) that
neither names nor records one: the default from 2026-11-23 until reports recorded their
scheme (2026-11-28). A report of that format written on 2026-11-23 before the default
changed would be misread; none is stored."""

FORMER_SCHEME = "paper"
"""The scheme of a report in the format before the estimators' rule (no ``design``
attribute, before 2026-11-23) that names none: the only scheme there was, then the
default (data/calibration.nc, predictions.nc and the *_quick reports)."""

REPORT_SCHEME_ATTR = "scheme"
"""A report's attribute with the scheme its runs used (written since reports record it)."""


def report_scheme(ds: xr.Dataset) -> str:
    """The ``numerics.scheme`` the runs of report `ds` used.

    The scheme its ``base_config`` names, else the one its :data:`REPORT_SCHEME_ATTR`
    attribute records, else the default of the report's time: :data:`FORMER_SCHEME`
    for a report in the format before the estimators' rule (no ``design`` attribute),
    :data:`DEFAULT_SCHEME` after it. A report that names no scheme is resolved, never
    taken to match any table.
    """
    fixed = json.loads(ds.attrs.get("base_config", "{}"))
    named = fixed.get("numerics", {}).get("scheme")
    if named:
        return str(named)
    if REPORT_SCHEME_ATTR in ds.attrs:
        return str(ds.attrs[REPORT_SCHEME_ATTR])
    return DEFAULT_SCHEME if "design" in ds.attrs else FORMER_SCHEME


def scheme_origin(ds: xr.Dataset) -> str:
    """How :func:`report_scheme` found the scheme of report `ds`, in words."""
    fixed = json.loads(ds.attrs.get("base_config", "{}"))
    if fixed.get("numerics", {}).get("scheme"):
        return "named by its base config"
    if REPORT_SCHEME_ATTR in ds.attrs:
        return f"recorded in its attribute {REPORT_SCHEME_ATTR!r}"
    if "design" in ds.attrs:
        return "named nowhere: the default of its report format"
    return (
        "named nowhere: its report format predates 2026-11-23, when the paper scheme "
        "was the default"
    )


def report_config(ds: xr.Dataset) -> dict[str, Any]:
    """The base config of report `ds` with its scheme resolved (:func:`report_scheme`)."""
    fixed = json.loads(ds.attrs.get("base_config", "{}"))
    fixed.setdefault("numerics", {})["scheme"] = report_scheme(ds)
    return fixed


def report_grids(ds: xr.Dataset) -> list[float]:
    """The dx values of report `ds`: its dx axis, else its base grid.dx."""
    if "dx" in ds.dims:
        return [float(v) for v in ds["dx"].values]
    return [float(report_config(ds).get("grid", {}).get("dx", RotorConfig().grid.dx))]


def table_for(
    ds: xr.Dataset, directory: Path, dx: float | None = None
) -> tuple[Path, DecisionTable] | None:
    """The decision table under `directory` (``*.nc``, by name) that holds the model of
    report `ds` (at grid `dx` of a report along dx): the same physics
    (:func:`pde_rotor.config.physics_differences`, the scheme resolved by
    :func:`report_scheme`) in every setting but :data:`PREDICTED`. None where no table
    does, e.g. for a report on another grid, or one whose axes vary anything else."""
    if set(ds["P"].dims) - {"t_stop", "asymmetry", "sigma", "dx"}:
        return None
    fixed = report_config(ds)
    if dx is not None:
        fixed.setdefault("grid", {})["dx"] = dx
    elif "dx" in ds.dims:
        return None
    config = RotorConfig.model_validate(fixed)
    for path in sorted(Path(directory).glob("*.nc")):
        table = load_table(path)
        other = RotorConfig.model_validate_json(table.attrs["config"])
        if not physics_differences(config, other, ignore=PREDICTED):
            return path, table
    return None


def is_ensemble(ds: xr.Dataset) -> bool:
    """Whether report `ds` holds the conditionals' counts (a restart or bank ensemble)."""
    return ds.attrs.get("estimator") in ("restart", "bank") and all(c in ds for c in COUNTS)


def stored_matches(
    reports: Sequence[tuple[Path, xr.Dataset]], directory: Path
) -> tuple[list[tuple[Path, xr.Dataset, Path, DecisionTable]], list[str]]:
    """Every (report, table) pair of `reports` that a table under `directory` predicts.

    A report along dx is split by grid: each dx goes with its own table. Returns the
    pairs and one line per report (or grid of one) that no table predicts."""
    pairs, left_out = [], []
    for path, ds in reports:
        for dx in report_grids(ds):
            found = table_for(ds, directory, dx if "dx" in ds.dims else None)
            if found is None:
                fixed = report_config(ds)
                left_out.append(
                    f"{path.name}: no table under {directory} holds its physics (dx = {dx:.4g}, "
                    f"scheme {fixed['numerics']['scheme']}, flow "
                    f"{'off' if fixed.get('flow', {}).get('enabled') is False else 'on'})"
                )
                continue
            pairs.append((path, ds, *found))
    return pairs, left_out


def report_points(ds: xr.Dataset) -> list[dict[str, float]]:
    """Every point of a report as a dict: t_stop, asymmetry, sigma, dx, stops and the
    :data:`COLUMNS` with their intervals. Values that are not axes of the report come
    from its ``base_config``."""
    fixed = json.loads(ds.attrs.get("base_config", "{}"))
    defaults = {
        "t_stop": fixed.get("protocol", {}).get("t_stop", math.nan),
        "asymmetry": fixed.get("geometry", {}).get("asymmetry", 0.0),
        "sigma": fixed.get("noise", {}).get("sigma", 0.0),
        "dx": fixed.get("grid", {}).get("dx", math.nan),
    }
    names = [f"{c}{s}" for c in COLUMNS for s in ("", "_low", "_high")] + ["stops", *COUNTS]
    values = ds[[n for n in names if n in ds]]
    if not values["P"].dims:
        values = values.expand_dims("point")
    points = []
    for _, row in values.to_dataframe().reset_index().iterrows():
        point = {k: float(row[k]) if k in row else float(v) for k, v in defaults.items()}
        point.update({n: float(row[n]) for n in names if n in row})
        points.append(point)
    return points


def mismatch(
    table: DecisionTable, fixed: Mapping[str, Any], axes: Sequence[str] = ()
) -> str | None:
    """Which setting of an ensemble's base config `fixed` differs from the table's config
    (or None); settings that `fixed` leaves out are taken to match, and so are those the
    ensemble varies along its `axes` (dimension names: ``dx`` of a grid comparison,
    whose points :func:`table_points` selects)."""
    config = RotorConfig.model_validate_json(table.attrs["config"]).model_dump(mode="json")
    for section, key in MATCHED:
        if key in axes:
            continue
        if key in fixed.get(section, {}) and not _same(fixed[section][key], config[section][key]):
            return (
                f"{section}.{key} = {fixed[section][key]!r} in the ensemble, "
                f"{config[section][key]!r} in the table"
            )
    return None


def _same(a: Any, b: Any) -> bool:
    """Equal settings; numbers to 1e-6 relative (a YAML's 0.0333333333 is dx = 1/30)."""
    numbers = all(isinstance(x, float | int) and not isinstance(x, bool) for x in (a, b))
    if numbers:
        return math.isclose(a, b, rel_tol=1e-6)
    return a == b


def table_points(table: DecisionTable, ds: xr.Dataset) -> list[dict[str, float]]:
    """The measured points of `ds` on the table's grid: all of them, or those of its dx
    along a dx axis (a report that compares grids). Points without a
    finished stop (a partial report of a sweep still running) are left out.

    Raises:
        ValueError: a point's t_stop lies beyond the table's t_max (named, with the
            table's range).
    """
    dx = RotorConfig.model_validate_json(table.attrs["config"]).grid.dx
    points = [
        p
        for p in report_points(ds)
        if (math.isnan(p["dx"]) or math.isclose(p["dx"], dx, rel_tol=1e-6))
        and p.get("stops", 1) > 0
        and math.isfinite(p["P"])
    ]
    beyond = sorted({p["t_stop"] for p in points if p["t_stop"] > table.t_max + 1e-12})
    if beyond:
        msg = (
            f"report {ds.attrs.get('sweep', '?')}: t_stop = {beyond[0]:g} lies beyond the "
            f"table's range [0, {table.t_max:g}] (measure the table with --t-max "
            f"{beyond[-1]:g} or more)"
        )
        raise ValueError(msg)
    return points


@dataclass(frozen=True)
class Comparison:
    """Predictions beside ensemble values.

    Attributes:
        rows: one dict per point and column: where (t_stop, asymmetry, sigma), column,
            measured, low, high, predicted, inside, and for the conditionals the counts
            behind them (inverted, stops; None where the report lacks them).
    """

    rows: list[dict[str, Any]]

    def coverage(self, column: str | None = None) -> float:
        """Fraction of the intervals (of `column`, default all) holding the prediction."""
        rows = [r for r in self.rows if column in (None, r["column"])]
        return float(np.mean([r["inside"] for r in rows])) if rows else math.nan

    def largest_deviation(self) -> dict[str, Any]:
        """The row with the largest |predicted - measured|."""
        return max(self.rows, key=lambda r: abs(r["predicted"] - r["measured"]))


def compare(table: DecisionTable, reports: Sequence[xr.Dataset]) -> Comparison:
    """The model's P, P(inv | CCW), P(inv | CW) at every point of `reports`.

    Raises:
        ValueError: a report was computed with another grid, smoothing, flow or scheme
            (a report that names no scheme has the one :func:`report_scheme` resolves),
            or a point's t_stop lies outside the table.
    """
    rows = []
    for ds in reports:
        problem = mismatch(table, report_config(ds), list(ds.dims))
        if problem and problem.startswith("numerics.scheme"):
            problem += f" (the ensemble's scheme is {scheme_origin(ds)})"
        if problem:
            msg = f"report {ds.attrs.get('sweep', '?')}: {problem}"
            raise ValueError(msg)
        for point in table_points(table, ds):
            dw = diffusion_of(point["sigma"], table.inertia)
            t, d = point["t_stop"], point["asymmetry"]
            a, b = table.conditionals(t, d, dw)
            predicted = {"P": table.probability(t, d, dw), "P_ccw": a, "P_cw": b}
            for column in COLUMNS:
                if column not in point or not np.isfinite(point[column]):
                    continue
                low, high = point[f"{column}_low"], point[f"{column}_high"]
                value = float(predicted[column])
                direction = column.removeprefix("P_")
                inverted, stops = (
                    point.get(f"inversions_{direction}"),
                    point.get(f"stops_{direction}"),
                )
                rows.append(
                    {
                        "inverted": int(inverted)
                        if column != "P" and inverted is not None
                        else None,
                        "stops": int(stops) if column != "P" and stops is not None else None,
                        "sweep": ds.attrs.get("sweep", "?"),
                        "dx": point["dx"],
                        "t_stop": t,
                        "asymmetry": d,
                        "sigma": point["sigma"],
                        "column": column,
                        "measured": point[column],
                        "low": low,
                        "high": high,
                        "predicted": value,
                        "inside": bool(low - 1e-12 <= value <= high + 1e-12),
                    }
                )
    return Comparison(rows)


def master_points(table: DecisionTable, reports: Sequence[xr.Dataset]) -> list[dict[str, float]]:
    """Every conditional of `reports` on the master curve P(+1) = Φ(x).

    x = β̄ / sqrt(λ Dw), with β̄ the angle-mean bias of the point and direction; the
    measured P(direction after = +1) is 1 - P(inv | CCW) after CCW and P(inv | CW) after
    CW. Points without noise (x infinite) are left out. Where the lattice spread of β is
    small against sqrt(λ Dw) all points fall on Φ(x), whatever t_stop, Δ, sigma and flow.
    """
    out = []
    for ds in reports:
        for point in table_points(table, ds):
            if point["sigma"] <= 0:
                continue
            scale = math.sqrt(table.growth_rate * diffusion_of(point["sigma"], table.inertia))
            beta = table.release_bias(point["t_stop"], point["asymmetry"]).mean(axis=1)
            for d, (column, flip) in enumerate((("P_ccw", True), ("P_cw", False))):
                if column not in point or not np.isfinite(point[column]):
                    continue
                low, high = point[f"{column}_low"], point[f"{column}_high"]
                value = point[column]
                if flip:
                    value, low, high = 1 - value, 1 - high, 1 - low
                out.append({"x": float(beta[d]) / scale, "P": value, "low": low, "high": high})
    return out
