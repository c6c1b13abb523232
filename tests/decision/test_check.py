"""The model against reports: coverage and deviation on reports made from the model."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from pde_rotor.cli.main import app
from pde_rotor.config import RotorConfig
from pde_rotor.decision.check import compare, report_points, report_scheme, table_for
from pde_rotor.decision.table import diffusion_of
from tests.decision.test_table import synthetic


def model_report(shift: float = 0.0, **base: dict) -> xr.Dataset:
    """A report whose values are the synthetic table's predictions plus `shift`, +-0.05."""
    table = synthetic()
    t_stop, sigma = np.array([1.0, 2.0, 3.0]), np.array([1e-7, 2e-7])
    data = {}
    for name in ("P", "P_ccw", "P_cw"):
        values = np.empty((3, 2))
        for j, s in enumerate(sigma):
            a, b = table.conditionals(t_stop, 2e-5, diffusion_of(s, table.inertia))
            p = table.probability(t_stop, 2e-5, diffusion_of(s, table.inertia))
            values[:, j] = {"P": p, "P_ccw": a, "P_cw": b}[name] + shift
        for suffix, offset in (("", 0.0), ("_low", -0.05), ("_high", 0.05)):
            data[name + suffix] = (("t_stop", "sigma"), values + offset)
    ds = xr.Dataset(data, coords={"t_stop": t_stop, "sigma": sigma})
    ds.attrs["base_config"] = json.dumps({"geometry": {"asymmetry": 2e-5}, **base})
    ds.attrs["sweep"] = "model"
    ds.attrs["design"] = "independent: every run has its own stop"  # today's report format
    return ds


def test_points_read_axes_and_fixed_values() -> None:
    points = report_points(model_report())
    assert len(points) == 6
    assert {p["asymmetry"] for p in points} == {2e-5}
    assert sorted({p["sigma"] for p in points}) == [1e-7, 2e-7]


def test_the_model_covers_its_own_values_and_not_shifted_ones() -> None:
    table = synthetic()
    exact = compare(table, [model_report()])
    assert len(exact.rows) == 18 and exact.coverage() == 1.0
    assert (
        abs(exact.largest_deviation()["predicted"] - exact.largest_deviation()["measured"]) < 1e-12
    )
    shifted = compare(table, [model_report(shift=0.2)])
    assert shifted.coverage("P") == 0.0
    assert shifted.largest_deviation()["predicted"] - shifted.largest_deviation()["measured"] == (
        pytest.approx(-0.2)
    )


def test_a_report_of_another_grid_or_flow_is_refused() -> None:
    table = synthetic()
    with pytest.raises(ValueError, match=r"grid\.dx"):
        compare(table, [model_report(grid={"dx": 0.05})])
    with pytest.raises(ValueError, match=r"flow\.enabled"):
        compare(table, [model_report(flow={"enabled": False})])


def test_a_point_beyond_the_table_is_named() -> None:
    """A stop longer than the table's t_max has no prediction: the error names the
    report, the stop and the table's range, not a bare interpolation failure."""
    report = model_report().assign_coords(t_stop=[1.0, 2.0, 3.75])
    message = r"report model: t_stop = 3\.75 lies beyond the table's range \[0, 3\.5\]"
    with pytest.raises(ValueError, match=message):
        compare(synthetic(), [report])


def test_a_grid_comparison_contributes_the_points_of_the_tables_grid() -> None:
    """A report with a dx axis is accepted whatever its base dx; only the
    table's dx is compared (the other grid's values here are off by 0.3)."""
    table = synthetic()
    table_dx = RotorConfig.model_validate_json(table.attrs["config"]).grid.dx
    exact, off = model_report(), model_report(shift=0.3)
    ds = xr.concat([exact, off], dim=xr.DataArray([table_dx, 1 / 30], dims="dx"))
    base = {"geometry": {"asymmetry": 2e-5}, "grid": {"dx": 1 / 30}}
    ds.attrs = {**exact.attrs, "base_config": json.dumps(base)}
    result = compare(table, [ds])
    assert len(result.rows) == 18 and result.coverage() == 1.0


