"""The per-cell right-hand sides of Eqs. (eqc) and (eqv), written once.

* :func:`rate_coefficients`: the coefficients of a step from the parameter record;
* :func:`plate_rates`: dc/dt and dv/dt of one cell under a plate moving with the
  velocity u (5-point Laplacian, central divergence); the rotor's :func:`cell_rates`
  with u = omega (-y, x); a body's plate velocity u_k = U_k + omega_k z x (r - X_k)
  (:func:`plate_velocity`) on the cells it owns (:func:`owner_plate`);
* behind a no-flux dish wall, the cut cells' inflow through the open part of their
  faces (:func:`cut_cell_inflow`) and the local terms (:func:`local_rate`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple


class Rates(NamedTuple):
    """The compiled rate functions for one target (see the module docstring)."""

    rate_coefficients: Callable
    plate_velocity: Callable
    owner_plate: Callable
    plate_rates: Callable
    cut_cell_inflow: Callable
    local_rate: Callable
    cell_rates: Callable


def make_rates(jit: Callable[[Callable], Callable]) -> Rates:
    """Compile the rate functions with `jit`.

    Args:
        jit: decorator turning a scalar Python function into a compiled one that other
            compiled functions of the same target can call (numba ``njit`` or
            ``cuda.jit(device=True)``, :func:`pde_rotor.physics.build.make_physics`).

    Returns:
        The compiled functions.
    """

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
    def plate_velocity(u, v, omega, rx, ry):
        """u_k at r = X_k + (rx, ry): U_k + omega_k z x (r - X_k) = (u - omega ry, v + omega rx)."""
        return u - omega * ry, v + omega * rx

    @jit
    def owner_plate(F, G, owner, pose, o, x, y):
        """F, G and the plate velocity u_k of the owner k of the cell at offset `o`,
        centred at (x, y) in the dish frame: the plate terms of Eqs. (eqc), (eqv) with K
        bodies, (f, g, px, py); a cell without an owner has no plate velocity."""
        k = owner[o]
        if k < 0:
            return F[o], G[o], 0.0, 0.0
        px, py = plate_velocity(pose[k, 3], pose[k, 4], pose[k, 5], x - pose[k, 0], y - pose[k, 1])
        return F[o], G[o], px, py

    @jit
    def plate_rates(buf, o, strides, f, g, u, coef, flow, plate):
        """Right-hand sides of Eqs. (eqc) and (eqv) at cell offset `o`, plate velocity
        u = (px, py).

        dc/dt = D lap c - div(c v) - a (1 - F) c + s0 / (pi rho^2) G,
        dv/dt = eta F (u - v) - eta_b v + D_eta lap v, u = (px, py) the velocity of the
        plate over the cell (omega (-y, x) for the rotor, :func:`cell_rates`; U + omega z x
        (r - X) for a body, :func:`plate_velocity`);
        5-point Laplacian and central divergence, all at the old time level; `coef` is
        :func:`rate_coefficients` of the parameter record. `strides` is (sx, sy, nn):
        the offsets of the x and y neighbours (n and 1) and that of the next field, all
        three of the caller's integer type (unsigned on the CPU, so that no index
        needs a negative-wraparound check). With `plate` False the cell lies outside the
        support of F and G (both 0) and the plate terms are skipped; without `flow`
        v = 0 and only c has a rate.

        Returns:
            (rate of c, rate of v_x, rate of v_y).
        """
        inv_dx2, inv_2dx, diff, evap, src, eta, eta_b, d_eta = coef
        sx, sy, nn = strides
        px, py = u
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
    def cut_cell_inflow(buf, o, strides, faces, coef, flow):
        """Net inflow Q of camphor into the cell at offset `o` behind a no-flux dish wall.

        The transport terms of Eq. (eqc), D lap c - div(c v), as fluxes through the open
        part of each face (:mod:`pde_rotor.model.wall`):

            Q = D / dx^2 sum_f beta_f (c_N - c_P) - 1 / (2 dx) sum_f alpha_f n_f . (c v_P + c v_N),

        `faces` is (open_x, open_y, pass_x, pass_y): alpha_f the apertures `pass_x`,
        `pass_y` (flat arrays: the face towards +x of cell
        o at [o], towards -x at [o - sx], likewise along y), beta_f those of `open_x`,
        `open_y` (the apertures of the explicit faces: 0 where the diffusion is implicit).
        A full cell (every alpha = beta = 1) gets the 5-point Laplacian and the central
        divergence of :func:`plate_rates`; a cut cell Q per dx^2 of its own area. Offsets
        (`strides`) and `coef` as for :func:`plate_rates`.
        """
        inv_dx2, inv_2dx, diff, _, _, _, _, _ = coef
        sx, sy, nn = strides
        open_x, open_y, pass_x, pass_y = faces
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
    def cell_rates(buf, o, strides, f, g, omega, r, coef, flow, plate):
        """:func:`plate_rates` of the rotor turning at omega about the origin: the plate
        velocity omega (-y, x) at the cell centre r = (x, y)."""
        u = plate_velocity(0.0, 0.0, omega, r[0], r[1])
        return plate_rates(buf, o, strides, f, g, u, coef, flow, plate)

    return Rates(
        rate_coefficients=rate_coefficients,
        plate_velocity=plate_velocity,
        owner_plate=owner_plate,
        plate_rates=plate_rates,
        cut_cell_inflow=cut_cell_inflow,
        local_rate=local_rate,
        cell_rates=cell_rates,
    )
