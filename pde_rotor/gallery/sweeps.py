"""The sweeps of the gallery's probability figures (Figs. 5, 7, 8, 9 and the convergence
page): which sweep file a fidelity runs, the stored reports under data/ that go before
running anything, and the drawing of P curves, crossings and paper-resolution points.

Paths and the dask scheduler are read from :mod:`.common` when a function runs (tests
point ``common.DATA`` and ``common.SWEEPS`` elsewhere).
"""

from __future__ import annotations

import json
import logging
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from pde_rotor.config import PAPER_SCHEME_SIGMA, set_key
from pde_rotor.paper import (
    DECAY_STOP,
    NO_FLOW_FAVOURED,
    ONSET_ASYMMETRY,
    ONSET_STOP,
    PLATEAU,
    PLATEAU_ASYMMETRY,
)
from pde_rotor.plotting.figures import (
    count_range,
    draw_conditionals,
    errorbar_p,
    probability_axes,
)
from pde_rotor.statistics.proportions import chain_probability
from pde_rotor.sweep import stored
from pde_rotor.sweep.stored import SweepData, curve
from pde_rotor.units import TIME_UNITS

from . import common
from .common import CPU_BACKEND, Fidelity, fidelity

__all__ = [
    "ASYMMETRY_LABEL",
    "MODEL_LABEL",
    "PAPER_CLAIMS",
    "STOP_LABEL",
    "curve",
    "draw_conditionals",
    "draw_crossing",
    "draw_model",
    "draw_paper_claims",
    "draw_paper_points",
    "draw_shared_points",
    "errorbar_p",
    "print_points",
    "probability_axes",
    "probability_footer",
    "sweep_data",
]

_logger = logging.getLogger("gallery")


def sweep_file(name: str, fid: Fidelity) -> Path:
    """The sweep specification configs/sweeps/<name><variant>.yaml for this fidelity.

    Raises:
        FileNotFoundError: the statistics module provides no such sweep.
    """
    path = common.SWEEPS / f"{name}{fid.sweep_variant}.yaml"
    if not path.exists():
        msg = f"{path} not found: the sweeps of the probability figures live in {common.SWEEPS}"
        raise FileNotFoundError(msg)
    return path


def tiny_sweep(spec_path: Path, work: Path) -> Any:
    """A smoke-test version of a sweep file: tiny domain, two values per axis, 1 sample.

    The base, estimator kind, axes keys and seed are those of the file; only sizes and
    times shrink, so the tiny run exercises the same code path as the real one.
    """
    import yaml

    from pde_rotor.sweep import Sweep, SweepSpec

    data = yaml.safe_load(spec_path.read_text(encoding="utf-8"))
    spec = SweepSpec.model_validate(data)
    sweep = Sweep.from_spec(spec, root=spec_path.parent)
    tiny = fidelity("tiny")
    base = dict(sweep.base)
    for text in tiny.grid:
        key, value = text.split("=")
        set_key(base, key, float(value))
    set_key(base, "protocol.t_ini", 1.0)
    set_key(base, "protocol.t_release", 1.0)
    set_key(base, "protocol.cycles", 2)
    axes = {}
    for key, values in sweep.axes.items():
        picked = [values[0], values[-1]] if len(values) > 1 else list(values)
        if key == "protocol.t_stop":  # short stops on the tiny time scale
            picked = [0.4, 0.8][: len(picked)]
        axes[key] = picked
    estimator = spec.estimator.model_dump(mode="json")
    if estimator.get("kind") == "restart":
        estimator.update(warmup=2.0, release_cap=1.6, check_interval=0.04)
    new = SweepSpec.model_validate(
        {
            "name": f"{spec.name}_tiny",
            "base": base,
            "axes": axes,
            "estimator": estimator,
            "samples": 1,
            "seed": spec.seed,
        }
    )
    return Sweep.from_spec(new)


