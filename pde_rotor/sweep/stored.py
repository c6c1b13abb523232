"""Stored sweep reports: find them under a data directory, read their curves and the
stored points that lie on a curve, from other reports (the probability figures of the
gallery)."""

from __future__ import annotations

import json
import logging
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..config import RotorConfig, physics_differences
from ..plotting.figures import count_range
from ..statistics.crossing import partial_points
from ..statistics.proportions import wilson_interval
from .estimates import CHAIN, POOLED
from .reporting import P_RULE, VARIABLES

_logger = logging.getLogger(__name__)


@dataclass
class SweepData:
    """A sweep report and where it came from.

    Attributes:
        report: Dataset of :func:`pde_rotor.sweep.report` (P, P_low, P_high, stops, ...).
        source: file or directory it was read from or computed into.
        computed: whether the gallery ran the sweep (False: a stored report).
    """

    report: xr.Dataset
    source: Path
    computed: bool

    def label(self) -> str:
        """Fidelity of the report: estimator, stops per measured point (and how many of
        the design's points are measured, where some are not yet), grid and noise (a
        value that is an axis of the report: "swept")."""
        attrs = self.report.attrs
        stops = np.asarray(self.report["stops"].values).ravel()
        measured = stops[stops > 0]
        n = f"{count_range(measured) if measured.size else 0} stops per point"
        if 0 < measured.size < stops.size:
            n += f" ({measured.size} of {stops.size} points measured)"
        base = attrs.get("base_config", "{}")
        values = {
            "grid.dx": ("dx", f"{float(attrs.get('grid_dx', math.nan)):.4g}"),
            "grid.dt": ("dt", f"{float(attrs.get('grid_dt', math.nan)):.3g}"),
            "geometry.smoothing": (
                "\u03b4",
                f"{_base_value(base, ('geometry', 'smoothing'), math.nan):.4g}",
            ),
            "grid.domain_radius": ("L", f"{_base_value(base, ('grid', 'domain_radius'), 3.0):g}"),
            "noise.sigma": ("\u03c3", f"{_base_value(base, ('noise', 'sigma'), 0.0):g}"),
        }
        swept = {self.report[d].attrs.get("config_key") for d in self.report.dims}
        model = ", ".join(
            f"{symbol} swept" if key in swept else f"{symbol} = {value}"
            for key, (symbol, value) in values.items()
        )
        return (
            f"sweep {attrs.get('sweep', '?')}: {attrs.get('estimator', '?')} estimator, "
            f"{n}; {model}"
        )

    def interval(self) -> str:
        """How the report's 95 % intervals of P were computed, by estimator."""
        report = self.report
        kinds = set(np.unique(report["P_estimator"])) if "P_estimator" in report else set()
        if report.attrs.get("estimator") == "protocol":
            return "Wilson score"
        if kinds == {POOLED}:
            return "Wilson score of the count pooled over both directions (\u0394 = 0)"
        return "two-state chain of the 97.5 % Wilson bounds of P(inv | CCW), P(inv | CW)"


def _base_value(base_json: str, keys: tuple[str, ...], default: float) -> float:
    try:
        node: Any = json.loads(base_json)
        for key in keys:
            node = node[key]
        return float(node)
    except (ValueError, KeyError, TypeError):
        return default


