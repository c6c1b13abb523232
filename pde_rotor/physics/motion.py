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

A ``track`` body (a boat in a ring channel) is kept on the circle of radius R about the
track's centre C, its heading along the tangent: one degree of freedom, its place
theta on the circle (X = C + R e_r(theta)) with the arc speed w = R dtheta/dt
(positive counterclockwise). Its plate turns with the place, phi - theta constant, so
it moves as a rigid body turning about C: U = w e_theta, omega = w / R, and the plate
velocity u_k(r) = (w / R) z x (r - C) is what the friction integrals and the water see.
The tension, friction and external forces are projected on the tangent e_theta (the
normal part is the track's reaction), and a tangential force f_t along the direction
of travel d = +-1 (``track_direction``) is added:

    m dw/dt = (f + f_fr + f_ext) . e_theta + d f_t.

The body's torque about X does not enter (the heading is the track's); the
accelerations returned are the tangential one as a vector, a e_theta, and a / R.
Both integrators step theta and w and put X back on the circle from theta, so the pose
stays on it to round-off (:func:`track_step`).

A footprint that crosses a wall of an annular or rectangular vessel (:func:`leaves_vessel`)
ends the run as one that reaches the dish's edge, unless contact is on (``contact:``,
:mod:`pde_rotor.config.contact`): then a linear spring and dashpot
kappa (ell - g) - gamma dg/dt on the gap g between footprints (:func:`pair_contact`) and
between a footprint and a wall (:func:`wall_contact`), while g < ell, pushes them apart,
its force added to a free body's and projected on a track body's tangent
(:func:`contact_loads`); the record's ``contact_stiffness`` kappa, ``contact_range`` ell
(0: off) and ``contact_damping`` gamma. The force acts along the line of the footprints'
centres or the wall's normal through X, so it has no torque about X.

The body's parameters come as a record `b` read by field name: a body's row of the
``BODY`` records or the rotor's ``PARAMS`` (:mod:`pde_rotor.kernels.records`), both with
``motion``, ``mass``, ``inertia``, ``friction``, ``kick``, the stop schedule in steps
(``n_ini``, ``n_stop``, ``n_period``, ``cycles``), the external load
(``external_force_x``, ``external_force_y``, ``external_torque``) and the track
(``track_x``, ``track_y``: C; ``track_radius`` R; ``track_direction`` d;
``track_force`` f_t; read for a ``track`` body only).

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

from .tension import Tension

MOTION_FIXED, MOTION_FIXED_AXIS, MOTION_FREE, MOTION_TRACK = 0, 1, 2, 3
"""Motions in the body record."""

VESSEL_DISH, VESSEL_ANNULUS, VESSEL_RECTANGLE = 0, 1, 2
"""Vessels in the run record (``vessel``; the dish's edge is the drawing's)."""

N_INTEGRALS = 10
"""Integrals of a body per step (see the module docstring)."""


class Motion(NamedTuple):
    """The compiled motion functions for one target (see the module docstring)."""

    stopped_at: Callable
    held: Callable
    hold: Callable
    friction_moments: Callable
    cell_integrals: Callable
    wet_cell_integrals: Callable
    body_loads: Callable
    finite_loads: Callable
    euler_pose: Callable
    heun_pose: Callable
    noise_kick: Callable
    track_place: Callable
    track_step: Callable
    leaves_vessel: Callable
    pair_contact: Callable
    wall_contact: Callable
    contact_loads: Callable


