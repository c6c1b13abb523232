"""``pde-rotor predict``: point, calibrate and map read a table; bad input is one line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from pde_rotor.cli.main import app
from tests.decision.test_table import synthetic


@pytest.fixture
def table_path(tmp_path: Path) -> Path:
    path = tmp_path / "table.nc"
    synthetic().save(path)
    return path


def invoke(*args: str):
    return CliRunner().invoke(app, ["predict", *args])


def test_point_prints_the_table_probabilities(table_path: Path) -> None:
    args = ["--t-stop", "3", "--asymmetry", "2e-5", "--dw", "1e-4"]
    result = invoke("point", str(table_path), *args)
    assert result.exit_code == 0, result.output
    p = float(synthetic().probability(3.0, 2e-5, 1e-4))
    assert f"P = {p:.3f}" in result.output


def test_point_takes_the_stop_duration_repeated(table_path: Path) -> None:
    args = ["--t-stop", "1", "--t-stop", "2.5", "--asymmetry", "2e-5", "--dw", "1e-4"]
    result = invoke("point", str(table_path), *args)
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert [line.split(",")[0] for line in lines] == ["t_stop = 1", "t_stop = 2.5"]
    for t, line in zip((1.0, 2.5), lines, strict=True):
        assert f"P = {float(synthetic().probability(t, 2e-5, 1e-4)):.3f}" in line


def test_point_takes_the_asymmetry_repeated(table_path: Path) -> None:
    """Two --asymmetry values give every t_stop at both (the option kept only the last)."""
    args = ["--t-stop", "1", "--t-stop", "3", "--asymmetry", "0", "--asymmetry", "2e-5"]
    result = invoke("point", str(table_path), *args, "--dw", "1e-4")
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    points = [(1.0, 0.0), (3.0, 0.0), (1.0, 2e-5), (3.0, 2e-5)]
    assert len(lines) == len(points)
    for (t, delta), line in zip(points, lines, strict=True):
        assert line.startswith(f"t_stop = {t:g}, Delta = {delta:g},")
        assert f"P = {float(synthetic().probability(t, delta, 1e-4)):.3f}" in line


def test_sigma_and_dw_give_the_same_point(table_path: Path) -> None:
    by_dw = invoke("point", str(table_path), "--t-stop", "2", "--dw", "4e-4")
    by_sigma = invoke("point", str(table_path), "--t-stop", "2", "--sigma", "2e-7")
    assert by_dw.exit_code == by_sigma.exit_code == 0
    assert by_dw.output.split("P(inv|CCW)")[1] == by_sigma.output.split("P(inv|CCW)")[1]


def test_calibrate_prints_dw_and_sigma(table_path: Path) -> None:
    result = invoke("calibrate", str(table_path), "--target", "0.2")
    assert result.exit_code == 0, result.output
    dw = synthetic().calibrate(0.2, 3.0, 2e-5, (1e-9, 1e2))
    assert f"Dw = {dw:.4g}" in result.output


def test_map_draws_the_predicted_fig9_with_report_points(table_path: Path, tmp_path: Path) -> None:
    report = xr.Dataset(
        {name: (("asymmetry", "t_stop"), np.full((2, 2), 0.4)) for name in ("P", "P_low")}
        | {"P_high": (("asymmetry", "t_stop"), np.full((2, 2), 0.6))},
        coords={"asymmetry": [0.0, 2e-5], "t_stop": [1.0, 3.0]},
    )
    report.to_netcdf(tmp_path / "report.nc")
    out = tmp_path / "figs"
    result = invoke(
        "map", str(table_path), "--dw", "2e-4", "--out", str(out), "--resolution", "20",
        "--report", str(tmp_path / "report.nc"),
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert (out / "fig9_predicted.png").stat().st_size > 0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["point", "{table}", "--t-stop", "1"], "exactly one of --dw"),
        (["point", "{table}", "--t-stop", "1", "--dw", "1", "--sigma", "1"], "exactly one"),
        (["point", "{table}", "--t-stop", "9", "--dw", "1e-4"], "--t-stop 9"),
        (["point", "{table}", "--t-stop", "1", "--dw", "-1"], "--dw -1"),
        (["point", "missing.nc", "--t-stop", "1", "--dw", "1"], "no such decision table"),
        (["calibrate", "{table}", "--target", "0.95"], "not reached"),
        (["map", "{table}", "--dw", "1e-4", "--t-stop-max", "9"], "--t-stop-max 9"),
    ],
)
def test_bad_input_is_one_line(table_path: Path, args: list[str], message: str) -> None:
    result = invoke(*[a.format(table=table_path) for a in args])
    assert result.exit_code == 2
    assert message in result.output
    assert result.output.count("error:") == 1


def test_measure_refuses_a_symmetric_reference_before_running(tmp_path: Path) -> None:
    config = tmp_path / "c.yaml"
    config.write_text("geometry: {asymmetry: 0.0}\n")
    result = invoke("measure", str(config), "--out", str(tmp_path / "t.nc"))
    assert result.exit_code == 2
    assert "geometry.asymmetry = 0" in result.output
    base = invoke("measure", "paper", "--out", str(tmp_path / "t.nc"))  # a shipped base
    assert base.exit_code == 2 and "geometry.asymmetry = 0" in base.output
    bad = invoke("measure", str(config), "--out", str(tmp_path / "t.nc"), "--set", "grid.dx=-1")
    assert bad.exit_code == 2 and "grid.dx" in bad.output


def test_check_prints_coverage_and_refuses_another_grid(table_path: Path, tmp_path: Path) -> None:
    from tests.decision.test_check import model_report

    model_report().to_netcdf(tmp_path / "same.nc")
    result = invoke("check", str(table_path), str(tmp_path / "same.nc"), "--plot", str(tmp_path))
    assert result.exit_code == 0, result.output
    assert "all 1.00 of 18 intervals" in result.output
    assert "master curve: 12 conditionals" in result.output
    assert (tmp_path / "master_curve.png").stat().st_size > 0
    model_report(grid={"dx": 0.05}).to_netcdf(tmp_path / "other.nc")
    other = invoke("check", str(table_path), str(tmp_path / "other.nc"))
    assert other.exit_code == 2 and other.output.count("error:") == 1
    assert "grid.dx = 0.05 in the ensemble" in other.output


def fake_bank_store(path: Path, base: dict, **axes: list) -> None:
    """A bank sweep at t_stop = 3, Δ = 2e-5, two sigma (and `axes` by dotted key), 20
    stops per direction, whose releases all go CW (against Δ from CCW: an inversion;
    from CW: none)."""
    from pde_rotor.sweep.store import RunLog, prepare
    from tests.sweep.test_sweep import tiny_sweep

    sweep = tiny_sweep(
        base=base,
        set={"geometry.asymmetry": 2e-5, "protocol.t_stop": 3.0},
        axes={"noise.sigma": [1e-7, 2e-7], **axes},
        estimator={"kind": "bank", "warmup": 2.0},
        samples=20,
    )
    prepare(sweep, path)
    with RunLog(path) as log:
        for run in sweep.runs():
            result = {"direction_before": run.direction, "direction_after": -1}
            log.append({"key": run.key, "result": result})


def test_calibrate_fits_the_ensemble_of_a_sweep(table_path: Path, tmp_path: Path) -> None:
    fake_bank_store(tmp_path / "bank", {})
    result = invoke("calibrate", str(table_path), "--sweep", str(tmp_path / "bank"))
    assert result.exit_code == 0, result.output
    assert "ensemble (40 stops, 4 noisy counts)" in result.output
    assert "calibrated: Dw = " in result.output


def test_calibrate_takes_the_table_grid_of_a_sweep_along_dx(
    table_path: Path, tmp_path: Path
) -> None:
    """A grid comparison gives its runs at the table's dx (0.025, matched
    to 1e-6), and says how many of the other grid's it leaves out: never pooled."""
    fake_bank_store(tmp_path / "bank", {}, **{"grid.dx": [0.0333333333, 0.025000000001]})
    result = invoke("calibrate", str(table_path), "--sweep", str(tmp_path / "bank"))
    assert result.exit_code == 0, result.output
    assert "80 runs left out (grid.dx = 0.0333333333 in the ensemble" in result.output
    assert "ensemble (40 stops, 4 noisy counts)" in result.output


