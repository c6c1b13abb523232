"""Onsets of motion of camphor bodies, simulated: the runs behind the bodies' gallery pages.

* :func:`free_disk_config`: one free camphor disk (no plate, the pill is the object) at
  the dish centre, held while c relaxes to the rest state (no flow unless asked);
* :func:`kick_growth_rate`: the growth rate of its velocity after a small kick, the
  quantity the linear stability of docs/bodies.md predicts
  (:func:`pde_rotor.model.onsets.free_disk_growth_rate`);
* :func:`sized_rotor`, :func:`rotation_samples`, :func:`extrapolated_limit`: the steady
  angular velocity of the two-disk rotor against its size.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..config import RotorConfig
from ..solver.simulation import Simulation


def _held_config(
    dx: float, dt: float, radius: float, body: dict, t_end: float, relax: float, flow: bool
) -> RotorConfig:
    """`body` (at its own start, the dish centre by default) held for `relax` by a stop of
    its own, paper scheme,
    the run ending at `t_end`; the surface flow only if `flow`."""
    held = {"t_ini": 0.0, "t_stop": relax, "t_release": t_end, "cycles": 1}
    return RotorConfig.model_validate(
        {
            "grid": {"domain_radius": radius, "dx": dx, "dt": dt},
            "numerics": {"scheme": "paper"},
            "flow": {"enabled": flow},
            "protocol": {"t_ini": t_end, "cycles": 0},
            "bodies": [{**body, "protocol": held}],
        }
    )


def _growth_after_kick(
    config: RotorConfig,
    relax: float,
    column: int,
    kick: float,
    fit: tuple[float, float],
    measure: Callable[[np.ndarray], float],
) -> float:
    """lambda fitted to log `measure`(pose) over `fit` after the release, where the pose's
    `column` was set to `kick` at the end of the hold."""
    sim = Simulation(config)
    sim.run(relax)
    sim.bodies.poses[0, column] = kick
    times, values = [], []
    for t in np.arange(fit[0], fit[1] + 1e-9, (fit[1] - fit[0]) / 20):
        sim.run(relax + round(t / config.grid.dt) * config.grid.dt)
        times.append(t)
        values.append(measure(sim.bodies.poses[0]))
    return float(np.polyfit(times, np.log(values), 1)[0])


def free_disk_config(
    dx: float,
    dt: float,
    radius: float,
    mass: float,
    mu: float,
    t_end: float,
    relax: float,
    flow: bool = False,
    x: float = 0.0,
) -> RotorConfig:
    """One free disk at (x, 0) of the dish (its centre by default), held for `relax`,
    paper scheme; no flow (the limit of the linear stability) unless `flow`."""
    disk = {
        "name": "disk",
        "pills": [{"x": 0.0, "y": 0.0}],
        "motion": {"kind": "free", "mass": mass, "friction": mu},
        "start": {"x": x, "y": 0.0},
    }
    return _held_config(dx, dt, radius, disk, t_end, relax, flow)


def released_speeds(config: RotorConfig, relax: float, u0: float, times: np.ndarray) -> np.ndarray:
    """The free disk's speed |U| at `times` after its release from the hold, at U = (u0, 0)
    (its steady speed approached from nearby: a dish of finite size holds the run for a
    few time units only)."""
    sim = Simulation(config)
    sim.run(relax)
    sim.bodies.poses[0, 3] = u0
    speeds = []
    for t in times:
        sim.run(relax + round(t / config.grid.dt) * config.grid.dt)
        speeds.append(math.hypot(*sim.bodies.poses[0, 3:5]))
    return np.array(speeds)


def kick_growth_rate(
    config: RotorConfig, relax: float, u0: float, fit: tuple[float, float]
) -> float:
    """lambda fitted to log |U| of the released disk over `fit` (times after the release),
    kicked to U = (u0, 0)."""
    return _growth_after_kick(config, relax, 3, u0, fit, lambda pose: math.hypot(*pose[3:5]))


def two_disk_rotor_config(
    dx: float,
    dt: float,
    radius: float,
    half_length: float,
    inertia: float,
    mu: float,
    t_end: float,
    relax: float,
    flow: bool = False,
) -> RotorConfig:
    """The two-disk rotor of Koyano et al. (PRE 2017): two camphor disks at (+-l, 0) on
    a strip that does not touch the water (plate none), turning about the dish centre;
    held for `relax`, paper scheme; no flow unless `flow`."""
    rotor = {
        "name": "rotor",
        "pills": [{"x": half_length, "y": 0.0}, {"x": -half_length, "y": 0.0}],
        "motion": {"kind": "fixed_axis", "inertia": inertia, "friction": mu},
    }
    return _held_config(dx, dt, radius, rotor, t_end, relax, flow)


def kick_rotation_rate(
    config: RotorConfig, relax: float, omega0: float, fit: tuple[float, float]
) -> float:
    """lambda fitted to log |omega| of the released rotor over `fit` (after the release),
    kicked to omega0."""
    return _growth_after_kick(config, relax, 5, omega0, fit, lambda pose: abs(pose[5]))


def sized_rotor(
    config: RotorConfig, half_length: float, radius: float, **sections: dict
) -> RotorConfig:
    """`config`'s two-disk rotor (its one body with pills at (+-l, 0)) at half-length `l`
    in a dish of radius `radius`, with the top-level `sections` merged in (e.g.
    ``flow={"enabled": True}``)."""
    data = config.model_dump(mode="json")
    data["grid"]["domain_radius"] = radius
    body = data["bodies"][0]
    body["pills"] = [
        {**pill, "x": sign * half_length, "y": 0.0}
        for pill, sign in zip(body["pills"], (1.0, -1.0), strict=True)
    ]
    for name, values in sections.items():
        data[name] = {**data[name], **values}
    return RotorConfig.model_validate(data)


def rotation_samples(config: RotorConfig, times: np.ndarray) -> np.ndarray:
    """omega of the first body at `times` (ascending, from the start of the run)."""
    sim = Simulation(config)
    omega = []
    for t in times:
        sim.run(round(t / config.grid.dt) * config.grid.dt)
        omega.append(sim.bodies.poses[0, 5])
    return np.array(omega)


def extrapolated_limit(values: np.ndarray) -> float:
    """Aitken's Delta^2 limit of the last three of equally spaced samples approaching a
    steady value exponentially (near an onset the approach is slow: critical slowing
    down); the last sample where the differences do not shrink geometrically."""
    w1, w2, w3 = (float(v) for v in values[-3:])
    if w2 == w1:
        return w3
    ratio = (w3 - w2) / (w2 - w1)
    if not 0.0 < ratio < 1.0:
        return w3
    return w3 + (w3 - w2) * ratio / (1.0 - ratio)
