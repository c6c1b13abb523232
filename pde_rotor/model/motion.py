"""The equation of motion of K bodies, Eq. (eq_motion), with numpy: the test oracle.

Written apart from the compiled :mod:`pde_rotor.physics.motion` on purpose, from the
forces of :meth:`pde_rotor.model.surface.SurfacePDE.body_forces` (or the rotor's
:meth:`pde_rotor.model.pde.RotorPDE.rotor_torques`: the paper's rotor is the
``fixed_axis`` body at the origin). Body k, position X, angle phi, velocity U, angular
velocity omega:

    m dU/dt = f + f_fr + f_ext,   I domega/dt = T + T_fr + T_ext,
    dX/dt = U,                    dphi/dt = omega,

X and U only for a ``free`` body; a held body (``fixed``, or in a stop of its schedule)
keeps its pose with U = 0, omega = 0. Time: forward Euler, or Heun's trapezoid of the
rates at the start and at the Euler-predicted pose (:func:`euler_poses`,
:func:`heun_poses`); the noise kick of Eq. (noiseav) is added apart, once per step.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

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
    """

    mass: np.ndarray
    inertia: np.ndarray
    free: np.ndarray
    fixed: np.ndarray
    external: np.ndarray

    @classmethod
    def of(cls, bodies: Sequence[Body]) -> Inertia:
        """The parameters of `bodies`."""
        return cls(
            mass=np.array([b.mass for b in bodies], dtype=float),
            inertia=np.array([b.inertia for b in bodies], dtype=float),
            free=np.array([b.motion == "free" for b in bodies]),
            fixed=np.array([b.motion == "fixed" for b in bodies]),
            external=np.array([b.external for b in bodies], dtype=float).reshape(-1, 3),
        )


def held_bodies(bodies: Sequence[Body], step: int, dt: float) -> np.ndarray:
    """(K,) whether each body is held during the step from t = step dt: ``fixed``, or in a
    stop of its own schedule."""
    held = []
    for body in bodies:
        stopped = body.protocol is not None and StopSchedule.from_config(
            body.protocol, dt
        ).is_stopped(step)
        held.append(body.motion == "fixed" or stopped)
    return np.array(held, dtype=bool)


def accelerations(forces: np.ndarray, inertia: Inertia) -> np.ndarray:
    """(K, 3) dU/dt (x, y) and domega/dt of Eq. (eq_motion) from the (K, 6) forces
    (tension f_x, f_y, T, friction f_x, f_y, T_fr): 0 along x, y where not ``free``."""
    load = forces[:, :3] + forces[:, 3:] + inertia.external
    out = np.zeros_like(load)
    free = inertia.free
    out[free, :2] = load[free, :2] / inertia.mass[free, None]
    moving = ~inertia.fixed
    out[moving, 2] = load[moving, 2] / inertia.inertia[moving]
    return out


def euler_poses(
    poses: np.ndarray, accel: np.ndarray, held: np.ndarray, inertia: Inertia, dt: float
) -> np.ndarray:
    """(K, 6) poses (x, y, phi, u, v, omega) after one forward Euler step: phi, omega of
    every body not held, X and U of the free ones."""
    new = poses.copy()
    turn = ~held
    new[turn, 2] += dt * poses[turn, 5]
    new[turn, 5] += dt * accel[turn, 2]
    move = turn & inertia.free
    new[move, 0:2] += dt * poses[move, 3:5]
    new[move, 3:5] += dt * accel[move, 0:2]
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
    `predicted` and of the accelerations at both, for the bodies not held."""
    new = poses.copy()
    turn = ~held
    new[turn, 2] += 0.5 * dt * (poses[turn, 5] + predicted[turn, 5])
    new[turn, 5] += 0.5 * dt * (accel[turn, 2] + accel_p[turn, 2])
    move = turn & inertia.free
    new[move, 0:2] += 0.5 * dt * (poses[move, 3:5] + predicted[move, 3:5])
    new[move, 3:5] += 0.5 * dt * (accel[move, 0:2] + accel_p[move, 0:2])
    return new
