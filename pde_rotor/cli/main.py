"""The ``pde-rotor`` command line: run, show, check, info (and sweep, report: cli_sweep;
gallery: cli_gallery; predict: cli_predict).

Exit codes: 0 success; 1 the simulation diverged (NaN/Inf; everything recorded up to
then is kept) or its files could not be written (a full disk: one line, every file written
until then readable); 2 bad input (config, --set, paths, backend), always one line
``error: ...`` naming the key path and the allowed values, printed before anything is
compiled; 3 a body reached the dish's edge or another body (one line naming them; the run
ends there and keeps what it recorded); 130 interrupted with Ctrl-C.

Each command imports what it needs when it runs: ``--version``, ``--help``, ``check`` and
``info`` never import the solver, py-pde, xarray or dask, and take under a second of CPU
time.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from .common import (
    EXIT_BAD_INPUT,
    EXIT_CONTACT,
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    SetOption,
    fail,
    output_file,
    warnings_shown,
)
from .gallery import register as register_gallery_commands
from .plot import register as register_plot_command
from .predict import register as register_predict_commands
from .stability import register as register_stability_command
from .sweep import register as register_sweep_commands

if TYPE_CHECKING:
    from ..api import RunResult

app = typer.Typer(
    name="pde-rotor",
    help="Camphor rotor under stop-and-release operations (Koyano et al., Chaos 2020).",
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    # plain help: rich markup would eat "[default: ...]" and label every flag <bool>
    rich_markup_mode=None,
)


def _version(value: bool) -> None:
    if value:
        from .._version import __version__

        typer.echo(f"pde-rotor {__version__}")
        raise typer.Exit()


@app.callback()
def options(
    version: Annotated[
        bool,
        typer.Option(
            "--version", callback=_version, is_eager=True, help="Print the version and exit."
        ),
    ] = False,
) -> None:
    """Camphor rotor under stop-and-release operations (Koyano et al., Chaos 2020)."""


@app.command(short_help="Run a config into a run directory.")
@warnings_shown()
def run(
    config: Annotated[
        Path, typer.Argument(metavar="CONFIG", help="YAML config file (see configs/).")
    ],
    set_: SetOption = None,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out", "-o", metavar="DIR", help="Run directory [default: runs/<config>-<time>]."
        ),
    ] = None,
    movie: Annotated[
        bool | None,
        typer.Option("--movie/--no-movie", help="Render movie.mp4 [default: output.movie]."),
    ] = None,
    seed: Annotated[
        int | None,
        typer.Option(
            metavar="N",
            help="Seed of the noise (sets noise.seed) [default: the config's noise.seed; a "
            "random one, recorded in config.yaml, where that is null].",
            show_default=False,
        ),
    ] = None,
    backend: Annotated[
        str | None,
        typer.Option(
            metavar="cpu|gpu|auto",
            help="Compute backend (sets solver.backend) [default: the config's solver.backend].",
            show_default=False,
        ),
    ] = None,
    overwrite: Annotated[
        bool, typer.Option(help="Replace the files of an earlier run in --out.")
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
) -> None:
    """Run CONFIG and write a run directory (config, time series, events, fields, movie)."""
    from ..api import RunError
    from ..backends import BackendError, backend_for
    from ..config import ConfigError, load_config
    from ..io.output import OutputError, RunDirectory
    from ..sweep.cost import estimate_run
    from ..trackers.budget import check_budget

    overrides = list(set_ or [])
    for option, value, key in (
        ("--seed", seed, "noise.seed"),
        ("--backend", backend, "solver.backend"),
    ):
        if value is None:
            continue
        clash = [o for o in overrides if o.split("=", 1)[0].strip() == key]
        if clash:
            fail(f"{option} {value} and --set {clash[0]} both set {key}: give one of them")
        overrides.append(f"{key}={value}")
    try:
        cfg = load_config(config, overrides)
        backend_for(cfg)
        run_dir = out if out is not None else RunDirectory.default_path(config)
        check_budget(cfg, run_dir, movie)
        RunDirectory.create(run_dir, overwrite=overwrite)
    except (ConfigError, BackendError, OutputError) as err:
        fail(str(err))

    from ..api import run as run_config

    estimate = estimate_run(cfg, movie)
    long_run = f"long run, {estimate.describe()}: " if estimate.long else ""
    typer.echo(f"pde-rotor: {long_run}running {config} -> {run_dir}")
    try:
        result = run_config(
            cfg,
            run_dir,
            movie=movie,
            progress=False if quiet else None,
            overwrite=True,
            check=False,
        )
    except (ConfigError, BackendError, OutputError) as err:
        fail(str(err))
    except RunError as err:
        fail(str(err), EXIT_FAILED)
    except OSError as err:  # a full disk before the first step (config.yaml, reserve)
        fail(f"cannot write the run's files in {run_dir}: {err.strerror or err}", EXIT_FAILED)
    _report(result)
    if result.status == "diverged":
        fail(result.message, EXIT_FAILED)
    if result.status == "stopped":  # a body at the dish's edge or at another body
        fail(result.message, EXIT_CONTACT)
    if result.status != "completed":
        fail(f"run {result.status}: {result.message}", EXIT_INTERRUPTED)


def _report(result: RunResult) -> None:
    t_final = float(result.timeseries["time"].values[-1]) if result.timeseries.sizes["time"] else 0
    typer.echo(f"run {result.status} (last sample t = {t_final:g}) after {result.wall_time:.1f} s")
    events = result.events
    if "body" in events:  # a run with bodies: the inversions of each body with stops
        for name in dict.fromkeys(events["body"].values):
            inverted = events["inverted"].values[events["body"].values == name]
            typer.echo(f"{name}: inversions {int(inverted.sum())}/{inverted.size}")
    else:
        n = events.sizes.get("cycle", 0)
        inversions = int(events["inverted"].values.sum()) if n else 0
        typer.echo(f"inversions: {inversions}/{n}" + (f" = {inversions / n:.2f}" if n else ""))
    typer.echo(f"run directory: {result.run_dir}")
    for name in result.files:
        typer.echo(f"  {name}")


@app.command(short_help="Draw the summary figure of a run.")
def show(
    run_dir: Annotated[
        Path, typer.Argument(metavar="RUN_DIR", help="Run directory written by `pde-rotor run`.")
    ],
    out: Annotated[
        Path | None,
        typer.Option(
            "--out", "-o", metavar="FILE", help="Image file [default: RUN_DIR/summary.png]."
        ),
    ] = None,
    display: Annotated[bool, typer.Option(help="Also open the figure in a window.")] = False,
) -> None:
    """Plot phi(t) and omega(t) with the stops shaded, the events table and a c/v snapshot."""
    from ..api import RunResult
    from ..config import ConfigError
    from ..io.output import RunDirectory

    try:
        result = RunResult.load(run_dir)
    except ConfigError as err:
        fail(str(err))
    target = output_file(out if out is not None else RunDirectory(run_dir).summary)
    from ..io.output import atomic_path
    from ..plotting.run import SUMMARY_SIZE, summary_figure

    fig = None
    if display:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=SUMMARY_SIZE, layout="constrained")
    fig = summary_figure(
        result.config, result.timeseries, result.events, result.snapshot(), fig=fig
    )
    suffix = target.suffix.lstrip(".") or "png"
    try:
        with atomic_path(target) as tmp:
            fig.savefig(tmp, format=suffix, dpi=110)
    except (OSError, ValueError) as err:
        fail(f"cannot write {target}: {err}")
    typer.echo(f"wrote {target}")
    if display:
        import matplotlib as mpl
        import matplotlib.pyplot as plt

        if mpl.get_backend().lower() == "agg":
            typer.echo("no display available (matplotlib backend Agg); see the image file")
        else:
            plt.show()


@app.command(short_help="Validate configs; print the run cost.")
@warnings_shown()
def check(
    configs: Annotated[
        list[Path],
        typer.Argument(metavar="CONFIG", help="YAML config files (e.g. configs/*.yaml)."),
    ],
    set_: SetOption = None,
) -> None:
    """Validate CONFIG (with overrides); print it fully resolved, or one line per file."""
    from ..config import ConfigError, dump_config, load_config
    from ..sweep.cost import estimate_run
    from ..trackers.budget import check_budget

    failed = 0
    for config in configs:
        try:
            cfg = load_config(config, set_ or [])
        except ConfigError as err:
            where = "" if len(configs) == 1 or str(config) in str(err) else f"{config}: "
            typer.echo(f"error: {where}{err}", err=True)
            failed += 1
            continue
        try:
            check_budget(cfg)
        except ConfigError as err:
            typer.echo(f"error: {'' if len(configs) == 1 else f'{config}: '}{err}", err=True)
            failed += 1
            continue
        steps = round(cfg.protocol.t_end / cfg.grid.dt)
        summary = (
            f"t_end = {cfg.protocol.t_end:g} ({steps} steps), dt limit {cfg.dt_limit():.4g}, "
            f"config hash {cfg.config_hash()}; run time {estimate_run(cfg).describe()}"
        )
        if len(configs) == 1:
            typer.echo(dump_config(cfg), nl=False)
            typer.echo(f"# ok: {summary}")
        else:
            typer.echo(f"ok: {config}: {summary}")
    if failed:
        raise typer.Exit(EXIT_BAD_INPUT)


@app.command(short_help="Versions, compute backend and threads.")
def info() -> None:
    """Versions, compute backend and threads."""
    from importlib.metadata import version

    import numba

    from .._version import versions
    from ..backends import gpu_unavailable_reason
    from ..solver.threads import resolve_threads

    for name, number in versions().items():
        typer.echo(f"{name:<12} {number}")
    typer.echo(f"{'matplotlib':<12} {version('matplotlib')}")
    typer.echo("backend      cpu: numba fused kernel (solver.threads)")
    reason = gpu_unavailable_reason()
    typer.echo(f"gpu          {'available' if reason is None else 'unavailable: ' + reason}")
    try:
        affinity = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        affinity = os.cpu_count() or 1
    typer.echo(
        f"threads      numba {numba.config.NUMBA_NUM_THREADS} "
        f"(layer {numba.config.THREADING_LAYER}), cpus usable {affinity}, "
        f"cpus total {os.cpu_count()}, a run now: {resolve_threads(None)} "
        "(solver.threads: null)"
    )
    try:
        import imageio_ffmpeg

        typer.echo(f"ffmpeg       {imageio_ffmpeg.get_ffmpeg_exe()}")
    except (ImportError, RuntimeError) as err:
        typer.echo(f"ffmpeg       unavailable ({err})")
    typer.echo(f"executable   {sys.executable}")


register_sweep_commands(app)  # pde-rotor sweep / report
register_plot_command(app)  # pde-rotor plot
register_gallery_commands(app)  # pde-rotor gallery
register_predict_commands(app)  # pde-rotor predict
register_stability_command(app)  # pde-rotor stability


def main() -> None:
    """Entry point equivalent to the ``pde-rotor`` script."""
    app()
