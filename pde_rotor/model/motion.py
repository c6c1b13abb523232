"""The equation of motion of K bodies, Eq. (eq_motion), with numpy: the test oracle.

Written apart from the compiled :mod:`pde_rotor.physics.motion` on purpose, from the
forces of :meth:`pde_rotor.model.surface.SurfacePDE.body_forces` (or the rotor's
:meth:`pde_rotor.model.pde.RotorPDE.rotor_torques`: the paper's rotor is the
``fixed_axis`` body at the origin). Body k, position X, angle phi, velocity U, angular
velocity omega:

    m dU/dt = f + f_fr + f_ext,   I domega/dt = T + T_fr + T_ext,
    dX/dt = U,                    dphi/dt = omega,

X and U only for a ``free`` body; a held body (``fixed``, or in a stop of its schedule)
keeps its pose with U = 0, omega = 0. A ``track`` body has one degree of freedom, its
angle theta about the track's centre C with the arc speed w = R dtheta/dt:

    m dw/dt = (f + f_fr + f_ext) . e_theta + d f_t,   R dtheta/dt = w,

X = C + R e_r(theta), phi = theta + d pi/2 + const, U = w e_theta, omega = w / R;
here theta is stepped as an angle and X recomputed from it. Time: forward Euler, or
Heun's trapezoid of the rates at the start and at the Euler-predicted pose
(:func:`euler_poses`, :func:`heun_poses`); the noise kick of Eq. (noiseav) is added
apart, once per step.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..config import RotorConfig
from .bodies import Body
from .protocol import StopSchedule


@dataclass(frozen=True)
class Inertia:
    """The motion parameters of K bodies as arrays.

    Attributes:
        mass: (K,) m (used where ``free``).
        inertia: (K,) I.
        free: (K,) whether the body translates.
        fixed: (K,) whether it never moves.
        external: (K, 3) the external force (x, y) and torque.
        track: (K,) whether the body moves along a track.
        centre: (K, 2) C of each track body's circle (0 for the others).
        radius: (K,) R (1 for the others).
        along: (K,) d f_t, the tangential external force (counterclockwise positive).
    """

    mass: np.ndarray
    inertia: np.ndarray
    free: np.ndarray
    fixed: np.ndarray
    external: np.ndarray
    track: np.ndarray
    centre: np.ndarray
    radius: np.ndarray
    along: np.ndarray

    @classmethod
    def of(cls, bodies: Sequence[Body]) -> Inertia:
        """The parameters of `bodies`."""
        return cls(
            mass=np.array([b.mass for b in bodies], dtype=float),
            inertia=np.array([b.inertia for b in bodies], dtype=float),
            free=np.array([b.motion == "free" for b in bodies]),
            fixed=np.array([b.motion == "fixed" for b in bodies]),
            external=np.array(
                [(*b.config.external_force, b.config.external_torque) for b in bodies],
                dtype=float,
            ).reshape(-1, 3),
            track=np.array([b.track is not None for b in bodies], dtype=bool),
            centre=np.array(
                [b.track.centre if b.track else (0.0, 0.0) for b in bodies], dtype=float
            ).reshape(-1, 2),
            radius=np.array([b.track.radius if b.track else 1.0 for b in bodies], dtype=float),
            along=np.array(
                [b.track.direction * b.track.force if b.track else 0.0 for b in bodies],
                dtype=float,
            ),
        )

    def tangents(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(theta, e_theta (K, 2), w): each body's angle about its track's centre, the
        unit tangent there and its arc speed U . e_theta (meaningful for track bodies)."""
        rel = poses[:, 0:2] - self.centre
        theta = np.arctan2(rel[:, 1], rel[:, 0])
        tangent = np.stack([-np.sin(theta), np.cos(theta)], axis=1)
        return theta, tangent, np.sum(poses[:, 3:5] * tangent, axis=1)


def held_bodies(
    bodies: Sequence[Body], schedules: Sequence[StopSchedule | None], step: int
) -> np.ndarray:
    """(K,) whether each body is held during the step from t = step dt: ``fixed``, or in a
    stop of its own schedule (`schedules`: each body's, None for none,
    :attr:`pde_rotor.model.setup.Setup.body_schedules`)."""
    held = []
    for body, schedule in zip(bodies, schedules, strict=True):
        stopped = schedule is not None and schedule.is_stopped(step)
        held.append(body.motion == "fixed" or stopped)
    return np.array(held, dtype=bool)


def contact_forces(poses: np.ndarray, bodies: Sequence[Body], config: RotorConfig) -> np.ndarray:
    """(K, 2) the contact forces of ``contact:`` on each body at `poses` (positions and
    velocities; 0 where off): kappa (ell - g) - gamma dg/dt for each gap g < ell between
    two footprints, along their centres' line, and between a footprint and each wall,
    along the wall's normal (:mod:`pde_rotor.config.contact`; none from the walls on a
    body that spans its channel). A footprint here is the body's contact radius
    (:attr:`~pde_rotor.model.bodies.BodyShape.contact`), whatever
    ``numerics.footprint_widths`` draws."""
    out = np.zeros((len(bodies), 2))
    contact = config.contact
    if not contact.enabled:
        return out
    kappa, ell, gamma = contact.stiffness, contact.range, contact.damping

    def push(gap: np.ndarray, rate: np.ndarray) -> np.ndarray:
        """The force along the gap's normal where the gap is in range."""
        return np.where(gap < ell, kappa * (ell - gap) - gamma * rate, 0.0)

    reach = np.array([b.shape.contact for b in bodies])
    centres = poses[:, 0:2]
    velocities = poses[:, 3:5]
    for k in range(len(bodies)):
        for j in range(len(bodies)):
            if j != k:
                line = centres[k] - centres[j]
                d = float(np.hypot(*line))
                rate = float(line @ (velocities[k] - velocities[j])) / d
                out[k] += push(np.array(d - reach[k] - reach[j]), np.array(rate)) * line / d
    grid = config.grid
    vessel = grid.vessel
    rel = centres - np.array(grid.domain_centre)
    walled = np.array([not b.spans for b in bodies])  # a spanning body crosses the walls
    if vessel is not None and vessel.shape == "rectangle":
        for axis, half in enumerate(vessel.half_widths):
            for sign in (1.0, -1.0):  # the wall at -sign half: its clearance grows with sign U
                gap = half + sign * rel[:, axis] - reach
                out[:, axis] += walled * sign * push(gap, sign * velocities[:, axis])
        return out
    r = np.hypot(rel[:, 0], rel[:, 1])
    normal = rel / r[:, None]
    outward = np.sum(normal * velocities, axis=1)
    outer = grid.domain_radius - grid.dx if vessel is None else vessel.outer_radius
    force = -push(outer - r - reach, -outward)
    if vessel is not None:
        force += push(r - reach - vessel.inner_radius, outward)
    return out + (walled * force)[:, None] * normal