def stored_reports(name: str, fid: Fidelity) -> list[Path]:
    """Stored reports of sweep `name` under data/ on the grid of the sweep file that
    `fid` runs (:func:`sweep_file`), best first
    (:func:`pde_rotor.sweep.stored.stored_reports`): the full gallery draws the paper
    grid's reports, ``--quick`` the coarse ones."""
    from pde_rotor.sweep import base_config

    grid_dx = base_config(sweep_file(name, fid)).grid.dx
    return stored.stored_reports(name, common.DATA, grid_dx)


def paper_points(x_dim: str, **fixed: float) -> xr.Dataset | None:
    """The paper-resolution points of data/ on one curve
    (:func:`pde_rotor.sweep.stored.curve_points`)."""
    return stored.curve_points(common.DATA, x_dim, **fixed)


def sweep_data(name: str, fid: Fidelity, out: Path) -> SweepData:
    """The report of sweep `name` (e.g. "fig5") at fidelity `fid`.

    * full and quick: a stored report from data/ on the grid of this fidelity's sweep
      file if there is one (:func:`stored_reports`; the footer names it); otherwise the
      sweep configs/sweeps/<name>.yaml
      (full) or <name>_quick.yaml (quick, with at most ``fid.sweep_samples`` restarts per
      direction and point) is run through :func:`pde_rotor.sweep.run_sweep` into
      data/sweeps/<file stem> (resumable: a rerun continues where it stopped; the
      directory ``pde-rotor sweep`` uses by default) and its report is written there;
    * tiny: a shrunken copy of the quick sweep (:func:`tiny_sweep`) run into
      `out`/sweeps/.
    """
    from pde_rotor.sweep import REPORT_FILE, report, run_sweep

    if not fid.is_tiny:
        for path in stored_reports(name, fid):
            _logger.info("%s: stored report %s", name, path)
            return SweepData(stored.load_report(path), path, computed=False)
    spec_path = sweep_file(name, fid)
    if fid.is_tiny:
        sweep: Any = tiny_sweep(spec_path, out)
        sweep_dir = out / "sweeps" / f"{name}_tiny"
        workers = 1
    else:
        from pde_rotor.sweep import Sweep

        sweep = Sweep.load(spec_path)
        if fid.sweep_samples is not None and sweep.spec.samples > fid.sweep_samples:
            fewer = sweep.spec.model_copy(update={"samples": fid.sweep_samples})
            sweep = Sweep.from_spec(fewer)
        sweep_dir = common.SWEEP_RUNS / spec_path.stem
        workers = None
    _logger.info("%s: running sweep %s into %s", name, spec_path, sweep_dir)
    outcome = run_sweep(
        sweep, sweep_dir, scheduler=common.SCHEDULER, workers=workers, progress=not fid.is_tiny
    )
    if outcome.failed:
        key, message = outcome.failed[0]
        msg = f"sweep {spec_path}: {len(outcome.failed)} runs failed, e.g. {key}: {message}"
        raise RuntimeError(msg)
    ds = report(sweep_dir, echo=not fid.is_tiny)
    return SweepData(ds, sweep_dir / REPORT_FILE, computed=True)


def print_points(prefix: str, x_name: str, x: np.ndarray, ds: xr.Dataset) -> None:
    """Print ``PREFIX X_NAME = x: P = p [lo, hi] (n stops)`` for every point of a 1-D curve."""
    for xv, p, lo, hi, n in zip(
        x, ds["P"].values, ds["P_low"].values, ds["P_high"].values, ds["stops"].values, strict=True
    ):
        print(f"{prefix}{x_name} = {xv:g}: P = {p:.3f} [{lo:.3f}, {hi:.3f}] ({int(n)} stops)")


