"""``pde-rotor sweep``, ``report`` and ``compact``: parameter sweeps of inversion statistics.

Registered on the main typer app by :func:`register` (called from :mod:`pde_rotor.cli.main`).
Exit codes as for ``pde-rotor run``: 0 success, 1 some runs failed (the others are
stored; rerun the same command to retry them), 2 bad input (or a sweep directory that
another sweep is writing to, or that cannot be written), 130 interrupted by Ctrl-C or
SIGTERM (finished runs are kept; rerun to resume).
"""

from __future__ import annotations

import math
import signal
from pathlib import Path
from typing import Annotated

import typer

from .common import EXIT_FAILED, EXIT_INTERRUPTED, fail, output_dir, output_file


def _interrupt(signum: int, frame: object) -> None:
    raise KeyboardInterrupt


def register(app: typer.Typer) -> None:
    """Add the ``sweep``, ``report`` and ``compact`` commands to `app`."""

    @app.command("sweep", short_help="Run a parameter sweep (resumable).")
    def sweep_command(
        sweep: Annotated[
            Path, typer.Argument(metavar="SWEEP", help="Sweep YAML file (see configs/sweeps/).")
        ],
        scheduler: Annotated[
            str | None,
            typer.Option(
                metavar="ADDRESS",
                help="Address of a running dask scheduler, e.g. tcp://node:8786 "
                "[default: start a LocalCluster here].",
            ),
        ] = None,
        workers: Annotated[
            int | None,
            typer.Option(
                min=1,
                metavar="N",
                help="LocalCluster worker processes [default: usable cores / --threads].",
            ),
        ] = None,
        threads: Annotated[
            int,
            typer.Option(
                min=1,
                metavar="T",
                help="Threads of each worker's runs (their solver.threads); workers x T may "
                "not exceed the usable cores.",
            ),
        ] = 1,
        out: Annotated[
            Path | None,
            typer.Option(
                "--out",
                "-o",
                metavar="DIR",
                help="Sweep directory [default: data/sweeps/<sweep file stem>, in the repository: "
                "commit it to resume elsewhere].",
            ),
        ] = None,
        quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
        set_: Annotated[
            list[str] | None,
            typer.Option(
                "--set",
                metavar="KEY=VALUE",
                show_default=False,
                help="Change a key of the sweep file (repeatable): samples=5, seed=1, "
                "axes.protocol.t_stop=[0.5,3], axes.KEY=null (drop the axis), "
                "set.noise.sigma=0 (base config), estimator.release_cap=5, base=coarse, "
                "crowd.count=16 (a crowd sweep).",
            ),
        ] = None,
        dry_run: Annotated[
            bool,
            typer.Option(
                "--dry-run",
                help="Print the number of runs and the estimated cost, compute nothing.",
            ),
        ] = False,
    ) -> None:
        """Run SWEEP on dask (resumable: finished runs are skipped), then write the report."""
        from ..sweep.store import DEFAULT_ROOT, StoreBusyError, check_not_busy

        if not dry_run:  # a second sweep on one directory: refused before anything else
            try:
                check_not_busy(out if out is not None else DEFAULT_ROOT / sweep.stem)
            except StoreBusyError as err:
                fail(str(err))
        from ..sweep import (
            Sweep,
            SweepError,
            check_scheduler,
            format_table,
            gather,
            local_workers,
            read_runs,
            report,
            run_sweep,
            sweep_backend,
            usable_cores,
        )
        from ..sweep.cost import estimate_sweep

        try:
            spec = Sweep.load(sweep, set_ or [])
            backend = sweep_backend(spec)
        except SweepError as err:
            fail(str(err))
        sweep_dir = out if out is not None else DEFAULT_ROOT / sweep.stem
        runs = spec.runs()
        n_runs = len(runs)
        each = f", {threads} thread{'s' if threads != 1 else ''} each"
        n = None
        if backend == "gpu":
            where = "the GPU in ensemble batches"
            n = workers or usable_cores()
        elif scheduler:
            where = f"the dask scheduler at {scheduler} (runs of {threads} "
            where += f"thread{'s' if threads != 1 else ''} each, at most a worker's cores)"
        else:
            try:
                n = local_workers(workers, threads)
            except SweepError as err:
                fail(str(err))
            where = (
                f"a LocalCluster of {n} worker process{'es' if n != 1 else ''}{each} "
                f"({n * threads} of the {usable_cores()} usable cores)"
            )
        if dry_run:
            try:
                stored = read_runs(sweep_dir)
            except SweepError as err:
                fail(str(err))
            todo = [run for run in runs if run.key not in stored]
            points = math.prod(spec.shape)
            typer.echo(
                f"dry run: sweep {spec.spec.name}, {spec.spec.estimator.kind} estimator: "
                f"{points} point{'s' if points != 1 else ''} x {n_runs // points} runs = "
                f"{n_runs} runs, {n_runs - len(todo)} already done in {sweep_dir}"
                + ("" if spec.spec.axes else " (no axes: every run is of the base config)")
            )
            typer.echo(f"to compute: {len(todo)} runs on {where}")
            typer.echo(f"estimated cost: {estimate_sweep(todo, n, threads).describe()}")
            return
        output_dir(sweep_dir)
        if scheduler and backend != "gpu":
            try:
                check_scheduler(scheduler)
            except SweepError as err:
                fail(str(err))
        if sweep_dir.is_dir() and not (sweep_dir / "sweep.yaml").is_file():
            others = sorted(p.name for p in sweep_dir.iterdir() if not p.name.startswith("."))
            if others:
                fail(
                    f"--out {str(sweep_dir)!r} holds {others[0]} but no sweep (no sweep.yaml): "
                    "choose a new or empty directory, or a sweep directory to resume"
                )
        typer.echo(f"pde-rotor: sweep {sweep} ({n_runs} runs) on {where} -> {sweep_dir}", err=True)
        # SIGTERM (a batch system ending the job, kill PID) stops like Ctrl-C: the
        # cluster is closed and every finished run is kept
        previous = signal.signal(signal.SIGTERM, _interrupt)
        try:
            outcome = run_sweep(
                spec,
                sweep_dir,
                scheduler=scheduler,
                workers=n,
                threads=threads,
                progress=not quiet,
            )
        except SweepError as err:  # the directory is busy or cannot be written
            fail(str(err))
        except KeyboardInterrupt:
            stored = read_runs(sweep_dir)
            kept = sum(run.key in stored for run in runs)
            typer.echo(
                f"interrupted: {kept} of {n_runs} runs are kept in {sweep_dir}; rerun the same "
                "command to resume",
                err=True,
            )
            raise typer.Exit(EXIT_INTERRUPTED) from None
        finally:
            signal.signal(signal.SIGTERM, previous)
        typer.echo(
            f"runs: {outcome.total} ({outcome.skipped} already done, {outcome.computed} "
            f"computed, {len(outcome.failed)} failed)"
        )
        # the table of the runs asked for; report.nc of the directory's design, which a
        # run of a subset of it leaves whole (store.prepare)
        typer.echo(format_table(gather(spec, sweep_dir)))
        report(sweep_dir, echo=False)
        typer.echo(f"report: {sweep_dir / 'report.nc'}")
        if outcome.failed:
            for key, message in outcome.failed[:5]:
                typer.echo(f"failed run {key}: {message}", err=True)
            raise typer.Exit(EXIT_FAILED)

    @app.command("report", short_help="Gather a sweep's runs into a report.")
    def report_command(
        sweep_dir: Annotated[
            Path,
            typer.Argument(
                metavar="SWEEP",
                help="Directory written by `pde-rotor sweep` (the design in its sweep.yaml), "
                "or a sweep file: its whole design, read from data/sweeps/<file stem>.",
            ),
        ],
        out: Annotated[
            Path | None,
            typer.Option(
                "--out",
                "-o",
                metavar="FILE.nc",
                help="NetCDF file [default: runs/NAME-report-TIME/report.nc, NAME: the "
                "sweep's; SWEEP is never written to].",
            ),
        ] = None,
        crossing: Annotated[
            list[float] | None,
            typer.Option(
                min=0.0,
                max=1.0,
                metavar="LEVEL",
                help="Also print where P crosses this level along --along, with its 95 % "
                "intervals (Delta = 0 decay: 0.95 where it starts, 0.75 halfway; onset: "
                "0.5); repeatable.",
            ),
        ] = None,
        along: Annotated[
            str,
            typer.Option(
                metavar="AXIS",
                help="The axis the crossings are read along (a dimension of the report, "
                "e.g. sigma).",
            ),
        ] = "t_stop",
        rising: Annotated[
            bool,
            typer.Option(
                "--rising",
                help="P rises along the axis (P(3, 2e-5) against sigma) [default: it falls].",
            ),
        ] = False,
        plot: Annotated[
            bool,
            typer.Option(
                "--plot",
                help="Also draw the report (as `pde-rotor plot` does) into an image beside "
                "it: the report's file name with suffix png.",
            ),
        ] = False,
        explain: Annotated[
            bool,
            typer.Option(
                "--explain", help="Also say what the table's terms mean: P, from CCW and the rest."
            ),
        ] = False,
        plot_out: Annotated[
            Path | None,
            typer.Option(
                "--plot-out",
                metavar="FILE",
                help="Draw the report into this image file (implies --plot).",
            ),
        ] = None,
    ) -> None:
        """Gather the finished runs of SWEEP into NetCDF and print a table."""
        from ..statistics.crossing import report_crossings
        from ..sweep import DEFAULT_ROOT, Sweep, SweepError, report
        from ..sweep.reporting import GLOSSARY
        from .plot import check_target, draw, output_folder, report_name, save

        design = None
        name = report_name(sweep_dir)
        if sweep_dir.is_file():
            try:
                design = Sweep.load(sweep_dir)
            except SweepError as err:
                fail(str(err))
            sweep_dir = DEFAULT_ROOT / sweep_dir.stem
        if not (sweep_dir / "sweep.yaml").is_file():
            fail(f"{sweep_dir} holds no sweep.yaml (not a sweep directory)")
        # SWEEP is only read: the report goes where --out says or into a new run folder
        target = output_file(
            out if out is not None else output_folder(name, "report") / "report.nc"
        )
        figure = plot_out or (target.with_suffix(".png") if plot else None)
        if figure is not None:
            check_target(figure)
        try:
            ds = report(sweep_dir, target, sweep=design)
        except SweepError as err:
            fail(str(err))
        typer.echo(f"report: {target}")
        if explain:
            typer.echo(GLOSSARY)
        if figure is not None:
            save(draw(ds, None, target), figure)
        for level in crossing or []:
            try:
                curves = report_crossings(ds, level, along, falling=not rising)
            except ValueError as err:
                fail(f"--crossing {level:g}: {err}")
            for where, found in curves:
                at = ", ".join(f"{k} = {v:g}" for k, v in where.items())
                text = found if isinstance(found, str) else found.describe(along)
                typer.echo(f"crossing{f' ({at})' if at else ''}: {text}")

    @app.command("compact", short_help="Merge a sweep's run logs into one file.")
    def compact_command(
        sweep_dirs: Annotated[
            list[Path],
            typer.Argument(
                metavar="SWEEP",
                help="Sweep directories, or sweep files (their data/sweeps/<file stem>).",
            ),
        ],
    ) -> None:
        """Merge the run logs of each SWEEP into one sorted SWEEP_DIR/runs/runs.jsonl.

        Every finished run is kept once (duplicates and torn lines of interrupted writes
        are dropped, each torn line with a warning); the file is written atomically and
        then the logs merged into it are removed. A legacy store (runs/<key>.json, one
        file per run) is converted. Reports are unchanged, and compacting again changes
        nothing. A directory that a sweep is writing to is refused. Compact a store
        before committing it: a compacted store is a handful of files.
        """
        from ..sweep import DEFAULT_ROOT, SweepError, compact

        for sweep_dir in sweep_dirs:
            if sweep_dir.is_file():
                sweep_dir = DEFAULT_ROOT / sweep_dir.stem
            if not (sweep_dir / "sweep.yaml").is_file():
                fail(f"{sweep_dir} holds no sweep.yaml (not a sweep directory)")
            try:
                done = compact(sweep_dir)
            except SweepError as err:
                fail(str(err))
            dropped = (
                f", {done.dropped} unreadable record{'s' if done.dropped != 1 else ''} dropped"
                if done.dropped
                else ""
            )
            typer.echo(
                f"compacted {sweep_dir}: {done.runs} runs from {done.merged} "
                f"file{'s' if done.merged != 1 else ''} into {done.path}{dropped}"
            )
