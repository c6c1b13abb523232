"""Onsets of motion of camphor bodies, simulated: the runs behind the bodies' gallery pages.

* :func:`free_disk_config`: one free camphor disk (no plate, the pill is the object) at
  the dish centre, held while c relaxes to the rest state (no flow unless asked);
* :func:`kick_growth_rate`: the growth rate of its velocity after a small kick, the
  quantity the linear stability of docs/bodies.md predicts
  (:func:`pde_rotor.theory.free_disk.free_disk_growth_rate`);
* :func:`kicked_series`, :func:`gap_window`, :func:`fitted_rate`,
  :func:`two_mode_rates`: a kicked body's amplitude, and its rate (or the rates of a slow
  pair) fitted after the next faster mode of the spectrum has decayed;
* :func:`disk_in_dish_config`, :func:`kick_orbit`, :func:`kick_hopf_rate`,
  :func:`dragged_orbit`: the disk in a no-flux dish, its Hopf pair after a kick, and the
  branch (rotation, or motion back and forth) it settles on after a given wake;
* :func:`sized_rotor`, :func:`rotation_samples`, :func:`extrapolated_limit`: the steady
  angular velocity of the two-disk rotor against its size.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..config import RotorConfig
from ..solver.bodies import BodyContactError
from ..solver.simulation import Simulation


def _held_config(
    dx: float,
    dt: float,
    radius: float,
    body: dict,
    t_end: float,
    relax: float,
    flow: bool = False,
    wall: str = "absorbing",
) -> RotorConfig:
    """`body` (at its own start, the dish centre by default) held for `relax` by a stop of
    its own, paper scheme, the run ending at `t_end`; the surface flow only if `flow`, the
    dish's `wall` (``grid.wall``)."""
    held = {"t_ini": 0.0, "t_stop": relax, "t_release": t_end, "cycles": 1}
    return RotorConfig.model_validate(
        {
            "grid": {"domain_radius": radius, "dx": dx, "dt": dt, "wall": wall},
            "numerics": {"scheme": "paper"},
            "flow": {"enabled": flow},
            "protocol": {"t_ini": t_end, "cycles": 0},
            "bodies": [{**body, "protocol": held}],
        }
    )


def kicked_series(
    config: RotorConfig,
    relax: float,
    column: int,
    kick: float,
    times: np.ndarray,
    measure: Callable[[np.ndarray], float],
) -> np.ndarray:
    """`measure`(pose) at `times` after the release, where the pose's `column` was set to
    `kick` at the end of the hold of `relax`."""
    sim = Simulation(config)
    sim.run(relax)
    sim.bodies.poses[0, column] = kick
    values = []
    for t in times:
        sim.run(relax + round(t / config.grid.dt) * config.grid.dt)
        values.append(measure(sim.bodies.poses[0]))
    return np.array(values)


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
    times = np.arange(fit[0], fit[1] + 1e-9, (fit[1] - fit[0]) / 20)
    values = kicked_series(config, relax, column, kick, times, measure)
    return float(np.polyfit(times, np.log(values), 1)[0])


def gap_window(
    eigenvalues: np.ndarray, decay: float = 1e4, span: float = 2.0, modes: int = 1
) -> tuple[float, float]:
    """The window of times after a kick in which only the `modes` slowest modes remain.

    A kick excites the leading modes and faster ones; the first faster one,
    e^{lambda_{n+1} t}, falls behind the n-th (n = `modes`) by
    e^{-(Re lambda_n - Re lambda_{n+1}) t}. The window starts when that ratio is
    1 / `decay`, t_0 = ln(decay) / gap, and lasts `span`. With n = 1 the slope of
    log |amplitude| there differs from Re lambda_1 by at most gap a / decay, a the two
    modes' amplitude ratio at the kick; with n = 2 a fit of two modes
    (:func:`hopf_rate`) gives both.

    Args:
        eigenvalues: the leading eigenvalues of the linearisation, by decreasing real part
            (:class:`pde_rotor.stability.eigen.Spectrum`); copies of one (a degenerate pair,
            the conjugate of a complex one) count as one mode.
        decay: the factor by which the first faster mode has fallen behind.
        span: the window's length.
        modes: how many distinct slow modes the fit keeps.

    Raises:
        ValueError: fewer than `modes` + 1 distinct eigenvalues.
    """
    distinct: list[complex] = []
    for lam in eigenvalues:
        scale = 1e-6 * max(abs(lam), 1.0)
        if all(abs(lam - o) > scale and abs(lam - np.conj(o)) > scale for o in distinct):
            distinct.append(complex(lam))
    if len(distinct) <= modes or distinct[modes].real >= distinct[modes - 1].real:
        msg = f"no eigenvalue below the {modes} leading ones in {eigenvalues}"
        raise ValueError(msg)
    start = math.log(decay) / (distinct[modes - 1].real - distinct[modes].real)
    return start, start + span


def fitted_rate(
    times: np.ndarray, values: np.ndarray, window: tuple[float, float]
) -> tuple[float, float]:
    """The slope of log `values` against `times` over `window` by least squares, and its
    standard error (what the samples' scatter about the line allows)."""
    keep = (times >= window[0] - 1e-9) & (times <= window[1] + 1e-9)
    t, y = times[keep], np.log(values[keep])
    (slope, _), cov = np.polyfit(t, y, 1, cov=True)
    return float(slope), float(math.sqrt(cov[0, 0]))


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


