"""``pde-rotor stability``: a spectrum and a branch on a coarse grid; bad input is one line."""

from __future__ import annotations

from pathlib import Path

import pytest
import xarray as xr
from typer.testing import CliRunner

from pde_rotor.cli.main import app

COARSE = "grid: {dx: 0.05, dt: 4.0e-4}\nflow: {enabled: false}\n"


@pytest.fixture
def config(tmp_path: Path) -> Path:
    path = tmp_path / "coarse.yaml"
    path.write_text(COARSE)
    return path


def invoke(*args: str):
    return CliRunner().invoke(app, ["stability", *args])


def test_spectrum_prints_the_leading_eigenvalue_and_draws_its_mode(
    config: Path, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    result = invoke(str(config), "--k", "3", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert "lambda_0 = +15." in result.output
    assert (out / "mode0.png").stat().st_size > 0
    assert (out / "spectrum.json").exists()


def test_branch_finds_the_rotor_onset_friction(config: Path, tmp_path: Path) -> None:
    out = tmp_path / "branch"
    args = ["--param", "rotor.friction", "--from", "1e-3", "--to", "1e-2", "--points", "2"]
    result = invoke(str(config), *args, "--k", "3", "--rtol", "1e-3", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert "critical rotor.friction = " in result.output
    assert "pitchfork" in result.output
    with xr.open_dataset(out / "branch.nc") as data:
        assert data.attrs["key"] == "rotor.friction"
        assert data.attrs["critical_kind_0"] == "pitchfork"
    assert (out / "branch.png").exists()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--param", "rotor.fiction", "--from", "1", "--to", "2"], "--param rotor.fiction = 1"),
        (["--param", "rotor.friction", "--from", "1e-3", "--to", "7"], "rotor.friction = 7"),
        (["--param", "rotor.friction", "--from", "1e-3"], "--from A --to B"),
        (["--param", "rotor.friction", "--from", "1", "--to", "1"], "an empty range"),
        (["--param", "rotor.friction", "--from", "1e-3", "--to", "2e-3", "--points", "1"],
         "--points 1"),
        (["--from", "1", "--to", "2"], "without --param"),
        (["--k", "0"], "--k 0"),
    ],
)  # fmt: skip
def test_bad_input_is_one_line(config: Path, args: list[str], message: str) -> None:
    result = invoke(str(config), *args)
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    assert message in lines[0]


def test_two_rotors_have_two_turning_modes(tmp_path: Path) -> None:
    """configs/bodies/two_rotors.yaml (two hexagon rotors 3 apart, fixed axes) on the coarse
    grid: one mechanical unknown per rotor, and two unstable real modes, each at about the
    rate of a lone paper rotor (+15, the test above), then the camphor's decaying ones."""
    args = ["--set", "grid.dx=0.05", "--set", "grid.dt=4e-4", "--set", "grid.domain_radius=3"]
    result = invoke("configs/bodies/two_rotors.yaml", *args, "--k", "3", "-o", str(tmp_path))
    assert result.exit_code == 0, result.output
    assert "2 mechanical" in result.output
    rates = [
        float(line.split("=")[1].split()[0])
        for line in result.output.splitlines()
        if line.startswith("lambda_")
    ]
    assert len(rates) == 3
    assert 13.0 < rates[1] <= rates[0] < 17.0
    assert rates[2] < 0.0
