"""``pde-rotor plot``: the figure of a sweep report (:mod:`pde_rotor.sweep.plot`).

PATH is a report file (``pde-rotor report``'s NetCDF), a sweep directory (its report.nc;
where there is none yet, the report is gathered from its run files) or a sweep file (its
directory data/sweeps/<file stem>). PATH is only read: the figure goes to ``--out`` or,
by default, into a new folder ``runs/<name>-plot-<time>/`` (with the report gathered for
it, if any), never into the repository's data/ or another input folder. Bad input is one
line ``error: ...`` and exit code 2, checked before anything is written.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from .common import fail, output_file

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

SWEEP_SUFFIXES = (".yaml", ".yml")
"""Suffixes of a sweep file."""


def output_folder(name: str, command: str) -> Path:
    """``runs/<name>-<command>-<YYYYmmdd-HHMMSS>``: where ``plot`` and ``report`` write
    without ``--out`` (as ``run`` does), so that they never write into what they read."""
    from ..io.output import RunDirectory

    return RunDirectory.default_path(f"{name}-{command}")


def report_name(path: Path) -> str:
    """The name of what PATH holds: a report file's stem, a sweep directory's or sweep
    file's name."""
    return path.stem if path.is_file() else path.absolute().name


def check_target(target: Path) -> None:
    """Fail (one line, exit 2) unless `target` can be written as a figure.

    The suffix must name a format matplotlib writes, and the file must be writable
    (:func:`~pde_rotor.cli.common.output_file`; missing directories are created when the
    figure is written).
    """
    from matplotlib.figure import Figure

    if target.is_dir():
        fail(f"{target} is a directory: give an image file, e.g. {target / 'report.png'}")
    formats = Figure().canvas.get_supported_filetypes()
    suffix = target.suffix.lstrip(".").lower()
    if suffix not in formats:
        fail(f"{target}: unknown image format {suffix!r} (use one of {', '.join(sorted(formats))})")
    output_file(target)


def draw(ds: xr.Dataset, x: str | None, source: Path) -> Figure:
    """The figure of the report `ds` read from `source`
    (:func:`~pde_rotor.sweep.plot.report_figure`), or a one-line failure if it
    cannot be drawn (no axis `x`, nothing measured)."""
    from ..sweep.plot import ReportError, report_figure

    try:
        return report_figure(ds, x, source)
    except ReportError as err:
        fail(f"{source}: {err}")


def save(fig: Figure, target: Path) -> None:
    """Write `fig` to `target` atomically, creating missing directories; a one-line
    failure if it cannot be written, leaving no file or directory behind."""
    from ..io.output import atomic_path

    created = [p for p in reversed(target.parents) if not p.exists()]
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(target) as tmp:
            fig.savefig(tmp, format=target.suffix.lstrip(".").lower(), dpi=110)
    except OSError as err:
        for directory in reversed(created):
            if directory.is_dir():
                directory.rmdir()
        fail(f"cannot write {target}: {err.strerror or err}")
    typer.echo(f"wrote {target}")


def load_report(path: Path) -> xr.Dataset:
    """The report file `path`, or a one-line failure if it is not one."""
    from ..sweep.plot import ReportError, report_axes
    from ..sweep.stored import load_report as load_stored

    try:
        ds = load_stored(path)
    except (OSError, ValueError) as err:
        reason = str(err).splitlines()[0] if str(err) else type(err).__name__
        fail(f"{path} is not a sweep report: cannot read it as NetCDF ({reason})")
    try:
        report_axes(ds)
    except ReportError as err:
        fail(f"{path}: {err}")
    return ds


def sweep_report(path: Path) -> tuple[xr.Dataset, Path, bool]:
    """The report of PATH (see the module): (report, its file, whether it was gathered
    now from the run files and is still to be written there)."""
    from ..sweep import DEFAULT_ROOT, REPORT_FILE, SPEC_FILE, Sweep, SweepError, gather

    if not path.exists():
        fail(f"{path}: no such file or directory")
    design = None
    if path.is_file() and path.suffix.lower() in SWEEP_SUFFIXES:
        try:
            design = Sweep.load(path)
        except SweepError as err:
            fail(str(err))
        sweep_dir = DEFAULT_ROOT / path.stem
        if not sweep_dir.is_dir():
            fail(f"{path}: its sweep directory {sweep_dir} does not exist (run `pde-rotor sweep`)")
    elif path.is_file():
        return load_report(path), path, False
    else:
        sweep_dir = path
    report_path = sweep_dir / REPORT_FILE
    if report_path.is_file():
        return load_report(report_path), report_path, False
    if not (sweep_dir / SPEC_FILE).is_file():
        fail(f"{sweep_dir} holds neither {REPORT_FILE} nor {SPEC_FILE} (not a sweep directory)")
    try:
        ds = gather(design if design is not None else Sweep.load(sweep_dir), sweep_dir)
    except SweepError as err:
        fail(str(err))
    return ds, report_path, True


def register(app: typer.Typer) -> None:
    """Add the ``plot`` command to `app`."""

    @app.command("plot")
    def plot_command(
        path: Annotated[
            Path,
            typer.Argument(
                metavar="PATH",
                help="Report file (`pde-rotor report`), sweep directory or sweep file.",
            ),
        ],
        out: Annotated[
            Path | None,
            typer.Option(
                "--out",
                "-o",
                metavar="FILE",
                help="Image file, format by its suffix: png, pdf, svg [default: "
                "runs/NAME-plot-TIME/NAME.png, NAME: the report's or sweep's name; PATH is "
                "never written to].",
            ),
        ] = None,
        x: Annotated[
            str | None,
            typer.Option(
                "--x",
                metavar="AXIS",
                help="Axis to draw P against [default: t_stop if swept, else the first axis].",
            ),
        ] = None,
    ) -> None:
        """Draw P of a sweep against its axis with 95 % intervals (two axes: a heat map)."""
        from ..io.output import write_netcdf_atomic
        from ..sweep.store import REPORT_FILE

        ds, report_path, gathered = sweep_report(path)
        name = report_name(path)
        target = out if out is not None else output_folder(name, "plot") / f"{name}.png"
        check_target(target)
        if gathered:  # the report drawn, kept beside the figure (not in the sweep's folder)
            report_path = target.parent / REPORT_FILE
            if report_path.exists():
                fail(f"{report_path} exists: give another --out for the figure")
        fig = draw(ds, x, report_path)
        if gathered:
            target.parent.mkdir(parents=True, exist_ok=True)
            write_netcdf_atomic(ds, report_path)
            typer.echo(f"report: {report_path}")
        save(fig, target)
