"""``pde-rotor plot`` and ``pde-rotor report --plot``: what they draw from a report file, a
sweep directory or a sweep file, and one line with exit code 2 for bad input."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from matplotlib.collections import QuadMesh
from matplotlib.figure import Figure
from typer.testing import CliRunner

from pde_rotor.cli.main import app
from pde_rotor.statistics.proportions import CCW, CW
from pde_rotor.sweep import REPORT_FILE, gather
from pde_rotor.sweep import plot as report_module
from pde_rotor.sweep.store import prepare
from tests.sweep.test_plot import p_line
from tests.sweep.test_sweep import TINY_SWEEP, fake_restarts, tiny_sweep

DATA = Path(__file__).resolve().parents[2] / "data"
runner = CliRunner()


def invoke(*args: object):
    return runner.invoke(app, [str(a) for a in args], catch_exceptions=False)


@pytest.fixture
def drawn(monkeypatch) -> list[Figure]:
    """The figures the command draws (report_figure spied on)."""
    figures: list[Figure] = []
    original = report_module.report_figure

    def spy(*args, **kwargs) -> Figure:
        figures.append(original(*args, **kwargs))
        return figures[-1]

    monkeypatch.setattr(report_module, "report_figure", spy)
    return figures


def sweep_dir(path: Path, t_stop: list[float]) -> Path:
    """A sweep directory of the tiny restart sweep along t_stop, with faked run files
    (3 of 4 inversions from CCW, none from CW) and no report yet."""
    sweep = tiny_sweep(samples=4, axes={"protocol.t_stop": t_stop})
    fake_restarts(path, sweep, {CCW: 3, CW: 0})
    prepare(sweep, path)
    return path


def listing(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


def written_to(result) -> Path:
    """The file a command reported writing last ("wrote FILE")."""
    return Path(result.output.splitlines()[-1].removeprefix("wrote "))


def test_a_stored_report_is_drawn_into_a_run_folder_or_into_out(
    tmp_path, monkeypatch, drawn
) -> None:
    """Without --out the figure goes into a new folder runs/<name>-plot-<time>/, never
    beside the report it reads (the repository's data/ stays clean)."""
    monkeypatch.chdir(tmp_path)
    shutil.copy(DATA / "fig5.nc", tmp_path / "fig5.nc")
    result = invoke("plot", tmp_path / "fig5.nc")
    assert result.exit_code == 0, result.output
    figure = written_to(result)
    assert figure.name == "fig5.png" and figure.parent.name.startswith("fig5-plot-")
    assert figure.parent.parent == Path("runs")
    assert figure.read_bytes()[:4] == b"\x89PNG"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig5.nc", "runs"]
    (fig,) = drawn
    assert len(p_line(fig.axes[0])) == 16
    result = invoke("plot", DATA / "fig9.nc", "--out", tmp_path / "new" / "fig9.svg")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "new" / "fig9.svg").read_text().startswith("<?xml")
    (mesh,) = [c for c in drawn[1].axes[0].collections if isinstance(c, QuadMesh)]
    assert np.ma.count_masked(mesh.get_array()) == 176 - 32


def test_x_picks_the_axis(tmp_path, drawn) -> None:
    result = invoke("plot", DATA / "fig9.nc", "--x", "asymmetry", "-o", tmp_path / "f.png")
    assert result.exit_code == 0, result.output
    assert drawn[0].axes[0].get_xlabel().startswith("asymmetry")


def test_a_sweep_directory_without_report_gets_one_beside_the_figure(
    tmp_path, monkeypatch, drawn
) -> None:
    monkeypatch.chdir(tmp_path)
    store = sweep_dir(tmp_path / "store", [0.2, 0.6, 1.2])
    before = listing(store)
    result = invoke("plot", store)
    assert result.exit_code == 0, result.output
    figure = written_to(result)
    assert result.output.splitlines() == [
        f"report: {figure.parent / REPORT_FILE}",
        f"wrote {figure}",
    ]
    assert figure.name == "store.png" and listing(store) == before
    written = xr.load_dataset(figure.parent / REPORT_FILE, engine="h5netcdf")
    sweep = tiny_sweep(samples=4, axes={"protocol.t_stop": [0.2, 0.6, 1.2]})
    xr.testing.assert_identical(written, gather(sweep, store))
    np.testing.assert_allclose(p_line(drawn[0].axes[0])[:, 1], written["P"].values)


def test_a_sweep_file_is_drawn_from_its_default_directory(tmp_path, monkeypatch, drawn) -> None:
    monkeypatch.chdir(tmp_path)
    spec = {**TINY_SWEEP, "samples": 4, "axes": {"protocol.t_stop": [0.2, 1.2]}}
    path = tmp_path / "mine.yaml"
    path.write_text(yaml.safe_dump(spec), encoding="utf-8")
    missing = invoke("plot", path)
    assert missing.exit_code == 2
    assert "its sweep directory data/sweeps/mine does not exist" in missing.stderr
    sweep_dir(tmp_path / "data" / "sweeps" / "mine", [0.2, 1.2])
    before = listing(tmp_path / "data")
    result = invoke("plot", path)
    assert result.exit_code == 0, result.output
    assert written_to(result).name == "mine.png" and listing(tmp_path / "data") == before
    assert len(p_line(drawn[0].axes[0])) == 2


