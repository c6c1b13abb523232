"""What every ``pde-rotor`` command shares: the exit codes, the one-line failure and the
``--set`` option.

Exit codes: 0 success; 1 the simulation diverged or a figure failed; 2 bad input (always
one line ``error: ...`` on stderr, before anything is computed); 130 interrupted.
"""

from __future__ import annotations

from typing import Annotated, NoReturn

import typer

EXIT_BAD_INPUT = 2
EXIT_FAILED = 1
"""A run diverged (NaN/Inf), sweep runs failed or a gallery figure failed."""
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
