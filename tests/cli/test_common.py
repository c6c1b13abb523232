"""The shared CLI pieces: one line on stderr and the exit code, for every command."""

from __future__ import annotations

import pytest
import typer
from typer.testing import CliRunner

from pde_rotor.cli.common import (
    EXIT_BAD_INPUT,
    EXIT_CONTACT,
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    SetOption,
    fail,
)


def test_exit_codes_are_distinct_and_nonzero():
    codes = {EXIT_BAD_INPUT, EXIT_FAILED, EXIT_CONTACT, EXIT_INTERRUPTED}
    assert len(codes) == 4
    assert 0 not in codes


@pytest.mark.parametrize("code", [EXIT_BAD_INPUT, EXIT_FAILED])
def test_fail_prints_one_error_line_and_exits_with_the_code(code, capsys):
    with pytest.raises(typer.Exit) as err:
        fail("noise.sigma: must be >= 0", code)
    assert err.value.exit_code == code
    assert capsys.readouterr().err == "error: noise.sigma: must be >= 0\n"


def test_set_option_collects_repeated_overrides():
    app = typer.Typer()

    @app.command()
    def show(set_: SetOption = None) -> None:
        typer.echo(repr(set_))

    result = CliRunner().invoke(app, ["--set", "a.b=1", "--set", "c=2"])
    assert result.exit_code == 0
    assert result.output.strip() == "['a.b=1', 'c=2']"