def draw_crossing(ax: Any, prefix: str, ds: xr.Dataset, level: float, name: str) -> str:
    """Mark where the curve `ds` (P against t_stop) crosses `level`: the estimate and its
    95 % interval (:func:`pde_rotor.statistics.crossing.report_crossing`) as a horizontal bar at the
    level, open ends drawn to the curve's last point and dashed. Prints and returns the
    line ``PREFIX NAME: P = level at t_stop = ... [..., ...]``; draws nothing where the
    curve has fewer than two complete points (partial points, whose runs are not all
    done, are left out) or does not cross."""
    from pde_rotor.statistics.crossing import report_crossing

    measured = ds.where(np.isfinite(ds["P"]), drop=True)
    try:
        found = report_crossing(measured, level)
    except ValueError:
        return ""
    line = f"{prefix}{name}: {found.describe()}"
    print(line)
    if found.value is None:
        return line
    t = measured["t_stop"].values
    low = t.min() if found.low is None else found.low
    high = t.max() if found.high is None else found.high
    ax.hlines(level, low, high, color="k", lw=2.5, alpha=0.5, zorder=3)
    for end, is_open, reach in ((low, found.low is None, -0.1), (high, found.high is None, 0.1)):
        if is_open:
            ax.hlines(level, end, end + reach, color="k", ls=":")
    low_text = "open" if found.low is None else f"{found.low:.3g}"
    high_text = "open" if found.high is None else f"{found.high:.3g}"
    label = f"{name}: P = {level:g} at t_stop = {found.value:.3g} [{low_text}, {high_text}]"
    ax.plot([found.value], [level], "kD", ms=6, zorder=4, label=label)
    return line


STOP_LABEL = f"stop duration t_stop [{TIME_UNITS}]"
"""Axis label of t_stop."""
ASYMMETRY_LABEL = "asymmetry \u0394 [rad]"
"""Axis label of Delta."""


def probability_footer(fid: Fidelity, data: SweepData) -> str:
    """Footer of a probability figure: the report's fidelity and where it came from."""
    where = "computed now" if data.computed else f"stored: {_relative(data.source)}"
    return (
        f"pde_rotor, {fid.name} run of the gallery; {data.label()}; {where}; "
        f"95 % interval: {data.interval()}; backend {CPU_BACKEND}"
    )


@dataclass(frozen=True)
class PaperClaim:
    """A value the paper states in words for one of its probability figures.

    Attributes:
        text: the statement, as the legend gives it after "paper: ".
        level: the stated P (a horizontal line), or None.
        at: the stated t_stop or Delta (a vertical line), or None; with `level`, a star at
            (at, level).
        asymmetry: the curve of a multi-curve figure it belongs to (Fig. 8), or None.
    """

    text: str
    level: float | None = None
    at: float | None = None
    asymmetry: float | None = None


_CHAIN_NO_FLOW = chain_probability(NO_FLOW_FAVOURED, 1 - NO_FLOW_FAVOURED)
PAPER_CLAIMS: dict[str, tuple[PaperClaim, ...]] = {
    "fig5": (
        PaperClaim(f"P decays near t_stop \u2248 {DECAY_STOP:g}", at=DECAY_STOP),
        PaperClaim("\u2192 0.5 for long stops", level=0.5),
    ),
    "fig7a": (
        PaperClaim(f"P starts to decay near t_stop \u2248 {ONSET_STOP:g}", at=ONSET_STOP),
        PaperClaim("\u2192 0 for long stops", level=0.0),
    ),
    "fig7b": (PaperClaim(f"long-stop plateau \u2248 {PLATEAU:g} (experiment)", level=PLATEAU),),
    "fig7c": (
        PaperClaim("0.5 at \u0394 = 0", level=0.5, at=0.0),
        PaperClaim("\u2192 0 as \u0394 grows", level=0.0),
    ),
    "fig8": (
        PaperClaim("\u0394 = 0 random", level=0.5, asymmetry=0.0),
        PaperClaim(
            f"\u0394 = {PLATEAU_ASYMMETRY:g} favourable w.p. {NO_FLOW_FAVOURED:g}, "
            f"P = 2ab/(a+b) = {_CHAIN_NO_FLOW:.2f}",
            level=_CHAIN_NO_FLOW,
            asymmetry=PLATEAU_ASYMMETRY,
        ),
        PaperClaim(
            f"\u0394 = {ONSET_ASYMMETRY:g} always favourable", level=0.0, asymmetry=ONSET_ASYMMETRY
        ),
    ),
}
"""The values the paper states for Figs. 5, 7 and 8 (its text; its figures have no
tabulated data), by sweep name: every probability figure marks them."""


