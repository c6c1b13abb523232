"""The report of a collective sweep: its stored runs as an xarray Dataset and a table.

Dimensions: the sweep axes, ``sample`` and ``time`` (record k at k x record_interval; a
run that ended early is NaN after its last record); for dish measures also ``r_bin``.
Variables (docs/collective.md defines each):

* per record (axes, sample, time): the measures of
  :func:`pde_rotor.sweep.estimators.collective.collective_result`;
* per run (axes, sample): their time averages after ``settle`` (``mean_<name>``), and for
  ring measures ``gap_mobility``, ``abs_arc_speed`` and ``mode`` (the index into the
  attribute ``modes``); ``ended_early`` (1 where the run ended before t_end);
* per point (axes, r_bin), dish measures: ``g`` pooled over the samples (pairs counted /
  pairs expected of uncorrelated centres) at the bin centres ``r``;
* ``runs_done``, ``runs_expected`` per point.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import xarray as xr

from ..collective.ring import MODES
from .plan import Sweep, dim_names
from .store import read_runs

SERIES = {
    "ring": {
        "angular_speed": ("mean angular velocity of the bodies about the centre", "1/time"),
        "arc_speed": ("mean arc speed r d theta / dt of the bodies", "length/time"),
        "spacing_spread": ("std(gaps) / mean(gaps) of the bodies' angles", "1"),
        "lattice_order": ("|<exp(i N theta_k)>|: 1 when evenly spaced", "1"),
        "cluster_order": ("max over 1 <= m <= N/2 of |<exp(i m theta_k)>|", "1"),
        "clusters": ("the m of cluster_order", "1"),
    },
    "dish": {
        "mean_speed": ("<|U_k|> over the bodies", "length/time"),
        "polar_order": ("|sum U_k / |U_k|| / K", "1"),
        "rotational_order": ("<r_k x U_k / (|r_k| |U_k|)> about the dish's centre", "1"),
    },
}
"""The per-record measures of each kind: long name and units."""
EXTRA = {
    "ring": {
        "abs_arc_speed": ("<|arc speed|> over bodies and records after settle", "length/time"),
        "gap_mobility": ("mean_k std_t(gap_k) / mean gap after settle", "1"),
    },
    "dish": {
        "abs_rotational_order": ("<|rotational_order|> over the records after settle", "1"),
    },
}
"""Per-run averages besides the means of :data:`SERIES`."""


def gather_collective(sweep: Sweep, sweep_dir: str | Path) -> xr.Dataset:
    """Collect the stored runs of a collective `sweep` from `sweep_dir` (no writing)."""
    stored = read_runs(sweep_dir)
    runs = sweep.runs()
    contents = {run.key: stored[run.key]["result"] for run in runs if run.key in stored}
    estimator = sweep.spec.estimator
    interval = estimator.record_interval
    kinds = {c["measures"] for c in contents.values()}
    kind = kinds.pop() if len(kinds) == 1 else _kind(sweep)
    shape, samples = sweep.shape, sweep.spec.samples
    n_time = 1 + max((round(c["t"][-1] / interval) for c in contents.values() if c["t"]), default=0)
    names = dim_names(list(sweep.axes))
    dims = [names[key] for key in sweep.axes]
    coords: dict[str, xr.Variable] = {}
    for key, values in sweep.axes.items():
        if all(isinstance(v, bool) for v in values):
            values = [int(v) for v in values]
        coords[names[key]] = xr.Variable(names[key], values, attrs={"config_key": key})
    coords["sample"] = xr.Variable("sample", np.arange(samples))
    coords["time"] = xr.Variable(
        "time", interval * np.arange(n_time), attrs={"units": "time", "long_name": "time"}
    )
    run_dims, series_dims = [*dims, "sample"], [*dims, "sample", "time"]
    series = {name: np.full((*shape, samples, n_time), np.nan) for name in SERIES[kind]}
    names = [f"mean_{name}" for name in SERIES[kind]] + list(EXTRA[kind])
    per_run = {name: np.full((*shape, samples), np.nan) for name in names}
    mode = np.full((*shape, samples), -1, dtype=np.int64)
    ended = np.full((*shape, samples), -1, dtype=np.int64)
    done = np.zeros(shape, dtype=np.int64)
    expected = np.zeros(shape, dtype=np.int64)
    counts: dict[tuple[int, ...], list[np.ndarray]] = {}
    r_centres: dict[tuple[int, ...], np.ndarray] = {}
    for run in runs:
        expected[run.point] += 1
        result = contents.get(run.key)
        if result is None:
            continue
        done[run.point] += 1
        at = (*run.point, run.sample)
        steps = np.rint(np.asarray(result["t"]) / interval).astype(int)
        for name in SERIES[kind]:
            series[name][at][steps] = result[name]
        summary = result["summary"]
        for name in SERIES[kind]:
            per_run[f"mean_{name}"][at] = summary[name]
        for name in EXTRA[kind]:
            per_run[name][at] = summary[name]
        if kind == "ring":
            mode[at] = summary["mode"]
        ended[at] = int(bool(result["end"]))
        if kind == "dish":
            pooled = counts.setdefault(run.point, [0.0, 0.0])
            pooled[0] = pooled[0] + np.asarray(result["pair_counts"])
            pooled[1] = pooled[1] + np.asarray(result["pair_expected"])
            edges = np.asarray(result["r_edges"])
            r_centres[run.point] = 0.5 * (edges[1:] + edges[:-1])
    data_vars: dict[str, xr.Variable] = {}
    for name, (long_name, units) in SERIES[kind].items():
        attrs = {"long_name": long_name, "units": units}
        data_vars[name] = xr.Variable(series_dims, series[name], attrs=attrs)
        mean_attrs = {"long_name": f"time average after settle of {name}", "units": units}
        data_vars[f"mean_{name}"] = xr.Variable(run_dims, per_run[f"mean_{name}"], mean_attrs)
    for name, (long_name, units) in EXTRA[kind].items():
        attrs = {"long_name": long_name, "units": units}
        data_vars[name] = xr.Variable(run_dims, per_run[name], attrs=attrs)
    if kind == "ring":
        data_vars["mode"] = xr.Variable(
            run_dims,
            mode,
            attrs={"long_name": "collective mode: index into the attribute modes (-1: no run)"},
        )
    data_vars["ended_early"] = xr.Variable(
        run_dims, ended, attrs={"long_name": "1: the run ended before t_end (-1: no run)"}
    )
    if kind == "dish":
        bins = estimator.bins
        g = np.full((*shape, bins), np.nan)
        r = np.full((*shape, bins), np.nan)
        for point, (num, den) in counts.items():
            with np.errstate(invalid="ignore", divide="ignore"):
                g[point] = np.where(den > 0, num / den, np.nan)
            r[point] = r_centres[point]
        g_attrs = {
            "long_name": "pair correlation g(r), pooled over the samples, normalised by the "
            "pair distances of uncorrelated centres in the dish (after settle)",
            "units": "1",
        }
        data_vars["g"] = xr.Variable([*dims, "r_bin"], g, attrs=g_attrs)
        r_attrs = {"long_name": "centre of the bin of r", "units": "length"}
        data_vars["r"] = xr.Variable([*dims, "r_bin"], r, attrs=r_attrs)
    data_vars["runs_done"] = xr.Variable(dims, done, attrs={"long_name": "runs stored"})
    data_vars["runs_expected"] = xr.Variable(
        dims, expected, attrs={"long_name": "runs of the sweep at this point"}
    )
    attrs = {
        "sweep": sweep.spec.name,
        "description": sweep.spec.description,
        "estimator": "collective",
        "measures": kind,
        "estimator_settings": json.dumps(estimator.model_dump(mode="json")),
        "samples_per_point": samples,
        "seed": sweep.spec.seed,
        "modes": ", ".join(MODES),
        "base_config": json.dumps(sweep.base, sort_keys=True),
        "crowd": json.dumps(sweep.spec.crowd.model_dump(mode="json") if sweep.spec.crowd else None),
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _kind(sweep: Sweep) -> str:
    """The measures of a sweep without stored runs: those of its first run."""
    from ..config import RotorConfig

    return sweep.spec.estimator.resolve(RotorConfig.model_validate(sweep.runs()[0].config))


def format_collective_table(ds: xr.Dataset) -> str:
    """One row per point: axis values, the sample means of the run averages, runs done."""
    dims = [d for d in ds["runs_done"].dims]
    kind = ds.attrs["measures"]
    means = [f"mean_{name}" for name in SERIES[kind] if name != "clusters"]
    extra = list(EXTRA[kind])
    header = [*dims, *(m.removeprefix("mean_") for m in means), *extra]
    header += ["modes" if kind == "ring" else "ended early", "runs done"]
    flat = ds.stack(point=dims) if dims else ds.expand_dims(point=[0])
    modes = ds.attrs["modes"].split(", ")
    rows = []
    for i in range(flat.sizes["point"]):
        row = flat.isel(point=i)
        cells = [f"{row[d].item():.6g}" for d in dims]
        for name in [*means, *extra]:
            values = row[name].values
            value = float(np.nanmean(values)) if np.isfinite(values).any() else math.nan
            cells.append("nan" if math.isnan(value) else f"{value:.3g}")
        if kind == "ring":
            found = sorted({modes[m] for m in row["mode"].values if m >= 0})
            cells.append("/".join(found) or "-")
        else:
            cells.append(str(int((row["ended_early"].values == 1).sum())))
        cells.append(f"{int(row['runs_done'])}/{int(row['runs_expected'])}")
        rows.append(cells)
    widths = [max(len(h), *(len(r[k]) for r in rows)) for k, h in enumerate(header)]
    lines = [
        f"{ds.attrs.get('sweep', '')} (collective estimator, {kind} measures; sample means "
        "of each run's time averages, docs/collective.md)",
        "  ".join(h.rjust(w) for h, w in zip(header, widths, strict=True)),
    ]
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
    return "\n".join(lines)
