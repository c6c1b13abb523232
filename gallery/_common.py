"""Shared helpers of the gallery scripts: fidelities, configs, sweeps, saving and captions.

Every gallery script reproduces one figure of Koyano, Kitahata, Nakata & Gorecki, Chaos 30
(2020) (or adds a page the paper does not have) at one of three fidelities:

* ``full`` (default): the paper's resolution from configs/ (dx = delta = 0.025,
  dt = 1e-4, domain radius 3) and the paper's protocol (t_ini = t_release = 10, M = 100);
* ``quick`` (``--quick``): the coarse grid of configs/quickstart.yaml (dx = delta = 0.05,
  dt = 4e-4) and short protocols, so that all figures together run in minutes;
* ``tiny`` (``--tiny``): the coarse grid on a small domain (radius 1.75) with very short
  times, only to prove in CI that a script runs end to end; its images mean nothing.

Figures are written as PNG and PDF to gallery/output/ (or ``--out``); every figure carries
a footer that states the fidelity it was computed at (dx, dt, delta, samples, backend).
"""

from __future__ import annotations

import argparse
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from pde_rotor.config import (
    PAPER_SCHEME_SIGMA,
    RotorConfig,
    load_config,
    read_config_data,
    set_key,
)
from pde_rotor.figures import (
    FOOTER_FONTSIZE,
    add_footer,
    count_range,
    draw_conditionals,
    errorbar_p,
    format_p,
    grid_label,
    new_figure,
    probability_axes,
    wilson_text,
)
from pde_rotor.figures import save_figure as save
from pde_rotor.sweep import stored
from pde_rotor.sweep.estimates import POOLED
from pde_rotor.sweep.stored import PAPER_REPORTS, SweepData, curve
from pde_rotor.units import TIME_UNITS

__all__ = [
    "ASYMMETRY_LABEL",
    "FOOTER_FONTSIZE",
    "PAPER_REPORTS",
    "STOP_LABEL",
    "SweepData",
    "add_footer",
    "count_range",
    "curve",
    "draw_conditionals",
    "draw_crossing",
    "draw_paper_points",
    "errorbar_p",
    "fidelity_label",
    "format_p",
    "grid_label",
    "new_figure",
    "parse_args",
    "print_points",
    "probability_axes",
    "probability_footer",
    "save",
    "sweep_data",
    "wilson_text",
]

GALLERY = Path(__file__).resolve().parent
"""The gallery directory (scripts, committed PNGs, README)."""
ROOT = GALLERY.parent
"""Repository root."""
CONFIGS = ROOT / "configs"
"""Run configurations read by the scripts."""
SWEEPS = CONFIGS / "sweeps"
"""Sweep specifications of the probability figures (``pde-rotor sweep``)."""
DATA = ROOT / "data"
"""Stored sweep reports (NetCDF written by :func:`pde_rotor.sweep.report`)."""
SWEEP_RUNS = ROOT / "data" / "sweeps"
"""Where sweeps run by the gallery keep their results (the CLI's default: resumable, and
committed results travel with the repository)."""
OUTPUT = GALLERY / "output"
"""Default output directory (gitignored)."""
SCHEDULER: str | None = None
"""Dask scheduler address for the sweeps (``--scheduler``); None: a LocalCluster per sweep."""

PAPER_CONFIG = CONFIGS / "paper_fig4a.yaml"
"""Paper-resolution config of the symmetric rotor (Delta = 0): base of Fig. 3 and the movie."""
QUICK_CONFIG = CONFIGS / "quickstart.yaml"
"""Source of the coarse grid used by the quick and tiny fidelities."""

QUICK_SWEEP_SAMPLES = 10
"""Restarts per direction and point of the sweeps the quick gallery runs itself (20 stops
per point): all six probability sweeps then take about 10 minutes on 2 cores."""
TINY_DOMAIN_RADIUS = 1.75
"""Domain radius of the tiny fidelity: the support of F and G (radius 1.655 at delta = 0.05)
stays inside the disk (the config rejects smaller domains)."""

_logger = logging.getLogger("gallery")


