"""The collective estimator: measures of synthetic trajectories with known answers, and
one tiny crowd run stored, reported and resumed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor.collective.ring import MODES
from pde_rotor.config import RotorConfig
from pde_rotor.model.surface import POSE_COLUMNS
from pde_rotor.sweep import Sweep, SweepSpec, gather, read_runs
from pde_rotor.sweep.estimators.collective import (
    Trajectory,
    centres_radius,
    collective_result,
)
from pde_rotor.sweep.spec import CollectiveEstimator
from pde_rotor.sweep.store import RunLog, prepare
from pde_rotor.sweep.tasks import execute_group

DISK = {
    "plate": {"shape": "none"},
    "pills": [{"radius": 0.1}],
    "motion": {"kind": "free", "mass": 1.0e-3, "inertia": 5.0e-6, "friction": 1.0},
}
TINY = {
    "grid": {"domain_radius": 2.0, "dx": 0.04, "dt": 2.0e-4, "wall": "no_flux"},
    "geometry": {"smoothing": 0.02},
    "numerics": {"scheme": "paper"},
    "flow": {"enabled": False},
    "protocol": {"t_ini": 0.02, "cycles": 0},
    "output": {"progress": False},
}
"""A dish of radius 2 on a coarse grid (6 k cells), run for 100 steps."""


def dish_sweep(**changes) -> Sweep:
    spec = {
        "name": "tiny_crowd",
        "base": TINY,
        "crowd": {
            "count": 3,
            "body": DISK,
            "placement": {"kind": "scatter", "radius": 1.0, "min_distance": 1.05},
            "seed": 1,
        },
        "axes": {"crowd.count": [2, 3]},
        "estimator": {"kind": "collective", "record_interval": 0.01, "bins": 4},
        "samples": 2,
        "seed": 3,
    } | changes
    return Sweep.from_spec(SweepSpec.model_validate(spec))


def ring_config(n: int) -> RotorConfig:
    base = TINY | {
        "grid": {
            "domain_radius": 2.2,
            "dx": 0.04,
            "dt": 2.0e-4,
            "domain_centre": [0.5, -0.25],
            "vessel": {"shape": "annulus", "inner_radius": 1.0, "outer_radius": 2.2},
        }
    }
    spec = {
        "base": base,
        "crowd": {"count": n, "body": DISK, "placement": {"kind": "ring", "radius": 1.6}},
        "estimator": {"kind": "collective"},
        "samples": 1,
        "seed": 0,
    }
    sweep = Sweep.from_spec(SweepSpec.model_validate(spec))
    return RotorConfig.model_validate(sweep.runs()[0].config)


def poses(xy: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """(T, K, columns) poses with the given centres and velocities."""
    p = np.zeros((*xy.shape[:2], len(POSE_COLUMNS)))
    p[..., 0:2], p[..., 3:5] = xy, uv
    return p


def test_evenly_spaced_bodies_turning_together_are_uniform() -> None:
    config = ring_config(4)
    estimator = CollectiveEstimator(settle=0.5)
    assert estimator.resolve(config) == "ring"
    t = np.linspace(0, 2, 21)
    omega, r = 0.8, 1.6
    angle = omega * t[:, None] + 2 * math.pi * np.arange(4) / 4
    centre = np.array(config.grid.domain_centre)
    xy = centre + r * np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    uv = omega * r * np.stack([-np.sin(angle), np.cos(angle)], axis=-1)
    result = collective_result(config, estimator, Trajectory(t, poses(xy, uv), ""))
    summary = result["summary"]
    assert summary["angular_speed"] == pytest.approx(omega)
    assert summary["arc_speed"] == summary["abs_arc_speed"] == pytest.approx(omega * r)
    assert summary["spacing_spread"] == pytest.approx(0, abs=1e-12)
    assert summary["lattice_order"] == pytest.approx(1)
    assert MODES[summary["mode"]] == "uniform"
    assert len(result["t"]) == len(result["spacing_spread"]) == 21


def test_bodies_at_rest_have_stopped() -> None:
    config = ring_config(2)
    t = np.linspace(0, 1, 5)
    angle = np.array([0.0, 2.0])
    xy = np.tile(1.6 * np.stack([np.cos(angle), np.sin(angle)], axis=-1), (5, 1, 1))
    path = Trajectory(t, poses(xy + config.grid.domain_centre, np.zeros_like(xy)), "")
    result = collective_result(config, CollectiveEstimator(), path)
    assert MODES[result["summary"]["mode"]] == "stop"


def test_uncorrelated_disks_in_the_dish_pool_to_g_one() -> None:
    """Centres uniform in the centres' disk over many records: counted / expected = 1
    within the counting noise; a flock moving one way has polar order 1."""
    run = dish_sweep().runs()[-1]
    config = RotorConfig.model_validate(run.config)
    radius = centres_radius(config)
    assert radius == pytest.approx(2.0 - (0.1 + 20 * 0.02))
    rng = np.random.default_rng(0)
    frames = 3000
    r = radius * np.sqrt(rng.uniform(size=(frames, 3)))
    a = rng.uniform(0, 2 * math.pi, size=(frames, 3))
    xy = np.stack([r * np.cos(a), r * np.sin(a)], axis=-1)
    uv = np.tile([0.1, 0.0], (frames, 3, 1))
    estimator = CollectiveEstimator(bins=4)
    t = np.arange(frames) * 0.01
    result = collective_result(config, estimator, Trajectory(t, poses(xy, uv), ""))
    counts, expected = np.array(result["pair_counts"]), np.array(result["pair_expected"])
    assert expected.sum() == pytest.approx(3 * frames)
    np.testing.assert_allclose(counts / expected, 1.0, atol=5 / np.sqrt(expected.min()))
    assert result["summary"]["polar_order"] == pytest.approx(1.0)
    assert result["summary"]["mean_speed"] == pytest.approx(0.1)


def test_a_tiny_crowd_sweep_is_stored_reported_and_resumed(tmp_path) -> None:
    """Two runs computed as a dask worker would, stored, gathered; the sweep read again
    finds them by their keys (nothing to recompute)."""
    sweep = dish_sweep(axes={"crowd.count": [2]})
    runs = sweep.runs()
    assert [len(r.config["bodies"]) for r in runs] == [2, 2]
    assert runs[0].key != runs[1].key  # each sample its own scatter and seed
    prepare(sweep, tmp_path)
    with RunLog(tmp_path) as log:
        for group in runs:
            for content in execute_group([group]):
                log.append(content)
    stored = read_runs(tmp_path)
    again = dish_sweep(axes={"crowd.count": [2]})
    assert {r.key for r in again.runs()} == set(stored)
    record = stored[runs[0].key]
    assert record["cpu_time"] > 0 and record["result"]["end"] == ""
    assert record["result"]["t"] == pytest.approx([0.0, 0.01, 0.02])
    ds = gather(sweep, tmp_path)
    assert ds.attrs["measures"] == "dish" and int(ds["runs_done"].sum()) == 2
    assert ds["mean_speed"].sizes == {"count": 1, "sample": 2, "time": 3}
    assert np.isfinite(ds["g"]).any()
