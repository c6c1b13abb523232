"""The predicted Fig. 9 map: the report points it draws and the map it returns."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pde_rotor.decision.map import draw_map, ensemble_points, model_curve
from pde_rotor.decision.table import diffusion_of
from tests.decision.test_table import synthetic


def report(sigmas: list[float]) -> xr.Dataset:
    shape = (2, 3, len(sigmas))
    p = np.arange(np.prod(shape), dtype=float).reshape(shape) / 100
    dims = ("asymmetry", "t_stop", "sigma")
    return xr.Dataset(
        {"P": (dims, p), "P_low": (dims, p - 0.01), "P_high": (dims, p + 0.01)},
        coords={"asymmetry": [0.0, 2e-5], "t_stop": [1.0, 2.0, 3.0], "sigma": sigmas},
    )


def test_points_at_the_maps_noise_only() -> None:
    ds = report([0.0, 1.5e-7, 3e-7])
    points = ensemble_points(synthetic(), [ds], sigma=1.5e-7)
    assert len(points) == 6
    want = ds.sel(sigma=1.5e-7)
    for t, d, p, low, high in points:
        value = float(want["P"].sel(t_stop=t, asymmetry=d))
        assert (p, low, high) == (value, value - 0.01, value + 0.01)
    assert ensemble_points(synthetic(), [ds], sigma=2e-7) == []  # no report point at that noise


def test_fixed_values_come_from_the_base_config() -> None:
    ds = report([1.5e-7]).isel(asymmetry=0, t_stop=2, drop=True)
    ds.attrs["base_config"] = json.dumps(
        {"geometry": {"asymmetry": 2e-5}, "protocol": {"t_stop": 3.0}}
    )
    ((t, d, p, _, _),) = ensemble_points(synthetic(), [ds], sigma=1.5e-7)
    assert (t, d, p) == (3.0, 2e-5, float(ds["P"].values.item()))


def test_points_of_another_grid_are_left_out() -> None:
    """A report comparing grids (a dx axis) gives the points of the table's dx only."""
    base = report([1.5e-7]).isel(sigma=0, drop=True)
    dx = synthetic().attrs["config"]
    table_dx = json.loads(dx)["grid"]["dx"]
    ds = xr.concat([base, base + 0.5], dim=xr.DataArray([table_dx, 1 / 30], dims="dx"))
    ds.attrs["base_config"] = json.dumps({"noise": {"sigma": 1.5e-7}})
    points = ensemble_points(synthetic(), [ds], sigma=1.5e-7)
    assert len(points) == 6
    assert all(p < 0.5 for _, _, p, _, _ in points)  # the table's grid, not the other


def test_map_is_the_tables_probability(tmp_path: Path) -> None:
    table = synthetic()
    paths, p = draw_map(table, 2e-4, tmp_path, resolution=(12, 5), t_range=(0.5, 3.0))
    assert [x.suffix for x in paths] == [".png", ".pdf"]
    np.testing.assert_allclose(p[2], table.probability(np.linspace(0.5, 3.0, 12), 5e-5, 2e-4))


def test_reports_of_another_scheme_or_flow_are_left_out() -> None:
    """The paper scheme's and the no-flow reports at the same noise give no points."""
    ds = report([1.5e-7])
    for other in ({"numerics": {"scheme": "paper"}}, {"flow": {"enabled": False}}):
        ds.attrs["base_config"] = json.dumps(other)
        assert ensemble_points(synthetic(), [ds], sigma=1.5e-7) == []


def test_model_curve_is_the_closed_form_escape_along_either_axis() -> None:
    """Along t_stop and along Delta the curve is the chain value 2ab/(a + b) of the
    closed-form conditionals a = 1 - Phi(beta_CCW / s), b = Phi(beta_CW / s),
    s = sqrt(lambda Dw) (:func:`test_decision.closed_bias`), and the two axes meet."""
    from scipy.stats import norm

    from tests.decision.test_table import LAM, closed_bias

    table, sigma = synthetic(), 1.5e-7
    scale = np.sqrt(LAM * diffusion_of(sigma, table.inertia))

    def closed(t: np.ndarray, delta: float) -> np.ndarray:
        a = 1 - norm.cdf(closed_bias(t, 1, delta) / scale)
        b = norm.cdf(closed_bias(t, -1, delta) / scale)
        return 2 * a * b / (a + b)

    t = np.array([0.5, 1.0, 1.5, 3.0])
    along_t = model_curve(table, "t_stop", t, sigma, asymmetry=2e-5)
    np.testing.assert_allclose(along_t, closed(t, 2e-5), atol=2e-3)
    deltas = np.array([1e-5, 2e-5, 4e-5])
    along_delta = model_curve(table, "asymmetry", deltas, sigma, t_stop=3.0)
    want = [closed(np.array([3.0]), d)[0] for d in deltas]
    np.testing.assert_allclose(along_delta, want, atol=2e-3)
    assert along_delta[1] == pytest.approx(along_t[-1], abs=1e-12)
    with pytest.raises(ValueError, match="x_dim"):
        model_curve(table, "sigma", deltas, sigma, t_stop=3.0)


def test_map_draws_and_counts_only_the_points_in_its_frame(tmp_path: Path, monkeypatch) -> None:
    """A point beyond the drawn t_stop range is neither drawn nor counted in the title."""
    import pde_rotor.decision.map as module

    drawn = {}
    original = module.save_figure

    def keep(fig, *args, **kwargs):
        drawn["title"] = fig.axes[0].get_title()
        drawn["markers"] = len(fig.axes[0].collections)
        return original(fig, *args, **kwargs)

    monkeypatch.setattr(module, "save_figure", keep)
    inside, beyond = (1.0, 2e-5, 0.9, 0.8, 1.0), (3.75, 0.0, 0.6, 0.5, 0.7)
    draw_map(synthetic(), 2e-4, tmp_path, resolution=(12, 5), points=[inside, beyond])
    with_one = (drawn["title"], drawn["markers"])
    draw_map(synthetic(), 2e-4, tmp_path, resolution=(12, 5), points=[inside])
    assert with_one == (drawn["title"], drawn["markers"])
    assert "; 1 ensemble points (markers)" in with_one[0]