@dataclass(frozen=True)
class Fidelity:
    """How a gallery figure is computed.

    Attributes:
        name: "full", "quick" or "tiny".
        grid: ``key.path=value`` overrides of grid and smoothing (empty: the config's own).
        protocol: overrides of the stop-and-release protocol for the time-series figures
            (Figs. 4 and 6; empty: the config's own, the paper's t_ini = t_release = 10 and
            M = 100).
        spinup: time of free rotation before a steady state is used (Fig. 3, movie).
        sweep_variant: which variant of a figure's sweep to run when no stored report
            exists ("" for the full sweep file, "_quick" for the quick one).
        sweep_samples: at most this many restarts per direction and point when the
            gallery runs a sweep itself (None: the sweep file's ``samples``). The runs are
            the first ones of the sweep file's (same seeds, same run files), so a later
            ``pde-rotor sweep`` of the file into the same directory reuses them.
    """

    name: str
    grid: tuple[str, ...] = ()
    protocol: tuple[str, ...] = ()
    spinup: float = 10.0
    sweep_variant: str = ""
    sweep_samples: int | None = None

    @property
    def is_tiny(self) -> bool:
        """Whether this is the CI smoke-test size."""
        return self.name == "tiny"

    def config(self, path: str | Path = PAPER_CONFIG, *overrides: str) -> RotorConfig:
        """Load a config from configs/ with this fidelity's grid and the given overrides.

        Output trackers that write files (movie, snapshots) and the progress bar are off:
        the gallery runs in memory.
        """
        return load_config(
            path,
            [
                *self.grid,
                *overrides,
                "output.progress=false",
                "output.movie=false",
                "output.snapshot_interval=null",
            ],
        )


def _quick_grid() -> tuple[str, ...]:
    """The coarse grid of configs/quickstart.yaml as overrides (one home for the numbers)."""
    data = read_config_data(QUICK_CONFIG)
    grid, geometry = data.get("grid", {}), data.get("geometry", {})
    return (
        f"grid.dx={grid['dx']!r}",
        f"grid.dt={grid['dt']!r}",
        f"geometry.smoothing={geometry['smoothing']!r}",
    )


def fidelity(name: str) -> Fidelity:
    """The :class:`Fidelity` called `name` ("full", "quick" or "tiny")."""
    if name == "full":
        return Fidelity("full")
    quick = _quick_grid()
    if name == "quick":
        return Fidelity(
            "quick",
            grid=quick,
            protocol=("protocol.t_ini=6.0", "protocol.t_release=6.0", "protocol.cycles=6"),
            spinup=8.0,
            sweep_variant="_quick",
            sweep_samples=QUICK_SWEEP_SAMPLES,
        )
    if name == "tiny":
        return Fidelity(
            "tiny",
            grid=(*quick, f"grid.domain_radius={TINY_DOMAIN_RADIUS}"),
            protocol=("protocol.t_ini=1.0", "protocol.t_release=1.0", "protocol.cycles=2"),
            spinup=1.0,
            sweep_variant="_quick",
        )
    msg = f"unknown fidelity {name!r} (allowed: full, quick, tiny)"
    raise ValueError(msg)


def parse_args(
    description: str,
    argv: Sequence[str] | None = None,
    extra: Callable[[argparse.ArgumentParser], None] | None = None,
) -> argparse.Namespace:
    """Command line shared by the scripts: ``[--quick | --tiny] [--out DIR]``.

    The namespace gets ``fidelity`` (a :class:`Fidelity`) and ``out`` (a Path, created).
    """
    parser = argparse.ArgumentParser(description=description)
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument(
        "--quick", action="store_true", help="coarse grid, short protocol, few samples"
    )
    mode.add_argument(
        "--tiny", action="store_true", help="smoke-test size (CI): tiny domain, seconds"
    )
    parser.add_argument(
        "--out", type=Path, default=OUTPUT, help=f"output directory [default: {OUTPUT}]"
    )
    parser.add_argument(
        "--scheduler",
        default=None,
        help="address of a running dask scheduler for the sweeps [default: a LocalCluster]",
    )
    if extra is not None:
        extra(parser)
    args = parser.parse_args(argv)
    args.fidelity = fidelity("tiny" if args.tiny else "quick" if args.quick else "full")
    global SCHEDULER
    SCHEDULER = args.scheduler
    args.out.mkdir(parents=True, exist_ok=True)
    logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")
    for name in ("pde", "distributed"):  # py-pde's per-run and dask's cluster INFO lines
        logging.getLogger(name).setLevel(logging.WARNING)
    return args


# ---------------------------------------------------------------------------------------
# captions and saving
# ---------------------------------------------------------------------------------------


CPU_BACKEND = "cpu (numba fused kernel)"
"""Backend label of everything the gallery computes (single runs and sweeps run on CPU)."""


def fidelity_label(
    fid: Fidelity, config: RotorConfig | None, detail: str = "", backend: str | None = CPU_BACKEND
) -> str:
    """Footer text: fidelity, grid, noise, backend and any detail (samples, M)."""
    parts = [f"pde_rotor, {fid.name} fidelity"]
    if config is not None:
        parts.append(grid_label(config))
        parts.append(f"\u03c3 = {config.noise.sigma:g}")
    if detail:
        parts.append(detail)
    if backend:
        parts.append(f"backend {backend}")
    return "; ".join(parts)


# ---------------------------------------------------------------------------------------
# sweeps and probabilities
# ---------------------------------------------------------------------------------------


