"""The linearisation of the discrete model about its rest state: the Jacobian J, as blocks.

About the rest state (c0, v = 0, the bodies at q0 with p = 0; :mod:`.rest`) a small
perturbation (dc, dv, dq, dp) obeys d/dt x = J x with

    J = [ A    B ]     A: the fields' operator at rest, Eqs. (eqc), (eqv), sparse;
        [ C    D ]     B: the fields' response to the bodies' coordinates and velocities;
                       C: the bodies' accelerations from the fields, Eq. (eq_motion);
                       D: their accelerations from their own coordinates and velocities.

Every block is read off the reference's rates (:mod:`.system`), so J is the Jacobian of
the right-hand side the solver steps (forward Euler: one step is x -> x + dt J x):

* A by probing (:func:`~pde_rotor.stability.fields.probe_operator`), exactly: at v = 0
  the rates are affine in c and in v separately (the only product, div(c v), is then
  linear in each): D lap c - a (1 - F) c - div(c0 dv), and
  -eta F dv - eta_b dv + D_eta lap dv;
* the columns of the coordinates (F and G moving with the bodies) and the rows'
  dependence on them (the rest field's tension force as the body moves through it) by
  fourth-order central differences with a step of 1e-3 delta (error ~1e-12);
* the columns of the velocities (the plates dragging the flow, eta F u_k) and the
  accelerations' dependence on the fields (tension force and torque, linear in c; the
  friction's r x v) and on the velocities (friction -mu int F |r|^2 omega) exactly, as
  differences of functions affine in them.

C is applied as a function (a call of the reference's force integrals), not stored: its
rows are dense over the plates.

**Positions.** A body's coordinates matter only where its rest state is not symmetric
under moving it (a wall, the lattice, another body). With ``positions=False`` the
linearisation is taken in the bodies' co-moving frame: dc~ = dc - c_q dq with c_q =
-A^{-1} dR/dq the rest field's shift, which removes dq exactly up to the *stiffness*
K = d/dq (force on the held body at its rest state), the term dropped; K is computed and
reported (:attr:`Linearisation.stiffness`). Without it, every translation or rotation
leaves a neutral eigenvalue 0 beside the onset. ``positions=None`` includes them behind a
no-flux wall (the dish, where K drives the Hopf pair) and not otherwise.

**Track bodies.** Boats on circles about the centre of a round vessel (the dish, or an
annulus about its centre) can all move along their tracks together, turning by one angle
alpha: a symmetry of the rest state (broken only by the lattice), whose coordinate is the
direction g = (R_1, ..., R_N) / |R| of the arc positions. Their spacings are not: a boat's
camphor pushes its neighbours, and the spacing modes (m >= 1 of N boats) need the
coordinates. So ``positions=None`` takes them in the frame that turns with the boats
(:func:`symmetry_frame`): the field co-moves along g only, dc~ = dc - c_q g sigma with
sigma = g . dq, the coordinates kept are an orthonormal basis P of the directions normal
to g, and the term dropped is K g, the lattice force on the boats turned together. One
boat alone keeps no coordinate (its co-moving frame, the clean pitchfork); N boats keep N
- 1 relative ones and no neutral eigenvalue 0 (with ``positions=True`` it is there,
moved off 0 by the lattice's K g, and can take the lead or turn the onset into a slow
pair). In general the blocks are, with G the co-moving
directions (all of them without positions, none with ``positions=True``):

    B = [B_q P, B_p - c_q G G^T],    D = [[0, P^T], [g_q P, D_p]].
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from itertools import pairwise

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, splu

from .fields import FieldLayout, probe_operator
from .rest import RestState, rest_state
from .system import DiscreteModel

FD_STEP = 1e-3
"""Step of the coordinates' differences, in units of the smoothing width delta (lengths)
or of delta / (body extent) (angles)."""
FD_WEIGHTS = ((2.0, -1.0 / 12.0), (1.0, 8.0 / 12.0), (-1.0, -8.0 / 12.0), (-2.0, 1.0 / 12.0))
"""Fourth-order central difference f'(0) ~ sum w f(k h) / h."""


