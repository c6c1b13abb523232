"""Time-series figures of the gallery (paper Figs. 4 and 6): phi(t) and omega(t) per run.

Each panel is one run of a paper config (configs/paper_fig4a.yaml, ...). At the paper's
M = 100 cycles a run takes more than an hour, so a script can read its runs from run
directories instead of computing them (``--runs DIR``): the panel of config
``configs/NAME.yaml`` is ``DIR/NAME``, as written by
``pde-rotor run configs/NAME.yaml --out DIR/NAME`` (the runs of one figure can then go
in parallel, on this machine or elsewhere). A stored run is used only if it completed
and its physics (everything but output, solver and the drawn noise seed) is the
config's at the chosen fidelity; a missing one is computed and written there.

The runs behind the committed full-fidelity figures are kept in the repository, in
data/runs/<config name> (:data:`ARCHIVE`), written by ``--archive DIR`` (:func:`archive_run`):
the run's config (with its drawn seed), events and log, and its time series thinned to
every :data:`ARCHIVE_INTERVAL` time units plus both samples of every stop and release;
no field snapshots. At full fidelity a script reads them from there when no ``--runs``
is given, so the figure is redrawn in seconds from the committed data.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from pde_rotor.api import RunResult, run
from pde_rotor.config import RotorConfig, physics_differences
from pde_rotor.io.output import RunDirectory, write_netcdf_atomic, write_text_atomic
from pde_rotor.plotting.run import stop_intervals
from pde_rotor.units import OMEGA_UNITS, TIME_UNITS

from .common import (
    DATA,
    ROOT,
    Fidelity,
    add_footer,
    fidelity_label,
    new_figure,
    parse_args,
    save,
    wilson_text,
)

ARCHIVE = DATA / "runs"
"""The committed runs of the full-fidelity time-series figures (:func:`archive_run`)."""
ARCHIVE_INTERVAL = 0.05
"""Sample spacing of an archived time series: 0.05 time units, 20 samples over the
shortest stop, far finer than a line over the M = 100 cycles of a figure can show."""


def _options(parser: argparse.ArgumentParser) -> None:
    """``--cycles M``, ``--runs DIR`` and ``--archive DIR`` of the time-series scripts."""
    parser.add_argument(
        "--cycles",
        type=int,
        default=None,
        help="stop-and-release cycles per run [default: the fidelity's; full: the paper's 100]",
    )
    parser.add_argument(
        "--runs",
        type=Path,
        default=None,
        help="read each panel's run from DIR/<config name> (pde-rotor run CONFIG --out "
        "DIR/<config name>), computing and writing there the ones missing [default: "
        "full fidelity reads the committed data/runs/ where it holds the run; otherwise "
        "every run is computed in memory]",
    )
    parser.add_argument(
        "--archive",
        type=Path,
        default=None,
        help="also write each panel's run, its time series thinned, to DIR/<config name> "
        "(data/runs keeps the committed ones); needs --runs",
    )


def stored_run(run_dir: Path, config: RotorConfig) -> RunResult | None:
    """The completed run in `run_dir` if it is a run of `config`, None if there is none.

    Runs match when their physics (:meth:`~pde_rotor.config.RotorConfig.physics`) is
    the same, apart from the noise seed where `config` draws it (seed null): a stored
    run's seed is the one it drew.

    Raises:
        ValueError: `run_dir` holds a run of another config (the keys named) or one that
            did not complete (its status and message).
    """
    if not (run_dir / "config.yaml").is_file():
        return None
    result = RunResult.load(run_dir)
    ignore = ("noise.seed",) if config.noise.seed is None else ()
    differ = physics_differences(result.config, config, ignore)
    if differ:
        values = ", ".join(f"{k} = {a} (wanted {b})" for k, (a, b) in differ.items())
        msg = f"{run_dir} holds a run of another config: {values}"
        raise ValueError(msg)
    if not result.ok:
        msg = f"{run_dir}: the run is {result.status} ({result.message or 'no message'})"
        raise ValueError(msg)
    return result


def thin(ts: xr.Dataset, interval: float) -> xr.Dataset:
    """The samples of a time series on multiples of `interval`, the first and the last,
    and both samples of every stop and release (where omega jumps).

    Args:
        ts: a run's time series (``stopped`` and ``time``, as written by a run).
        interval: the new spacing; a multiple of the series' own sample interval.
    """
    t = ts["time"].values
    steps = t / interval
    keep = np.isclose(steps, np.round(steps), rtol=0.0, atol=1e-6)
    keep[[0, -1]] = True
    edges = np.flatnonzero(np.diff(ts["stopped"].values) != 0)
    keep[edges] = keep[edges + 1] = True
    out = ts.isel(time=keep)
    out.attrs["sampling"] = (
        f"thinned to every {interval:g} and both samples of every stop and release, "
        f"from {ts.attrs.get('sampling', 'the run')}"
    )
    out.attrs["sample_interval"] = interval
    return out


def archive_run(source: Path, dest: Path, interval: float = ARCHIVE_INTERVAL) -> Path:
    """Write the completed run in `source` to `dest`, small enough to commit: the config
    (with the run's drawn seed), events and log as they are, the time series thinned
    (:func:`thin`), no snapshots or movie. :meth:`pde_rotor.api.RunResult.load` reads it.

    Returns:
        `dest`.
    """
    result = RunResult.load(source)
    src, run_dir = RunDirectory(source), RunDirectory.create(dest, overwrite=True)
    for name in ("config.yaml", "events.csv", "run.log"):
        write_text_atomic(run_dir / name, (src / name).read_text(encoding="utf-8"))
    write_netcdf_atomic(result.events, run_dir.events_nc)
    write_netcdf_atomic(thin(result.timeseries, interval), run_dir.timeseries)
    return dest


def panel_run(
    path: Path,
    fid: Fidelity,
    cycles: int | None,
    runs: Path | None,
    archive: Path | None = None,
) -> RunResult:
    """The run of one panel: config `path` at fidelity `fid` (and `cycles`), read from
    ``runs/<config name>`` where it is stored there, else computed (and written there
    when `runs` is given). Without `runs`, a matching run in ``archive/<config name>``
    is read instead of computing one (a run of another config there is named and
    passed over)."""
    extra = () if cycles is None else (f"protocol.cycles={cycles}",)
    config = fid.config(path, *fid.protocol, *extra)
    run_dir = None if runs is None else runs / path.stem
    found = None if run_dir is None else stored_run(run_dir, config)
    if run_dir is None and archive is not None:
        try:
            found = stored_run(archive / path.stem, config)
        except ValueError as err:
            print(f"{path.name}: not reading the committed run: {err}; computing it")
    if found is not None:
        print(f"{path.name}: read from {found.run_dir}")
        return found
    return run(config, run_dir, progress=False)


def timeseries_figure(
    title: str,
    panels: Sequence[tuple[str, Path]],
    fid: Fidelity,
    cycles: int | None = None,
    runs: Path | None = None,
) -> tuple[Figure, list[str]]:
    """phi(t) (row 1) and omega(t) (row 2) of one run per column, stops shaded.

    Args:
        title: figure title.
        panels: (panel letter, config path) per column.
        fid: fidelity.
        cycles: number of cycles M per run (None: the fidelity's protocol).
        runs: directory of stored runs (:func:`panel_run`); None: the committed
            :data:`ARCHIVE` at full fidelity where it holds the run, else in memory.

    Returns:
        The figure and one summary line per panel (inversions with the Wilson interval).
    """
    fig = new_figure(5.2 * len(panels), 6.4)
    axes = fig.subplots(2, len(panels), squeeze=False, sharex="col")
    lines = []
    archive = ARCHIVE if fid.name == "full" and cycles is None else None
    results = [panel_run(path, fid, cycles, runs, archive) for _, path in panels]
    for col, ((letter, _), result) in enumerate(zip(panels, results, strict=True)):
        config = result.config
        ts = result.timeseries
        t = ts["time"].values
        events = result.events
        n = int(events.sizes.get("cycle", 0))
        k = int(events["inverted"].values.sum()) if n else 0
        committed = int(events["committed"].values.sum()) if n else 0
        p = config.protocol
        summary = f"({letter}) t_stop = {p.t_stop:g}: inversions {wilson_text(k, n)}" + (
            f", {n - committed} not committed" if committed < n else ""
        )
        lines.append(summary)
        for row, (name, label) in enumerate(
            (("phi", "angle \u03c6 [rad]"), ("omega", f"angular velocity \u03c9 [{OMEGA_UNITS}]"))
        ):
            ax = axes[row, col]
            for a, b in stop_intervals(config, float(t[-1]) if t.size else None):
                ax.axvspan(a, b, color="tab:red", alpha=0.25, lw=0)
            ax.plot(t, ts[name].values, color="k", lw=0.8)
            ax.grid(alpha=0.3)
            if col == 0:
                ax.set_ylabel(f"({row + 1}) {label}")
        axes[0, col].set_title(
            f"({letter}) t_stop = {p.t_stop:g}, \u0394 = {config.geometry.asymmetry:g}: "
            f"{k}/{n} inverted",
            fontsize=10,
        )
        axes[1, col].set_xlabel(f"time t [{TIME_UNITS}] (stops shaded)")
        if result.status != "completed":
            axes[0, col].text(
                0.02, 0.95, f"run {result.status}", transform=axes[0, col].transAxes, color="r"
            )
    fig.suptitle(title, fontsize=11)
    config = results[-1].config
    p = config.protocol
    stored = [r.run_dir.parent for r in results if r.run_dir is not None]
    stored = [d.relative_to(ROOT) if d.is_relative_to(ROOT) else d for d in stored]
    where = (
        f"runs stored in {stored[0]}/"
        if stored
        else f"wall {sum(r.wall_time for r in results):.0f} s"
    )
    add_footer(
        fig,
        fidelity_label(
            fid,
            config,
            f"t_ini = {p.t_ini:g}, t_release = {p.t_release:g}, M = {p.cycles} cycles per run; "
            f"{where}",
        ),
    )
    return fig, lines


@dataclass(frozen=True)
class TimeseriesFigure:
    """One time-series figure: its file name, title and one (label, config) per panel."""

    name: str
    title: str
    panels: Sequence[tuple[str, Path]]


def timeseries_main(
    figures: Sequence[TimeseriesFigure], description: str, argv: Sequence[str] | None = None
) -> list[Path]:
    """The whole script of the time-series figures (Figs. 4 and 6).

    Parses ``[--quick | --tiny] [--out DIR] [--cycles M] [--runs DIR] [--archive DIR]``,
    and for each figure gets one run per panel (:func:`timeseries_figure`), prints the
    inversion counts, archives the runs if asked (:func:`archive_run`) and writes it as
    PNG and PDF.
    """
    args = parse_args(description, argv, extra=_options)
    if args.archive is not None and args.runs is None:
        msg = "--archive thins the runs of --runs DIR: give --runs too"
        raise SystemExit(msg)
    if args.archive is not None and args.archive.resolve() == args.runs.resolve():
        msg = f"--archive {args.archive} is the --runs directory: the archive needs its own"
        raise SystemExit(msg)
    written: list[Path] = []
    for figure in figures:
        fig, lines = timeseries_figure(
            figure.title, figure.panels, args.fidelity, args.cycles, args.runs
        )
        for line in lines:
            print(f"{figure.name}: {line}")
        for _, path in figure.panels if args.archive is not None else ():
            dest = archive_run(args.runs / path.stem, args.archive / path.stem)
            print(f"{figure.name}: {path.name} archived in {dest}")
        written += save(fig, args.out, figure.name)
    return written