def sweep_file(name: str, fid: Fidelity) -> Path:
    """The sweep specification configs/sweeps/<name><variant>.yaml for this fidelity.

    Raises:
        FileNotFoundError: the statistics module provides no such sweep.
    """
    path = SWEEPS / f"{name}{fid.sweep_variant}.yaml"
    if not path.exists():
        msg = f"{path} not found: the sweeps of the probability figures live in {SWEEPS}"
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


def stored_reports(name: str) -> list[Path]:
    """Stored reports of sweep `name` under data/, best fidelity first
    (:func:`pde_rotor.sweep.stored.stored_reports`)."""
    return stored.stored_reports(name, DATA)


def paper_points(x_dim: str, **fixed: float) -> xr.Dataset | None:
    """The paper-resolution points of data/ on one curve
    (:func:`pde_rotor.sweep.stored.paper_points`)."""
    return stored.paper_points(DATA, x_dim, **fixed)


def sweep_data(name: str, fid: Fidelity, out: Path) -> SweepData:
    """The report of sweep `name` (e.g. "fig5") at fidelity `fid`.

    * full and quick: a stored report from data/ if there is one (the best fidelity
      stored, which the footer names); otherwise the sweep configs/sweeps/<name>.yaml
      (full) or <name>_quick.yaml (quick, with at most ``fid.sweep_samples`` restarts per
      direction and point) is run through :func:`pde_rotor.sweep.run_sweep` into
      data/sweeps/<file stem> (resumable: a rerun continues where it stopped; the
      directory ``pde-rotor sweep`` uses by default) and its report is written there;
    * tiny: a shrunken copy of the quick sweep (:func:`tiny_sweep`) run into
      `out`/sweeps/.
    """
    from pde_rotor.sweep import REPORT_FILE, report, run_sweep

    if not fid.is_tiny:
        for path in stored_reports(name):
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
        sweep_dir = SWEEP_RUNS / spec_path.stem
        workers = None
    _logger.info("%s: running sweep %s into %s", name, spec_path, sweep_dir)
    outcome = run_sweep(
        sweep, sweep_dir, scheduler=SCHEDULER, workers=workers, progress=not fid.is_tiny
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
    95 % interval (:func:`pde_rotor.crossing.report_crossing`) as a horizontal bar at the
    level, open ends drawn to the curve's last point and dashed. Prints and returns the
    line ``PREFIX NAME: P = level at t_stop = ... [..., ...]``; draws nothing where the
    curve has fewer than two complete points (partial points, whose runs are not all
    done, are left out) or does not cross."""
    from pde_rotor.crossing import report_crossing

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
    ax.plot([found.value], [level], "kD", ms=6, zorder=4, label=f"{name}: {found.describe()}")
    return line


STOP_LABEL = f"stop duration t_stop [{TIME_UNITS}]"
"""Axis label of t_stop."""
ASYMMETRY_LABEL = "asymmetry \u0394 [rad]"
"""Axis label of Delta."""


def probability_footer(fid: Fidelity, data: SweepData) -> str:
    """Footer of a probability figure: the report's fidelity and where it came from."""
    where = "computed now" if data.computed else f"stored: {_relative(data.source)}"
    chain = "two-state chain of the 97.5 % Wilson bounds of P(inv | CCW), P(inv | CW)"
    kinds = set(np.unique(data.report["P_estimator"])) if "P_estimator" in data.report else set()
    if data.report.attrs.get("estimator") == "protocol":
        interval = "Wilson score"
    elif kinds == {POOLED}:
        interval = "Wilson score of the count pooled over both directions (\u0394 = 0)"
    else:
        interval = chain
    return (
        f"pde_rotor, {fid.name} run of the gallery; {data.label()}; {where}; "
        f"95 % interval: {interval}; backend {CPU_BACKEND}"
    )


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
    x = pts[x_dim].values
    kwargs: dict[str, Any] = {
        "fmt": "D",
        "color": "k",
        "mfc": "gold",
        "ms": 7,
        "zorder": 5,
        "label": f"paper resolution, paper scheme, \u03c3 = {fixed['sigma']:g}",
    }
    kwargs.update(style or {})
    errorbar_p(ax, x, pts, **kwargs)
    print_points(f"{prefix}paper resolution: ", x_dim, x, pts)
    files = ", ".join(f"data/{name}.nc" for name in sorted(set(pts["report"].values.tolist())))
    return (
        f"Diamonds: paper resolution dx = \u03b4 = 0.025, dt = 1e-4, paper scheme (lattice "
        f"torque), bank estimator, \u03c3 = {fixed['sigma']:g}, "
        f"{count_range(pts['stops'].values)} stops per "
        f"point; stored: {files}"
    )


def _relative(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)
