"""K bodies on one surface as a py-pde PDE: the numpy reference of the generalised model.

The paper's model (Koyano et al., Chaos 2020) with its rotor replaced by the bodies of a
``bodies:`` config (:mod:`pde_rotor.config.bodies`, :mod:`pde_rotor.model.bodies`):

* Eq. (eqc): dc/dt = D lap c - div(c v) - a (1 - sum_k F_k) c + sum_k sources of G_k;
* Eq. (eqv): dv/dt = eta sum_k F_k (u_k - v) - eta_b v + D_eta lap v with the plate
  velocity u_k = U_k + omega_k z x (r - X_k);
* Eq. (eq_motion) per body about X_k: m dU/dt = f_k, I domega/dt = T_k with

      f_k = s k int F_k grad c dA - mu int F_k (u_k - v) dA,
      T_k = s k int F_k (r - X_k) x grad c dA - mu int F_k (r - X_k) x (u_k - v) dA,

  s the sign of ``rotor.torque`` (:data:`pde_rotor.model.pde.TORQUE_SIGN`); a ``fixed``
  body does not move, a ``fixed_axis`` body only turns, and a body in a stop of its own
  protocol is held (U = 0, omega = 0).

The scheme (``numerics.scheme``): ``paper`` samples F_k and G_k at the cell centres and
takes the tension force and torque in the area form above with central differences;
``consistent`` filters F_k and G_k and takes them in contour form,
-k oint c n ds and -k oint (r - X_k) x n c ds over the smoothed contour
(:mod:`pde_rotor.model.body_schemes`); the friction integrals are area integrals of
F_k in both.

:class:`SurfacePDE` holds the equations written plainly with numpy
(:meth:`SurfacePDE.evolution_rate`, :meth:`SurfacePDE.body_forces`, the equation of
motion of :mod:`pde_rotor.model.motion`, and a whole step of both,
:meth:`SurfacePDE.reference_step`); the compiled loop
:func:`pde_rotor.kernels.bodies.advance_bodies` computes the same from the compiled physics
and is tested against them. :class:`SurfaceFields` carries the bodies' state with c and
v, as :class:`pde_rotor.model.pde.RotorFields` carries the rotor.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Any

import numpy as np
from pde import FieldCollection, ScalarField, VectorField
from pde.pdes.base import PDEBase

from ..config import RotorConfig
from .bodies import Body, Pose, footprint_mask, pill_source, plate_indicator
from .body_schemes import contour_integrals, filtered_body_fields
from .domain import Domain, make_domain
from .geometry import RotorShape
from .motion import (
    Inertia,
    accelerations,
    contact_forces,
    euler_poses,
    held_bodies,
    heun_poses,
)
from .pde import BOUNDARY, TORQUE_SIGN
from .rates import camphor_local_rate, flow_local_rate
from .schemes import surface_pressure
from .setup import Setup, as_setup
from .wall import make_wall_step, wall_fluxes, wall_rate

POSE_COLUMNS = (
    "x",
    "y",
    "phi",
    "u",
    "v",
    "omega",
    "force_x",
    "force_y",
    "torque",
    "drag_x",
    "drag_y",
    "friction",
    "stopped",
    "contact_x",
    "contact_y",
)
"""The columns of :attr:`BodiesState.poses`: position, angle, velocity U, angular
velocity, then the last step's tension force and torque, the friction force and torque,
whether the body was held (1) or free to move (0), and the last step's contact force
(``contact:``; 0 where off; it has no torque about X)."""


@dataclass
class BodiesState:
    """The bodies' degrees of freedom and their diagnostics of the last step.

    Attributes:
        names: the bodies' names.
        poses: (K, 15) float array, columns :data:`POSE_COLUMNS`, positions on the surface.
    """

    names: tuple[str, ...]
    poses: np.ndarray

    def __copy__(self) -> BodiesState:
        return BodiesState(self.names, self.poses.copy())

    def column(self, name: str) -> np.ndarray:
        """One column of :attr:`poses` by name (a view)."""
        return self.poses[:, POSE_COLUMNS.index(name)]

    def pose(self, k: int) -> Pose:
        """Body k's pose (X, Y, phi)."""
        return Pose(*(float(v) for v in self.poses[k, :3]))


