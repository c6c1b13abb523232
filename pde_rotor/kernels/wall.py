"""Compiled Euler step of the fields on cut cells: behind a no-flux dish wall
(``grid.wall: no_flux``) or in a vessel (``grid.vessel``).

:func:`euler_walled_fields` advances c on the cut cells of the circle (or vessel) and v
on the cells whose centre lies inside it, walking only the runs of wet cells of each
row (two across an annulus' hole), so that dry cells cost nothing, as
:func:`pde_rotor.kernels.body_fields.euler_body_fields` does with the absorbing wall: the
transport of c through the open part of each face (the physics' ``cut_cell_inflow``) and
its local terms (``local_rate``) by forward Euler, then the diffusion through the faces
of the stiff cut cells by backward Euler, cluster by cluster with the inverses computed
once per run (:mod:`pde_rotor.model.wall`, which takes the same step with numpy and
computes the geometry these loops read). v and the plate terms are the physics'
``plate_rates``.

The `wall` argument is :meth:`pde_rotor.model.wall.CutCells.arrays`: (volume, aperture_x,
aperture_y, explicit apertures along x and y, row_start, span_lo, span_hi, flowing,
cluster members, cluster offsets, inverse blocks, block offsets); :data:`NO_WALL` is the
same tuple, empty, for the absorbing dish wall.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ..physics.build import CPU, FASTMATH

_plate_rates = CPU.rates.plate_rates
_cut_cell_inflow = CPU.rates.cut_cell_inflow
_local_rate = CPU.rates.local_rate
_owner_plate = CPU.rates.owner_plate

_NONE = np.zeros(0)
_NO_INDEX = np.zeros(0, dtype=np.int64)
NO_WALL = (_NONE, _NONE, _NONE, _NONE, _NONE, _NO_INDEX, _NO_INDEX, _NO_INDEX,
           np.zeros(0, dtype=np.uint8), _NO_INDEX, _NO_INDEX, _NONE, _NO_INDEX)  # fmt: skip
"""The `wall` of the absorbing wall: no cut cells (the compiled step takes the same types)."""


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def euler_walled_fields(cur, nxt, F, G, owner, domain, wall, coef, dt, pose, flow, rhs):
    """One step of Eqs. (eqc), (eqv) on cut cells (compiled).

    Args:
        cur, nxt: flat states (c, v_x, v_y) now and after the step.
        F, G, owner: flat indicators and owner map (as for ``euler_body_fields``).
        domain: (coords, lo, hi, slo, shi): slo, shi the rows' support of the bodies.
        wall: the cut cells (:meth:`pde_rotor.model.wall.CutCells.arrays`).
        coef: the physics' ``rate_coefficients``.
        dt: time step.
        pose: (K, 13) the bodies' poses (plate velocity of each cell's owner).
        flow: whether v evolves (else v = 0).
        rhs: scratch of n^2 values: kappa c' of the explicit part, per cell.
    """
    coords, _, _, slo, shi = domain
    volume, pass_x, pass_y, open_x, open_y, row_start, span_lo, span_hi, flowing = wall[:9]
    members, offsets, blocks, starts = wall[9:]
    n = coords.size
    sx = np.uint64(n)
    sy = np.uint64(1)
    nn = np.uint64(n * n)
    for i in range(n):
        x = coords[i]
        for s in range(row_start[i], row_start[i + 1]):
            for j in range(span_lo[s], span_hi[s]):
                o = np.uint64(i * n + j)
                plate = slo[i] <= j < shi[i] and owner[o] >= 0
                f, g, px, py = 0.0, 0.0, 0.0, 0.0
                if plate:
                    f, g, px, py = _owner_plate(F, G, owner, pose, o, x, coords[j])
                cc = cur[o]
                kappa = volume[o]
                q = _cut_cell_inflow(cur, o, sx, sy, nn, open_x, open_y, pass_x, pass_y, coef, flow)
                r = kappa * cc + dt * (q + kappa * _local_rate(cc, f, g, coef, plate))
                rhs[o] = r
                nxt[o] = r / kappa
                if flow and flowing[o]:
                    _, rate_x, rate_y = _plate_rates(
                        cur, o, sx, sy, nn, f, g, px, py, coef, flow, plate
                    )
                    nxt[o + nn] = cur[o + nn] + dt * rate_x
                    nxt[o + nn + nn] = cur[o + nn + nn] + dt * rate_y
    implicit_clusters(nxt, rhs, members, offsets, blocks, starts)


@nb.njit(cache=True, nogil=True, fastmath=FASTMATH)
def implicit_clusters(nxt, rhs, members, offsets, blocks, starts):
    """c' = inverse (kappa c' of the explicit part) on each cluster of implicit faces
    (:func:`pde_rotor.model.wall.implicit_blocks`)."""
    for b in range(offsets.size - 1):
        first = offsets[b]
        size = offsets[b + 1] - first
        block = starts[b]
        for u in range(size):
            total = 0.0
            row = block + u * size
            for w in range(size):
                total += blocks[row + w] * rhs[members[first + w]]
            nxt[members[first + u]] = total