def test_unmeasured_points_of_a_partial_report_are_left_out() -> None:
    """A sweep still running reports its unmeasured points as NaN with 0 stops, some
    beyond the table's t_stop range: they are not compared (nor refused)."""
    table = synthetic()
    ds = model_report()
    ds["stops"] = (("t_stop", "sigma"), np.full((3, 2), 200))
    far = ds.isel(t_stop=[0]).assign_coords(t_stop=[99.0])
    far["stops"][:] = 0
    for name in ("P", "P_ccw", "P_cw"):
        far[name][:] = np.nan
    result = compare(table, [xr.concat([ds, far], dim="t_stop")])
    assert len(result.rows) == 18 and result.coverage() == 1.0


def test_master_points_of_the_model_lie_on_the_normal_cdf() -> None:
    """Without a lattice spread the model's own conditionals are Phi(x) exactly."""
    from scipy.stats import norm

    from pde_rotor.decision.check import master_points

    points = master_points(synthetic(), [model_report()])
    assert len(points) == 12
    for p in points:
        assert p["P"] == pytest.approx(norm.cdf(p["x"]), abs=1e-9)
        assert p["low"] <= p["P"] <= p["high"]


def test_the_table_of_a_report_is_the_one_holding_its_model(tmp_path) -> None:
    """Of several tables the one whose physics equals the report's in all but t_stop,
    Delta and sigma; none for a report of another grid or one comparing grids."""
    from dataclasses import replace

    flow = synthetic()
    no_flow_config = RotorConfig.model_validate({"flow": {"enabled": False}})
    no_flow = replace(flow, attrs={**flow.attrs, "config": no_flow_config.model_dump_json()})
    no_flow.save(tmp_path / "a_no_flow.nc")
    flow.save(tmp_path / "b_flow.nc")
    path, table = table_for(model_report(), tmp_path)
    assert path.name == "b_flow.nc" and table.growth_rate == flow.growth_rate
    path, _ = table_for(model_report(flow={"enabled": False}), tmp_path)
    assert path.name == "a_no_flow.nc"
    assert table_for(model_report(grid={"dx": 0.05}), tmp_path) is None
    grids = xr.concat([model_report(), model_report()], dim=xr.DataArray([0.025, 0.05], dims="dx"))
    assert table_for(grids, tmp_path) is None


def test_a_report_that_names_no_scheme_has_the_scheme_of_its_time() -> None:
    """Named in the base config or recorded in the attribute: that one; named nowhere:
    the default of its format (a report without the estimators' ``design`` attribute
    predates the default scheme and ran the paper's)."""
    assert report_scheme(model_report()) == "consistent"
    assert report_scheme(model_report(numerics={"scheme": "paper"})) == "paper"
    old = model_report()
    del old.attrs["design"]
    assert report_scheme(old) == "paper"
    old.attrs["scheme"] = "consistent"
    assert report_scheme(old) == "consistent"


def test_a_report_of_another_scheme_is_refused_even_when_it_names_none() -> None:
    table = synthetic()  # the default (consistent) scheme
    old = model_report()
    del old.attrs["design"]
    with pytest.raises(ValueError, match=r"numerics\.scheme = 'paper' in the ensemble"):
        compare(table, [old])
    with pytest.raises(ValueError, match=r"numerics\.scheme = 'paper'"):
        compare(table, [model_report(numerics={"scheme": "paper"})])
    assert compare(table, [model_report()]).coverage() == 1.0


ROOT = Path(__file__).resolve().parents[2]