def central_difference(func: Callable[[float], np.ndarray], step: float) -> np.ndarray:
    """d func / dh at 0, fourth order."""
    return sum(w * func(k * step) for k, w in FD_WEIGHTS) / step


@dataclass
class Linearisation:
    """J of a config about its rest state (see the module docstring).

    Attributes:
        model: the discrete model.
        rest: the rest state.
        layout: the field unknowns (c, and v with flow).
        positions: whether the bodies' coordinates are unknowns.
        fields: A, (n_f, n_f) sparse.
        coordinate_columns: (n_f, m) d(field rates)/dq.
        velocity_columns: (n_f, m) d(field rates)/dp.
        coordinate_rows: (m, m) d(accelerations)/dq at the rest field.
        velocity_rows: (m, m) d(accelerations)/dp.
        rest_shift: c_q, (n_f, m): the rest field's derivative along each coordinate.
        stiffness: K, (m, m): d/dq of the held bodies' accelerations at their rest state.
        comoving: G, (m, g) orthonormal: with positions, the directions of the
            coordinates taken in the co-moving frame (:func:`symmetry_frame`; none: every
            active coordinate is an unknown).
    """

    model: DiscreteModel
    rest: RestState
    layout: FieldLayout
    positions: bool
    fields: sp.csr_matrix
    coordinate_columns: np.ndarray
    velocity_columns: np.ndarray
    coordinate_rows: np.ndarray
    velocity_rows: np.ndarray
    rest_shift: np.ndarray
    stiffness: np.ndarray
    comoving: np.ndarray | None = None

    @property
    def frame(self) -> np.ndarray:
        """G, (m, g): the co-moving directions (all without positions)."""
        if not self.positions:
            return np.eye(self.n_dofs)
        if self.comoving is None:
            return np.zeros((self.n_dofs, 0))
        return self.comoving

    @property
    def kept(self) -> np.ndarray:
        """P, (m, a): the coordinates that are unknowns, as directions: the active unit
        vectors (with positions), less the co-moving directions (an orthonormal basis of
        the rest); none without positions."""
        m = self.n_dofs
        if not self.positions:
            return np.zeros((m, 0))
        units = np.eye(m)[:, self.active]
        g = self.frame
        if not g.shape[1]:
            return units
        rest = units - g @ (g.T @ units)
        basis, sizes, _ = np.linalg.svd(rest, full_matrices=False)
        return basis[:, sizes > 1e-9]

    @property
    def columns(self) -> np.ndarray:
        """B, (n_f, m_s): the kept coordinates' columns, then the velocities' less the
        rest field's shift c_q along the co-moving directions (module docstring)."""
        g = self.frame
        coords = self.coordinate_columns @ self.kept
        velocities = self.velocity_columns - self.rest_shift @ g @ g.T
        return np.concatenate([coords, velocities], axis=1)

    @property
    def active(self) -> np.ndarray:
        """Indices of the coordinates that enter the rates: a coordinate that moves
        nothing (the angle of a round disk turning about its centre) is ignorable, its
        eigenvalue exactly 0, and is left out even with positions."""

        def moves(block: np.ndarray) -> np.ndarray:
            size = np.abs(block).max(axis=0, initial=0.0)
            return size > 1e-12 * max(float(size.max(initial=0.0)), 1e-300)

        moving = moves(self.coordinate_columns) | moves(self.coordinate_rows)
        return np.nonzero(moving)[0]

    @property
    def small(self) -> np.ndarray:
        """D, (m_s, m_s)."""
        kept = self.kept
        a = kept.shape[1]
        if not a:
            return self.velocity_rows
        return np.block(
            [
                [np.zeros((a, a)), kept.T],
                [self.coordinate_rows @ kept, self.velocity_rows],
            ]
        )

    def with_positions(self, positions: bool, comoving: np.ndarray | None = None) -> Linearisation:
        """The same blocks with or without the coordinates as unknowns (with them, those
        along `comoving` taken in the co-moving frame; None: none)."""
        return replace(self, positions=positions, comoving=comoving)

    @property
    def frame_name(self) -> str:
        """How the coordinates enter, in words."""
        if not self.positions:
            return "co-moving frame"
        if not self.frame.shape[1]:
            return "coordinates included"
        if not self.kept.shape[1]:
            return "co-moving frame: the common turn"
        return f"{self.kept.shape[1]} relative coordinates, co-moving with the common turn"

    @property
    def rest_acceleration(self) -> np.ndarray:
        """(m,) the bodies' accelerations at the rest state if released: 0 where the rest
        state is a fixed point of the free bodies (by symmetry); the lattice torque or an
        asymmetry otherwise, which the linearisation about the held state leaves out."""
        model = self.model
        zero_v = np.zeros((2, *model.shape))
        return model.accelerations(self.rest.c, zero_v, model.q0, np.zeros(self.n_dofs))

    @property
    def n_fields(self) -> int:
        """Field unknowns."""
        return self.layout.size

    @property
    def n_dofs(self) -> int:
        """Mechanical degrees of freedom m."""
        return len(self.model.dofs)

    @property
    def size(self) -> int:
        """All unknowns: fields, then (coordinates,) velocities."""
        return self.n_fields + self.small.shape[0]

    @property
    def labels(self) -> list[str]:
        """Names of the mechanical unknowns, in order."""
        dofs = self.model.dofs
        coords = []
        for j, column in enumerate(self.kept.T):
            i = int(np.argmax(np.abs(column)))
            unit = abs(abs(column[i]) - 1.0) < 1e-12
            coords.append(f"{dofs[i].name}.{dofs[i].coordinate}" if unit else f"relative{j}")
        return coords + [d.label for d in dofs]

    def rows(self, x_fields: np.ndarray) -> np.ndarray:
        """C x_f: the mechanical unknowns' rates from field unknowns (zero for the
        coordinates, whose rate is the velocity)."""
        model = self.model
        c, v = self.layout.unpack(x_fields)
        q, zero = model.q0, np.zeros(self.n_dofs)
        if np.iscomplexobj(x_fields):
            acc = model.accelerations(c.real, v.real, q, zero) + 1j * model.accelerations(
                c.imag, v.imag, q, zero
            )
        else:
            acc = model.accelerations(c, v, q, zero)
        return np.concatenate([np.zeros(self.kept.shape[1], dtype=acc.dtype), acc])

    def matvec(self, x: np.ndarray) -> np.ndarray:
        """J x."""
        n = self.n_fields
        x_f, x_s = x[:n], x[n:]
        return np.concatenate(
            [self.fields @ x_f + self.columns @ x_s, self.rows(x_f) + self.small @ x_s]
        )

    def operator(self) -> LinearOperator:
        """J as a scipy LinearOperator."""
        return LinearOperator((self.size, self.size), matvec=self.matvec, dtype=float)

    def factor(self, sigma: float) -> Callable[[np.ndarray], np.ndarray]:
        """x -> (A - sigma)^{-1} x by sparse LU. A is block upper triangular in (c, v_x,
        v_y) (the flow carries camphor, the camphor does not drive the flow at rest), so
        each diagonal block is factored alone and the solve is a back substitution."""
        n = self.n_fields
        shifted = (self.fields - sigma * sp.identity(n, format="csr")).tocsr()
        bounds = self.layout.offsets
        blocks = list(pairwise(bounds))
        lower = [shifted[lo:hi, : blocks[i][0]] for i, (lo, hi) in enumerate(blocks)]
        if any(part.nnz for part in lower):
            lu = splu(shifted.tocsc())
            return lu.solve
        lus = [splu(shifted[lo:hi, lo:hi].tocsc()) for lo, hi in blocks]
        uppers = [shifted[lo:hi, hi:] for lo, hi in blocks]

        def solve(b: np.ndarray) -> np.ndarray:
            x = np.empty_like(b)
            for (lo, hi), lu, upper in reversed(list(zip(blocks, lus, uppers, strict=True))):
                x[lo:hi] = lu.solve(np.ascontiguousarray(b[lo:hi] - upper @ x[hi:]))
            return x

        return solve

    def _schur(self, sigma: float) -> tuple[Callable, np.ndarray, np.ndarray]:
        solve = self.factor(sigma)
        columns = self.columns
        w = solve(np.ascontiguousarray(columns)) if columns.size else columns
        cw = np.stack([self.rows(w[:, j]) for j in range(w.shape[1])], axis=1)
        return solve, w, self.small - sigma * np.eye(self.small.shape[0]) - cw

    def shift_invert(self, sigma: float) -> LinearOperator:
        """(J - sigma)^{-1} as a LinearOperator: sparse LUs of A - sigma
        (:meth:`factor`) and the m_s x m_s Schur complement S = D - sigma - C (A -
        sigma)^{-1} B."""
        n = self.n_fields
        solve, w, schur = self._schur(sigma)

        def apply(b: np.ndarray) -> np.ndarray:
            b = np.ravel(b)
            y = solve(b[:n])
            x_s = np.linalg.solve(schur, b[n:] - self.rows(y))
            return np.concatenate([y - w @ x_s, x_s])

        return LinearOperator((self.size, self.size), matvec=apply, dtype=float)

    def schur(self, sigma: float) -> np.ndarray:
        """S(sigma) = D - sigma - C (A - sigma)^{-1} B, the bodies' m_s x m_s reduced
        problem: an eigenvalue lambda of J outside the spectrum of A is a root of
        det S(lambda) (S(0) is the quasi-static response)."""
        return self._schur(sigma)[2]

    def split(self, x: np.ndarray, eigenvalue: complex | None = None) -> dict[str, np.ndarray]:
        """A vector of unknowns as the physicist's pieces in the lab frame: dc (n, n), dv
        (2, n, n), dq (m,), dp (m,). In the co-moving frame (no positions) an eigenmode's
        dq = dp / lambda and dc = dc~ + c_q dq."""
        n = self.n_fields
        x_f, x_s = x[:n], x[n:]
        kept, g = self.kept, self.frame
        a = kept.shape[1]
        dp = x_s[a:]
        along = g.T @ dp / eigenvalue if eigenvalue not in (None, 0) else np.zeros(g.shape[1])
        dq = kept @ x_s[:a] + g @ along
        x_f = x_f + self.rest_shift @ (g @ along)
        c, v = self.layout.unpack(x_f)
        return {"dc": c, "dv": v, "dq": dq, "dp": dp}