def load_report(path: Path) -> xr.Dataset:
    """A stored report, loaded into memory, with P by the current rule (:mod:`.estimates`).

    A restart or bank report written before the rule (without ``P_estimator``) holds the
    chain value 2ab/(a+b) in P at every Delta: where Delta = 0, P becomes the pooled
    fraction inversions / stops with its Wilson interval, recomputed from the counts,
    and ``P_estimator`` is added (the attribute ``P`` says so).
    """
    with xr.open_dataset(path, engine="h5netcdf") as stored:
        ds = stored.load()
    if "P_estimator" in ds or ds.attrs.get("estimator") not in ("restart", "bank"):
        return ds
    base = json.loads(ds.attrs.get("base_config", "{}"))
    if "asymmetry" in ds.coords:
        delta = ds["asymmetry"]
    else:
        delta = xr.DataArray(float(base.get("geometry", {}).get("asymmetry", 0.0)))
    dims = ds["P"].dims
    chain = (delta != 0).broadcast_like(ds["P"]).transpose(*dims).values
    k = np.asarray(ds["inversions"].transpose(*dims).values, dtype=int)
    n = np.asarray(ds["stops"].transpose(*dims).values, dtype=int)
    pooled = np.where(n > 0, k / np.maximum(n, 1), np.nan)
    bounds = np.vectorize(wilson_interval)(k, n)
    for name, value in (("P", pooled), ("P_low", bounds[0]), ("P_high", bounds[1])):
        new = np.where(chain, ds[name].transpose(*dims).values, value)
        ds[name] = (dims, new, ds[name].attrs)
    ds["P_estimator"] = (
        dims,
        np.where(chain, CHAIN, POOLED),
        {"long_name": VARIABLES["P_estimator"][0]},
    )
    rule = P_RULE["restart"]
    ds["P"].attrs["long_name"] = (
        f"inversion probability ({ds.attrs.get('estimator')} estimator): {rule}"
    )
    ds.attrs["P"] = f"{rule} (P where Delta = 0 recomputed from the counts of an older report)"
    return ds


def stored_reports(name: str, data_dir: Path, grid_dx: float | None = None) -> list[Path]:
    """Stored reports of sweep `name` under `data_dir` (any variant), best fidelity first.

    A report is a NetCDF file whose name (or directory name) is `name` or starts with
    `name` followed by "_" or "-"; the finest grid is preferred, then more stops in all
    (a whole design's partial report, data/NAME.nc, before the report of its last
    subset run that a sweep directory holds).

    Args:
        name: the sweep's name (e.g. "fig5").
        data_dir: where to look (recursively).
        grid_dx: only reports computed at this dx (their ``grid_dx`` attribute), so that a
            coarse fidelity never draws the paper grid's data nor the other way round;
            None: every grid.
    """
    if not data_dir.is_dir():
        return []
    found: list[tuple[tuple[float, float], Path]] = []
    for path in data_dir.rglob("*.nc"):
        label = path.stem if path.stem != "report" else path.parent.name
        if label == name or label.startswith((f"{name}_", f"{name}-")):
            dx, stops = _grid_and_stops(path)
            if grid_dx is None or math.isclose(dx, grid_dx, rel_tol=1e-6):
                found.append(((dx, -stops), path))
            elif math.isinf(dx):
                _logger.warning("%s: unreadable or without grid_dx, not used for %s", path, name)
    return [path for _, path in sorted(found)]


def _grid_and_stops(path: Path) -> tuple[float, float]:
    """dx and the stops in all of a stored report (inf and 0 where it cannot be read)."""
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            return float(ds.attrs.get("grid_dx", math.inf)), float(ds["stops"].sum())
    except (OSError, ValueError, KeyError):
        return math.inf, 0.0


def curve(ds: xr.Dataset, x_dim: str, **fixed: float) -> xr.Dataset:
    """One curve of a report: every dimension but `x_dim` fixed.

    Dimensions of length one are squeezed; others must be given in `fixed` (nearest value).

    Raises:
        ValueError: `x_dim` is missing or another dimension is left free.
    """
    if x_dim not in ds.dims:
        msg = f"report has no dimension {x_dim!r} (dimensions: {', '.join(ds.dims) or 'none'})"
        raise ValueError(msg)
    if fixed:
        ds = ds.sel(fixed, method="nearest")
    extra = [d for d in ds.dims if d != x_dim]
    free = [d for d in extra if ds.sizes[d] > 1]
    if free:
        msg = f"report dimension(s) {', '.join(free)} must be fixed to draw P against {x_dim}"
        raise ValueError(msg)
    return ds.squeeze(extra, drop=False) if extra else ds