def test_the_cli_refuses_the_stored_paper_scheme_reports_in_one_line() -> None:
    """data/calibration.nc and predictions.nc name no scheme; they ran the paper's."""
    data = ROOT / "data"
    result = CliRunner().invoke(
        app,
        [
            "predict",
            "check",
            str(data / "decision" / "dx40.nc"),
            str(data / "calibration.nc"),
            str(data / "predictions.nc"),
        ],
    )
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("error: report calibration")
    assert "numerics.scheme = 'paper' in the ensemble, 'consistent' in the table" in result.stderr
    assert "observed" not in result.stdout


def counted_report(shift: float = 0.0, **base: dict) -> xr.Dataset:
    """:func:`model_report` with the counts of 100 stops per direction behind its
    conditionals (rounded model values plus `shift`), as a restart ensemble."""
    ds = model_report(shift, **base)
    for column, direction in (("P_ccw", "ccw"), ("P_cw", "cw")):
        k = np.clip(np.round(100 * ds[column].values), 0, 100).astype(int)
        ds[f"inversions_{direction}"] = (("t_stop", "sigma"), k)
        ds[f"stops_{direction}"] = (("t_stop", "sigma"), np.full(k.shape, 100))
    ds["stops"] = (("t_stop", "sigma"), np.full((3, 2), 200))
    ds["inversions"] = ds["inversions_ccw"] + ds["inversions_cw"]
    ds.attrs["estimator"] = "restart"
    return ds


def test_the_cli_finds_every_stored_ensemble_and_its_table(tmp_path) -> None:
    """Without TABLE: every restart or bank report of DATA with the flow on against the
    table of its physics; one on a grid no table holds is named as left out; the flow-off
    report only with --flow off."""
    (tmp_path / "decision").mkdir()
    synthetic().save(tmp_path / "decision" / "table.nc")
    counted_report().to_netcdf(tmp_path / "near.nc", engine="h5netcdf")
    counted_report(shift=0.3).to_netcdf(tmp_path / "far.nc", engine="h5netcdf")
    counted_report(grid={"dx": 0.05}).to_netcdf(tmp_path / "coarse.nc", engine="h5netcdf")
    off = counted_report(flow={"enabled": False})
    off.attrs["sweep"] = "no_flow"
    off.to_netcdf(tmp_path / "off.nc", engine="h5netcdf")
    runner = CliRunner()
    result = runner.invoke(app, ["predict", "check", "--data", str(tmp_path), "--draws", "200"])
    assert result.exit_code == 0, result.output
    assert "left out: coarse.nc: no table" in result.stdout and "dx = 0.05" in result.stdout
    assert "table table.nc: model" in result.stdout
    assert "24 conditionals" in result.stdout  # near and far, 12 each
    assert "200 parametric-bootstrap draws" in result.stdout
    assert "no_flow" not in result.stdout
    result = runner.invoke(app, ["predict", "check", "--data", str(tmp_path), "--flow", "off"])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1
    assert "no table" in result.stderr and "off.nc" in result.stderr


def test_a_new_report_records_its_scheme_whether_or_not_its_base_names_it(tmp_path) -> None:
    """The report of a sweep whose base names no scheme records the one its runs used,
    so the default can change without the report changing meaning."""
    from pde_rotor.statistics.proportions import CCW, CW
    from pde_rotor.sweep import gather
    from tests.sweep.test_sweep import fake_restarts, tiny_sweep

    sweep = tiny_sweep(samples=2, axes={"protocol.t_stop": [0.5]})
    fake_restarts(tmp_path, sweep, {CCW: 1, CW: 0})
    report = gather(sweep, tmp_path)
    assert "scheme" not in json.loads(report.attrs["base_config"]).get("numerics", {})
    assert report.attrs["scheme"] == RotorConfig().numerics.scheme
    report.attrs["scheme"] = "paper"  # as if the default had been another
    assert report_scheme(report) == "paper"


def test_the_help_states_the_bootstraps_defaults() -> None:
    from pde_rotor.decision.goodness import DRAWS, SEED

    text = " ".join(CliRunner().invoke(app, ["predict", "check", "--help"]).stdout.split())
    assert f"[default: {DRAWS}]" in text and f"[default: {SEED}]" in text
