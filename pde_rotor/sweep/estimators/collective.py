"""The collective estimator: one bodies run per sample, its collective measures stored.

A run advances its bodies config from rest (c = v = 0, every body at its start) to
``protocol.t_end``, recording every body's pose and velocity each ``record_interval``
(:func:`trajectory`: the CPU's :class:`~pde_rotor.solver.simulation.Simulation` or one
member of :func:`pde_rotor.backends.gpu_bodies.run_bodies_ensemble`). A run that ends
early (two footprints meet, a body reaches the wall) keeps what it recorded and says why.
The records go to the measures of :mod:`pde_rotor.collective` (:func:`collective_result`):

* ``ring``: per record the mean angular velocity and arc speed about the vessel's
  centre, spacing spread, lattice and cluster order; time averages after ``settle``, the
  gap mobility and the mode;
* ``dish``: per record the mean speed, polar and rotational order; the pair distances
  counted in the bins of g(r) after ``settle`` with the pairs uncorrelated centres would
  give there (g = counted / expected, pooled over the samples of a point by the report).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...collective import dish, ring
from ...config import RotorConfig
from ...model.protocol import steps_of
from ...model.surface import POSE_COLUMNS
from ..plan import Run
from ..spec import CollectiveEstimator

X, Y, U, V = (POSE_COLUMNS.index(name) for name in ("x", "y", "u", "v"))


@dataclass(frozen=True)
class Trajectory:
    """Every body's pose at the record times of one run.

    Attributes:
        t: (T,) record times.
        poses: (T, K, len(POSE_COLUMNS)) poses on the surface.
        end: why the run ended before ``protocol.t_end`` ("" if it did not).
    """

    t: np.ndarray
    poses: np.ndarray
    end: str


def trajectory(config: RotorConfig, record_interval: float, backend: str = "cpu") -> Trajectory:
    """Advance `config` from rest to ``protocol.t_end``, recording every body's pose.

    Args:
        config: a config with ``bodies:``.
        record_interval: time between records (a multiple of dt).
        backend: ``cpu`` (the run's Simulation) or ``gpu`` (one ensemble member).
    """
    t_end = config.protocol.t_end
    if backend == "gpu":
        from ...backends.gpu_bodies import run_bodies_ensemble

        result = run_bodies_ensemble([config], t_end, record_interval=record_interval)
        kept = ~np.isnan(result.poses[0]).any(axis=(1, 2))
        end = "" if np.isnan(result.ended_at[0]) else f"ended at t = {result.ended_at[0]:g}"
        return Trajectory(result.t[kept], result.poses[0][kept], end)
    from ...solver.bodies import BodyContactError
    from ...solver.rotor import SimulationDivergedError
    from ...solver.simulation import Simulation

    sim = Simulation(config)
    dt = config.grid.dt
    every, total = steps_of(record_interval, dt), steps_of(t_end, dt)
    times, poses = [0.0], [sim.bodies.poses.copy()]
    end, step = "", 0
    while step < total:
        step = min(step + every, total)
        try:
            sim.run(step * dt)
        except (BodyContactError, SimulationDivergedError) as err:
            end = str(err)
            break
        times.append(step * dt)
        poses.append(sim.bodies.poses.copy())
    return Trajectory(np.array(times), np.stack(poses), end)


def _mean(values: np.ndarray) -> float:
    """Mean of the finite values (NaN if none)."""
    finite = values[np.isfinite(values)]
    return float(finite.mean()) if finite.size else math.nan


def _list(values: np.ndarray) -> list[float]:
    return [float(v) for v in values]


def centres_radius(config: RotorConfig) -> float:
    """Radius of the disk the bodies' centres may occupy in the dish: its radius less the
    largest footprint (a footprint that reaches the edge ends the run)."""
    reach = max(body.reach(config.geometry.smoothing) for body in config.bodies or [])
    return config.grid.domain_radius - reach


def collective_result(
    config: RotorConfig, estimator: CollectiveEstimator, path: Trajectory
) -> dict[str, Any]:
    """The stored result of one run: its measures per record and their time averages."""
    measures = estimator.resolve(config)
    cx, cy = config.grid.domain_centre
    p = path.poses
    dx, dy, u, v = p[..., X] - cx, p[..., Y] - cy, p[..., U], p[..., V]
    late = path.t >= estimator.settle - 1e-9
    result: dict[str, Any] = {
        "measures": measures,
        "bodies": p.shape[1],
        "t": _list(path.t),
        "end": path.end,
        "settle": estimator.settle,
    }
    if measures == "ring":
        omega, arc = ring.angular_velocity(dx, dy, u, v)
        theta = ring.ring_angles(dx, dy, (0.0, 0.0))
        order, clusters = ring.cluster_order(theta)
        series = {
            "angular_speed": omega.mean(axis=1),
            "arc_speed": arc.mean(axis=1),
            "spacing_spread": ring.spacing_spread(theta),
            "lattice_order": ring.lattice_order(theta),
            "cluster_order": order,
            "clusters": clusters,
        }
        mobility = ring.gap_mobility(theta[late]) if late.sum() > 1 else math.nan
        speed = _mean(np.abs(arc[late]))
        spread = _mean(series["spacing_spread"][late])
        summary = {name: _mean(values[late]) for name, values in series.items()}
        summary |= {"abs_arc_speed": speed, "gap_mobility": mobility}
        net = summary["arc_speed"]
        summary["mode"] = ring.MODES.index(ring.ring_mode(speed, net, spread, mobility))
    else:
        xy, uv = np.stack([dx, dy], axis=-1), np.stack([u, v], axis=-1)
        rotation = dish.rotational_order(xy, uv)
        series = {
            "mean_speed": dish.mean_speed(uv),
            "polar_order": dish.polar_order(uv),
            "rotational_order": rotation,
        }
        summary = {name: _mean(values[late]) for name, values in series.items()}
        summary["abs_rotational_order"] = _mean(np.abs(rotation[late]))
        radius = centres_radius(config)
        edges = np.linspace(0.0, estimator.r_max or 2 * radius, estimator.bins + 1)
        k = p.shape[1]
        frames = int(late.sum())
        result["pair_counts"] = _list(dish.pair_counts(xy[late], edges))
        expected = frames * k * (k - 1) / 2 * dish.bin_probabilities(edges, radius)
        result["pair_expected"] = _list(expected)
        result["r_edges"] = _list(edges)
    result |= {name: _list(values) for name, values in series.items()}
    result["summary"] = summary
    return result


def collective_runs(runs: Sequence[Run], backend: str = "cpu") -> tuple[list[dict], str]:
    """The collective estimator: each run's trajectory and measures, one after another.

    Returns:
        One :func:`collective_result` per run, and the backend that computed them.
    """
    results = []
    for run in runs:
        config = RotorConfig.model_validate(run.config)
        estimator = CollectiveEstimator.model_validate(run.estimator)
        path = trajectory(config, estimator.record_interval, backend)
        results.append(collective_result(config, estimator, path))
    return results, backend