def test_calibrate_refuses_a_sweep_of_another_grid(table_path: Path, tmp_path: Path) -> None:
    fake_bank_store(tmp_path / "bank", {"grid": {"dx": 0.05, "dt": 4e-4}})
    result = invoke("calibrate", str(table_path), "--sweep", str(tmp_path / "bank"))
    assert result.exit_code == 2
    assert result.output.count("\n") == 1
    assert "grid.dx = 0.05 in the ensemble" in result.output
    missing = invoke("calibrate", str(table_path), "--sweep", str(tmp_path))
    assert missing.exit_code == 2
    assert "not a sweep directory" in missing.output


def test_check_reads_an_older_report_with_the_current_rule(
    table_path: Path, tmp_path: Path
) -> None:
    """A report written before the Delta = 0 rule holds the chain value in P; check
    compares the model with the pooled fraction that the gallery draws."""
    from pde_rotor.statistics.proportions import wilson_interval
    from tests.decision.test_check import model_report

    old = model_report(geometry={"asymmetry": 0.0}).isel(t_stop=[2], sigma=[0])
    old["inversions"] = (("t_stop", "sigma"), [[14]])
    old["stops"] = (("t_stop", "sigma"), [[40]])
    old.attrs["estimator"] = "restart"
    old.to_netcdf(tmp_path / "old.nc", engine="h5netcdf")
    result = invoke("check", str(table_path), str(tmp_path / "old.nc"))
    assert result.exit_code == 0, result.output
    low, high = wilson_interval(14, 40)
    assert f"P = 0.350 [{low:.3f}, {high:.3f}]" in result.output


def test_map_names_a_report_point_beyond_the_table(table_path: Path, tmp_path: Path) -> None:
    from tests.decision.test_check import model_report

    model_report().assign_coords(t_stop=[1.0, 2.0, 3.75]).to_netcdf(tmp_path / "far.nc")
    result = invoke(
        "map", str(table_path), "--dw", "2e-4", "--out", str(tmp_path / "figs"),
        "--report", str(tmp_path / "far.nc"),
    )  # fmt: skip
    assert result.exit_code == 2
    assert result.output.count("error:") == 1
    assert "t_stop = 3.75 lies beyond the table's range [0, 3.5]" in result.output
