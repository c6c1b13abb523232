"""The physics core: every per-cell update and rotor integral of the model, written once.

The functions below are plain scalar Python functions built by :func:`make_core` for a
given compiler: :data:`CPU` compiles them with numba's ``njit`` (inlined into the CPU
loops of :mod:`pde_rotor.kernels.cpu`), :mod:`pde_rotor.kernels.cuda` compiles the same
source as CUDA device functions. The loops that call them (rows of a grid on the CPU,
threads of a block on the GPU) hold no physics of their own, so the two backends cannot
drift apart. :mod:`pde_rotor.model.pde` keeps an independent numpy version of the same
equations as the test oracle.

numba caches each compiled loop on disk keyed by its own file: after editing this module,
delete the ``__pycache__/*.nbi`` and ``*.nbc`` files of the package, or the CPU loops of
:mod:`pde_rotor.kernels.cpu` keep the inlined old version.

State layout: a flat float64 buffer holding c, v_x, v_y of one member one after the
other, each an n x n grid with x along axis 0; the cell (i, j) of a field starting at
offset ``o0`` sits at ``o0 + i n + j``. So ``buf[o + n]`` is the east (x + dx), ``buf[o + 1]``
the north (y + dx) neighbour of ``buf[o]``.

Physics (section "Model" of Koyano et al., Chaos 2020):

* :func:`rotor_table`: edge normals e_j, Eq. (ejt0) rotated by phi, and pill centres
  R_j = R_c e(phi + 2 pi j / N + Delta), Eq. (rc) with the pills at the corners
  (erratum of Eq. (rj), see :mod:`pde_rotor.model.geometry`);
* :func:`plate_cell`, :func:`pill_cell`: the smoothed indicators F and G (the
  equations after Eq. (rj)) at one cell centre (scheme ``paper``), built from the
  plate's profile of the gauge h(r) (:func:`plate_profile`) and one pill's term
  (:func:`pill_term`), with the tanh written as a branch-free :func:`logistic` of a
  polynomial :func:`vector_expm1`; :func:`filtered_plate`, :func:`filtered_pills`: the
  same after the isotropic Gaussian prefilter of the scheme ``consistent``, from the
  tables of :mod:`pde_rotor.model.filtering` (:func:`filtered_edge`, :func:`filtered_corner`,
  :func:`filtered_pill_term`). The GPU calls the cell functions once per cell; the CPU
  calls the terms in loops over a row's cells, four at a time (SIMD);
* the geometry of F and G shared by the cell functions and the CPU's row loops: the
  plate's gauge h(r) = max_j r . e_j (:func:`projection`, :func:`farther`,
  :func:`gauge_step`), the frame
  of the nearest edge (:func:`tangential`, :func:`nearer_edge`, :func:`near_corner`) and
  the pills' reach (:func:`pill_reach`, :func:`filtered_pill_reach`);
* :func:`cell_rates`: the right-hand sides of Eqs. (eqc) and (eqv) of one cell
  (5-point Laplacian, central divergence), with the coefficients of
  :func:`rate_coefficients`;
* :func:`cell_integrals`: one cell's share of the integrals of Eq. (eq_motion):
  F r x grad c (area form of the torque, Eq. (torque)), F |r|^2 and F r x v;
* :func:`contour_node`: one node of the contour form of the same torque integral
  (scheme ``consistent``, see :mod:`pde_rotor.model.schemes`), with c from its interpolating
  cubic spline (:func:`spline_line`, :func:`interpolate`); the node's taps and weight
  (:func:`contour_place`) apart from the sum over the taps (:func:`spline_sum`), so that
  the CPU places many nodes at once;
* the rotor, Eq. (eq_motion): :func:`rotor_torques` (T of Eq. (torque) and the friction
  torque from the integrals), :func:`angular_acceleration`, the steps :func:`euler_rotor`
  and :func:`heun_rotor`, the Euler-Maruyama kick of Eq. (noiseav) (:func:`noise_kick`),
  and the stop schedule :func:`stopped_at`.

The scalar parameters come as one record `p` (:mod:`pde_rotor.kernels.records`), read by
field name (``p.dt``) on both targets.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numba as nb

from ..config import X_SATURATION

SPLINE_POLE = math.sqrt(3.0) - 2.0
"""Pole of the cubic B-spline prefilter (Unser, IEEE Signal Process. Mag. 1999)."""

SPLINE_MARGIN = 24
"""Cells the spline window extends beyond the contour's taps: |pole|^24 = 2e-14."""


