"""The equation of motion of a body, Eq. (eq_motion), written once for every body.

Body k (the paper's rotor is the ``fixed_axis`` body at the origin) has a position X, an
angle phi, a velocity U = (u, v) and an angular velocity omega; its plate moves with
u_k(r) = U + omega z x (r - X). About X,

    m dU/dt = f + f_fr + f_ext,        f = s k int F grad c dA,
    I domega/dt = T + T_fr + T_ext + xi,   T = s k int F (r - X) x grad c dA,

    f_fr = -mu int F (u_k - v) dA,   T_fr = -mu int F (r - X) x (u_k - v) dA,

dX/dt = U, dphi/dt = omega, with s the sign of ``rotor.torque``, k the tension slope,
(f_ext, T_ext) the body's external load, and the Gaussian white noise xi of Eq.
(noiseav) as the Euler-Maruyama kick sqrt(2 dt) sigma / I times a standard normal. The
tension integrals are :mod:`.tension`'s; the friction's are written with the plate's
moments (:func:`friction_moments`): with A = int F, M = int F (r - X), J = int F |r - X|^2,

    f_fr = -mu (A U + omega z x M - int F v),
    T_fr = -mu (omega J + M x U - int F (r - X) x v).

A ``fixed`` body does not move, a ``fixed_axis`` body only turns, and a body in a stop
of its schedule (:func:`stopped_at`) is held: U = 0, omega = 0, no step, no kick.

The body's parameters come as a record `b` read by field name: a body's row of the
``BODY`` records or the rotor's ``PARAMS`` (:mod:`pde_rotor.kernels.records`), both with
``motion``, ``mass``, ``inertia``, ``friction``, ``kick``, the stop schedule in steps
(``n_ini``, ``n_stop``, ``n_period``, ``cycles``) and the external load
(``external_force_x``, ``external_force_y``, ``external_torque``).

A pose is the tuple (x, y, phi, u, v, omega); the integrals are the tuple (or array)
(int F grad c (x, y), int F (r - X) x grad c, A, M (x, y), J, int F (r - X) x v,
int F v (x, y)), each times dA. Every loop takes the same tail of a step:
:func:`held` (stop), :func:`body_loads` (forces, torques, accelerations),
:func:`finite_loads`, :func:`euler_pose` or :func:`heun_pose` (step), :func:`noise_kick`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

MOTION_FIXED, MOTION_FIXED_AXIS, MOTION_FREE = 0, 1, 2
"""Motions in the body record."""

N_INTEGRALS = 10
"""Integrals of a body per step (see the module docstring)."""


class Motion(NamedTuple):
    """The compiled motion functions for one target (see the module docstring)."""

    stopped_at: Callable
    held: Callable
    hold: Callable
    friction_moments: Callable
    body_loads: Callable
    finite_loads: Callable
    euler_pose: Callable
    heun_pose: Callable
    noise_kick: Callable


def make_motion(jit: Callable[[Callable], Callable]) -> Motion:
    """Compile the motion functions with `jit`.

    Args:
        jit: decorator turning a scalar Python function into a compiled one that other
            compiled functions of the same target can call (numba ``njit`` or
            ``cuda.jit(device=True)``, :func:`pde_rotor.physics.build.make_physics`).

    Returns:
        The compiled functions.
    """

    @jit
    def stopped_at(step, n_ini, n_stop, n_period, cycles):
        """Whether the step from t = step dt lies in a stop phase (section "Model"):
        stop m = 1..M covers the steps [n_ini + (m - 1) n_period, ... + n_stop)."""
        rel = step - n_ini
        if rel < 0 or rel >= cycles * n_period:
            return False
        return rel % n_period < n_stop

    @jit
    def held(step, b):
        """Whether body `b` is held during the step from t = step dt: ``fixed``, or in a
        stop of its schedule."""
        return b.motion == MOTION_FIXED or stopped_at(step, b.n_ini, b.n_stop, b.n_period, b.cycles)

    @jit
    def hold(pose, is_held):
        """The pose with U = 0, omega = 0 where `is_held` (else unchanged)."""
        x, y, phi, u, v, omega = pose
        if is_held:
            return x, y, phi, 0.0, 0.0, 0.0
        return x, y, phi, u, v, omega

    @jit
    def friction_moments(buf, o, nn, f, rx, ry, flow):
        """One cell's share of the friction integrals (no dA): F, F (r - X) (x, y),
        F |r - X|^2, F (r - X) x v and F v (x, y) ((rx, ry) = r - X; v read at the
        offsets o + nn, o + 2 nn, 0 without `flow`)."""
        cross_v = 0.0
        f_vx = 0.0
        f_vy = 0.0
        if flow:
            ox = o + nn
            vx = buf[ox]
            vy = buf[ox + nn]
            cross_v = f * (rx * vy - ry * vx)
            f_vx = f * vx
            f_vy = f * vy
        return f, f * rx, f * ry, f * (rx * rx + ry * ry), cross_v, f_vx, f_vy

    @jit
    def body_loads(integrals, pose, b, sign_k):
        """The equation of motion of body `b` from its integrals (module docstring).

        Args:
            integrals: the body's 10 integrals (module docstring).
            pose: (x, y, phi, u, v, omega).
            b: the body's record.
            sign_k: s k, the sign of ``rotor.torque`` times the tension slope.

        Returns:
            (f_x, f_y, T, friction f_x, friction f_y, friction torque, dU/dt, dV/dt,
            domega/dt): tension force and torque, friction force and torque, and the
            accelerations (f + f_fr + f_ext) / m (0 for a body that does not
            translate), (T + T_fr + T_ext) / I.
        """
        u, v, omega = pose[3], pose[4], pose[5]
        area, m_x, m_y, polar, cross_v = (
            integrals[3],
            integrals[4],
            integrals[5],
            integrals[6],
            integrals[7],
        )
        flow_x, flow_y = integrals[8], integrals[9]
        mu = b.friction
        torque = sign_k * integrals[2]
        friction = -mu * (polar * omega - cross_v + (m_x * v - m_y * u))
        force_x = sign_k * integrals[0]
        force_y = sign_k * integrals[1]
        drag_x = -mu * (area * u - omega * m_y - flow_x)
        drag_y = -mu * (area * v + omega * m_x - flow_y)
        accel_x = 0.0
        accel_y = 0.0
        if b.motion == MOTION_FREE:
            inv_m = 1.0 / b.mass
            accel_x = (force_x + drag_x + b.external_force_x) * inv_m
            accel_y = (force_y + drag_y + b.external_force_y) * inv_m
        return (
            force_x,
            force_y,
            torque,
            drag_x,
            drag_y,
            friction,
            accel_x,
            accel_y,
            (friction + torque + b.external_torque) * (1.0 / b.inertia),
        )

    @jit
    def finite_loads(loads):
        """Whether the accelerations of :func:`body_loads` are finite."""
        return math.isfinite(loads[6]) and math.isfinite(loads[7]) and math.isfinite(loads[8])

    @jit
    def euler_pose(pose, loads, dt, b):
        """One forward Euler step of dX/dt = U, dphi/dt = omega and the accelerations of
        `loads` (:func:`body_loads`): X and U only for a ``free`` body."""
        x, y, phi, u, v, omega = pose
        phi, omega = phi + dt * omega, omega + dt * loads[8]
        if b.motion == MOTION_FREE:
            x, u = x + dt * u, u + dt * loads[6]
            y, v = y + dt * v, v + dt * loads[7]
        return x, y, phi, u, v, omega

    @jit
    def heun_pose(pose, loads, predicted, loads_p, dt, b):
        """Heun's corrector of the pose from the rates at the start (the velocities of
        `pose`, the accelerations of `loads`) and at the predicted pose (`predicted`,
        `loads_p`): the trapezoidal average; X and U only for a ``free`` body."""
        x, y, phi, u, v, omega = pose
        half = 0.5 * dt
        phi, omega = phi + half * (omega + predicted[5]), omega + half * (loads[8] + loads_p[8])
        if b.motion == MOTION_FREE:
            x, u = x + half * (u + predicted[3]), u + half * (loads[6] + loads_p[6])
            y, v = y + half * (v + predicted[4]), v + half * (loads[7] + loads_p[7])
        return x, y, phi, u, v, omega

    @jit
    def noise_kick(pose, xi, b):
        """The pose with omega plus the Euler-Maruyama increment of the noise of Eqs.
        (eq_motion) and (noiseav), sqrt(2 dt) sigma / I xi for the standard normal xi."""
        x, y, phi, u, v, omega = pose
        return x, y, phi, u, v, omega + b.kick * xi

    return Motion(
        stopped_at=stopped_at,
        held=held,
        hold=hold,
        friction_moments=friction_moments,
        body_loads=body_loads,
        finite_loads=finite_loads,
        euler_pose=euler_pose,
        heun_pose=heun_pose,
        noise_kick=noise_kick,
    )