def disk_in_dish_config(dx: float, dt: float, radius: float, mass: float, mu: float,
                        t_end: float, relax: float) -> RotorConfig:  # fmt: skip
    """One free disk at the centre of a dish with a no-flux wall (``grid.wall: no_flux``,
    Koyano, Suematsu & Kitahata 2019), held for `relax`, no flow, paper scheme."""
    disk = {
        "name": "disk",
        "pills": [{"x": 0.0, "y": 0.0}],
        "motion": {"kind": "free", "mass": mass, "friction": mu},
    }
    return _held_config(dx, dt, radius, disk, t_end, relax, wall="no_flux")


def kick_orbit(
    config: RotorConfig,
    relax: float,
    velocity: tuple[float, float],
    times: np.ndarray,
    offset: tuple[float, float] = (0.0, 0.0),
) -> np.ndarray:
    """The released disk's position (x, y) at `times` after the release, kicked to U =
    `velocity` and moved by `offset` at the end of the hold (the run ends early if it
    reaches the wall). A kick with the offset 0 or parallel to U keeps the disk on the
    line through the centre along U (the mirror symmetry about that line); an offset
    across U gives it angular momentum about the centre.

    Returns:
        (len(times), 2) positions; rows after an early end are nan.
    """
    sim = Simulation(config)
    sim.run(relax)
    sim.bodies.poses[0, 3:5] = velocity
    sim.bodies.poses[0, 0:2] += offset
    out = np.full((len(times), 2), np.nan)
    for m, t in enumerate(times):
        try:
            sim.run(relax + round(t / config.grid.dt) * config.grid.dt)
        except BodyContactError:
            break
        out[m] = sim.bodies.poses[0, :2]
    return out


def dragged_orbit(
    config: RotorConfig,
    relax: float,
    ellipse: tuple[float, float, float],
    drag: float,
    times: np.ndarray,
) -> np.ndarray:
    """The disk's pose after it was dragged along an ellipse and released.

    The disk of :func:`disk_in_dish_config` is nearly overdamped (m / mu ~ 1e-3): a
    velocity given at the release is forgotten within a few steps, and what the motion
    remembers is the camphor about it. So after the hold of `relax` it is dragged for
    `drag` time units along X(t) = (a cos w t, b sin w t), `ellipse` = (a, b, w), its
    position and velocity set every 0.02 time units, so that c takes the wake of that
    motion: the counter-clockwise and clockwise circular parts (a + b) / 2 and
    (a - b) / 2 (b = a: rotation about the centre; b = 0: motion back and forth along x,
    which the mirror symmetry y -> -y keeps on that line).

    Returns:
        (len(times), 4) rows (x, y, U_x, U_y) at `times` after the release; rows after
        an early end (the disk reached the wall) are nan.
    """
    a, b, w = ellipse
    dt = config.grid.dt
    sim = Simulation(config)
    sim.run(relax)
    every = max(1, round(0.02 / dt))
    for n in range(1, round(drag / dt) // every + 1):
        t = n * every * dt
        sim.run(relax + n * every * dt)
        sim.bodies.poses[0, 0:2] = (a * math.cos(w * t), b * math.sin(w * t))
        sim.bodies.poses[0, 3:5] = (-a * w * math.sin(w * t), b * w * math.cos(w * t))
    start = sim.t
    out = np.full((len(times), 4), np.nan)
    for m, t in enumerate(times):
        try:
            sim.run(start + round(t / dt) * dt)
        except BodyContactError:
            break
        out[m] = sim.bodies.poses[0, [0, 1, 3, 4]]
    return out


def hopf_rate(times: np.ndarray, xy: np.ndarray) -> complex:
    """lambda = sigma + i omega of a pair of modes e^{lambda t}, e^{conj(lambda) t} fitted to
    the positions `xy` at the uniform `times` (Prony's method of order 2).

    Both coordinates obey x_{k+2} = p x_{k+1} + q x_k with the same real p, q; their least
    squares fit gives the roots r of r^2 = p r + q, r = e^{lambda (t_1 - t_0)}. A pair of
    real rates (no oscillation) returns the larger as sigma, omega = 0.
    """
    lam = two_mode_rates(times, xy)
    return complex(lam[np.argmax(lam.imag)] if np.any(lam.imag > 0) else lam[np.argmax(lam.real)])


def two_mode_rates(times: np.ndarray, series: np.ndarray) -> np.ndarray:
    """Both rates lambda of two modes e^{lambda t} fitted to the columns of `series` (one
    per coordinate, at the uniform `times`) by Prony's method of order 2
    (:func:`hopf_rate`), by decreasing real part."""
    cols = range(series.shape[1])
    rows = np.concatenate([np.stack([series[1:-1, a], series[:-2, a]], axis=1) for a in cols])
    rhs = np.concatenate([series[2:, a] for a in cols])
    (p, q), *_ = np.linalg.lstsq(rows, rhs, rcond=None)
    roots = np.roots([1.0, -p, -q]).astype(complex)
    lam = np.log(roots) / (times[1] - times[0])
    return lam[np.argsort(-lam.real)]


def kick_hopf_rate(
    config: RotorConfig, relax: float, u0: float, fit: tuple[float, float], samples: int = 61
) -> complex:
    """lambda = sigma + i omega of the disk's orbit about the dish centre after a kick to
    U = (u0, 0), fitted (:func:`hopf_rate`) to `samples` positions over `fit` after the
    release."""
    times = np.linspace(fit[0], fit[1], samples)
    return hopf_rate(times, kick_orbit(config, relax, (u0, 0.0), times))


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