class Core(NamedTuple):
    """The compiled physics functions for one target (see the module docstring)."""

    vector_expm1: Callable
    logistic: Callable
    rotor_table: Callable
    projection: Callable
    farther: Callable
    gauge_step: Callable
    tangential: Callable
    nearer_edge: Callable
    near_corner: Callable
    pill_reach: Callable
    filtered_pill_reach: Callable
    plate_profile: Callable
    pill_term: Callable
    plate_cell: Callable
    pill_cell: Callable
    filtered_edge: Callable
    corner_taps: Callable
    corner_sum: Callable
    filtered_corner: Callable
    filtered_plate: Callable
    filtered_pill_term: Callable
    filtered_pills: Callable
    rate_coefficients: Callable
    stopped_at: Callable
    rotor_torques: Callable
    angular_acceleration: Callable
    euler_rotor: Callable
    heun_rotor: Callable
    noise_kick: Callable
    plate_rates: Callable
    cut_cell_inflow: Callable
    local_rate: Callable
    cell_rates: Callable
    cell_integrals: Callable
    spline_causal: Callable
    spline_anticausal_start: Callable
    spline_anticausal: Callable
    spline_gain: Callable
    spline_line: Callable
    bspline_weights: Callable
    spline_node: Callable
    spline_sum: Callable
    interpolate: Callable
    contour_place: Callable
    contour_point: Callable
    contour_node: Callable


