"""What every ``pde-rotor`` command shares: the exit codes, the one-line failure and the
``--set`` option.

Exit codes: 0 success; 1 the simulation diverged or a figure failed; 2 bad input (always
one line ``error: ...`` on stderr, before anything is computed); 3 a body reached the dish's
edge or another body (the run ends there, everything recorded is kept); 130 interrupted.
"""

from __future__ import annotations

import logging
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, NoReturn

import typer
import typer.core

from ..io.output import OutputError, check_output_dir, check_output_file


def _argument_type(self: typer.core.TyperArgument, ctx: object) -> str | None:
    """No ``<list[Path]>`` after an argument's metavar: ``CONFIG...`` says it already."""
    return None if self.metavar is not None else _typer_argument_type(self, ctx)


# typer (>= 0.16) prints a Python type after every argument, e.g. ``REPORT...
# <list[Path]>``; every argument of this CLI has a metavar that names what it takes
_typer_argument_type = getattr(typer.core.TyperArgument, "display_type_rich", None)
if _typer_argument_type is not None:
    typer.core.TyperArgument.display_type_rich = _argument_type

EXIT_BAD_INPUT = 2
EXIT_FAILED = 1
"""A run diverged (NaN/Inf), sweep runs failed or a gallery figure failed."""
EXIT_CONTACT = 3
"""A body reached the dish's edge or two bodies' footprints met: the run ended there."""
EXIT_INTERRUPTED = 130

SetOption = Annotated[
    list[str] | None,
    typer.Option(
        "--set",
        metavar="KEY.PATH=VALUE",
        help="Override one config value, e.g. --set protocol.t_stop=1.5 (repeatable).",
        show_default=False,
    ),
]


def fail(message: str, code: int = EXIT_BAD_INPUT) -> NoReturn:
    """Print ``error: message`` on stderr and exit with `code`."""
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(code)


class _WarningLine(logging.Handler):
    """Prints each warning record of the package as one line ``warning: ...`` on stderr
    (through tqdm, so that a progress bar on screen moves below it)."""

    def emit(self, record: logging.LogRecord) -> None:
        if record.levelno != logging.WARNING:
            return  # errors reach the user as the command's own `error:` line
        from tqdm import tqdm

        tqdm.write(f"warning: {record.getMessage()}", file=sys.stderr)


@contextmanager
def warnings_shown() -> Iterator[None]:
    """While inside, every warning the package logs (a body outrunning the lattice, a
    ``--set protocol...`` that reaches no body) is also one line on stderr."""
    logger = logging.getLogger("pde_rotor")
    handler = _WarningLine(logging.WARNING)
    logger.addHandler(handler)
    try:
        yield
    finally:
        logger.removeHandler(handler)


def output_dir(path: Path, option: str = "--out") -> Path:
    """`path` if a command can create and write the directory there, else one line, exit 2.

    Called before any compute (:func:`pde_rotor.io.output.check_output_dir`).
    """
    try:
        return check_output_dir(path, option)
    except OutputError as err:
        fail(str(err))


def output_file(path: Path, option: str = "--out") -> Path:
    """`path` if a command can write that file, else one line and exit 2 (before compute)."""
    try:
        return check_output_file(path, option)
    except OutputError as err:
        fail(str(err))