def draw_paper_claims(
    ax: Any, sweep: str, asymmetry: float | None = None, color: str = "0.35"
) -> list[str]:
    """Mark the paper's stated values of `sweep` (:data:`PAPER_CLAIMS`) in grey: a
    dash-dotted line at a stated P, a dashed one at a stated t_stop or Delta, a star where
    both are stated. With `asymmetry`, only that curve's claims (Fig. 8).

    Returns:
        The statements drawn.
    """
    drawn = []
    for claim in PAPER_CLAIMS[sweep]:
        if asymmetry is not None and (
            claim.asymmetry is None or not math.isclose(claim.asymmetry, asymmetry, abs_tol=1e-12)
        ):
            continue
        label = f"paper: {claim.text}"
        if claim.level is not None and claim.at is not None:
            ax.plot(claim.at, claim.level, "*", color=color, mec="k", ms=13, zorder=6, label=label)
        elif claim.level is not None:
            ax.axhline(claim.level, color=color, lw=1.1, ls="-.", zorder=1, label=label)
        elif claim.at is not None:
            ax.axvline(claim.at, color=color, lw=1.1, ls="--", zorder=1, label=label)
        drawn.append(claim.text)
    return drawn


def draw_paper_points(
    ax: Any, prefix: str, x_dim: str, style: dict[str, Any] | None = None, **fixed: float
) -> str:
    """Draw the paper-resolution points of one curve (diamonds) and print them.

    The stored reports are of the ``paper`` scheme; the noise is the one calibrated
    on it, :data:`pde_rotor.config.PAPER_SCHEME_SIGMA`, unless `fixed` names sigma.

    Args:
        ax: the axes.
        prefix: start of the printed lines.
        x_dim: the curve's variable.
        style: errorbar keywords replacing the default black-and-gold diamonds.
        fixed: the curve's other settings (see :func:`paper_points`).

    Returns:
        A footer line naming their fidelity, or "" if there are none.
    """
    fixed.setdefault("sigma", PAPER_SCHEME_SIGMA)
    pts = paper_points(x_dim, **fixed)
    if pts is None:
        return ""
    kwargs: dict[str, Any] = {
        "fmt": "D",
        "color": "k",
        "mfc": "gold",
        "ms": 7,
        "zorder": 5,
        "label": f"paper resolution, paper scheme, \u03c3 = {fixed['sigma']:g}",
    }
    kwargs.update(style or {})
    files = _draw_points(ax, f"{prefix}paper resolution: ", x_dim, pts, kwargs)
    return (
        f"Diamonds: paper resolution dx = \u03b4 = 0.025, dt = 1e-4, paper scheme (lattice "
        f"torque), bank estimator, \u03c3 = {fixed['sigma']:g}, "
        f"{count_range(pts['stops'].values)} stops per point; stored: {files}"
    )


def draw_shared_points(
    ax: Any, prefix: str, x_dim: str, sweeps: tuple[str, ...], like: str, **fixed: float
) -> str:
    """Draw the points that other sweeps measured on this curve (squares) and print them.

    Fig. 7(c) (P against Delta at t_stop = 3) shares its points at Delta = 0, 2e-5 and
    1e-4 with the t_stop curves of Figs. 5, 7(a) and 7(b): their stored reports
    (data/<sweep>.nc) give them where they hold the same model as the full-fidelity
    sweep `like` (same grid, scheme and noise; :func:`pde_rotor.sweep.stored.curve_points`),
    so the curve's sweep need not measure them again.

    Args:
        ax: the axes.
        prefix: start of the printed lines.
        x_dim: the curve's variable.
        sweeps: names of the sweeps whose reports may hold points of the curve.
        like: name of the curve's own sweep (configs/sweeps/<like>.yaml).
        fixed: the curve's other settings (e.g. ``t_stop=3.0``).

    Returns:
        A footer line naming the reports, or "" if none holds such points.
    """
    from pde_rotor.sweep.plan import read_spec, resolve_base

    base = resolve_base(*read_spec(sweep_file(like, fidelity("full"))))
    pts = stored.curve_points(common.DATA, x_dim, sweeps, like=base, **fixed)
    if pts is None:
        return ""
    setting = ", ".join(f"{k} = {v:g}" for k, v in fixed.items())
    names = ", ".join(sorted(set(pts["report"].values.tolist())))
    kwargs = {"fmt": "s", "color": "tab:green", "mfc": "w", "mew": 1.5, "ms": 9, "zorder": 4}
    kwargs["label"] = f"P (95 % CI) from sweeps {names}"
    files = _draw_points(ax, f"{prefix}from other sweeps: ", x_dim, pts, kwargs)
    return (
        f"Squares: the {setting} points of sweeps {names}, at the model of {like} "
        f"({count_range(pts['stops'].values)} stops per point); stored: {files}"
    )