PAPER_REPORTS = ("calibration", "predictions", "predictions_no_flow")
"""Stored reports (data/<name>.nc) at the paper's resolution, drawn over the curves."""
_BASE_KEYS = {
    "sigma": "noise.sigma",
    "asymmetry": "geometry.asymmetry",
    "t_stop": "protocol.t_stop",
    "enabled": "flow.enabled",
}


def _base_setting(config: RotorConfig, key: str) -> float:
    section, name = key.split(".")
    return float(getattr(getattr(config, section), name))


def curve_points(
    data_dir: Path,
    x_dim: str,
    reports: tuple[str, ...] = PAPER_REPORTS,
    like: dict[str, Any] | None = None,
    **fixed: float,
) -> xr.Dataset | None:
    """Points of stored reports that lie on one curve: by default the paper-resolution
    reports (:data:`PAPER_REPORTS`), or the named sweeps' reports, e.g. the t_stop = 3
    points of Figs. 5, 7(a) and 7(b) on the curve of Fig. 7(c).

    Only measured points whose runs are all done count (a partial point,
    :func:`pde_rotor.statistics.crossing.partial_points`, is left out).

    Args:
        data_dir: where the reports are (data/ of the repository).
        x_dim: the curve's variable ("t_stop" or "asymmetry").
        reports: names of the reports (data_dir/<name>.nc; missing ones are skipped).
        like: a sweep's base config (overrides of the defaults); if given, a report
            counts only where its model equals this one in every setting but the
            curve's (`x_dim`, `fixed`) and the report's own axes.
        fixed: the curve's other settings by dimension name ("sigma", "asymmetry",
            "t_stop", "enabled" for flow.enabled); a setting that is not an axis of a
            report is read from its base config.

    Returns:
        P, P_low, P_high, stops and the report's name against `x_dim` (sorted), or None
        if no stored report has such points.
    """
    reference = None if like is None else RotorConfig.model_validate(like)
    rows = []
    for name in reports:
        path = data_dir / f"{name}.nc"
        if not path.exists():
            continue
        ds = load_report(path)
        config = RotorConfig.model_validate(json.loads(ds.attrs["base_config"]))
        if reference is not None:
            free = {_BASE_KEYS[d] for d in (x_dim, *fixed, *ds.dims) if d in _BASE_KEYS}
            if physics_differences(config, reference, free):
                continue
        index: dict[str, int] = {}
        for dim, value in fixed.items():
            if dim in ds.dims:
                match = np.isclose(ds[dim].values.astype(float), value, rtol=1e-6, atol=1e-12)
                if not match.any():
                    break
                index[dim] = int(np.argmax(match))
            elif not math.isclose(_base_setting(config, _BASE_KEYS[dim]), value, abs_tol=1e-12):
                break
        else:
            sub = ds.isel(index)
            if x_dim in sub.dims:
                sub = sub.squeeze([d for d in sub.dims if d != x_dim], drop=True)
                xs = sub[x_dim].values.astype(float)
            else:
                xs = np.array([_base_setting(config, _BASE_KEYS[x_dim])])
                sub = sub.squeeze(drop=True).expand_dims(x_dim)
            done = np.isfinite(np.ravel(sub["P"].values)) & ~np.ravel(partial_points(sub))
            for k, x in enumerate(xs):
                if not done[k]:
                    continue
                row = {v: float(np.ravel(sub[v].values)[k]) for v in ("P", "P_low", "P_high")}
                rows.append((float(x), row, int(np.ravel(sub["stops"].values)[k]), name))
    if not rows:
        return None
    rows.sort(key=lambda r: r[0])
    data = {v: (x_dim, np.array([r[1][v] for r in rows])) for v in ("P", "P_low", "P_high")}
    data["stops"] = (x_dim, np.array([r[2] for r in rows]))
    data["report"] = (x_dim, np.array([r[3] for r in rows]))
    return xr.Dataset(data, coords={x_dim: [r[0] for r in rows]})
