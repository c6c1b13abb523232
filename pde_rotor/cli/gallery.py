"""``pde-rotor gallery``: reproduce the paper's figures (scripts in gallery/).

Registered on the main typer app by :func:`register` (called from :mod:`pde_rotor.cli.main`).
Exit codes: 0 every selected figure was written; 1 some scripts failed (the others
ran); 2 bad input (unknown --only name, no gallery directory).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from .common import EXIT_FAILED, fail, output_dir


def register(app: typer.Typer) -> None:
    """Add the ``gallery`` command to `app`."""

    @app.command("gallery", short_help="Reproduce the paper's figures.")
    def gallery_command(
        quick: Annotated[
            bool, typer.Option("--quick", help="Coarse grid, short protocols, few samples.")
        ] = False,
        tiny: Annotated[
            bool, typer.Option("--tiny", help="Smoke-test size (seconds per figure; CI).")
        ] = False,
        only: Annotated[
            list[str] | None,
            typer.Option(
                "--only",
                metavar="NAME",
                help="Run only these scripts, by name or prefix, e.g. --only fig5 --only movie "
                "(repeatable; commas also separate) [default: all].",
                show_default=False,
            ),
        ] = None,
        out: Annotated[
            Path | None,
            typer.Option(
                "--out", "-o", metavar="DIR", help="Output directory [default: gallery/output]."
            ),
        ] = None,
        scheduler: Annotated[
            str | None,
            typer.Option(
                metavar="ADDRESS", help="Address of a running dask scheduler for the sweeps."
            ),
        ] = None,
        publish: Annotated[
            bool,
            typer.Option(
                "--publish", help="Copy the PNGs and the GIF written into gallery/ (committed)."
            ),
        ] = False,
    ) -> None:
        """Reproduce the paper's figures 1 and 3-9, the inversion movie and the convergence page."""
        from ..gallery.runner import GalleryError, gallery_dir, run_gallery

        if quick and tiny:
            fail("--quick and --tiny are two sizes of the gallery: give one of them")
        names = [n.strip() for item in only or [] for n in item.split(",") if n.strip()]
        try:
            target = output_dir(out if out is not None else gallery_dir() / "output")
            result = run_gallery(
                quick, names or None, target, tiny=tiny, scheduler=scheduler, publish=publish
            )
        except GalleryError as err:
            fail(str(err))
        for name, files in result.files.items():
            status = "FAILED" if name in result.failed else "ok"
            typer.echo(f"{name:<20} {status:<6} {result.seconds[name]:7.1f} s  {len(files)} files")
        typer.echo(f"output: {result.out}")
        if result.failed:
            for name, message in result.failed.items():
                typer.echo(f"error: {name}: {message}", err=True)
            raise typer.Exit(EXIT_FAILED)
