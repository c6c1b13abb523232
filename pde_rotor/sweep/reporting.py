"""The report of a sweep: its stored runs gathered into an xarray Dataset and a table.

Coordinates are the sweep axes; every variable carries its definition in ``long_name``
(the definitions of P: :mod:`pde_rotor.sweep.estimates`).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..config import RotorConfig
from ..io.output import write_netcdf_atomic
from ..statistics.proportions import CONFIDENCE
from .estimates import CHAIN, P_DEFINITIONS, POOLED, inverted, mcnemar_p, point_statistics
from .plan import Run, Sweep, dim_names
from .store import REPORT_FILE, read_runs

P_RULE = {
    "protocol": "inversions / stops of all protocol runs (the paper's inversions / M), pooled",
    "restart": (
        f"where Delta = 0: {P_DEFINITIONS[POOLED]}; where Delta != 0: {P_DEFINITIONS[CHAIN]}; "
        "P_estimator says which"
    ),
}
"""What P is, by estimator (the bank estimator's rule is the restart one's)."""

VARIABLES: dict[str, tuple[str, str]] = {
    "P": ("inversion probability", "1"),  # + P_RULE[estimator] in gather()
    "P_low": ("lower bound of the 95 % interval of P", "1"),
    "P_high": ("upper bound of the 95 % interval of P", "1"),
    "P_estimator": (
        f"definition of P at this point: {POOLED} = {P_DEFINITIONS[POOLED]}; "
        f"{CHAIN} = {P_DEFINITIONS[CHAIN]}",
        "1",
    ),
    "P_pooled": (P_DEFINITIONS[POOLED].split(" (")[0], "1"),
    "P_pooled_low": ("Wilson 95 % lower bound of P_pooled", "1"),
    "P_pooled_high": ("Wilson 95 % upper bound of P_pooled", "1"),
    "P_chain": ("two-state chain 2ab/(a+b), a = P_ccw, b = P_cw", "1"),
    "P_chain_low": ("2ab/(a+b) at the 97.5 % Wilson lower bounds of a and b", "1"),
    "P_chain_high": ("2ab/(a+b) at the 97.5 % Wilson upper bounds of a and b", "1"),
    "inversions": ("inversions counted, both directions", "1"),
    "stops": ("stop-and-release operations counted, both directions", "1"),
    "P_ccw": ("P(inversion | CCW rotation before the stop)", "1"),
    "P_ccw_low": ("Wilson 95 % lower bound of P_ccw", "1"),
    "P_ccw_high": ("Wilson 95 % upper bound of P_ccw", "1"),
    "inversions_ccw": ("inversions from CCW rotation", "1"),
    "stops_ccw": ("stops from CCW rotation", "1"),
    "P_cw": ("P(inversion | CW rotation before the stop)", "1"),
    "P_cw_low": ("Wilson 95 % lower bound of P_cw", "1"),
    "P_cw_high": ("Wilson 95 % upper bound of P_cw", "1"),
    "inversions_cw": ("inversions from CW rotation", "1"),
    "stops_cw": ("stops from CW rotation", "1"),
    "pi_ccw": ("stationary fraction of CCW rotation of the two-state chain", "1"),
    "mean_abs_omega": ("mean |omega| just before the stops", "1/time"),
    "uncommitted": ("restarts without a committed direction at the release cap", "1"),
    "mean_commit_time": ("mean release time until |omega| >= commit_fraction |omega0|", "time"),
    "runs_done": ("runs with a stored result", "1"),
    "runs_expected": ("runs of the sweep at this point", "1"),
}
"""Every variable of a report: long name and units."""
_COUNTS = ("P_estimator", "inversions", "stops", "runs_done", "runs_expected", "uncommitted")


def paired_axes(sweep: Sweep) -> list[str]:
    """Axes whose values share their stops (a paired design): noise axes of a bank sweep."""
    if sweep.spec.estimator.kind != "bank":
        return []
    return [key for key in sweep.axes if key.startswith("noise.")]


def _mcnemar(
    sweep: Sweep, key: str, outcomes: dict[tuple[int, ...], dict[Any, bool]]
) -> np.ndarray:
    """McNemar p-values of every point against the points that differ only along `key`."""
    axis = list(sweep.axes).index(key)
    n = sweep.shape[axis]
    values = np.full((*sweep.shape, n), np.nan)
    for index, outcome in outcomes.items():
        for ref in range(n):
            other = (*index[:axis], ref, *index[axis + 1 :])
            values[(*index, ref)] = mcnemar_p(outcome, outcomes.get(other, {}))
    return values


def _grid_value(sweep: Sweep, name: str) -> float:
    """The sweep's grid.`name` (dx or dt): its axis's value where that axis has one, NaN
    where it has several (the report's coordinate then says), else the base config's."""
    key = f"grid.{name}"
    if key in sweep.axes:
        values = sweep.axes[key]
        return float(values[0]) if len(values) == 1 else math.nan
    return float(sweep.base.get("grid", {}).get(name, getattr(RotorConfig().grid, name)))


def gather(sweep: Sweep, sweep_dir: str | Path) -> xr.Dataset:
    """Collect the stored runs of `sweep` from `sweep_dir` into a Dataset (no writing).

    Coordinates are the sweep axes (dimension = last part of the dotted key, the full
    key in the attribute ``config_key``); a sweep without axes gives scalar variables.
    A collective sweep's report is :func:`.collective_report.gather_collective`'s.
    A bank sweep with a noise axis also gets ``mcnemar_p_<dim>``: the paired test of
    every point against each value of that axis.
    """
    if sweep.spec.estimator.kind == "collective":
        from .collective_report import gather_collective

        return gather_collective(sweep, sweep_dir)
    sweep_dir = Path(sweep_dir)
    keys = list(sweep.axes)
    dims = dim_names(keys)
    by_point: dict[tuple[int, ...], list[Run]] = {}
    for run in sweep.runs():
        by_point.setdefault(run.point, []).append(run)
    stored = read_runs(sweep_dir)
    kind = sweep.spec.estimator.kind
    arrays = {name: np.full(sweep.shape, np.nan) for name in VARIABLES}
    outcomes: dict[tuple[int, ...], dict[Any, bool]] = {}
    for index, runs in by_point.items():
        contents = [stored[run.key] for run in runs if run.key in stored]
        asymmetry = float(runs[0].config["geometry"]["asymmetry"])
        stats = point_statistics(kind, asymmetry, contents, len(runs))
        for name, value in stats.items():
            arrays[name][index] = value
        if kind == "bank":
            outcomes[index] = {(c["direction"], c["sample"]): inverted(c) for c in contents}
    coords = {}
    for key in keys:
        values = sweep.axes[key]
        if all(isinstance(v, bool) for v in values):
            values = [int(v) for v in values]
        coords[dims[key]] = xr.Variable(dims[key], values, attrs={"config_key": key})
    dim_list = [dims[k] for k in keys]
    rule = P_RULE["protocol" if kind == "protocol" else "restart"]
    data_vars = {}
    for name, (long_name, units) in VARIABLES.items():
        if name == "P":
            long_name = f"{long_name} ({kind} estimator): {rule}"
        arr = arrays[name]
        if name in _COUNTS or name.startswith(("inversions_", "stops_")):
            arr = arr.astype(np.int64)
        data_vars[name] = xr.Variable(dim_list, arr, attrs={"long_name": long_name, "units": units})
    paired = paired_axes(sweep)
    for key in paired:
        dim = dims[key]
        coords[f"{dim}_ref"] = xr.Variable(f"{dim}_ref", coords[dim].values)
        data_vars[f"mcnemar_p_{dim}"] = xr.Variable(
            [*dim_list, f"{dim}_ref"],
            _mcnemar(sweep, key, outcomes),
            attrs={
                "long_name": f"McNemar exact p-value of P here against P at {dim} = {dim}_ref "
                f"(paired design: the {dim} values share their stops; two-sided binomial "
                "test of the discordant pairs)",
                "units": "1",
            },
        )
    spec = sweep.spec
    attrs = {
        "sweep": spec.name,
        "description": spec.description,
        "estimator": kind,
        "estimator_settings": json.dumps(spec.estimator.model_dump(mode="json")),
        "samples_per_point": spec.samples,
        "seed": spec.seed,
        "confidence": CONFIDENCE,
        "P": rule,
        "design": (
            f"paired: the values of {', '.join(dims[k] for k in paired)} share each stop; "
            "compare them with mcnemar_p_*, not with the intervals"
            if paired
            else "independent: every run has its own stop, at a uniformly random angle"
        ),
        "base_config": json.dumps(sweep.base, sort_keys=True),
        "grid_dx": _grid_value(sweep, "dx"),
        "grid_dt": _grid_value(sweep, "dt"),
        # the scheme the runs used, whether or not the base names it: a report stays
        # readable against the right decision table when the default changes
        "scheme": RotorConfig.model_validate(sweep.base).numerics.scheme,
        "paper": "Koyano, Kitahata, Nakata, Gorecki, Chaos 30 (2020), Figs. 5, 7, 8, 9",
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def report(
    sweep_dir: str | Path,
    out: str | Path | None = None,
    echo: bool = True,
    sweep: Sweep | None = None,
) -> xr.Dataset:
    """Gather a sweep directory into a Dataset, write it as NetCDF and print a table.

    Args:
        sweep_dir: directory written by :func:`~pde_rotor.sweep.run_sweep` (holds
            sweep.yaml and runs/).
        out: NetCDF path (default: SWEEP_DIR/report.nc); written atomically with the
            h5netcdf engine.
        echo: print the table (:func:`format_table`).
        sweep: the design to report (default: SWEEP_DIR/sweep.yaml, which a run of a
            subset of it leaves whole); points without finished runs are NaN.
    """
    sweep_dir = Path(sweep_dir)
    ds = gather(sweep if sweep is not None else Sweep.load(sweep_dir), sweep_dir)
    target = Path(out) if out is not None else sweep_dir / REPORT_FILE
    target.parent.mkdir(parents=True, exist_ok=True)
    write_netcdf_atomic(ds, target)
    if echo:
        print(format_table(ds))
    return ds


LEGENDS = {
    "protocol": (
        "P: inversions / stops of the paper's protocol runs (inversions / M), 95 % interval;",
        "from CCW, from CW: inverted / stops by the direction before the stop.",
    ),
    "restart": (
        "P: probability that a stop inverts the rotor, with its 95 % interval; from CCW,",
        "from CW: inverted / stops by the direction before the stop. At Delta = 0 P pools",
        "both directions, else P = 2ab/(a+b) of the two (pde-rotor report --explain).",
    ),
}
"""The legend lines of :func:`format_table`, by estimator (bank: as restart)."""

GLOSSARY = """\
Terms of the sweep reports (docs/statistics.md has the derivations):
  stop            the forced stop of duration t_stop, then a release.
  inverted        the rotor turns the other way after the release than before the stop:
                  the sign of omega when |omega| first reaches commit_fraction times
                  |omega before the stop| (the release has "committed"); a release that
                  never commits is not an inversion.
  from CCW / CW   the stops that began with the rotor turning counter-clockwise /
                  clockwise; with an asymmetry (Delta != 0) the two differ.
  P               at Delta = 0: inversions / stops of both directions (Wilson interval);
                  at Delta != 0: 2ab/(a+b), a and b the fractions from CCW and CW, the
                  fraction of inversions of the two-state chain they define (the paper's
                  protocol of repeated stops); interval from the 97.5 % bounds of a and b.
  estimator       protocol: the paper's stop-and-release runs, M cycles each; restart:
                  independent single stops, each branched from a steadily turning rotor
                  at a random angle; bank: restarts whose stop is shared by several noise
                  intensities (a paired design, compared by McNemar's test).
  Dw              the angular-velocity diffusion of the noise, Dw = (sigma / I)^2.
  mean |omega|    the mean |omega| just before the stops: the steady rotation."""
"""What ``pde-rotor report --explain`` prints."""


def _attr_text(ds: xr.Dataset, name: str) -> str:
    """A grid attribute of a report for its table's header: ``swept`` where it is NaN."""
    value = ds.attrs.get(name)
    if value is None:
        return "unknown"
    return "swept" if math.isnan(float(value)) else f"{float(value):g}"


def format_table(ds: xr.Dataset) -> str:
    """One row per point: axis values, P and its 95 % interval, the inverted stops by
    starting direction, mean |omega| and the runs done; for a paired design the McNemar
    p-value against the previous value of each paired axis."""
    kind = str(ds.attrs.get("estimator", ""))
    if kind == "collective":
        from .collective_report import format_collective_table

        return format_collective_table(ds)
    dims = [d for d in ds.sizes if not d.endswith("_ref")]
    paired = [d for d in dims if f"mcnemar_p_{d}" in ds]
    header = [*dims, "P", "95% interval", "from CCW", "from CW", "mean |omega|", "runs done"]
    header += [f"McNemar p vs previous {d}" for d in paired]
    flat = ds.stack(point=dims) if dims else ds.expand_dims(point=[0])
    rows = []
    for i in range(flat.sizes["point"]):
        row = flat.isel(point=i)

        def fmt(name: str, row: xr.Dataset = row) -> str:
            value = float(row[name])
            return "nan" if math.isnan(value) else f"{value:.3f}"

        cells = [f"{row[d].item():.6g}" for d in dims]
        cells += [
            fmt("P"),
            f"[{fmt('P_low')}, {fmt('P_high')}]",
            f"{int(row['inversions_ccw'])}/{int(row['stops_ccw'])}",
            f"{int(row['inversions_cw'])}/{int(row['stops_cw'])}",
            f"{float(row['mean_abs_omega']):.1f}",
            f"{int(row['runs_done'])}/{int(row['runs_expected'])}",
        ]
        for d in paired:
            at = int(np.flatnonzero(ds[d].values == row[d].item())[0])
            p = float(row[f"mcnemar_p_{d}"].isel({f"{d}_ref": at - 1})) if at else math.nan
            cells.append("-" if math.isnan(p) else f"{p:.3g}")
        rows.append(cells)
    widths = [max(len(h), *(len(r[k]) for r in rows)) for k, h in enumerate(header)]
    lines = [
        f"{ds.attrs.get('sweep', '')} ({kind} estimator, "
        f"dx = {_attr_text(ds, 'grid_dx')}, dt = {_attr_text(ds, 'grid_dt')})",
        *LEGENDS["protocol" if kind == "protocol" else "restart"],
    ]
    if paired:
        lines.append(f"design: {ds.attrs['design']}")
    lines.append("  ".join(h.rjust(w) for h, w in zip(header, widths, strict=True)))
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
    return "\n".join(lines)