def symmetry_frame(model: DiscreteModel) -> np.ndarray | None:
    """g, (m, 1): the common turn of the track bodies about the centre of a round vessel
    (the arc positions' direction (R_1, ..., R_N) / |R|), where every body is a track body
    on a circle about it (module docstring); None where the bodies break the symmetry (a
    body of another kind, a track about another point, a rectangular tank)."""
    if model.rotor or not model.dofs:
        return None
    grid = model.config.grid
    if grid.vessel is not None and grid.vessel.shape == "rectangle":
        return None
    centre = np.asarray(grid.domain_centre, dtype=float)
    radii = []
    for body in model.pde.bodies:
        if body.track is None or not np.allclose(body.track.centre, centre, atol=1e-12):
            return None
        radii.append(body.track.radius)
    radii = np.array(radii)
    return (radii / np.linalg.norm(radii))[:, None]


def _positions_default(model: DiscreteModel) -> tuple[bool, np.ndarray | None]:
    frame = symmetry_frame(model)
    if frame is not None:
        return True, frame
    return model.pde.domain.cut_cells is not None, None


def linearise(
    model: DiscreteModel, rest: RestState | None = None, positions: bool | None = None
) -> Linearisation:
    """The Jacobian of `model`'s discrete rates about its rest state.

    Args:
        model: the discrete model of a config.
        rest: its rest state (computed if None).
        positions: include the bodies' coordinates (None: behind a no-flux wall only, and
            for track bodies about a round vessel's centre the relative coordinates,
            co-moving with their common turn: module docstring).

    Returns:
        The linearisation, every block assembled except C (applied on demand).
    """
    rest = rest if rest is not None else rest_state(model)
    comoving = None
    if positions is None:
        positions, comoving = _positions_default(model)
    layout = FieldLayout(model.shape, model.c_mask, model.v_mask, flow=model.flow)
    c0, q0 = rest.c, model.q0
    m = len(model.dofs)
    zero_p = np.zeros(m)
    zero_v = np.zeros((2, *model.shape))
    base_c, base_v = model.field_rates(c0, zero_v, q0, zero_p)

    def apply(c: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        rate_c, rate_v = model.field_rates(c0 + c, v, q0, zero_p)
        return rate_c - base_c, rate_v - base_v

    fields = probe_operator(layout, apply)

    def steps() -> list[float]:
        delta = model.config.geometry.smoothing
        out = []
        for dof in model.dofs:
            if dof.coordinate == "phi":
                extent = 1.0 if model.rotor else model.pde.bodies[dof.body].shape.extent
                out.append(FD_STEP * delta / max(extent, delta))
            else:
                out.append(FD_STEP * delta)
        return out

    coord_cols, coord_rows = [], []
    for i, h in enumerate(steps()):
        unit = np.zeros(m)
        unit[i] = 1.0

        def rates_at(s: float, unit: np.ndarray = unit) -> np.ndarray:
            rc, rv = model.field_rates(c0, zero_v, q0 + s * unit, zero_p)
            return layout.pack(rc, rv)

        def forces_at(s: float, unit: np.ndarray = unit) -> np.ndarray:
            return model.accelerations(c0, zero_v, q0 + s * unit, zero_p)

        coord_cols.append(central_difference(rates_at, h))
        coord_rows.append(central_difference(forces_at, h))
    base_fields = layout.pack(base_c, base_v)
    zero_c = np.zeros(model.shape)
    base_acc = model.accelerations(zero_c, zero_v, q0, zero_p)
    vel_cols, vel_rows = [], []
    for i in range(m):
        unit = np.zeros(m)
        unit[i] = 1.0
        rc, rv = model.field_rates(c0, zero_v, q0, unit)
        vel_cols.append(layout.pack(rc, rv) - base_fields)
        vel_rows.append(model.accelerations(zero_c, zero_v, q0, unit) - base_acc)
    n = layout.size
    coord_b = np.stack(coord_cols, axis=1) if m else np.zeros((n, 0))
    vel_b = np.stack(vel_cols, axis=1) if m else np.zeros((n, 0))
    g_q = np.stack(coord_rows, axis=1) if m else np.zeros((0, 0))
    g_p = np.stack(vel_rows, axis=1) if m else np.zeros((0, 0))
    # the rest field's shift along each coordinate: A_cc c_q = -dR_c/dq
    n_c = layout.sizes[0]
    shift = np.zeros((n, m))
    if m:
        lu = splu(rest.operator.tocsc())
        shift[:n_c] = lu.solve(-np.ascontiguousarray(coord_b[:n_c]))
    lin = Linearisation(
        model=model,
        rest=rest,
        layout=layout,
        positions=False,
        fields=fields,
        coordinate_columns=coord_b,
        velocity_columns=vel_b,
        coordinate_rows=g_q,
        velocity_rows=g_p,
        rest_shift=shift,
        stiffness=np.zeros((m, m)),
    )
    if m:
        response = np.stack([lin.rows(shift[:, j]) for j in range(m)], axis=1)
        lin.stiffness = response + g_q
    return lin.with_positions(positions, comoving)