def make_core(jit: Callable[[Callable], Callable]) -> Core:
    """Compile the physics functions with `jit` (numba ``njit`` or ``cuda.jit(device=True)``).

    Args:
        jit: decorator turning a scalar Python function into a compiled one that other
            compiled functions of the same target can call.

    Returns:
        The compiled functions; each calls only its siblings, so the set is self-contained.
    """

    @jit
    def vector_expm1(x: float) -> float:
        """exp(x) - 1 for 0 <= x <= 2 X_SATURATION in multiplications and additions only.

        The Taylor polynomial of degree 15 of expm1(x / 64) (remainder below 5e-17), then
        six doublings of the argument, (1 + q)^2 - 1 = q (2 + q), which keep the relative
        accuracy (2e-14 over the range, tests/test_core.py; squaring exp(x / 64) itself
        would lose 64 ulp). libm's exp is a call that stops LLVM from vectorising a loop;
        this is not, so the CPU loops over a row of cells run it four cells at a time.
        """
        r = x * (1.0 / 64.0)
        p = 1.0 / 1307674368000.0
        p = p * r + 1.0 / 87178291200.0
        p = p * r + 1.0 / 6227020800.0
        p = p * r + 1.0 / 479001600.0
        p = p * r + 1.0 / 39916800.0
        p = p * r + 1.0 / 3628800.0
        p = p * r + 1.0 / 362880.0
        p = p * r + 1.0 / 40320.0
        p = p * r + 1.0 / 5040.0
        p = p * r + 1.0 / 720.0
        p = p * r + 1.0 / 120.0
        p = p * r + 1.0 / 24.0
        p = p * r + 1.0 / 6.0
        p = p * r + 0.5
        p = p * r + 1.0
        q = p * r
        q = q * (2.0 + q)
        q = q * (2.0 + q)
        q = q * (2.0 + q)
        q = q * (2.0 + q)
        q = q * (2.0 + q)
        return q * (2.0 + q)

    @jit
    def logistic(arg: float) -> float:
        """1/2 (1 + tanh(arg)) = 1 / (1 + exp(-2 arg)), arg clipped to +-X_SATURATION
        (where it is 1 exactly, or 4.2e-18), written with E = exp(2 |arg|) >= 1 as
        E / (E + 1) or 1 / (E + 1): branch-free, so vectorisable, and within 1 ulp of 1.
        ``scipy.special.expit(2 arg)`` outside compiled code; the kernels cannot call it."""
        arg = arg if arg < X_SATURATION else X_SATURATION
        arg = arg if arg > -X_SATURATION else -X_SATURATION
        big = 1.0 + vector_expm1(2.0 * abs(arg))
        return (big if arg >= 0.0 else 1.0) / (big + 1.0)

    @jit
    def rotor_table(phi, n_corners, r_c, asym, tab):
        """Fill tab (4, >= N): edge normals (cos, sin), pill centres (x, y) at angle phi."""
        for k in range(n_corners):
            a_edge = phi + 2.0 * math.pi * (k + 0.5) / n_corners
            tab[0, k] = math.cos(a_edge)
            tab[1, k] = math.sin(a_edge)
            a_pill = phi + 2.0 * math.pi * (k + 1) / n_corners + asym
            tab[2, k] = r_c * math.cos(a_pill)
            tab[3, k] = r_c * math.sin(a_pill)

    @jit
    def projection(x, y, ex, ey):
        """r . e_j, the distance of (x, y) along the edge normal e_j = (ex, ey)."""
        return x * ex + y * ey

    @jit
    def farther(p, h):
        """Whether p = r . e_j exceeds h: strict, so that the first of equal edges wins."""
        return p > h

    @jit
    def gauge_step(h, x, y, ex, ey):
        """max(h, r . e_j): one edge's step of the gauge h(r) = max_j r . e_j (branch-free)."""
        p = projection(x, y, ex, ey)
        return p if farther(p, h) else h

    @jit
    def gauge(x, y, tab, n_corners):
        """h(r) = max_j r . e_j: the plate's level sets h = const are regular N-gons."""
        h = projection(x, y, tab[0, 0], tab[1, 0])
        for k in range(1, n_corners):
            h = gauge_step(h, x, y, tab[0, k], tab[1, k])
        return h

    @jit
    def tangential(x, y, ex, ey):
        """r . tau_j, tau_j = e_j = (ex, ey) turned by +pi/2: the position along edge j."""
        return y * ex - x * ey

    @jit
    def nearer_edge(h, q, x, y, ex, ey):
        """(h, q) of (x, y) in the frame of the nearer of the edge so far (h = r . e,
        q = r . tau) and edge (ex, ey): the new edge where r . e_j > h (so the first of
        equal edges wins; branch-free)."""
        p = projection(x, y, ex, ey)
        nearer = farther(p, h)
        return (p if nearer else h), (tangential(x, y, ex, ey) if nearer else q)

    @jit
    def near_corner(h, q, tan_half, crease, corner_end):
        """Whether (h, q) (frame of the nearest edge) lies within the crease width of a
        corner bisector, h tan(pi/N) - |q| <= crease, and short of the table's end
        h < `corner_end` (beyond, F_eps is below 1e-13: :mod:`pde_rotor.model.filtering`,
        ``corner_end``), where F_eps needs the 2-D table."""
        return (h * tan_half - abs(q) <= crease) & (h < corner_end)

    @jit
    def pill_reach(rho, inv_delta):
        """rho + X_SATURATION delta: beyond, a pill's term of G is below 4.3e-18."""
        return rho + X_SATURATION / inv_delta

    @jit
    def filtered_pill_reach(profile, inv_step):
        """The end of the filtered pill profile (spacing 1 / inv_step): beyond, G_eps's
        term is 0."""
        return (profile.size - 1) / inv_step

    @jit
    def plate_profile(h, apothem, inv_delta):
        """F as a function of the gauge h(r): 1/2 [1 + tanh((R cos(pi/N) - h) / delta)]."""
        return logistic((apothem - h) * inv_delta)

    @jit
    def pill_term(dx, dy, rho, inv_delta):
        """One pill's share of G at the offset (dx, dy) from its centre:
        1/2 [1 + tanh((rho - |(dx, dy)|) / delta)]."""
        return logistic((rho - math.sqrt(dx * dx + dy * dy)) * inv_delta)

    @jit
    def plate_cell(x, y, tab, n_corners, apothem, inv_delta):
        """F at the cell centre (x, y) (scheme ``paper``)."""
        return plate_profile(gauge(x, y, tab, n_corners), apothem, inv_delta)

    @jit
    def pill_cell(x, y, tab, n_corners, rho, inv_delta):
        """G at the cell centre (x, y) (scheme ``paper``): the sum over the pills within
        rho + X_SATURATION delta, in order (beyond, a pill's term is below 4.3e-18)."""
        reach = pill_reach(rho, inv_delta)
        g = 0.0
        for k in range(n_corners):
            dx = x - tab[2, k]
            dy = y - tab[3, k]
            if dx * dx + dy * dy < reach * reach:
                g += pill_term(dx, dy, rho, inv_delta)
        return g

    @jit
    def rate_coefficients(p):
        """(1/dx^2, 1/(2 dx), D, a, s0/(pi rho^2), eta, eta_b, D_eta) for :func:`cell_rates`
        from the parameter record `p` (:mod:`pde_rotor.kernels.records`), computed once per
        sweep so that the cell loop holds no division."""
        dx = p.dx
        return (
            1.0 / (dx * dx),
            0.5 / dx,
            p.diffusion,
            p.evaporation,
            p.source,
            p.drag,
            p.bulk_drag,
            p.viscosity,
        )

    @jit
    def stopped_at(step, n_ini, n_stop, n_period, cycles):
        """Whether the step from t = step dt lies in a stop phase (section "Model"):
        stop m = 1..M covers the steps [n_ini + (m - 1) n_period, ... + n_stop)."""
        rel = step - n_ini
        if rel < 0 or rel >= cycles * n_period:
            return False
        return rel % n_period < n_stop

    @jit
    def rotor_torques(cross_grad, moment, cross_v, omega, p):
        """Torque T, Eq. (torque), and friction torque of Eq. (eq_motion) from the integrals.

        T = sign k int F r x grad c dA (sign: ``rotor.torque``, :mod:`pde_rotor.model.pde`),
        friction = -mu (omega int F |r|^2 dA - int F r x v dA).

        Returns:
            (T, friction).
        """
        return (
            p.torque_sign * p.tension_slope * cross_grad,
            -p.friction * (moment * omega - cross_v),
        )

    @jit
    def angular_acceleration(torque, friction, p):
        """domega/dt of Eq. (eq_motion) without the noise: (T + friction) / I."""
        return (friction + torque) * (1.0 / p.inertia)

    @jit
    def euler_rotor(phi, omega, accel, dt):
        """One forward Euler step of dphi/dt = omega, domega/dt = accel: (phi, omega)."""
        return phi + dt * omega, omega + dt * accel

    @jit
    def heun_rotor(phi, omega, accel, omega_p, accel_p, dt):
        """Heun's corrector of (phi, omega) from the rates at the start (omega, accel)
        and at the predicted point (omega_p, accel_p): the trapezoidal average."""
        return phi + 0.5 * dt * (omega + omega_p), omega + 0.5 * dt * (accel + accel_p)

    @jit
    def noise_kick(omega, xi, p):
        """omega plus the Euler-Maruyama increment of the noise of Eqs. (eq_motion) and
        (noiseav), sqrt(2 dt) sigma / I xi for the standard normal xi of the step."""
        return omega + p.kick * xi

    @jit
    def plate_rates(buf, o, sx, sy, nn, f, g, px, py, coef, flow, plate):
        """Right-hand sides of Eqs. (eqc) and (eqv) at cell offset `o`, plate velocity (px, py).

        dc/dt = D lap c - div(c v) - a (1 - F) c + s0 / (pi rho^2) G,
        dv/dt = eta F (u - v) - eta_b v + D_eta lap v, u = (px, py) the velocity of the
        plate over the cell (omega (-y, x) for the rotor, :func:`cell_rates`; U + omega z x
        (r - X) for a body, :mod:`pde_rotor.kernels.body_core`);
        5-point Laplacian and central divergence, all at the old time level; `coef` is
        :func:`rate_coefficients` of the parameter record. `sx`, `sy`
        are the offsets of the x and y neighbours (n and 1), `nn` that of the next field;
        all three of the caller's integer type (unsigned on the CPU, so that no index
        needs a negative-wraparound check). With `plate` False the cell lies outside the
        support of F and G (both 0) and the plate terms are skipped; without `flow`
        v = 0 and only c has a rate.

        Returns:
            (rate of c, rate of v_x, rate of v_y).
        """
        inv_dx2, inv_2dx, diff, evap, src, eta, eta_b, d_eta = coef
        cc = buf[o]
        lap_c = buf[o + sx] + buf[o - sx] + buf[o + sy] + buf[o - sy]
        if not flow:
            rate_c = diff * (lap_c - 4.0 * cc) * inv_dx2 - evap * cc
            if plate:
                rate_c += evap * f * cc + src * g
            return rate_c, 0.0, 0.0
        ox = o + nn
        oy = ox + nn
        ux = buf[ox]
        uy = buf[oy]
        div_cv = (
            buf[o + sx] * buf[ox + sx]
            - buf[o - sx] * buf[ox - sx]
            + buf[o + sy] * buf[oy + sy]
            - buf[o - sy] * buf[oy - sy]
        )
        lap_x = buf[ox + sx] + buf[ox - sx] + buf[ox + sy] + buf[ox - sy]
        lap_y = buf[oy + sx] + buf[oy - sx] + buf[oy + sy] + buf[oy - sy]
        rate_c = diff * (lap_c - 4.0 * cc) * inv_dx2 - div_cv * inv_2dx - evap * cc
        rate_x = d_eta * (lap_x - 4.0 * ux) * inv_dx2 - eta_b * ux
        rate_y = d_eta * (lap_y - 4.0 * uy) * inv_dx2 - eta_b * uy
        if plate:
            rate_c += evap * f * cc + src * g
            rate_x += eta * f * (px - ux)
            rate_y += eta * f * (py - uy)
        return rate_c, rate_x, rate_y

    @jit
    def cut_cell_inflow(buf, o, sx, sy, nn, open_x, open_y, pass_x, pass_y, coef, flow):
        """Net inflow Q of camphor into the cell at offset `o` behind a no-flux dish wall.

        The transport terms of Eq. (eqc), D lap c - div(c v), as fluxes through the open
        part of each face (:mod:`pde_rotor.model.wall`):

            Q = D / dx^2 sum_f beta_f (c_N - c_P) - 1 / (2 dx) sum_f alpha_f n_f . (c v_P + c v_N),

        alpha_f the apertures `pass_x`, `pass_y` (flat arrays: the face towards +x of cell
        o at [o], towards -x at [o - sx], likewise along y), beta_f those of `open_x`,
        `open_y` (the apertures of the explicit faces: 0 where the diffusion is implicit).
        A full cell (every alpha = beta = 1) gets the 5-point Laplacian and the central
        divergence of :func:`plate_rates`; a cut cell Q per dx^2 of its own area. Offsets
        and `coef` as for :func:`plate_rates`.
        """
        inv_dx2, inv_2dx, diff, _, _, _, _, _ = coef
        cc = buf[o]
        q = (
            open_x[o] * (buf[o + sx] - cc)
            + open_x[o - sx] * (buf[o - sx] - cc)
            + open_y[o] * (buf[o + sy] - cc)
            + open_y[o - sy] * (buf[o - sy] - cc)
        ) * (diff * inv_dx2)
        if flow:
            ox = o + nn
            oy = ox + nn
            cvx = cc * buf[ox]
            cvy = cc * buf[oy]
            out = (
                pass_x[o] * (cvx + buf[o + sx] * buf[ox + sx])
                - pass_x[o - sx] * (cvx + buf[o - sx] * buf[ox - sx])
                + pass_y[o] * (cvy + buf[o + sy] * buf[oy + sy])
                - pass_y[o - sy] * (cvy + buf[o - sy] * buf[oy - sy])
            )
            q -= out * inv_2dx
        return q

    @jit
    def local_rate(cc, f, g, coef, plate):
        """The terms of Eq. (eqc) local to a cell, -a (1 - F) c + s0 / (pi rho^2) G, as
        :func:`plate_rates` adds them (`plate` False: F = G = 0)."""
        _, _, _, evap, src, _, _, _ = coef
        rate = -evap * cc
        if plate:
            rate += evap * f * cc + src * g
        return rate

    @jit
    def cell_rates(buf, o, sx, sy, nn, f, g, omega, x, y, coef, flow, plate):
        """:func:`plate_rates` of the rotor turning at omega about the origin: the plate
        velocity omega (-y, x) at the cell centre (x, y)."""
        return plate_rates(buf, o, sx, sy, nn, f, g, -omega * y, omega * x, coef, flow, plate)

    @jit
    def cell_integrals(buf, o, sx, sy, nn, f, x, y, inv_2dx, flow):
        """One cell's F r x grad c (central differences), F |r|^2 and F r x v (no dA).

        r x u = x u_y - y u_x; the three sums over cells, times dx^2, are the integrals
        of Eqs. (torque) and (eq_motion). Offsets as for :func:`cell_rates`.
        """
        dcdx = (buf[o + sx] - buf[o - sx]) * inv_2dx
        dcdy = (buf[o + sy] - buf[o - sy]) * inv_2dx
        cross_v = 0.0
        if flow:
            ox = o + nn
            cross_v = f * (x * buf[ox + nn] - y * buf[ox])
        return f * (x * dcdy - y * dcdx), f * (x * x + y * y), cross_v

    @jit
    def spline_causal(prev, value):
        """One step of the causal recursion of the cubic B-spline prefilter (Unser's
        recursive filter, pole z = sqrt(3) - 2): the sample `value` plus z times the
        previous output `prev`; the first output is the first sample."""
        return value + SPLINE_POLE * prev

    @jit
    def spline_anticausal_start(last):
        """The first (last-sample) output of the anticausal recursion, from the causal
        output `last` there: -z / (1 - z^2) times it (the samples beyond taken as 0)."""
        z = SPLINE_POLE
        return -z / (1.0 - z * z) * last

    @jit
    def spline_anticausal(nxt, causal):
        """One step of the anticausal recursion back along the line: z (next - causal),
        from the output `nxt` one sample on and the causal output `causal` here."""
        return SPLINE_POLE * (nxt - causal)

    @jit
    def spline_gain(anticausal):
        """The B-spline coefficient from the anticausal output: times 6 (the filter's gain)."""
        return 6.0 * anticausal

    @jit
    def spline_line(buf, o, stride, count):
        """Cubic B-spline prefilter, in place, of `count` samples buf[o + k stride].

        Turns samples into the coefficients of the interpolating cubic spline (Unser's
        recursive filter: :func:`spline_causal` forward, :func:`spline_anticausal_start`
        and :func:`spline_anticausal` back, :func:`spline_gain`), taking the samples
        beyond both ends as 0: a coefficient then errs by |z|^k = 0.268^k times the
        values k cells beyond the line's ends, so lines cut from a larger field need a
        margin. Written out because it runs inside the numba and CUDA kernels, which
        cannot call scipy.ndimage's prefilter (``map_coordinates`` applies it in
        :func:`pde_rotor.model.schemes.interpolate_spline`;
        tests/model/test_schemes.py compares them). The CPU filters many lines at once
        with the same steps (:mod:`pde_rotor.kernels.spline`).
        """
        prev = buf[o]
        for k in range(1, count):
            prev = spline_causal(prev, buf[o + k * stride])
            buf[o + k * stride] = prev
        last = o + (count - 1) * stride
        nxt = spline_anticausal_start(buf[last])
        buf[last] = spline_gain(nxt)
        for k in range(count - 2, -1, -1):
            nxt = spline_anticausal(nxt, buf[o + k * stride])
            buf[o + k * stride] = spline_gain(nxt)

    @jit
    def bspline_weights(t):
        """The 4 cubic B-spline weights of the nodes -1, 0, 1, 2 at t in [0, 1)."""
        u = 1.0 - t
        t2 = t * t
        return (
            u * u * u / 6.0,
            (t2 * (3.0 * t - 6.0) + 4.0) / 6.0,
            (t * (t * (3.0 - 3.0 * t) + 3.0) + 1.0) / 6.0,
            t2 * t / 6.0,
        )

    @jit
    def spline_node(x0, inv_dx, x):
        """(k, t): the node k = floor((x - x0) inv_dx) at or before the coordinate x on
        the nodes x0 + k / inv_dx, and the fraction t in [0, 1) of the way to the next;
        the cubic spline's taps along that axis are the nodes k - 1 .. k + 2, with the
        weights :func:`bspline_weights` of t."""
        f = (x - x0) * inv_dx
        # int(): numba-cuda types math.floor as float64, numba's CPU target as int64
        k = int(math.floor(f))  # noqa: RUF046
        return k, f - k

    @jit
    def spline_sum(coef, row, sx, sy, wx0, wx1, wx2, wx3, wy0, wy1, wy2, wy3):
        """sum_(a, b) wx_a wy_b coef[row + a sx + b sy], a, b = 0 .. 3: the 4 x 4 taps
        of a cubic spline from its first, `row`, the offsets `sx`, `sy` of the next node
        along x and y all of the caller's integer type (unsigned on the CPU: no index
        needs a negative-wraparound check), summed along y first."""
        r1 = row + sy
        r2 = r1 + sy
        r3 = r2 + sy
        acc = wx0 * (wy0 * coef[row] + wy1 * coef[r1] + wy2 * coef[r2] + wy3 * coef[r3])
        row += sx
        r1 += sx
        r2 += sx
        r3 += sx
        acc += wx1 * (wy0 * coef[row] + wy1 * coef[r1] + wy2 * coef[r2] + wy3 * coef[r3])
        row += sx
        r1 += sx
        r2 += sx
        r3 += sx
        acc += wx2 * (wy0 * coef[row] + wy1 * coef[r1] + wy2 * coef[r2] + wy3 * coef[r3])
        row += sx
        r1 += sx
        r2 += sx
        r3 += sx
        acc += wx3 * (wy0 * coef[row] + wy1 * coef[r1] + wy2 * coef[r2] + wy3 * coef[r3])
        return acc

    @jit
    def interpolate(coef, o0, n, x0, inv_dx, x, y):
        """Cubic spline at (x, y) from the n x n B-spline coefficients at offset o0.

        x0 is the coordinate of cell 0's centre; the 4 x 4 taps (:func:`spline_node`,
        :func:`spline_sum`) must lie in the prefiltered window (:func:`spline_line`
        along both axes). Written out because it runs inside the compiled kernels, where
        ``scipy.ndimage.map_coordinates`` cannot be called.
        """
        i, tx = spline_node(x0, inv_dx, x)
        j, ty = spline_node(x0, inv_dx, y)
        wx0, wx1, wx2, wx3 = bspline_weights(tx)
        wy0, wy1, wy2, wy3 = bspline_weights(ty)
        row = o0 + (i - 1) * n + j - 1
        return spline_sum(coef, row, n, 1, wx0, wx1, wx2, wx3, wy0, wy1, wy2, wy3)

    @jit
    def filtered_edge(h, apothem, edge, e_u0, e_inv):
        """F_eps = f_eps(apothem - h) away from the corners, from the 1-D edge profile
        `edge` (first node e_u0, 1 / spacing e_inv, linear): 0 before its first node, 1
        beyond its last (branch-free: the index is clipped, the value selected)."""
        last = edge.size - 1
        u = (apothem - h - e_u0) * e_inv
        i = min(max(int(u), 0), last - 1)
        value = edge[i] + (u - i) * (edge[i + 1] - edge[i])
        value = value if u > 0.0 else 0.0
        return value if u < last else 1.0

    @jit
    def corner_taps(h, q, t_n, t_x0, t_inv):
        """Where the cubic spline of the 2-D plate table (see :func:`filtered_corner`)
        takes its taps at (h, q): (inside, row, tx, ty), `inside` whether its 4 x 4 taps
        lie in the table, `row` the offset of the first (:func:`spline_sum`), tx, ty the
        fractions of :func:`spline_node` along h and q. Where the taps leave the table,
        those of a node inside instead (branch-free: the point is selected, so that the
        CPU computes many cells at once)."""
        fx = (h - t_x0) * t_inv
        fy = (q - t_x0) * t_inv
        inside = (fx >= 1.0) & (fy >= 1.0) & (fx < t_n - 2.0) & (fy < t_n - 2.0)
        node = t_x0 + 2.0 / t_inv
        i, tx = spline_node(t_x0, t_inv, h if inside else node)
        j, ty = spline_node(t_x0, t_inv, q if inside else node)
        return inside, (i - 1) * t_n + j - 1, tx, ty

    @jit
    def corner_sum(plate, row, sx, sy, tx, ty):
        """The cubic spline of the 2-D `plate` table from its taps (:func:`corner_taps`;
        `row`, `sx` = t_n and `sy` = 1 of the caller's integer type, as for
        :func:`spline_sum`)."""
        wx0, wx1, wx2, wx3 = bspline_weights(tx)
        wy0, wy1, wy2, wy3 = bspline_weights(ty)
        return spline_sum(plate, row, sx, sy, wx0, wx1, wx2, wx3, wy0, wy1, wy2, wy3)

    @jit
    def filtered_corner(h, q, plate, t_n, t_x0, t_inv):
        """F_eps near the corner bisectors, at (h, q) in the frame of the nearest edge:
        the cubic spline of the 2-D `plate` table (t_n x t_n coefficients on the nodes
        t_x0 + k / t_inv, edge 0's normal along +x), 0 where its taps leave the table
        (:func:`corner_taps`, :func:`corner_sum`)."""
        inside, row, tx, ty = corner_taps(h, q, t_n, t_x0, t_inv)
        if not inside:
            return 0.0
        return corner_sum(plate, row, t_n, 1, tx, ty)

    @jit
    def filtered_plate(
        x,
        y,
        tab,
        n_corners,
        apothem,
        tan_half,
        crease,
        corner_end,
        edge,
        e_u0,
        e_inv,
        plate,
        t_n,
        t_x0,
        t_inv,
    ):
        """F_eps of the cell centred at (x, y) (``consistent``, :mod:`pde_rotor.model.filtering`).

        The point is written in the frame of its nearest edge j (the one maximising
        r . e_j; the first of equals, :func:`nearer_edge`): h = r . e_j, q = r . tau_j,
        tau_j = e_j turned by +pi/2. Where h tan(pi/N) - |q| > `crease` (more than
        crease cos(pi/N) from the corner bisectors) or h >= `corner_end` (beyond the
        corners, :func:`near_corner`) F_eps comes from :func:`filtered_edge`, closer
        from :func:`filtered_corner`. Either way F_eps has
        the hexagon's symmetry exactly.
        """
        h = projection(x, y, tab[0, 0], tab[1, 0])
        q = tangential(x, y, tab[0, 0], tab[1, 0])
        for k in range(1, n_corners):
            h, q = nearer_edge(h, q, x, y, tab[0, k], tab[1, k])
        if near_corner(h, q, tan_half, crease, corner_end):
            return filtered_corner(h, q, plate, t_n, t_x0, t_inv)
        return filtered_edge(h, apothem, edge, e_u0, e_inv)

    @jit
    def filtered_pill_term(dx, dy, profile, inv_step):
        """One pill's share of G_eps at the offset (dx, dy) from its centre: the radial
        profile `profile` (spacing 1 / inv_step) interpolated linearly, 0 beyond its end
        (branch-free: the index is clipped, the value selected)."""
        last = profile.size - 1
        u = math.sqrt(dx * dx + dy * dy) * inv_step
        i = min(int(u), last - 1)
        value = profile[i] + (u - i) * (profile[i + 1] - profile[i])
        return value if u < last else 0.0

    @jit
    def filtered_pills(x, y, tab, n_corners, profile, inv_step):
        """G_eps of the cell centred at (x, y): sum_j g_eps(|r - R_j|) over the pills
        within the profile's reach, in order (beyond, a term is 0)."""
        reach = filtered_pill_reach(profile, inv_step)
        g = 0.0
        for k in range(n_corners):
            dx = x - tab[2, k]
            dy = y - tab[3, k]
            if dx * dx + dy * dy < reach * reach:
                g += filtered_pill_term(dx, dy, profile, inv_step)
        return g

    @jit
    def contour_place(n, x0, inv_dx, tab, apothem, delta, tan_half, quad_s, quad_t, j, m, k_t):
        """Where the contour node of edge j, band node m and edge node k_t (see
        :func:`contour_node`) takes the taps of the spline of c, and its weight.

        Returns:
            (row, tx, ty, w): the offset of its first tap in the n x n coefficients and
            the fractions along x and y (for :func:`bspline_weights` and
            :func:`spline_sum`, as :func:`interpolate`), and the weight w of c there in
            int F r x grad c dA.
        """
        h = apothem - delta * quad_s[0, m]
        half = h * tan_half
        t = half * quad_t[0, k_t]
        ex = tab[0, j]
        ey = tab[1, j]
        i, tx = spline_node(x0, inv_dx, h * ex - t * ey)
        k, ty = spline_node(x0, inv_dx, h * ey + t * ex)
        return (i - 1) * n + k - 1, tx, ty, -quad_s[1, m] * quad_t[1, k_t] * half * t

    @jit
    def contour_point(
        coef, o0, n, x0, inv_dx, tab, apothem, delta, tan_half, quad_s, quad_t, j, m, k_t
    ):
        """The contour node of edge j, band node m and edge node k_t (see :func:`contour_node`):
        its weight times the spline of c there (:func:`contour_place`).

        Returns:
            the node's weighted contribution to int F r x grad c dA.
        """
        row, tx, ty, w = contour_place(
            n, x0, inv_dx, tab, apothem, delta, tan_half, quad_s, quad_t, j, m, k_t
        )
        wx0, wx1, wx2, wx3 = bspline_weights(tx)
        wy0, wy1, wy2, wy3 = bspline_weights(ty)
        return w * spline_sum(coef, o0 + row, n, 1, wx0, wx1, wx2, wx3, wy0, wy1, wy2, wy3)

    @jit
    def contour_node(coef, o0, n, x0, inv_dx, tab, apothem, delta, tan_half, quad_s, quad_t, q):
        """Node q of the contour form of int F r x grad c dA (see :mod:`pde_rotor.model.schemes`).

        With h(r) = max_j r . e_j the level sets of F are N-gons, and

            int F r x grad c dA = - int w(h) sum_j int c(h e_j + t tau_j) t dt dh,

        w(h) = F'(s) / delta, s = (R cos(pi/N) - h) / delta, tau_j = e_j rotated by
        +pi/2, t in [-h tan(pi/N), h tan(pi/N)]. `quad_s` (2, M) holds the nodes s_m and
        weights of a Gauss rule for the weight 1/2 sech^2(s), `quad_t` (2, L) the
        Gauss-Legendre nodes and weights on [-1, 1]. Node q enumerates (edge j, m, l) as
        q = (j M + m) L + l (:func:`contour_point` of that triple). `coef` holds the
        B-spline coefficients of c (:func:`interpolate`).

        Returns:
            the node's weighted contribution to int F r x grad c dA.
        """
        n_s = quad_s.shape[1]
        n_t = quad_t.shape[1]
        k_t = q % n_t
        m = (q // n_t) % n_s
        j = q // (n_t * n_s)
        return contour_point(
            coef, o0, n, x0, inv_dx, tab, apothem, delta, tan_half, quad_s, quad_t, j, m, k_t
        )

    return Core(
        vector_expm1=vector_expm1,
        logistic=logistic,
        rotor_table=rotor_table,
        projection=projection,
        farther=farther,
        gauge_step=gauge_step,
        tangential=tangential,
        nearer_edge=nearer_edge,
        near_corner=near_corner,
        pill_reach=pill_reach,
        filtered_pill_reach=filtered_pill_reach,
        plate_profile=plate_profile,
        pill_term=pill_term,
        plate_cell=plate_cell,
        pill_cell=pill_cell,
        filtered_edge=filtered_edge,
        corner_taps=corner_taps,
        corner_sum=corner_sum,
        filtered_corner=filtered_corner,
        filtered_plate=filtered_plate,
        filtered_pill_term=filtered_pill_term,
        filtered_pills=filtered_pills,
        rate_coefficients=rate_coefficients,
        stopped_at=stopped_at,
        rotor_torques=rotor_torques,
        angular_acceleration=angular_acceleration,
        euler_rotor=euler_rotor,
        heun_rotor=heun_rotor,
        noise_kick=noise_kick,
        plate_rates=plate_rates,
        cut_cell_inflow=cut_cell_inflow,
        local_rate=local_rate,
        cell_rates=cell_rates,
        cell_integrals=cell_integrals,
        spline_causal=spline_causal,
        spline_anticausal_start=spline_anticausal_start,
        spline_anticausal=spline_anticausal,
        spline_gain=spline_gain,
        spline_line=spline_line,
        bspline_weights=bspline_weights,
        spline_node=spline_node,
        spline_sum=spline_sum,
        interpolate=interpolate,
        contour_place=contour_place,
        contour_point=contour_point,
        contour_node=contour_node,
    )


FASTMATH = {"contract", "arcp", "nsz"}
"""numba fastmath flags of the CPU kernels: contraction into FMAs, reciprocals, no signed
zeros; no reassociation, so sums keep their order (and CPU results their bits)."""


def _cpu_jit(func: Callable) -> Callable:
    """numba njit for the CPU loops: inlined into the caller, fastmath without reassociation."""
    return nb.njit(cache=True, nogil=True, fastmath=FASTMATH, inline="always")(func)


CPU: Core = make_core(_cpu_jit)
"""The physics core compiled for the CPU."""