def accelerations(
    forces: np.ndarray, inertia: Inertia, poses: np.ndarray, contact: np.ndarray | None = None
) -> np.ndarray:
    """(K, 3) dU/dt (x, y) and domega/dt of Eq. (eq_motion) from the (K, 6) forces
    (tension f_x, f_y, T, friction f_x, f_y, T_fr) at `poses` and the (K, 2)
    `contact` forces (:func:`contact_forces`; None: none): 0 along x, y where neither
    ``free`` nor ``track``; a track body's a e_theta and a / R (its tangential
    acceleration a)."""
    load = forces[:, :3] + forces[:, 3:] + inertia.external
    if contact is not None:
        load[:, :2] += contact
    out = np.zeros_like(load)
    free = inertia.free
    out[free, :2] = load[free, :2] / inertia.mass[free, None]
    moving = ~inertia.fixed & ~inertia.track
    out[moving, 2] = load[moving, 2] / inertia.inertia[moving]
    track = inertia.track
    _, tangent, _ = inertia.tangents(poses)
    along = (np.sum(load[:, :2] * tangent, axis=1) + inertia.along) / inertia.mass
    out[track, :2] = along[track, None] * tangent[track]
    out[track, 2] = along[track] / inertia.radius[track]
    return out


def _track_step(
    poses: np.ndarray, new: np.ndarray, rows: np.ndarray, inertia: Inertia,
    turn: np.ndarray, speed: np.ndarray,
) -> None:  # fmt: skip
    """new[rows] = the poses moved by the angles `turn` along their circles with the arc
    speeds `speed` (each (K,), read at `rows`)."""
    theta, _, _ = inertia.tangents(poses)
    angle = theta[rows] + turn[rows]
    radius = inertia.radius[rows]
    new[rows, 0] = inertia.centre[rows, 0] + radius * np.cos(angle)
    new[rows, 1] = inertia.centre[rows, 1] + radius * np.sin(angle)
    new[rows, 2] = poses[rows, 2] + turn[rows]
    new[rows, 3] = -speed[rows] * np.sin(angle)
    new[rows, 4] = speed[rows] * np.cos(angle)
    new[rows, 5] = speed[rows] / radius


def euler_poses(
    poses: np.ndarray, accel: np.ndarray, held: np.ndarray, inertia: Inertia, dt: float
) -> np.ndarray:
    """(K, 6) poses (x, y, phi, u, v, omega) after one forward Euler step: phi, omega of
    every body not held, X and U of the free ones, theta and w of the track ones."""
    new = poses.copy()
    turn = ~held & ~inertia.track
    new[turn, 2] += dt * poses[turn, 5]
    new[turn, 5] += dt * accel[turn, 2]
    move = turn & inertia.free
    new[move, 0:2] += dt * poses[move, 3:5]
    new[move, 3:5] += dt * accel[move, 0:2]
    _, tangent, speed = inertia.tangents(poses)
    along = np.sum(accel[:, :2] * tangent, axis=1)
    _track_step(poses, new, ~held & inertia.track, inertia, dt * speed / inertia.radius,
                speed + dt * along)  # fmt: skip
    return new


def heun_poses(
    poses: np.ndarray,
    accel: np.ndarray,
    predicted: np.ndarray,
    accel_p: np.ndarray,
    held: np.ndarray,
    inertia: Inertia,
    dt: float,
) -> np.ndarray:
    """(K, 6) poses after Heun's step: the trapezoid of the velocities at `poses` and
    `predicted` and of the accelerations at both, for the bodies not held (for a track
    body, of w and its tangential acceleration, each at its own place)."""
    new = poses.copy()
    turn = ~held & ~inertia.track
    new[turn, 2] += 0.5 * dt * (poses[turn, 5] + predicted[turn, 5])
    new[turn, 5] += 0.5 * dt * (accel[turn, 2] + accel_p[turn, 2])
    move = turn & inertia.free
    new[move, 0:2] += 0.5 * dt * (poses[move, 3:5] + predicted[move, 3:5])
    new[move, 3:5] += 0.5 * dt * (accel[move, 0:2] + accel_p[move, 0:2])
    _, tangent, speed = inertia.tangents(poses)
    _, tangent_p, speed_p = inertia.tangents(predicted)
    along = np.sum(accel[:, :2] * tangent, axis=1) + np.sum(accel_p[:, :2] * tangent_p, axis=1)
    turn = 0.5 * dt * (speed + speed_p) / inertia.radius
    _track_step(poses, new, ~held & inertia.track, inertia, turn, speed + 0.5 * dt * along)
    return new
