"""The field unknowns of the linearisation and the sparse matrices of the field operators.

:class:`FieldLayout` numbers the unknowns: c on the cells that hold camphor, then (with
flow) v_x and v_y on the dish's interior. :func:`probe_operator` turns a linear map of the
fields, given only as a function (the reference's rates of Eqs. (eqc) and (eqv)), into
the sparse matrix of the discrete operator, exactly: every operator of the solver is a
5-point stencil (the Laplacian, the central divergence, the cut cells' face fluxes), so
nine probes per field component, one per colour (i mod 3, j mod 3), recover every entry
(two cells of one colour are at least three cells apart, so no row hears two of them).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

STENCIL = ((0, 0), (1, 0), (-1, 0), (0, 1), (0, -1))
"""The 5-point stencil: every discrete operator of the model couples a cell to these."""
COLOURS = 9
"""(i mod 3) + 3 (j mod 3): cells of one colour share no row of a 5-point operator."""


@dataclass(frozen=True)
class FieldLayout:
    """Unknowns of the fields: c on ``c_mask``, then v_x and v_y on ``v_mask`` (with flow).

    Attributes:
        shape: the grid's (n, n).
        c_mask: cells that hold c.
        v_mask: cells that hold v (used only with flow).
        flow: whether v is an unknown.
    """

    shape: tuple[int, int]
    c_mask: np.ndarray
    v_mask: np.ndarray
    flow: bool

    @property
    def masks(self) -> tuple[np.ndarray, ...]:
        """The mask of each component: (c,) or (c, v_x, v_y)."""
        return (self.c_mask, self.v_mask, self.v_mask) if self.flow else (self.c_mask,)

    @property
    def sizes(self) -> tuple[int, ...]:
        """The number of unknowns of each component."""
        return tuple(int(m.sum()) for m in self.masks)

    @property
    def size(self) -> int:
        """All field unknowns."""
        return sum(self.sizes)

    @property
    def offsets(self) -> np.ndarray:
        """Where each component starts in the vector of unknowns."""
        return np.concatenate([[0], np.cumsum(self.sizes)])

    def index(self) -> np.ndarray:
        """(components, n, n): the unknown's number of each cell of each component, -1
        off its mask."""
        out = np.full((len(self.masks), *self.shape), -1, dtype=np.int64)
        for k, (mask, start) in enumerate(zip(self.masks, self.offsets, strict=False)):
            out[k][mask] = start + np.arange(mask.sum())
        return out

    def pack(self, c: np.ndarray, v: np.ndarray | None = None) -> np.ndarray:
        """The vector of unknowns of grid arrays c (n, n) and v (2, n, n)."""
        parts = [c[self.c_mask]]
        if self.flow:
            parts += [v[0][self.v_mask], v[1][self.v_mask]]
        return np.concatenate(parts)

    def unpack(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Grid arrays c (n, n) and v (2, n, n) of a vector of unknowns (0 off the masks)."""
        dtype = np.result_type(x.dtype, np.float64)
        c = np.zeros(self.shape, dtype=dtype)
        v = np.zeros((2, *self.shape), dtype=dtype)
        lo = self.offsets
        c[self.c_mask] = x[lo[0] : lo[1]]
        if self.flow:
            v[0][self.v_mask] = x[lo[1] : lo[2]]
            v[1][self.v_mask] = x[lo[2] : lo[3]]
        return c, v

    def grid_components(self, c: np.ndarray, v: np.ndarray) -> list[np.ndarray]:
        """[c] or [c, v_x, v_y] as (n, n) arrays."""
        return [c, v[0], v[1]] if self.flow else [c]


def probe_operator(
    layout: FieldLayout,
    apply: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]],
    inputs: tuple[int, ...] | None = None,
) -> sp.csr_matrix:
    """The sparse matrix of a linear map of the fields with a 5-point stencil.

    Args:
        layout: the unknowns.
        apply: (c, v) -> (c_rate, v_rate) as grid arrays, linear in (c, v) (a difference
            of the reference's rates).
        inputs: the components to probe (default all); the columns of the others are 0.

    Returns:
        (layout.size, layout.size) CSR matrix A with apply(unpack(x)) = unpack(A x) on the
        masks.
    """
    index = layout.index()
    n_comp = len(layout.masks)
    ii, jj = np.meshgrid(*(np.arange(s) for s in layout.shape), indexing="ij")
    colour = ii % 3 + 3 * (jj % 3)
    rows, cols, vals = [], [], []
    zero_c = np.zeros(layout.shape)
    zero_v = np.zeros((2, *layout.shape))
    for comp in range(n_comp) if inputs is None else inputs:
        mask = layout.masks[comp]
        for g in range(COLOURS):
            cells = mask & (colour == g)
            if not cells.any():
                continue
            probe = [zero_c.copy(), zero_v[0].copy(), zero_v[1].copy()]
            probe[comp][cells] = 1.0
            c_rate, v_rate = apply(probe[0], np.stack(probe[1:]))
            outputs = layout.grid_components(c_rate, v_rate)
            ci, cj = np.nonzero(cells)
            col = index[comp][ci, cj]
            for di, dj in STENCIL:
                ri, rj = ci + di, cj + dj
                inside = (ri >= 0) & (ri < layout.shape[0]) & (rj >= 0) & (rj < layout.shape[1])
                ri, rj, cc = ri[inside], rj[inside], col[inside]
                for out_comp, out in enumerate(outputs):
                    row = index[out_comp][ri, rj]
                    value = out[ri, rj]
                    keep = (row >= 0) & (value != 0)
                    rows.append(row[keep])
                    cols.append(cc[keep])
                    vals.append(value[keep])
    size = layout.size
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(size, size)
    )