def test_plot_and_report_of_the_shipped_sweeps_leave_the_repository_unchanged(
    tmp_path, monkeypatch, drawn
) -> None:
    """``plot`` and ``report`` of a stored sweep, with no --out, only read the folder:
    everything they write goes into runs/ of the working directory."""
    monkeypatch.chdir(tmp_path)
    store = DATA / "sweeps" / "fig7b"
    before = {p: p.stat().st_mtime_ns for p in store.rglob("*")}
    for command in (["plot", store], ["report", store, "--plot"]):
        result = invoke(*command)
        assert result.exit_code == 0, result.output
    assert {p: p.stat().st_mtime_ns for p in store.rglob("*")} == before
    assert [p.name for p in tmp_path.iterdir()] == ["runs"]


def test_report_plot_draws_the_report_it_writes(tmp_path, monkeypatch, drawn) -> None:
    monkeypatch.chdir(tmp_path)
    store = sweep_dir(tmp_path / "store", [0.2, 1.2])
    before = listing(store)
    result = invoke("report", store, "--plot")
    assert result.exit_code == 0, result.output
    figure = written_to(result)
    assert figure.parent.name.startswith("store-report-") and figure.name == "report.png"
    assert f"report: {figure.parent / REPORT_FILE}" in result.output
    assert listing(store) == before
    assert len(p_line(drawn[0].axes[0])) == 2
    result = invoke("report", store, "-o", tmp_path / "r.nc", "--plot-out", tmp_path / "r.pdf")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "r.pdf").read_bytes()[:4] == b"%PDF"
    footer = "".join(drawn[1].texts[-1].get_text().split())  # wrapped: no whitespace
    assert f"report:{tmp_path / 'r.nc'};" in footer


BAD = {
    "missing file": (["plot", "{tmp}/nothing.nc"], "{tmp}/nothing.nc: no such file or directory"),
    "not NetCDF": (["plot", "{tmp}/notes.txt"], "is not a sweep report: cannot read it as NetCDF"),
    "not a report": (["plot", str(DATA / "decision" / "dx40.nc")], "not a sweep report (no"),
    "not a sweep directory": (["plot", "{tmp}"], "holds neither report.nc nor sweep.yaml"),
    "unknown axis": (
        ["plot", str(DATA / "fig5.nc"), "--x", "sigma", "-o", "{tmp}/f.png"],
        "the report has no axis 'sigma' (its axes: t_stop)",
    ),
    "output is a directory": (
        ["plot", str(DATA / "fig5.nc"), "-o", "{tmp}"],
        "{tmp} is a directory: give an image file",
    ),
    "a file where a directory is needed": (
        ["plot", str(DATA / "fig5.nc"), "-o", "{tmp}/notes.txt/sub/f.png"],
        "{tmp}/notes.txt' is a file, not a directory",
    ),
    "unknown image format": (
        ["plot", str(DATA / "fig5.nc"), "-o", "{tmp}/f.xyz"],
        "unknown image format 'xyz'",
    ),
    "unwritable": (
        ["plot", str(DATA / "fig5.nc"), "-o", "/proc/f.png"],
        "'/proc/f.png': cannot create or write there",
    ),
    "report --plot-out a directory": (
        ["report", "{tmp}/store", "--plot-out", "{tmp}"],
        "{tmp} is a directory",
    ),
}


@pytest.mark.parametrize("case", BAD, ids=list(BAD))
def test_bad_input_is_one_line_and_leaves_nothing_behind(tmp_path, case) -> None:
    args, message = BAD[case]
    (tmp_path / "notes.txt").write_text("not a report\n")
    if "store" in args[1]:
        sweep_dir(tmp_path / "store", [0.2, 1.2])
    before = listing(tmp_path)
    result = invoke(*(a.format(tmp=tmp_path) for a in args))
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ") and result.stderr.count("\n") == 1
    assert message.format(tmp=tmp_path) in result.stderr
    assert listing(tmp_path) == before


def test_an_unknown_axis_leaves_no_report_in_a_sweep_directory(tmp_path) -> None:
    store = sweep_dir(tmp_path / "store", [0.2, 1.2])
    result = invoke("plot", store, "--x", "sigma")
    assert result.exit_code == 2 and "no axis 'sigma'" in result.stderr
    assert not (store / REPORT_FILE).exists()


def test_a_failed_write_removes_the_directories_it_made(tmp_path, monkeypatch) -> None:
    def full_disk(self, fname, **kwargs) -> None:
        Path(fname).write_bytes(b"partial")
        raise OSError(28, os.strerror(28))

    monkeypatch.setattr(Figure, "savefig", full_disk)
    result = invoke("plot", DATA / "fig5.nc", "-o", tmp_path / "a" / "b" / "f.png")
    assert result.exit_code == 2
    assert result.stderr == f"error: cannot write {tmp_path}/a/b/f.png: No space left on device\n"
    assert listing(tmp_path) == []
