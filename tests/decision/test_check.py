"""The model against reports: coverage and deviation on reports made from the model."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from pde_rotor.config import RotorConfig
from pde_rotor.decision.check import compare, report_points, table_for
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