class SurfaceFields(FieldCollection):
    """The state of the generalised model: c, v and the bodies.

    Attributes:
        bodies: the bodies' state at the fields' time.
    """

    def __init__(self, fields: Any, *args: Any, bodies: BodiesState | None = None, **kwargs: Any):
        """
        Args:
            fields: the fields [c, v], as for :class:`~pde.FieldCollection`.
            *args: passed to :class:`~pde.FieldCollection`.
            bodies: the bodies' state (py-pde's own copies pass none: :meth:`copy` sets it).
            **kwargs: passed to :class:`~pde.FieldCollection`.
        """
        super().__init__(fields, *args, **kwargs)
        none = BodiesState((), np.zeros((0, len(POSE_COLUMNS))))
        self.bodies = bodies if bodies is not None else none

    def copy(self, *, label: str | None = None, dtype: Any = None) -> SurfaceFields:
        """A copy of the fields' data and of the bodies (not of the grid)."""
        new = super().copy(label=label, dtype=dtype)
        new.bodies = copy.copy(self.bodies)
        return new


class SurfacePDE(PDEBase):
    """The camphor model with K bodies on one surface (see the module docstring).

    Attributes:
        setup: the run's objects (:class:`~pde_rotor.model.setup.Setup`).
        config: the run configuration.
        bodies: the bodies (the setup's).
        scheme: the discretisation of the parameter record (``numerics``).
        body_scheme: the bodies' discretisation (``paper``: point values, area-form
            integrals; ``consistent``: filtered indicators, contour forms).
        domain: grid and loop ranges (the dish of ``grid``).
        F, G: plate and pill indicators on the grid, maintained by the solver (G as the
            kernels hold it: source densities relative to the run's s0 / (pi rho^2)).
        owner: per cell, the index of the body whose footprint holds it (-1: none).
        drawn: (K, 3) the pose (x, y, phi in the dish frame) at which each body's F, G
            and owner were last drawn (nan: never), maintained by the solver.
        box: (K, 4) the rows and columns [i0, i1) x [j0, j1) of that drawing.
    """

    check_implementation = False

    def __init__(self, run: Setup | RotorConfig):
        """
        Args:
            run: the run's setup, or its configuration (with or without ``bodies``; made
                into a setup here).
        """
        super().__init__()
        setup = as_setup(run)
        self.setup = setup
        self.config = config = setup.config
        self.bodies: tuple[Body, ...] = setup.bodies
        self.scheme = setup.scheme
        self.body_scheme = setup.body_scheme
        # the dish's loop ranges; the bodies' supports are their own footprints
        self.domain: Domain = make_domain(config.grid, _NO_SUPPORT)
        shape = self.domain.grid.shape
        self.F = np.zeros(shape)
        self.G = np.zeros(shape)
        self.owner = np.full(shape, -1, dtype=np.int64)
        self.drawn = np.full((len(self.bodies), 3), np.nan)
        self.box = np.zeros((len(self.bodies), 4), dtype=np.int64)

    def initial_state(self) -> SurfaceFields:
        """c = 0, v = 0 and every body at its start pose and velocities."""
        grid = self.domain.grid
        poses = np.zeros((len(self.bodies), len(POSE_COLUMNS)))
        for k, body in enumerate(self.bodies):
            poses[k, :3] = body.start
            poses[k, 3:5] = body.velocity0
            poses[k, 5] = body.omega0
        return SurfaceFields(
            [ScalarField(grid, label="c"), VectorField(grid, label="v")],
            label="surface state",
            bodies=BodiesState(tuple(b.name for b in self.bodies), poses),
        )

    def cell_coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """(x, y) of every cell centre on the surface, each of shape (n, n)."""
        return np.meshgrid(self.domain.x_coords, self.domain.y_coords, indexing="ij")

    def body_fields(self, state: BodiesState) -> list[tuple[np.ndarray, np.ndarray]]:
        """(F_k, source_k) of every body at its pose (numpy): point values (``paper``) or
        the filtered fields (``consistent``), 0 outside its footprint
        (:func:`~pde_rotor.model.bodies.footprint_mask`)."""
        x, y = self.cell_coordinates()
        scheme = self.body_scheme
        out = []
        for k, body in enumerate(self.bodies):
            pose = state.pose(k)
            if scheme.consistent:
                filt = scheme.filters[k]
                f_k, s_k = filtered_body_fields(x, y, body.shape, pose, filt, scheme.profile_step)
            else:
                f_k = plate_indicator(x, y, body.shape, pose)
                s_k = pill_source(x, y, body.shape, pose)
            inside = footprint_mask(self.domain, body.shape, pose)
            out.append((np.where(inside, f_k, 0.0), np.where(inside, s_k, 0.0)))
        return out

    def evolution_rate(self, state: SurfaceFields, t: float = 0) -> FieldCollection:
        """Right-hand sides of Eqs. (eqc) and (eqv) with every body at its pose (numpy).

        Each body moves with its velocities in ``state.bodies`` (0 while it is held).
        Cells on and outside the circle of radius L keep v = 0, and c = 0 with the
        absorbing wall; with the no-flux wall c lives on the cut cells
        (:meth:`camphor_transport`).
        """
        cfg = self.config
        c, v = state
        x, y = self.cell_coordinates()
        poses = state.bodies.poses
        total_f = np.zeros_like(c.data)
        source = np.zeros_like(c.data)
        plate_flow = np.zeros_like(v.data)
        for k, (f_k, s_k) in enumerate(self.body_fields(state.bodies)):
            total_f += f_k
            source += s_k
            u, w, omega = poses[k, 3], poses[k, 4], poses[k, 5]
            plate_flow += f_k * np.stack(
                [u - omega * (y - poses[k, 1]), w + omega * (x - poses[k, 0])]
            )
        mask = self.domain.interior_mask
        c_rate = self.camphor_transport(state) + camphor_local_rate(
            cfg.camphor, c.data, total_f, source
        )
        v_rate = np.zeros_like(v.data)
        if cfg.flow.enabled:
            v_rate = flow_local_rate(cfg.flow, v.data, total_f, plate_flow)
            v_rate += cfg.flow.viscosity * v.laplace(BOUNDARY).data
        grid = self.domain.grid
        c_rate = c_rate * self.domain.camphor_mask
        return FieldCollection([ScalarField(grid, c_rate), VectorField(grid, v_rate * mask)])

    def camphor_transport(self, state: SurfaceFields) -> np.ndarray:
        """D lap c - div(c v) of Eq. (eqc) (without flow: D lap c), at the dish's wall.

        Absorbing wall: the 5-point Laplacian and central divergence with c = v = 0 on
        and outside the circle. No-flux wall: the conservative cut-cell fluxes through
        the open part of each face over each cell's volume fraction
        (:func:`~pde_rotor.model.wall.wall_fluxes`); the step the compiled loop takes
        with them is :meth:`camphor_step`.
        """
        cfg = self.config
        c, v = state
        cells = self.domain.cut_cells
        if cells is not None:
            flow = v.data if cfg.flow.enabled else None
            return wall_rate(wall_fluxes(c.data, flow, cells, cfg.camphor.diffusion), cells)
        rate = cfg.camphor.diffusion * c.laplace(BOUNDARY).data
        if cfg.flow.enabled:
            rate -= (c * v).divergence(BOUNDARY).data
        return rate

    def camphor_step(self, state: SurfaceFields, dt: float) -> np.ndarray:
        """c after one step of Eq. (eqc) behind the no-flux wall, the bodies at their poses:
        the step of :func:`pde_rotor.model.wall.make_wall_step` (the implicit diffusion
        through the faces of the stiff cut cells), which the compiled loop takes.

        Raises:
            ValueError: with the absorbing wall (its step is forward Euler of
                :meth:`evolution_rate`).
        """
        cells = self.domain.cut_cells
        if cells is None:
            msg = "camphor_step is the step of the no-flux wall (grid.wall: no_flux)"
            raise ValueError(msg)
        c, v = state
        total_f = np.zeros_like(c.data)
        source = np.zeros_like(c.data)
        for f_k, s_k in self.body_fields(state.bodies):
            total_f += f_k
            source += s_k
        step = make_wall_step(cells, self.config.camphor.diffusion, dt)
        flow = v.data if self.config.flow.enabled else None
        return step(c.data, flow, camphor_local_rate(self.config.camphor, c.data, total_f, source))

    def body_forces(self, state: SurfaceFields) -> np.ndarray:
        """Tension force and torque, friction force and torque of every body (numpy).

        Returns:
            (K, 6): f_x, f_y, T (Eq. (torque) about X_k, in the scheme's form), and the friction
            -mu int F_k (u_k - v) dA (x, y) and its torque, Eq. (eq_motion); for a body
            that spans its channel each over the wet cells (:meth:`_spanning_integrals`).
        """
        cfg = self.config
        c, v = state
        x, y = self.cell_coordinates()
        area = self.domain.cell_area
        pressure = ScalarField(c.grid, surface_pressure(c.data, cfg.camphor))
        grad = pressure.gradient(BOUNDARY).data
        flow = v.data if cfg.flow.enabled else np.zeros_like(v.data)
        sign_k = TORQUE_SIGN[cfg.rotor.torque] * cfg.camphor.tension_slope
        out = np.zeros((len(self.bodies), 6))
        poses = state.bodies.poses
        for k, (f_k, _) in enumerate(self.body_fields(state.bodies)):
            rx, ry = x - poses[k, 0], y - poses[k, 1]
            u, w, omega = poses[k, 3], poses[k, 4], poses[k, 5]
            slip_x = u - omega * ry - flow[0]
            slip_y = w + omega * rx - flow[1]
            mu = self.bodies[k].friction
            tension = np.array(
                [
                    np.sum(f_k * grad[0]) * area,
                    np.sum(f_k * grad[1]) * area,
                    np.sum(f_k * (rx * grad[1] - ry * grad[0])) * area,
                ]
            )
            if self.bodies[k].spans:
                tension, friction = self._spanning_integrals(pressure.data, f_k, rx, ry)
                out[k] = (
                    *(sign_k * tension),
                    -mu * np.sum(friction * slip_x) * area,
                    -mu * np.sum(friction * slip_y) * area,
                    -mu * np.sum(friction * (rx * slip_y - ry * slip_x)) * area,
                )
                continue
            if self.body_scheme.consistent:
                tension = contour_integrals(
                    c.data,
                    (float(x[0, 0]), float(y[0, 0])),
                    self.domain.dx,
                    self.bodies[k].shape,
                    state.bodies.pose(k),
                    self.body_scheme,
                    k,
                    cfg.camphor,
                )
            out[k] = (
                *(sign_k * tension),
                -mu * np.sum(f_k * slip_x) * area,
                -mu * np.sum(f_k * slip_y) * area,
                -mu * np.sum(f_k * (rx * slip_y - ry * slip_x)) * area,
            )
        return out

    def _spanning_integrals(
        self, pressure: np.ndarray, f_k: np.ndarray, rx: np.ndarray, ry: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """The tension's integrals of a body that spans its channel, over the wet cells:
        -sum_P kappa_P Pi(c_P) (D F)_P dA and its torque about X (D the central
        difference), and the plate weighted by the volume fractions, kappa F, that the
        friction integrates (:func:`pde_rotor.kernels.body_sums.spanning_integrals`).

        Args:
            pressure: Pi(c) / k on the cells.
            f_k: the body's F.
            rx, ry: r - X at the cell centres.
        """
        kappa = self.domain.cut_cells.volume
        inv_2dx = 0.5 / self.domain.dx
        dfx = np.zeros_like(f_k)
        dfy = np.zeros_like(f_k)
        dfx[1:-1, :] = (f_k[2:, :] - f_k[:-2, :]) * inv_2dx
        dfy[:, 1:-1] = (f_k[:, 2:] - f_k[:, :-2]) * inv_2dx
        weight = -kappa * pressure
        area = self.domain.cell_area
        tension = np.array(
            [
                np.sum(weight * dfx) * area,
                np.sum(weight * dfy) * area,
                np.sum(weight * (rx * dfy - ry * dfx)) * area,
            ]
        )
        return tension, kappa * f_k

    def reference_step(self, state: SurfaceFields, dt: float, step: int = 0) -> SurfaceFields:
        """One step of the fields and every body from step `step`, written with numpy.

        The bodies held in this step (:func:`~pde_rotor.model.motion.held_bodies`) get
        U = 0, omega = 0; then forward Euler of Eqs. (eqc), (eqv) (:meth:`evolution_rate`)
        and of Eq. (eq_motion) (:meth:`body_forces`,
        :func:`~pde_rotor.model.motion.accelerations`,
        :func:`~pde_rotor.model.motion.euler_poses`), or with ``numerics.integrator:
        heun`` the same at the Euler-predicted state and poses, and the trapezoid of both
        (:func:`~pde_rotor.model.motion.heun_poses`). No noise; the absorbing wall (the
        no-flux wall's step is :meth:`camphor_step`). The force columns of the result
        hold the forces at the step's start (the contact force of every body that is not
        ``fixed``), ``stopped`` whether a body was held.

        Returns:
            The new state (`state` is not changed).
        """
        inertia = Inertia.of(self.bodies)
        held = held_bodies(self.bodies, self.setup.at(dt).body_schedules, step)
        start = state.copy()
        start.bodies.poses[held, 3:6] = 0.0
        rate = self.evolution_rate(start).data
        forces = self.body_forces(start)
        poses = start.bodies.poses[:, :6]
        contact = contact_forces(poses, self.bodies, self.config)
        accel = accelerations(forces, inertia, poses, contact)
        new = start.copy()
        new.data[...] = start.data + dt * rate
        new.bodies.poses[:, :6] = euler_poses(poses, accel, held, inertia, dt)
        if self.config.numerics.integrator == "heun":
            rate_p = self.evolution_rate(new).data
            predicted = new.bodies.poses[:, :6].copy()
            contact_p = contact_forces(predicted, self.bodies, self.config)
            accel_p = accelerations(self.body_forces(new), inertia, predicted, contact_p)
            new.data[...] = start.data + 0.5 * dt * (rate + rate_p)
            new.bodies.poses[:, :6] = heun_poses(
                poses, accel, predicted, accel_p, held, inertia, dt
            )
        new.bodies.poses[:, 6:12] = forces
        new.bodies.poses[:, 12] = held
        new.bodies.poses[:, 13:15] = np.where(inertia.fixed[:, None], 0.0, contact)
        return new


_NO_SUPPORT = RotorShape(
    n_corners=3,
    radius=0.0,
    apothem=0.0,
    pill_radius=0.0,
    pill_distance=0.0,
    asymmetry=0.0,
    smoothing=0.0,
    support_radius=0.0,
)
"""A shape without support: :func:`make_domain` then gives the dish's interior only."""
