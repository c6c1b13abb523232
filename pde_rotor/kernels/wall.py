"""Compiled Euler step of the fields behind a no-flux dish wall (``grid.wall: no_flux``).

:func:`euler_walled_fields` advances c on the cut cells of the circle and v on the cells
whose centre lies inside it, as :func:`pde_rotor.kernels.bodies.euler_body_fields` does
with the absorbing wall: the transport of c through the open part of each face
(the core's ``cut_cell_inflow``), its local terms (``local_rate``), then flux
redistribution on the cut cells, so that no rate has the small volume of a cut cell as a
divisor and nothing is lost (:mod:`pde_rotor.model.wall`, which computes the same with
numpy and the geometry these loops take). v and the plate terms are the core's
``plate_rates``.

The `wall` argument is :meth:`pde_rotor.model.wall.CutCells.arrays`: (volume, aperture_x,
aperture_y, cut, near, lo, hi), the 2-D arrays flattened; :data:`NO_WALL` is the same
tuple, empty, for the absorbing wall.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from .body_core import CPU_BODIES
from .core import CPU, FASTMATH

_plate_rates = CPU.plate_rates
_cut_cell_inflow = CPU.cut_cell_inflow
_local_rate = CPU.local_rate
_plate_velocity = CPU_BODIES.plate_velocity

NO_WALL = (
    np.zeros(0),
    np.zeros(0),
    np.zeros(0),
    np.zeros(0, dtype=np.int64),
    np.zeros(0),
    np.zeros(0, dtype=np.int64),
    np.zeros(0, dtype=np.int64),
)
"""The `wall` of the absorbing wall: no cut cells (the compiled step takes the same types)."""


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def euler_walled_fields(cur, nxt, F, G, owner, domain, wall, coef, dt, pose, flow, inflow):
    """One Euler step of Eqs. (eqc), (eqv) with the no-flux wall (compiled).

    Args:
        cur, nxt: flat states (c, v_x, v_y) now and after the step.
        F, G, owner: flat indicators and owner map (as for ``euler_body_fields``).
        domain: (coords, lo, hi, slo, shi): lo, hi the cells with centre inside the circle
            (v), slo, shi the rows' support of the bodies.
        wall: the cut cells (:meth:`pde_rotor.model.wall.CutCells.arrays`).
        coef: the core's ``rate_coefficients``.
        dt: time step.
        pose: (K, 13) the bodies' poses (plate velocity of each cell's owner).
        flow: whether v evolves (else v = 0).
        inflow: scratch of n^2 values, 0 outside the circle on entry; holds each cell's
            inflow Q on return.
    """
    coords, lo, hi, slo, shi = domain
    volume, ax, ay, cut, near, wlo, whi = wall
    n = coords.size
    sx = np.uint64(n)
    sy = np.uint64(1)
    nn = np.uint64(n * n)
    for i in range(n):
        x = coords[i]
        for j in range(wlo[i], whi[i]):
            o = np.uint64(i * n + j)
            plate = slo[i] <= j < shi[i]
            f = 0.0
            g = 0.0
            px = 0.0
            py = 0.0
            if plate:
                f = F[o]
                g = G[o]
                k = owner[o]
                if k >= 0:
                    px, py = _plate_velocity(
                        pose[k, 3], pose[k, 4], pose[k, 5], x - pose[k, 0], coords[j] - pose[k, 1]
                    )
            cc = cur[o]
            q = _cut_cell_inflow(
                cur, o, sx, sy, nn, ax[o], ax[o - sx], ay[o], ay[o - sy], coef, flow
            )
            inflow[o] = q
            nxt[o] = cc + dt * (q + _local_rate(cc, f, g, coef, plate))
            if flow and lo[i] <= j < hi[i]:
                _, rate_x, rate_y = _plate_rates(
                    cur, o, sx, sy, nn, f, g, px, py, coef, flow, plate
                )
                nxt[o + nn] = cur[o + nn] + dt * rate_x
                nxt[o + nn + nn] = cur[o + nn + nn] + dt * rate_y
    redistribute(nxt, inflow, volume, cut, near, n, dt)


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def redistribute(nxt, inflow, volume, cut, near, n, dt):
    """Flux redistribution on the cut cells (:func:`pde_rotor.model.wall.redistributed_rate`).

    Each cut cell P (volume fraction kappa) gains dt (1 - kappa) D_nc, D_nc = sum Q / sum
    kappa over its 3 x 3 neighbourhood, and each neighbour with kappa > 0 gains
    dt (1 - kappa) (Q_P - kappa D_nc) / (sum kappa over the neighbours).
    """
    for m in range(cut.size):
        p = cut[m]
        total = 0.0
        for di in range(-n, n + 1, n):
            for dj in range(-1, 2):
                total += inflow[p + di + dj]
        kappa = volume[p]
        mean = total / near[p]
        nxt[p] += dt * (1.0 - kappa) * mean
        share = dt * (1.0 - kappa) * (inflow[p] - kappa * mean) / (near[p] - kappa)
        for di in range(-n, n + 1, n):
            for dj in range(-1, 2):
                o = p + di + dj
                if o != p and volume[o] > 0.0:
                    nxt[o] += share