MODEL_POINTS = 200
"""Points of a drawn model curve."""
MODEL_LABEL = "decision model"
"""Legend entry of the model's dashed curves."""


def draw_model(
    ax: Any,
    prefix: str,
    ds: xr.Dataset,
    x_dim: str,
    color: str,
    span: tuple[float, float] | None = None,
    label: str | None = MODEL_LABEL,
) -> str:
    """Draw the decision model's P along the curve `ds` as a dashed line.

    The table is the one of data/decision/ that holds the curve's model
    (:func:`pde_rotor.decision.check.table_for`: same grid, scheme, flow and smoothing);
    the noise and the curve's fixed t_stop or Delta are those of the report. The line
    is a prediction from the noise-free stop curves, not a fit to the points. Nothing
    is drawn for a curve of another model (the quick coarse grid).

    Args:
        ax: the axes.
        prefix: start of the printed line.
        ds: the curve (:func:`curve` of a report).
        x_dim: its variable.
        color: the line's colour.
        span: the range of `x_dim` drawn; default: that of the measured points (at
            least two).
        label: the legend entry (None: none, for a figure that keys several model
            lines once).

    Returns:
        A footer line naming the table, or "" if none holds the curve's model.
    """
    from pde_rotor.config import RotorConfig
    from pde_rotor.decision.check import table_for
    from pde_rotor.decision.map import model_curve

    found = table_for(ds, common.DATA / "decision")
    measured = ds[x_dim].values[np.isfinite(ds["P"].values)]
    if found is None or (span is None and measured.size < 2):
        return ""
    path, table = found
    config = RotorConfig.model_validate(json.loads(ds.attrs.get("base_config", "{}")))
    settings = {"t_stop": config.protocol.t_stop, "asymmetry": config.geometry.asymmetry}
    settings.update({k: float(ds[k]) for k in settings if k in ds.coords and k != x_dim})
    sigma = config.noise.sigma
    low, high = span or (measured.min(), measured.max())
    if x_dim == "t_stop":
        low, high = max(low, 0.0), min(high, table.t_max)
    x = np.linspace(low, high, MODEL_POINTS)
    fixed = {k: v for k, v in settings.items() if k != x_dim}
    p = model_curve(table, x_dim, x, sigma, **fixed)
    ax.plot(x, p, "--", color=color, lw=1.2, alpha=0.8, label=label)
    name = _relative(path)
    print(f"{prefix}decision model {name}: P = {p[0]:.3f} ... {p[-1]:.3f} over {x_dim} = "
          f"{low:g} ... {high:g}")  # fmt: skip
    return (
        f"Dashed: the decision model ({name}: noise-free stop curves, λ = "
        f"{table.growth_rate:.3g}) at \u03c3 = {sigma:g}, predicted, not fitted to the points"
    )


def _draw_points(ax: Any, prefix: str, x_dim: str, pts: xr.Dataset, style: dict[str, Any]) -> str:
    """Draw and print the points of :func:`pde_rotor.sweep.stored.curve_points`; return
    their report files, comma-separated."""
    x = pts[x_dim].values
    errorbar_p(ax, x, pts, **style)
    print_points(prefix, x_dim, x, pts)
    return ", ".join(f"data/{name}.nc" for name in sorted(set(pts["report"].values.tolist())))


def _relative(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(common.ROOT))
    except ValueError:
        return str(path)
