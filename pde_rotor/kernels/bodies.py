"""Compiled CPU step of K bodies on one surface: c, v and every body advanced together.

:func:`advance_bodies` is the loop of :func:`pde_rotor.kernels.cpu.advance` for the
generalised model (docs/bodies.md): every step it

1. holds the bodies that are fixed or in a stop of their own schedule (the motion's
   ``held``, ``hold``);
2. redraws F, G (filtered for ``consistent``) and the owner map of each body whose pose
   changed since it was last drawn (:func:`pde_rotor.kernels.body_draw.draw_body`;
   bodies may not overlap, so each cell belongs to one body at most, and the plate
   velocity of a cell is its owner's, the rates' ``plate_velocity``), and the rows' runs
   of each body's cells (:func:`pde_rotor.kernels.body_fields.body_segments`);
3. takes each moving body's integrals over its plate
   (:func:`pde_rotor.kernels.body_sums.body_integrals`, area form with central
   differences, the ``paper`` scheme; for ``consistent`` the force and torque in contour
   form, :func:`pde_rotor.kernels.body_sums.body_contour`);
4. advances c and v by one Euler step of Eqs. (eqc), (eqv)
   (:func:`pde_rotor.kernels.body_fields.fields`: the rates' ``plate_rates`` with the
   owner's plate velocity; behind a no-flux dish wall c on the cut cells of the circle,
   :func:`pde_rotor.kernels.wall.euler_walled_fields`);
5. advances the bodies, Eq. (eq_motion) about X_k (the motion's ``body_loads``,
   ``euler_pose``), forward Euler or Heun's method (the rotor's semantics, see
   :func:`advance_bodies`), and the noise kick of Eq. (noiseav) on omega.

The rotor's loop (:func:`pde_rotor.kernels.cpu.advance`) takes the same step's tail
with the same functions of :mod:`pde_rotor.physics.motion`: the paper's rotor is the
``fixed_axis`` body at the origin.

A body that reaches the dish's edge or another body ends the run: the step, the body
and the reason are returned (see :func:`advance_bodies`), and the solver raises with
them. The physics is :mod:`pde_rotor.physics`; these loops only walk the grid.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ..physics.build import CPU
from ..physics.motion import MOTION_FIXED, N_INTEGRALS
from .body_draw import (
    SCRATCH_ROWS,
    STATUS_EDGE,
    STATUS_FINITE,
    STATUS_OVERLAP,
    draw_body,
    footprint_rows,
)
from .body_fields import average_fields, body_segments, fields
from .body_sums import body_contour, body_integrals, spanning_integrals

_held = CPU.motion.held
_hold = CPU.motion.hold
_body_loads = CPU.motion.body_loads
_finite_loads = CPU.motion.finite_loads
_euler_pose = CPU.motion.euler_pose
_heun_pose = CPU.motion.heun_pose
_noise_kick = CPU.motion.noise_kick
_leaves_vessel = CPU.motion.leaves_vessel
_pair_contact = CPU.motion.pair_contact
_wall_contact = CPU.motion.wall_contact
_contact_loads = CPU.motion.contact_loads

N_LOADS = 11
"""A body's loads per evaluation: the motion's ``body_loads`` (9) and the contact force
(x, y) (0 without contact)."""


@nb.njit(cache=True, nogil=True)
def _draw_bodies(maps, domain, surface, bodies, p, work, status):
    """Draw every body whose pose changed since it was last drawn
    (:func:`~pde_rotor.kernels.body_draw.draw_body`), then the bodies' runs of each row
    (:func:`~pde_rotor.kernels.body_fields.body_segments`) (compiled); `maps` is (F, G,
    owner), `surface` is (wall, first: the first step of a call, whose chords of the
    bodies' last drawings are taken anew, :func:`~pde_rotor.kernels.body_draw.footprint_rows`,
    and whose runs are redone anyway), `bodies` as for :func:`advance_bodies`, `work`
    (the drawing's work: scratch, taps, chords, fresh; segments).

    Returns:
        True, or False on a contact (the reason and bodies in `status`).
    """
    F, G, owner = maps
    body, _, pose, drawn, _, _, _, _ = bodies
    draw_work, segments = work
    chords = draw_work[2]
    redrawn = surface[1]
    if redrawn:
        for k in range(body.shape[0]):
            footprint_rows(domain[0], k, bodies, chords)
    for k in range(body.shape[0]):
        moved = pose[k, 0] != drawn[k, 0] or pose[k, 1] != drawn[k, 1]
        if moved or pose[k, 2] != drawn[k, 2]:
            code = draw_body(F, G, owner, domain, k, bodies, p, draw_work, moved)
            if code != 0:
                status[0] = STATUS_EDGE if code > 0 else STATUS_OVERLAP
                status[1] = k
                status[2] = -1 - code if code < 0 else -1
                return False
            drawn[k, 0], drawn[k, 1], drawn[k, 2] = pose[k, 0], pose[k, 1], pose[k, 2]
            redrawn = True
    if redrawn:  # the runs are scratch of each call
        body_segments(bodies, chords, segments)
    return True


@nb.njit(cache=True, nogil=True)
def _loads(cur, F, domain, bodies, chords, p, integrals, loads, status, volume):
    """Each moving body's loads at its pose on the state `cur` into loads[k] (compiled):
    its integrals (:func:`~pde_rotor.kernels.body_sums.body_integrals`, and
    :func:`~pde_rotor.kernels.body_sums.body_contour` for the contour form; for a body
    that spans its channel :func:`~pde_rotor.kernels.body_sums.spanning_integrals` over
    the wet cells, `volume` the cut cells' kappa, flat)
    and the motion's ``body_loads``.

    With contact on, the contact forces are added (:func:`_contact`); `loads` is
    (K, :data:`N_LOADS`).

    Returns:
        True, or False where the footprint of a body that does not span its channel
        crosses a wall of the vessel (the motion's ``leaves_vessel``; ``STATUS_EDGE``,
        also with contact on, whose spring was then too weak) or its accelerations are
        not finite (the body in `status`).
    """
    body, _, pose, _, _, _, _, _ = bodies
    coords = domain[0]
    sign_k = p.torque_sign * p.tension_slope
    for k in range(body.shape[0]):
        b = body[k]
        if b.motion == MOTION_FIXED:
            continue
        if b.spans:
            spanning_integrals(cur, F, volume, coords, k, (bodies, chords), p, integrals)
        elif _leaves_vessel(pose[k, 0], pose[k, 1], b.contact, p):
            status[0] = STATUS_EDGE
            status[1] = k
            status[2] = -1
            return False
        else:
            body_integrals(cur, F, coords, k, (bodies, chords), p, integrals)
            if p.contour:
                body_contour(cur, coords, k, bodies, p, integrals)
        state = (pose[k, 0], pose[k, 1], pose[k, 2], pose[k, 3], pose[k, 4], pose[k, 5])
        out = _body_loads(integrals, state, b, sign_k)
        for m in range(9):
            loads[k, m] = out[m]
        if not _finite_loads(out):
            status[0] = STATUS_FINITE
            status[1] = k
            return False
    if p.contact_range > 0.0:
        _contact(body, pose, p, loads)
    return True


@nb.njit(cache=True, nogil=True)
def _contact(body, pose, p, loads):
    """Add each moving body's contact force with every other body and the walls (not for
    a body that spans its channel, whose plate crosses them by design) to its
    accelerations in loads[k, 6:9] and put the force into loads[k, 9:11] (compiled; the
    motion's ``pair_contact``, ``wall_contact`` at the poses' positions and velocities,
    ``contact_loads``)."""
    for k in range(body.shape[0]):
        b = body[k]
        if b.motion == MOTION_FIXED:
            continue
        here = (pose[k, 0], pose[k, 1], pose[k, 3], pose[k, 4])
        f_x, f_y = (0.0, 0.0) if b.spans else _wall_contact(here, b.contact, p)
        for j in range(body.shape[0]):
            if j != k:
                there = (pose[j, 0], pose[j, 1], pose[j, 3], pose[j, 4])
                g = _pair_contact(here, b.contact, there, body[j].contact, p)
                f_x += g[0]
                f_y += g[1]
        state = (pose[k, 0], pose[k, 1], pose[k, 2], pose[k, 3], pose[k, 4], pose[k, 5])
        out = _contact_loads(loads[k], state, f_x, f_y, b)
        for m in range(6, 9):
            loads[k, m] = out[m]
        loads[k, 9] = f_x
        loads[k, 10] = f_y


@nb.njit(cache=True, nogil=True)
def _set_poses(pose, poses):
    """pose[:, :6] = the (K, 6) `poses`."""
    for k in range(pose.shape[0]):
        for m in range(6):
            pose[k, m] = poses[k, m]


@nb.njit(cache=True, nogil=True)
def advance_bodies(states, maps, domain, wall, params, bodies, xi, status, steps):
    """Advance c, v and every body by `n_steps` steps, forward Euler or Heun (compiled).

    Each step, every body k:

    1. held (``fixed``, or in a stop of its own schedule: the motion's ``held``): U = 0,
       omega = 0 (``hold``), and the column ``stopped`` of its pose is 1;
    2. F, G and the owner map redrawn where a pose changed (:func:`_draw_bodies`);
    3. the loads of each moving body at the state y and pose P (:func:`_loads`, the
       motion's ``body_loads``, and with contact on the contact force), recorded in its
       pose's force columns (tension, friction; contact in ``contact_x``, ``contact_y``);
    4. the fields' Euler step y~ = y + dt f(y, P)
       (:func:`~pde_rotor.kernels.body_fields.fields`).

    Forward Euler (`stage` empty): 5. P <- ``euler_pose`` of every body not held.

    Heun (`stage` of the data's shape), the rotor's semantics
    (:func:`pde_rotor.kernels.cpu.advance`):

    5. the predicted poses P~ = ``euler_pose`` (P for a held body, whose velocities stay 0);
    6. F, G and the owner map redrawn at P~ (a contact there ends the run as at step 2);
    7. the loads at (y~, P~) (step 3, not recorded);
    8. a second Euler step of the fields from (y~, P~) into `stage`, y~ + dt f(y~, P~);
    9. the fields' average y + dt (f(y, P) + f(y~, P~)) / 2 = (y + stage) / 2 on the
       cells a step writes (:func:`~pde_rotor.kernels.body_fields.average_fields`);
    10. every body not held: P <- ``heun_pose`` (the trapezoid of X, phi with the
        velocities at P and P~, of U, omega with the accelerations at both).

    Then, both integrators: the noise kick of Eq. (noiseav) on omega of every body not
    held (``noise_kick``, once per step, after the average), and on to the next step.
    Every step ends with finite accelerations, or the run ends.

    Args:
        states: (data, spare, stage): the flat state (c, v_x, v_y), 3 n^2 values,
            updated in place; scratch of the same shape; scratch of the same shape for
            Heun's method, or empty for Euler.
        maps: (F, G, owner): flat indicator arrays and the owner map (-1: no body),
            updated.
        domain: (coords, lo, hi): the cells' centres of the dish frame and the interior
            columns [lo, hi) of each row.
        wall: the cut cells of a no-flux dish wall (:meth:`pde_rotor.model.wall.CutCells.arrays`;
            empty, :data:`pde_rotor.kernels.wall.NO_WALL`, for the absorbing wall).
        params: the run's parameter record (:func:`pde_rotor.kernels.records.make_record`).
        bodies: (body, pills, pose, drawn, box, normals, centres, tables):
            the bodies' records (``BODY``), their pills (P, 7): body-frame x, y, radius,
            relative source density, and polar form: distance from X and the angle as
            two terms (the paper's corner angle 2 pi j / N and the shift Delta, added in
            the rotor's order); the (K, 15) poses
            (:data:`pde_rotor.model.surface.POSE_COLUMNS`), updated in place; (K, 3) x,
            y, phi at which each body was last drawn (nan: never); (K, 4) int rows and
            columns of each body's last drawn footprint; scratch (2, max N, K) and
            (2, P); the ``consistent`` scheme's arrays
            (:func:`pde_rotor.kernels.records.make_body_tables`), read where the
            record's ``filtered`` and ``contour`` are set.
        xi: K standard normals per step for the noise (read where a body's kick != 0).
        status: (3,) ints: on an early end, the reason (``STATUS_*``) and the bodies.
        steps: (step0, n_steps): global index of the first step, number of steps.

    Returns:
        -1 on success, else the index of the step at which the run ended (state and
        poses left at the start of that step; the reason in `status`).
    """
    data, spare, stage = states
    F = maps[0]
    step0, n_steps = steps
    p = params[0]
    dt = p.dt
    body, _, pose, _, _, _, _, _ = bodies
    n_bodies = body.shape[0]
    coords = domain[0]
    n = coords.size
    nn = n * n
    cur = data
    nxt = spare
    heun = stage.size > 0
    integrals = np.zeros(N_INTEGRALS)
    loads = np.zeros((n_bodies, N_LOADS))
    loads_p = np.zeros((n_bodies, N_LOADS))
    start = np.zeros((n_bodies, 6))
    predicted = np.zeros((n_bodies, 6))
    rhs = np.zeros(nn if wall[0].size > 0 else 0)
    scratch = np.empty((SCRATCH_ROWS, n))
    taps = np.empty(n, np.uint64)
    chords = np.zeros((2, n_bodies, n), np.int64)
    draw_work = (scratch, taps, chords, np.zeros((2, n), np.int64))
    work = (draw_work, (np.zeros(n + 1, np.int64), np.zeros((3, n_bodies * n), np.int64)))
    surface = (wall, work[1])
    if not p.flow:
        data[nn:] = 0.0
        spare[nn:] = 0.0
        if heun:
            stage[nn:] = 0.0
    for s in range(n_steps):
        for k in range(n_bodies):
            is_held = _held(step0 + s, body[k])
            pose[k, 12] = 1.0 if is_held else 0.0
            state = (pose[k, 0], pose[k, 1], pose[k, 2], pose[k, 3], pose[k, 4], pose[k, 5])
            state = _hold(state, is_held)
            for m in range(6):
                start[k, m] = state[m]
        _set_poses(pose, start)
        ok = _draw_bodies(maps, domain, (wall, s == 0), bodies, p, work, status)
        if ok:
            ok = _loads(cur, F, domain, bodies, chords, p, integrals, loads, status, wall[0])
        if not ok:
            if s % 2 == 1:
                data[:] = spare
            return s
        for k in range(n_bodies):
            for m in range(6):
                pose[k, 6 + m] = loads[k, m]
            pose[k, 13] = loads[k, 9]
            pose[k, 14] = loads[k, 10]
        fields(cur, nxt, maps, domain, surface, p, pose, rhs)
        for k in range(n_bodies):
            b = body[k]
            state = (start[k, 0], start[k, 1], start[k, 2], start[k, 3], start[k, 4], start[k, 5])
            load = (loads[k, 0], loads[k, 1], loads[k, 2], loads[k, 3], loads[k, 4],
                    loads[k, 5], loads[k, 6], loads[k, 7], loads[k, 8])  # fmt: skip
            if pose[k, 12] == 0.0:
                state = _euler_pose(state, load, dt, b)
            for m in range(6):
                predicted[k, m] = state[m]
        _set_poses(pose, predicted)
        if heun:
            ok = _draw_bodies(maps, domain, (wall, False), bodies, p, work, status)
            if ok:
                ok = _loads(nxt, F, domain, bodies, chords, p, integrals, loads_p, status, wall[0])
            if not ok:
                _set_poses(pose, start)
                if s % 2 == 1:
                    data[:] = spare
                return s
            fields(nxt, stage, maps, domain, surface, p, pose, rhs)
            average_fields(cur, stage, nxt, domain, wall, p.flow)
            for k in range(n_bodies):
                if pose[k, 12] != 0.0:
                    continue
                state = (start[k, 0], start[k, 1], start[k, 2], start[k, 3], start[k, 4],
                         start[k, 5])  # fmt: skip
                load = (loads[k, 0], loads[k, 1], loads[k, 2], loads[k, 3], loads[k, 4],
                        loads[k, 5], loads[k, 6], loads[k, 7], loads[k, 8])  # fmt: skip
                guess = (predicted[k, 0], predicted[k, 1], predicted[k, 2], predicted[k, 3],
                         predicted[k, 4], predicted[k, 5])  # fmt: skip
                load_p = (loads_p[k, 0], loads_p[k, 1], loads_p[k, 2], loads_p[k, 3],
                          loads_p[k, 4], loads_p[k, 5], loads_p[k, 6], loads_p[k, 7],
                          loads_p[k, 8])  # fmt: skip
                state = _heun_pose(state, load, guess, load_p, dt, body[k])
                for m in range(6):
                    pose[k, m] = state[m]
        for k in range(n_bodies):
            b = body[k]
            if pose[k, 12] == 0.0 and b.kick != 0.0:
                state = (pose[k, 0], pose[k, 1], pose[k, 2], pose[k, 3], pose[k, 4], pose[k, 5])
                pose[k, 5] = _noise_kick(state, xi[s * n_bodies + k], b)[5]
        cur, nxt = nxt, cur
    if n_steps % 2 == 1:
        data[:] = spare
    return -1
