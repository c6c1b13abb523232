"""The report of a collective sweep, from records written here (no simulation)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.model.surface import POSE_COLUMNS
from pde_rotor.sweep import Sweep, SweepSpec, format_table, gather
from pde_rotor.sweep.estimators.base import run_content
from pde_rotor.sweep.estimators.collective import Trajectory, collective_result
from pde_rotor.sweep.spec import CollectiveEstimator
from pde_rotor.sweep.store import RunLog, prepare

DISK = {
    "plate": {"shape": "none"},
    "pills": [{"radius": 0.1}],
    "motion": {"kind": "free", "mass": 1.0e-3, "inertia": 5.0e-6},
}


def ring_sweep() -> Sweep:
    annulus = {"shape": "annulus", "inner_radius": 1.0, "outer_radius": 2.2}
    spec = {
        "name": "synthetic_ring",
        "base": {
            "grid": {"domain_radius": 2.2, "dx": 0.04, "dt": 2.0e-4, "vessel": annulus},
            "geometry": {"smoothing": 0.02},
            "protocol": {"t_ini": 1.0, "cycles": 0},
        },
        "crowd": {"count": 2, "body": DISK, "placement": {"kind": "ring", "radius": 1.6}},
        "axes": {"crowd.count": [2, 4]},
        "estimator": {"kind": "collective", "record_interval": 0.25},
        "samples": 2,
        "seed": 0,
    }
    return Sweep.from_spec(SweepSpec.model_validate(spec))


def turning(n: int, t: np.ndarray, omega: float) -> np.ndarray:
    """Poses of n bodies evenly spaced on the circle of radius 1.6, turning at omega."""
    angle = omega * t[:, None] + 2 * math.pi * np.arange(n) / n
    p = np.zeros((len(t), n, len(POSE_COLUMNS)))
    p[..., 0], p[..., 1] = 1.6 * np.cos(angle), 1.6 * np.sin(angle)
    p[..., 3], p[..., 4] = -omega * p[..., 1], omega * p[..., 0]
    return p


def test_a_ring_report_by_point_sample_and_time(tmp_path) -> None:
    """Runs of N = 2 turning at 0.5, of N = 4 at rest; sample 1 recorded to t = 0.5 only
    (NaN after it), the N = 4 run said to have ended early, its sample 1 missing."""
    sweep = ring_sweep()
    prepare(sweep, tmp_path)
    estimator = CollectiveEstimator.model_validate(sweep.runs()[0].estimator)
    with RunLog(tmp_path) as log:
        for run in sweep.runs()[:3]:
            n = run.coords["crowd.count"]
            t = np.arange(0, 1.01, 0.25) if run.sample == 0 else np.arange(0, 0.51, 0.25)
            path = Trajectory(t, turning(n, t, 0.5 if n == 2 else 0.0), "" if n == 2 else "x")
            config = RotorConfig.model_validate(run.config)
            result = collective_result(config, estimator, path)
            log.append(run_content(run, result, 1.0, "cpu", 0.5))
    ds = gather(sweep, tmp_path)
    assert ds.attrs["measures"] == "ring"
    assert ds["arc_speed"].sizes == {"count": 2, "sample": 2, "time": 5}
    np.testing.assert_allclose(ds["arc_speed"].sel(count=2, sample=0), 0.8)
    np.testing.assert_allclose(ds["arc_speed"].sel(count=2, sample=1)[:3], 0.8)
    assert np.isnan(ds["arc_speed"].sel(count=2, sample=1)[3:]).all()
    np.testing.assert_allclose(ds["arc_speed"].sel(count=4, sample=0), 0.0)
    assert np.isnan(ds["arc_speed"].sel(count=4, sample=1)).all()
    assert ds["runs_done"].values.tolist() == [2, 1]
    assert ds["mode"].values.tolist() == [[0, 0], [3, -1]]  # uniform; stop; no run
    assert ds["ended_early"].values.tolist() == [[0, 0], [1, -1]]
    table = format_table(ds)
    assert "uniform" in table and "stop" in table and "1/2" in table
    assert ds["mean_arc_speed"].sel(count=2).values == pytest.approx([0.8, 0.8])