def make_motion(jit: Callable[[Callable], Callable], tension: Tension) -> Motion:
    """Compile the motion functions with `jit`.

    Args:
        jit: decorator turning a scalar Python function into a compiled one that other
            compiled functions of the same target can call (numba ``njit`` or
            ``cuda.jit(device=True)``, :func:`pde_rotor.physics.build.make_physics`).
        tension: the tension functions compiled with the same `jit`.

    Returns:
        The compiled functions.
    """
    tension_integrand = tension.tension_integrand
    surface_pressure = tension.surface_pressure

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
    def cell_integrals(sums, buf, o, strides, f, r, inv_2dx, p, terms):
        """`sums` plus one cell's share of a body's integrals in area form (no dA): the
        tension's ``tension_integrand`` (central differences) and :func:`friction_moments`,
        in the order of the integrals (module docstring); the running sums of every loop
        that takes them, CPU and GPU.

        Args:
            sums: the 10 sums so far.
            buf, o: the flat state (c, v_x, v_y) and the cell's offset in it.
            strides: (sx, sy, nn), the offsets of the x and y neighbours and of the next
                field, of the caller's integer type.
            f: F at the cell.
            r: (rx, ry) = r - X at the cell centre.
            inv_2dx: 1 / (2 dx).
            p: the parameter record (the tension law).
            terms: (tension, flow): whether the tension's terms are taken (else 0: the
                contour form replaces them) and whether v is read (else 0).
        """
        sx, sy, nn = strides
        rx, ry = r
        tension, flow = terms
        t0 = 0.0
        t1 = 0.0
        t2 = 0.0
        if tension:
            t0, t1, t2 = tension_integrand(buf, o, sx, sy, f, rx, ry, inv_2dx, p)
        m0, m1, m2, m3, m4, m5, m6 = friction_moments(buf, o, nn, f, rx, ry, flow)
        return (
            sums[0] + t0, sums[1] + t1, sums[2] + t2, sums[3] + m0, sums[4] + m1,
            sums[5] + m2, sums[6] + m3, sums[7] + m4, sums[8] + m5, sums[9] + m6,
        )  # fmt: skip

    @jit
    def wet_cell_integrals(sums, buf, cell, F, strides, kappa, r, inv_2dx, p, flow):
        """`sums` plus one wet cell's share of the integrals of a body that spans its
        channel (no dA), weighted by the cell's volume fraction kappa: the tension's in
        the form that reads c on this cell only, -kappa Pi(c) (D F) and
        -kappa Pi(c) (r - X) x (D F) (D the central difference, Pi(c) / k the
        ``surface_pressure``), and kappa times :func:`friction_moments`, in the order of
        :func:`cell_integrals`; the running sums of the wet-cell loop, CPU
        (:func:`pde_rotor.kernels.body_sums.spanning_integrals`) and GPU
        (:func:`pde_rotor.kernels.cuda_body_sums.owned_sums`).

        Args:
            sums: the 10 sums so far.
            buf: the flat state (c, v_x, v_y).
            cell: (o, q), the cell's offsets in `buf` and in `F`.
            F: the bodies' plate indicator, flat.
            strides: (sx, nn), the offset of the x neighbour (the y neighbour's is 1) and
                of the next field in `buf`.
            kappa: the cell's volume fraction (> 0).
            r: (rx, ry) = r - X at the cell centre.
            inv_2dx: 1 / (2 dx).
            p: the parameter record (the tension law).
            flow: whether v is read (else 0).
        """
        o, q = cell
        sx, nn = strides
        rx, ry = r
        pressure = kappa * surface_pressure(buf[o], p)
        dfx = (F[q + sx] - F[q - sx]) * inv_2dx
        dfy = (F[q + 1] - F[q - 1]) * inv_2dx
        m0, m1, m2, m3, m4, m5, m6 = friction_moments(buf, o, nn, F[q], rx, ry, flow)
        return (
            sums[0] - pressure * dfx, sums[1] - pressure * dfy,
            sums[2] - pressure * (rx * dfy - ry * dfx), sums[3] + kappa * m0,
            sums[4] + kappa * m1, sums[5] + kappa * m2, sums[6] + kappa * m3,
            sums[7] + kappa * m4, sums[8] + kappa * m5, sums[9] + kappa * m6,
        )  # fmt: skip

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
            translate), (T + T_fr + T_ext) / I; for a ``track`` body a e_theta and
            a / R with its tangential acceleration a (module docstring).
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
        spin = (friction + torque + b.external_torque) * (1.0 / b.inertia)
        if b.motion == MOTION_FREE:
            inv_m = 1.0 / b.mass
            accel_x = (force_x + drag_x + b.external_force_x) * inv_m
            accel_y = (force_y + drag_y + b.external_force_y) * inv_m
        elif b.motion == MOTION_TRACK:
            place = track_place(pose, b)
            t_x, t_y = place[1], place[2]
            along = (force_x + drag_x + b.external_force_x) * t_x + (
                force_y + drag_y + b.external_force_y
            ) * t_y
            accel = (along + b.track_direction * b.track_force) / b.mass
            accel_x = accel * t_x
            accel_y = accel * t_y
            spin = accel / b.track_radius
        return (
            force_x,
            force_y,
            torque,
            drag_x,
            drag_y,
            friction,
            accel_x,
            accel_y,
            spin,
        )

    @jit
    def finite_loads(loads):
        """Whether the accelerations of :func:`body_loads` are finite."""
        return math.isfinite(loads[6]) and math.isfinite(loads[7]) and math.isfinite(loads[8])

    @jit
    def track_place(pose, b):
        """(theta, e_theta x, e_theta y, w): the place of a ``track`` body on its circle,
        the unit tangent there and the arc speed w = U . e_theta."""
        dx = pose[0] - b.track_x
        dy = pose[1] - b.track_y
        r = math.sqrt(dx * dx + dy * dy)
        t_x = -dy / r
        t_y = dx / r
        return math.atan2(dy, dx), t_x, t_y, pose[3] * t_x + pose[4] * t_y

    @jit
    def track_step(pose, turn, speed, b):
        """The pose of a ``track`` body moved by the angle `turn` along its circle, with
        the arc speed `speed`: X = C + R e_r(theta + turn), phi + turn, U = speed
        e_theta, omega = speed / R (module docstring)."""
        theta = track_place(pose, b)[0] + turn
        radius = b.track_radius
        cos_t = math.cos(theta)
        sin_t = math.sin(theta)
        return (
            b.track_x + radius * cos_t,
            b.track_y + radius * sin_t,
            pose[2] + turn,
            -speed * sin_t,
            speed * cos_t,
            speed / radius,
        )

    @jit
    def leaves_vessel(x, y, reach, p):
        """Whether the footprint of radius `reach` about (x, y) crosses a wall of the
        run's vessel (record `p`: ``vessel``, its centre ``vessel_x``, ``vessel_y`` and
        sizes ``vessel_a``, ``vessel_b``: an annulus' R1, R2, a tank's half widths); the
        dish's edge (``vessel`` 0) is caught where the footprint is drawn."""
        dx = x - p.vessel_x
        dy = y - p.vessel_y
        if p.vessel == VESSEL_ANNULUS:
            r = math.sqrt(dx * dx + dy * dy)
            return r - reach < p.vessel_a or r + reach > p.vessel_b
        if p.vessel == VESSEL_RECTANGLE:
            return abs(dx) + reach > p.vessel_a or abs(dy) + reach > p.vessel_b
        return False

    @jit
    def contact_push(gap, rate, p):
        """The contact's force along the gap's normal, kappa (ell - gap) - gamma rate for a
        gap below ell (`rate` its rate of change dg/dt), else 0 (record `p`)."""
        ell = p.contact_range
        if gap < ell:
            return p.contact_stiffness * (ell - gap) - p.contact_damping * rate
        return 0.0

    @jit
    def pair_contact(here, reach, there, reach_o, p):
        """The contact force on the footprint of radius `reach` whose centre and velocity
        are `here` = (x, y, u, v) from the one of radius `reach_o` at `there` (the
        same): kappa (ell - g) - gamma dg/dt along their centres' line, away from the
        other, for the gap g = d - reach - reach_o < ell (else 0), dg/dt = (X - X_o) .
        (U - U_o) / d."""
        dx = here[0] - there[0]
        dy = here[1] - there[1]
        d = math.sqrt(dx * dx + dy * dy)
        if d == 0.0:
            return 0.0, 0.0
        rate = (dx * (here[2] - there[2]) + dy * (here[3] - there[3])) / d
        size = contact_push(d - reach - reach_o, rate, p) / d
        return size * dx, size * dy

    @jit
    def wall_contact(here, reach, p):
        """The contact force on the footprint of radius `reach` whose centre and velocity
        are `here` = (x, y, u, v) from the walls within ell of it: kappa (ell - g) -
        gamma dg/dt along each wall's normal into the vessel, g the footprint's clearance
        (the dish's rim and an annulus' outer circle at ``vessel_b``, its inner one at
        ``vessel_a``, a tank's sides at +-a, +-b)."""
        dx = here[0] - p.vessel_x
        dy = here[1] - p.vessel_y
        u, v = here[2], here[3]
        if p.vessel == VESSEL_RECTANGLE:
            f_x = contact_push(p.vessel_a + dx - reach, u, p)
            f_x -= contact_push(p.vessel_a - dx - reach, -u, p)
            f_y = contact_push(p.vessel_b + dy - reach, v, p)
            f_y -= contact_push(p.vessel_b - dy - reach, -v, p)
            return f_x, f_y
        r = math.sqrt(dx * dx + dy * dy)
        if r == 0.0:
            return 0.0, 0.0
        outward = (dx * u + dy * v) / r
        push = -contact_push(p.vessel_b - r - reach, -outward, p)
        if p.vessel == VESSEL_ANNULUS:
            push += contact_push(r - reach - p.vessel_a, outward, p)
        return push * dx / r, push * dy / r

    @jit
    def contact_loads(loads, pose, f_x, f_y, b):
        """`loads` (:func:`body_loads`) with the contact force (f_x, f_y) in the
        accelerations: f / m of a free body, (f . e_theta) e_theta / m and
        f . e_theta / (m R) of a track body; unchanged for the others."""
        a_x, a_y, spin = loads[6], loads[7], loads[8]
        if b.motion == MOTION_FREE:
            a_x += f_x / b.mass
            a_y += f_y / b.mass
        elif b.motion == MOTION_TRACK:
            place = track_place(pose, b)
            along = (f_x * place[1] + f_y * place[2]) / b.mass
            a_x += along * place[1]
            a_y += along * place[2]
            spin += along / b.track_radius
        return (loads[0], loads[1], loads[2], loads[3], loads[4], loads[5], a_x, a_y, spin)

    @jit
    def euler_pose(pose, loads, dt, b):
        """One forward Euler step of dX/dt = U, dphi/dt = omega and the accelerations of
        `loads` (:func:`body_loads`): X and U only for a ``free`` body; theta and w for a
        ``track`` body (:func:`track_step`)."""
        if b.motion == MOTION_TRACK:
            place = track_place(pose, b)
            accel = loads[6] * place[1] + loads[7] * place[2]
            return track_step(pose, dt * place[3] / b.track_radius, place[3] + dt * accel, b)
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
        `loads_p`): the trapezoidal average; X and U only for a ``free`` body; theta and
        w for a ``track`` body, each rate projected on the tangent at its own place."""
        half = 0.5 * dt
        if b.motion == MOTION_TRACK:
            place = track_place(pose, b)
            guess = track_place(predicted, b)
            accel = loads[6] * place[1] + loads[7] * place[2]
            accel_p = loads_p[6] * guess[1] + loads_p[7] * guess[2]
            turn = half * (place[3] + guess[3]) / b.track_radius
            return track_step(pose, turn, place[3] + half * (accel + accel_p), b)
        x, y, phi, u, v, omega = pose
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
        cell_integrals=cell_integrals,
        wet_cell_integrals=wet_cell_integrals,
        body_loads=body_loads,
        finite_loads=finite_loads,
        euler_pose=euler_pose,
        heun_pose=heun_pose,
        noise_kick=noise_kick,
        track_place=track_place,
        track_step=track_step,
        leaves_vessel=leaves_vessel,
        pair_contact=pair_contact,
        wall_contact=wall_contact,
        contact_loads=contact_loads,
    )
